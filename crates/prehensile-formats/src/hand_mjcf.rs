//! Hands from MuJoCo MJCF: `<include>` files, default classes (with `childclass`), bodies with
//! `pos`/`quat`/`euler`/`axisangle`, hinge joints (two in one body become a two-axis joint),
//! collision geoms (capsule, cylinder, sphere, box; meshes as capsules inside their convex hull,
//! read from the `<asset>`'s files below the model's folder or from inline vertices; planes and
//! non-colliding geoms are skipped), fingertip sites and two-joint fixed tendons as couplings. The hand's root is the first body
//! where the kinematic tree branches (the palm); the bodies above it (forearm, wrist) are
//! dropped and named in the hand's description.

use std::collections::HashMap;
use std::path::Path;

use prehensile_core::hand::{Axis, BonePart, HandParts, Inertial, Joint};
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::HandModel;
use roxmltree::{Document, Node};

use crate::collision_mesh::{vertex_capsules, MeshCapsules, MeshFiles, MAX_HAND_MESH_VERTICES};
use crate::hand_import::{
    bone, box_capsules, build_in_hand_frame, farthest_capsule_end, file_stem, name_fingers, Sidecar,
};
use crate::FormatError;

/// Most nested `<include>` levels.
const MAX_INCLUDE_DEPTH: usize = 8;

/// Reads an MJCF hand, following `<include>` files relative to it.
pub fn load_hand_mjcf(path: &Path) -> Result<HandModel, FormatError> {
    let name = path.display().to_string();
    let text = expand_includes(path, 0, &mut IncludeBudget::new(), &Includes::Disk)?;
    parse_mjcf(
        &text,
        &name,
        Sidecar::beside(path)?.as_ref(),
        MeshFiles::Disk(path),
    )
}

/// Reads an MJCF hand from named files held in memory (files dropped on a web page, which come
/// without their folders): `main` is the hand's file, and an `<include file="…"/>` names another
/// of `files` by its file name, and so does a mesh asset's `file`. The same bounds as on disk
/// apply.
pub fn parse_hand_mjcf_files(
    main: &str,
    files: &[(String, Vec<u8>)],
) -> Result<HandModel, FormatError> {
    let text = expand_includes(
        Path::new(main),
        0,
        &mut IncludeBudget::new(),
        &Includes::Named(files),
    )?;
    parse_mjcf(&text, main, None, MeshFiles::Named(files))
}

/// Where included files are read from.
enum Includes<'a> {
    /// The file system, confined to the including file's folder and below.
    Disk,
    /// Files held in memory, found by file name.
    Named(&'a [(String, Vec<u8>)]),
}

impl Includes<'_> {
    /// The text of `path` and a name for it in messages.
    fn read(&self, path: &Path, limit: u64) -> Result<String, FormatError> {
        match self {
            Includes::Disk => crate::read_input_text(path, limit),
            Includes::Named(files) => {
                let name = path.file_name().unwrap_or_default().to_string_lossy();
                let (_, bytes) = files.iter().find(|(n, _)| *n == name).ok_or_else(|| {
                    FormatError::new(
                        &name,
                        format!(
                            "is included but was not given; open it together with the hand file (given: {})",
                            files.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ")
                        ),
                    )
                })?;
                if bytes.len() as u64 > limit {
                    return Err(FormatError::new(
                        &name,
                        format!(
                            "the included files add up to more than {} bytes",
                            crate::MAX_TEXT_BYTES
                        ),
                    ));
                }
                String::from_utf8(bytes.clone()).map_err(|e| {
                    FormatError::new(&name, format!("the file is not UTF-8 text: {e}"))
                })
            }
        }
    }

    /// The path of the file `file` that `including` includes.
    fn resolve(&self, including: &Path, file: &str) -> Result<std::path::PathBuf, FormatError> {
        match self {
            Includes::Disk => crate::confined(including, file),
            Includes::Named(_) => Ok(Path::new(file).file_name().map_or_else(
                || Path::new(file).to_path_buf(),
                |n| Path::new(n).to_path_buf(),
            )),
        }
    }
}

/// Most files an MJCF hand may include, all levels together.
const MAX_INCLUDES: usize = 256;

/// What the includes may still add: bytes of expanded text and files.
struct IncludeBudget {
    bytes: u64,
    files: usize,
}

impl IncludeBudget {
    /// The whole allowance: [`crate::MAX_TEXT_BYTES`] of text, [`MAX_INCLUDES`] files.
    fn new() -> Self {
        Self {
            bytes: crate::MAX_TEXT_BYTES,
            files: MAX_INCLUDES,
        }
    }
}

/// Text of an MJCF file with every `<include file="..."/>` element (found by parsing the XML, so
/// includes inside comments stay comments) replaced by the included file's content inside its
/// `<mujoco>` element. Included files must lie in the including file's folder or below; the
/// expanded text and the number of files are bounded, so a fan-out of includes cannot exhaust
/// memory.
fn expand_includes(
    path: &Path,
    depth: usize,
    budget: &mut IncludeBudget,
    source: &Includes,
) -> Result<String, FormatError> {
    let name = path.display().to_string();
    if depth > MAX_INCLUDE_DEPTH {
        return Err(FormatError::new(
            &name,
            "includes nest more than 8 deep; is there an include cycle?",
        ));
    }
    let text = source.read(path, budget.bytes)?;
    let doc = Document::parse(&text)
        .map_err(|e| FormatError::at(&name, format!("line {}", e.pos().row), e.to_string()))?;
    let mut includes: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    for node in doc.descendants().filter(|n| n.has_tag_name("include")) {
        let file = node.attribute("file").ok_or_else(|| {
            FormatError::at(
                &name,
                format!("line {}", doc.text_pos_at(node.range().start).row),
                "<include> has no file attribute",
            )
        })?;
        includes.push((node.range(), file.to_string()));
    }
    let mut out = String::with_capacity(text.len());
    let mut last = 0;
    for (range, file) in includes {
        if budget.files == 0 {
            return Err(FormatError::new(
                &name,
                format!("more than {MAX_INCLUDES} included files in all"),
            ));
        }
        budget.files -= 1;
        let included = expand_includes(&source.resolve(path, &file)?, depth + 1, budget, source)?;
        // Keep what is inside the included file's <mujoco> element.
        let inner = match (included.find("<mujoco"), included.rfind("</mujoco>")) {
            (Some(open), Some(close)) => {
                let body_start = included[open..]
                    .find('>')
                    .map(|g| open + g + 1)
                    .unwrap_or(open);
                included[body_start..close].to_string()
            }
            _ => included,
        };
        budget.bytes = budget
            .bytes
            .checked_sub(inner.len() as u64)
            .ok_or_else(|| {
                FormatError::new(
                    &name,
                    format!(
                        "the included files add up to more than {} bytes",
                        crate::MAX_TEXT_BYTES
                    ),
                )
            })?;
        out.push_str(&text[last..range.start]);
        out.push_str(&inner);
        last = range.end;
    }
    out.push_str(&text[last..]);
    Ok(out)
}

/// One default class: its parent class, and per element kind (`joint`, `geom`...) its attributes.
type ClassDefaults = (Option<String>, HashMap<String, Vec<(String, String)>>);

/// Attribute lookup through an element, its class's defaults and the classes above it.
struct Defaults {
    classes: HashMap<String, ClassDefaults>,
}

impl Defaults {
    /// Reads a `<default>` element and the ones nested in it. A nested default must name a class
    /// not defined before (MuJoCo refuses the same): a repeated or missing name would let a class
    /// inherit from itself.
    fn collect(
        node: Node,
        parent: Option<&str>,
        out: &mut HashMap<String, ClassDefaults>,
        source: &str,
    ) -> Result<(), FormatError> {
        let at = || {
            format!(
                "line {}",
                node.document().text_pos_at(node.range().start).row
            )
        };
        let class = match (node.attribute("class"), parent) {
            (Some(c), _) => c.to_string(),
            (None, None) => "main".to_string(),
            (None, Some(_)) => {
                return Err(FormatError::at(
                    source,
                    at(),
                    "a nested <default> needs a class attribute",
                ))
            }
        };
        if parent.is_some() && out.contains_key(&class) {
            return Err(FormatError::at(
                source,
                at(),
                format!("default class '{class}' is defined twice; give each class its own name"),
            ));
        }
        let mut kinds = HashMap::new();
        for c in node
            .children()
            .filter(|c| c.is_element() && !c.has_tag_name("default"))
        {
            let attrs = c
                .attributes()
                .map(|a| (a.name().to_string(), a.value().to_string()))
                .collect();
            kinds.insert(c.tag_name().name().to_string(), attrs);
        }
        out.insert(class.clone(), (parent.map(str::to_string), kinds));
        for c in node.children().filter(|c| c.has_tag_name("default")) {
            Self::collect(c, Some(&class), out, source)?;
        }
        Ok(())
    }

    fn get(&self, node: Node, class: &str, name: &str) -> Option<String> {
        if let Some(v) = node.attribute(name) {
            return Some(v.to_string());
        }
        let mut at = Some(class.to_string());
        // Every class at most once: an implicit step up to "main" could otherwise close a loop
        // (a class "main" nested in another).
        let mut steps = 0..=self.classes.len();
        while let (Some(c), Some(_)) = (at, steps.next()) {
            let (parent, kinds) = self.classes.get(&c)?;
            if let Some(v) = kinds
                .get(node.tag_name().name())
                .and_then(|attrs| attrs.iter().find(|(k, _)| k == name))
            {
                return Some(v.1.clone());
            }
            at = parent
                .clone()
                .or_else(|| (c != "main").then(|| "main".to_string()));
        }
        None
    }
}

/// The child bodies of a body.
fn bodies<'a, 'i>(n: Node<'a, 'i>) -> Vec<Node<'a, 'i>> {
    n.children().filter(|c| c.has_tag_name("body")).collect()
}

/// Parses MJCF text (includes already expanded) into a hand.
pub fn parse_hand_mjcf(text: &str, source: &str) -> Result<HandModel, FormatError> {
    parse_hand_mjcf_with(text, source, None)
}

/// As [`parse_hand_mjcf`], with a sidecar's overrides. Mesh geoms whose vertices are in files
/// are skipped (and named): [`load_hand_mjcf`] reads them.
pub fn parse_hand_mjcf_with(
    text: &str,
    source: &str,
    sidecar: Option<&Sidecar>,
) -> Result<HandModel, FormatError> {
    parse_mjcf(text, source, sidecar, MeshFiles::None)
}

/// MJCF text into a hand, its mesh files read from `meshes`.
fn parse_mjcf(
    text: &str,
    source: &str,
    sidecar: Option<&Sidecar>,
    meshes: MeshFiles,
) -> Result<HandModel, FormatError> {
    let doc = Document::parse(text)
        .map_err(|e| FormatError::at(source, format!("line {}", e.pos().row), e.to_string()))?;
    let root = doc.root_element();
    let mut reader = MjcfReader::new(&doc, source, meshes)?;
    reader.check_classes(root)?;
    let palm = reader.palm(root)?;
    let mut parts = HandParts {
        rigid_couplings: true,
        name: root
            .attribute("model")
            .map(str::to_string)
            .unwrap_or_else(|| file_stem(source)),
        ..Default::default()
    };
    // Depth first with an explicit stack (a crafted file may nest bodies deeply), parents
    // before children, children in file order.
    let mut stack = vec![(palm, None::<String>)];
    while let Some((body, parent)) = stack.pop() {
        let part = reader.one_body(body, parent.as_deref())?;
        // MuJoCo requires unique body names; the bone tree is linked by name.
        if parts.bones.iter().any(|b| b.name == part.name) {
            return Err(reader.error(
                body,
                format!(
                    "two bodies are named '{}'; body names must be unique",
                    part.name
                ),
            ));
        }
        for c in bodies(body).iter().rev() {
            stack.push((*c, Some(part.name.clone())));
        }
        parts.bones.push(part);
    }
    name_fingers(&mut parts);
    for tendon in root.descendants().filter(|n| n.has_tag_name("fixed")) {
        reader.one_fixed_tendon(tendon, &mut parts);
    }
    parts.description = reader.description();
    build_in_hand_frame(parts, source, sidecar)
}

/// Reads the elements of one MJCF document, one method per element (as MuJoCo's own
/// `mjXReader::OneBody`, `OneGeom`...), and notes what it leaves out for the description.
struct MjcfReader<'d, 'i> {
    doc: &'d Document<'i>,
    source: &'d str,
    defaults: Defaults,
    /// Angles in degrees (MuJoCo's default) rather than radians.
    degrees: bool,
    /// Bodies above the palm and the palm's own joints.
    dropped: Vec<String>,
    /// Box geoms and how many capsules stand in for each.
    boxes: Vec<String>,
    /// Where mesh assets' files are read from.
    mesh_files: MeshFiles<'d>,
    /// The `<asset>`'s meshes by name.
    mesh_assets: HashMap<String, MeshAsset>,
    /// Mesh geoms and what they became.
    meshes: Vec<String>,
    /// Vertices the collision meshes may still have.
    mesh_budget: usize,
    /// Colliding geoms that are not read, with the reason.
    skipped: Vec<String>,
}

/// A `<mesh>` of the `<asset>`: its file (with the compiler's `meshdir`) or inline vertices,
/// and its scale per axis.
struct MeshAsset {
    file: Option<String>,
    vertex: Option<Vec<f64>>,
    scale: Vec3,
}

/// One `<joint>` of a body.
enum JointElement {
    /// A hinge: its name and axis with limits.
    Hinge(String, Axis),
    /// A ball joint: its name and cone angle, radians.
    Ball(String, f64),
}

impl<'d, 'i> MjcfReader<'d, 'i> {
    /// The compiler's angle unit, every default class and every mesh asset of `doc`.
    fn new(
        doc: &'d Document<'i>,
        source: &'d str,
        mesh_files: MeshFiles<'d>,
    ) -> Result<Self, FormatError> {
        let root = doc.root_element();
        let compiler = root.descendants().find(|n| n.has_tag_name("compiler"));
        let degrees = compiler
            .and_then(|c| c.attribute("angle"))
            .is_none_or(|a| a != "radian");
        let mut classes = HashMap::new();
        for d in root.children().filter(|n| n.has_tag_name("default")) {
            Defaults::collect(d, None, &mut classes, source)?;
        }
        let mut reader = Self {
            doc,
            source,
            defaults: Defaults { classes },
            degrees,
            dropped: Vec::new(),
            boxes: Vec::new(),
            mesh_files,
            mesh_assets: HashMap::new(),
            meshes: Vec::new(),
            mesh_budget: MAX_HAND_MESH_VERTICES,
            skipped: Vec::new(),
        };
        let mesh_dir = compiler
            .and_then(|c| c.attribute("meshdir").or_else(|| c.attribute("assetdir")))
            .unwrap_or("");
        for mesh in root
            .children()
            .filter(|n| n.has_tag_name("asset"))
            .flat_map(|a| a.children().filter(|n| n.has_tag_name("mesh")))
        {
            reader.one_mesh_asset(mesh, mesh_dir)?;
        }
        Ok(reader)
    }

    /// One `<mesh>` of the `<asset>`: named by `name` or its file's stem, as MuJoCo names it.
    fn one_mesh_asset(&mut self, mesh: Node, mesh_dir: &str) -> Result<(), FormatError> {
        let file = mesh.attribute("file").map(|f| {
            if mesh_dir.is_empty() {
                f.to_string()
            } else {
                format!("{}/{f}", mesh_dir.trim_end_matches('/'))
            }
        });
        let name = match (mesh.attribute("name"), mesh.attribute("file")) {
            (Some(n), _) => n.to_string(),
            (None, Some(f)) => file_stem(f),
            (None, None) => return Err(self.error(mesh, "a <mesh> needs a name or a file")),
        };
        let vertex = match mesh.attribute("vertex") {
            Some(v) => Some(self.numbers(mesh, v, "vertex")?),
            None => None,
        };
        let scale = match self.get(mesh, "scale") {
            Some(s) => match self.numbers(mesh, &s, "scale")?.as_slice() {
                [x, y, z] => Vec3::new(*x, *y, *z),
                _ => return Err(self.error(mesh, "scale needs three numbers")),
            },
            None => Vec3::repeat(1.0),
        };
        self.mesh_assets.insert(
            name,
            MeshAsset {
                file,
                vertex,
                scale,
            },
        );
        Ok(())
    }

    /// Where `node` is, for messages.
    fn at(&self, node: Node) -> String {
        format!(
            "<{}> at line {}",
            node.tag_name().name(),
            self.doc.text_pos_at(node.range().start).row
        )
    }

    /// An error at `node`.
    fn error(&self, node: Node, message: impl Into<String>) -> FormatError {
        FormatError::at(self.source, self.at(node), message)
    }

    /// An angle read from the file, in radians.
    fn angle(&self, v: f64) -> f64 {
        if self.degrees {
            v.to_radians()
        } else {
            v
        }
    }

    /// The finite numbers of attribute value `value` of `node`.
    fn numbers(&self, node: Node, value: &str, what: &str) -> Result<Vec<f64>, FormatError> {
        value
            .split_whitespace()
            .map(|w| w.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| {
                self.error(
                    node,
                    format!("{what} '{value}' is not a list of finite numbers"),
                )
            })
    }

    /// Attribute `name` of `node`, from the element or its class's defaults.
    fn get(&self, node: Node, name: &str) -> Option<String> {
        let class = match node.attribute("class") {
            Some(c) => c,
            None => node
                .ancestors()
                .find_map(|a| a.attribute("childclass"))
                .unwrap_or("main"),
        };
        self.defaults.get(node, class, name)
    }

    /// Whether a `limited` joint attribute leaves the range in force.
    fn limited(&self, node: Node) -> bool {
        self.get(node, "limited").is_none_or(|l| l != "false")
    }

    /// Refuses a `class` or `childclass` that names no default class.
    fn check_classes(&self, root: Node) -> Result<(), FormatError> {
        for node in root
            .descendants()
            .filter(|n| n.is_element() && !n.has_tag_name("default"))
        {
            for name in ["class", "childclass"] {
                if let Some(c) = node.attribute(name) {
                    if !self.defaults.classes.contains_key(c) {
                        return Err(self.error(
                            node,
                            format!("default class '{c}' is not defined; load the model file that includes its defaults (for the Shadow hand: reach.xml, which includes shared.xml)"),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// The palm: in the top-level body tree with the most joints, the first body where the tree
    /// branches. The bodies above it are dropped.
    fn palm<'a>(&mut self, root: Node<'a, 'i>) -> Result<Node<'a, 'i>, FormatError> {
        let joints_in = |n: Node| n.descendants().filter(|d| d.has_tag_name("joint")).count();
        let Some(mut palm) = root
            .descendants()
            .filter(|n| {
                n.has_tag_name("body") && n.parent().is_some_and(|p| !p.has_tag_name("body"))
            })
            .max_by_key(|n| joints_in(*n))
        else {
            return Err(FormatError::new(
                self.source,
                "no <body> found; is this an MJCF model?",
            ));
        };
        while let [only] = bodies(palm).as_slice() {
            self.dropped
                .push(palm.attribute("name").unwrap_or("?").to_string());
            palm = *only;
        }
        Ok(palm)
    }

    /// The frame of `node` (a body, geom, site or inertial) in its parent's: `pos` and one of
    /// `quat`, `euler` (MuJoCo's default sequence, xyz about the moving axes) or `axisangle`.
    fn frame(&self, node: Node) -> Result<Transform, FormatError> {
        let pos = match self.get(node, "pos") {
            Some(p) => match self.numbers(node, &p, "pos")?.as_slice() {
                [x, y, z] => Vec3::new(*x, *y, *z),
                _ => return Err(self.error(node, "pos needs three numbers")),
            },
            None => Vec3::zeros(),
        };
        Ok(Transform::from_parts(pos.into(), self.orientation(node)?))
    }

    /// The orientation part of [`Self::frame`].
    fn orientation(&self, node: Node) -> Result<Rotation, FormatError> {
        if let Some(q) = self.get(node, "quat") {
            return match self.numbers(node, &q, "quat")?.as_slice() {
                [w, x, y, z] => Ok(Rotation::from_quaternion(nalgebra::Quaternion::new(
                    *w, *x, *y, *z,
                ))),
                _ => Err(self.error(node, "quat needs four numbers")),
            };
        }
        if let Some(e) = self.get(node, "euler") {
            return match self.numbers(node, &e, "euler")?.as_slice() {
                [a, b, c] => Ok(Rotation::from_axis_angle(&Vec3::x_axis(), self.angle(*a))
                    * Rotation::from_axis_angle(&Vec3::y_axis(), self.angle(*b))
                    * Rotation::from_axis_angle(&Vec3::z_axis(), self.angle(*c))),
                _ => Err(self.error(node, "euler needs three numbers")),
            };
        }
        if let Some(aa) = self.get(node, "axisangle") {
            return match self.numbers(node, &aa, "axisangle")?.as_slice() {
                [x, y, z, a] => Ok(Rotation::from_axis_angle(
                    &nalgebra::Unit::new_normalize(Vec3::new(*x, *y, *z)),
                    self.angle(*a),
                )),
                _ => Err(self.error(node, "axisangle needs four numbers")),
            };
        }
        if self.get(node, "xyaxes").is_some() || self.get(node, "zaxis").is_some() {
            return Err(self.error(
                node,
                "xyaxes and zaxis orientations are not supported yet; use quat or euler",
            ));
        }
        Ok(Rotation::identity())
    }

    /// One `<body>` as a bone: its frame (the palm's is the hand's), mass, joints, collision
    /// geoms and, at the end of a finger, its tip.
    fn one_body(&mut self, body: Node, parent: Option<&str>) -> Result<BonePart, FormatError> {
        let name = body
            .attribute("name")
            .map(str::to_string)
            .unwrap_or_else(|| format!("body@{}", self.at(body)));
        let rest = match parent {
            Some(_) => self.frame(body)?,
            None => Transform::identity(),
        };
        let mut part = bone(&name, parent, rest);
        if let Some(i) = body.children().find(|c| c.has_tag_name("inertial")) {
            part.inertial = Some(self.one_inertial(i)?);
        }
        self.body_joints(body, parent.is_none(), &mut part)?;
        for g in body.children().filter(|c| c.has_tag_name("geom")) {
            self.one_geom(g, &mut part)?;
        }
        if bodies(body).is_empty() {
            part.tip = Some(self.tip(body, &part)?);
        }
        Ok(part)
    }

    /// One `<inertial>`: mass, centre of mass and the inertia tensor in the body's frame.
    fn one_inertial(&self, i: Node) -> Result<Inertial, FormatError> {
        let frame = self.frame(i)?;
        let mass = i
            .attribute("mass")
            .map_or(Ok(vec![0.0]), |m| self.numbers(i, m, "mass"))?;
        let tensor = if let Some(d) = i.attribute("diaginertia") {
            match self.numbers(i, d, "diaginertia")?.as_slice() {
                [a, b, c] => nalgebra::Matrix3::from_diagonal(&Vec3::new(*a, *b, *c)),
                _ => return Err(self.error(i, "diaginertia needs three numbers")),
            }
        } else if let Some(f) = i.attribute("fullinertia") {
            match self.numbers(i, f, "fullinertia")?.as_slice() {
                [xx, yy, zz, xy, xz, yz] => {
                    nalgebra::Matrix3::new(*xx, *xy, *xz, *xy, *yy, *yz, *xz, *yz, *zz)
                }
                _ => return Err(self.error(i, "fullinertia needs six numbers")),
            }
        } else {
            nalgebra::Matrix3::zeros()
        };
        let r = frame.rotation.to_rotation_matrix().into_inner();
        Ok(Inertial {
            mass: mass.first().copied().unwrap_or(0.0),
            center_of_mass: Point3::from(frame.translation.vector),
            inertia: r * tensor * r.transpose(),
        })
    }

    /// A body's joints as the bone's: one hinge, two hinges (the first outermost, as MuJoCo
    /// applies them) or one ball joint. The palm's own joints move the whole hand, as the hook's
    /// rotations do, and are dropped.
    fn body_joints(
        &mut self,
        body: Node,
        is_palm: bool,
        part: &mut BonePart,
    ) -> Result<(), FormatError> {
        let joints: Vec<Node> = body
            .children()
            .filter(|c| c.has_tag_name("joint"))
            .collect();
        let mut hinges = Vec::new();
        for j in &joints {
            match self.one_joint(*j)? {
                JointElement::Hinge(name, axis) => hinges.push((name, axis)),
                JointElement::Ball(name, max) => {
                    if joints.len() != 1 {
                        return Err(self.error(
                            body,
                            format!(
                                "body '{}' mixes a ball joint with others; not supported",
                                part.name
                            ),
                        ));
                    }
                    part.joint = Joint::Ball {
                        limits: [[-max, max]; 3],
                    };
                    part.dof_names = ["x", "y", "z"]
                        .iter()
                        .map(|a| format!("{name}.{a}"))
                        .collect();
                }
            }
        }
        if is_palm && !hinges.is_empty() {
            self.dropped.extend(hinges.drain(..).map(|(n, _)| n));
        }
        match hinges.as_slice() {
            [] => {}
            [(n, a)] => {
                part.joint = Joint::Hinge(*a);
                part.dof_names = vec![n.clone()];
            }
            [(n0, outer), (n1, inner)] => {
                part.joint = Joint::TwoAxis {
                    flexion: *inner,
                    abduction: *outer,
                };
                part.dof_names = vec![n1.clone(), n0.clone()];
            }
            _ => {
                return Err(self.error(
                    body,
                    format!(
                        "body '{}' has more than two joints; not supported",
                        part.name
                    ),
                ))
            }
        }
        Ok(())
    }

    /// One `<joint>`: a hinge at its body's origin (axis and range) or a ball joint (MuJoCo
    /// limits it by one cone angle: each rotation-vector component within ± that angle).
    fn one_joint(&self, j: Node) -> Result<JointElement, FormatError> {
        let name = j.attribute("name").unwrap_or("?").to_string();
        let range = |j: Node| -> Result<Option<[f64; 2]>, FormatError> {
            match (self.get(j, "range"), self.limited(j)) {
                (Some(r), true) => match self.numbers(j, &r, "range")?.as_slice() {
                    [lo, hi] => Ok(Some([self.angle(*lo), self.angle(*hi)])),
                    _ => Err(self.error(j, "range needs two numbers")),
                },
                _ => Ok(None),
            }
        };
        match self.get(j, "type").as_deref().unwrap_or("hinge") {
            "hinge" => {}
            "ball" => {
                let max = range(j)?.map_or(std::f64::consts::PI, |[_, hi]| hi.abs());
                return Ok(JointElement::Ball(name, max));
            }
            other => {
                return Err(self.error(
                    j,
                    format!("joint '{name}' is of type '{other}'; hand bodies may use hinge and ball joints"),
                ))
            }
        }
        if let Some(p) = self.get(j, "pos") {
            if self.numbers(j, &p, "pos")?.iter().any(|v| v.abs() > 1e-9) {
                return Err(self.error(
                    j,
                    format!(
                        "joint '{name}' is not at its body's origin; this is not supported yet"
                    ),
                ));
            }
        }
        let axis = match self.get(j, "axis") {
            Some(a) => match self.numbers(j, &a, "axis")?.as_slice() {
                [x, y, z] if Vec3::new(*x, *y, *z).norm() > 1e-12 => Vec3::new(*x, *y, *z),
                _ => return Err(self.error(j, format!("joint '{name}' needs a non-zero axis"))),
            },
            None => Vec3::z(),
        };
        let limits = range(j)?.unwrap_or([-std::f64::consts::PI, std::f64::consts::PI]);
        Ok(JointElement::Hinge(name, Axis::new(axis, limits)))
    }

    /// One `<geom>` that collides, as capsules of the bone: capsules and cylinders by `fromto`
    /// or size, spheres, boxes as rows of capsules within 1 mm of their faces, meshes as
    /// capsules inside their convex hull. Planes, primitives fitted to a mesh and meshes that
    /// cannot be read are named in the description as skipped.
    fn one_geom(&mut self, g: Node, part: &mut BonePart) -> Result<(), FormatError> {
        let collides = self.get(g, "contype").is_none_or(|c| c != "0")
            || self.get(g, "conaffinity").is_none_or(|c| c != "0");
        if !collides {
            return Ok(());
        }
        let mesh = self.get(g, "mesh");
        let kind = self.get(g, "type").unwrap_or_else(|| "sphere".into());
        let geom_name = g
            .attribute("name")
            .map_or_else(|| format!("a geom of {}", part.name), str::to_string);
        match (kind.as_str(), mesh) {
            ("mesh", Some(mesh)) => return self.mesh_geom(g, &geom_name, &mesh, part),
            ("mesh", None) => {
                return Err(self.error(g, format!("mesh geom '{geom_name}' names no mesh")))
            }
            ("plane", _) => {
                self.skipped.push(format!("{geom_name} (a plane)"));
                return Ok(());
            }
            (_, Some(_)) => {
                self.skipped.push(format!(
                    "{geom_name} (a {kind} fitted to a mesh is not supported; give its size)"
                ));
                return Ok(());
            }
            _ => {}
        }
        let size = self.numbers(g, &self.get(g, "size").unwrap_or_default(), "size")?;
        if let (Some(ft), Some(r)) = (self.get(g, "fromto"), size.first()) {
            return match self.numbers(g, &ft, "fromto")?.as_slice() {
                [a, b, c, d, e, f] => {
                    part.capsules
                        .push((Point3::new(*a, *b, *c), Point3::new(*d, *e, *f), *r));
                    Ok(())
                }
                _ => Err(self.error(g, "fromto needs six numbers and size a radius")),
            };
        }
        let frame = self.frame(g)?;
        let (half, radius) = match (kind.as_str(), size.as_slice()) {
            ("capsule" | "cylinder", [r, h, ..]) => (Vec3::new(0.0, 0.0, *h), *r),
            ("sphere", [r, ..]) => (Vec3::zeros(), *r),
            ("box", [x, y, z]) => {
                let capsules = box_capsules(&frame, [*x, *y, *z]);
                self.boxes.push(format!("{geom_name} ({})", capsules.len()));
                part.capsules.extend(capsules);
                return Ok(());
            }
            (other, _) => {
                return Err(self.error(
                    g,
                    format!("geom type '{other}' with size {size:?} is not supported"),
                ))
            }
        };
        part.capsules.push((
            frame * Point3::from(-half),
            frame * Point3::from(half),
            radius,
        ));
        Ok(())
    }

    /// A mesh geom as capsules inside the mesh's hull, placed by the geom's frame (MuJoCo
    /// collides a mesh geom as its convex hull).
    fn mesh_geom(
        &mut self,
        g: Node,
        geom_name: &str,
        mesh: &str,
        part: &mut BonePart,
    ) -> Result<(), FormatError> {
        let frame = self.frame(g)?;
        let made: Result<MeshCapsules, String> = match self.mesh_assets.get(mesh) {
            None => Err(format!("{geom_name} (mesh '{mesh}' is not in the <asset>)")),
            Some(MeshAsset {
                vertex: Some(v),
                scale,
                ..
            }) => {
                if v.len() % 3 != 0 {
                    return Err(self.error(
                        g,
                        format!(
                            "mesh '{mesh}' has {} vertex numbers, not a multiple of 3",
                            v.len()
                        ),
                    ));
                }
                let points: Vec<Point3> = v
                    .chunks_exact(3)
                    .map(|c| Point3::new(c[0], c[1], c[2]))
                    .collect();
                vertex_capsules(geom_name, &points, *scale, &frame, &mut self.mesh_budget)
            }
            Some(MeshAsset {
                file: Some(file),
                scale,
                ..
            }) => self
                .mesh_files
                .capsules(geom_name, file, *scale, &frame, &mut self.mesh_budget),
            Some(_) => Err(format!(
                "{geom_name} (mesh '{mesh}' has neither a file nor vertices)"
            )),
        };
        match made {
            Ok(m) => {
                part.capsules.extend(m.capsules);
                self.meshes.push(m.note);
            }
            Err(note) => self.skipped.push(note),
        }
        Ok(())
    }

    /// The tip of a body that ends a finger: a site named `…tip…`, else the capsule end
    /// farthest from the body's origin.
    fn tip(&self, body: Node, part: &BonePart) -> Result<Point3, FormatError> {
        body.children()
            .filter(|c| {
                c.has_tag_name("site") && c.attribute("name").is_some_and(|n| n.contains("tip"))
            })
            .find_map(|s| self.frame(s).ok())
            .map(|f| Point3::from(f.translation.vector))
            .or_else(|| farthest_capsule_end(&part.capsules))
            .ok_or_else(|| {
                self.error(
                    body,
                    format!(
                        "body '{}' ends a finger but has no tip site or collision geom{}",
                        part.name,
                        if self.skipped.is_empty() {
                            String::new()
                        } else {
                            format!(" (skipped: {})", self.skipped.join(", "))
                        }
                    ),
                )
            })
    }

    /// One `<fixed>` tendon: two joints in a tight range hold c1·q1 + c2·q2 ≈ 0, so
    /// q1 = −(c2/c1)·q2, a coupling of the hand. Other tendons are not read.
    fn one_fixed_tendon(&self, t: Node, parts: &mut HandParts) {
        let members: Vec<(String, f64)> = t
            .children()
            .filter(|c| c.has_tag_name("joint"))
            .filter_map(|c| {
                Some((
                    c.attribute("joint")?.to_string(),
                    c.attribute("coef")?.parse().ok()?,
                ))
            })
            .collect();
        let tight = t
            .attribute("range")
            .and_then(|r| self.numbers(t, r, "range").ok())
            .is_some_and(|r| r.len() == 2 && r[0].abs() < 0.005 && r[1].abs() < 0.005);
        if let ([(follower, c1), (leader, c2)], true) = (members.as_slice(), tight) {
            let all: Vec<&String> = parts.bones.iter().flat_map(|b| &b.dof_names).collect();
            if all.contains(&follower) && all.contains(&leader) && c1.abs() > 1e-12 {
                parts
                    .couplings
                    .push((follower.clone(), leader.clone(), -c2 / c1));
            }
        }
    }

    /// The hand's description: its source and what was dropped, approximated or skipped.
    fn description(&self) -> String {
        let mut d = format!("imported from {}", self.source);
        if !self.dropped.is_empty() {
            d += &format!("; dropped above the palm: {}", self.dropped.join(", "));
        }
        if !self.boxes.is_empty() {
            d += &format!(
                "; boxes as capsules within 1 mm of their two largest faces, edges rounded: {}",
                self.boxes.join(", ")
            );
        }
        if !self.meshes.is_empty() {
            d += &format!("; meshes as capsules: {}", self.meshes.join(", "));
        }
        if !self.skipped.is_empty() {
            d += &format!("; collision geoms skipped: {}", self.skipped.join(", "));
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_class_main_nested_under_another_does_not_make_lookups_loop() {
        // <default class="outer"><default class="main">...: main's parent is outer, whose
        // implicit parent is main again.
        let text = r#"<mujoco><default class="outer"><default class="main"><joint damping="1"/></default></default><worldbody><geom/></worldbody></mujoco>"#;
        let doc = roxmltree::Document::parse(text).unwrap();
        let mut classes = HashMap::new();
        let root = doc.root_element();
        for d in root.children().filter(|n| n.has_tag_name("default")) {
            Defaults::collect(d, None, &mut classes, "x.xml").unwrap();
        }
        let defaults = Defaults { classes };
        let geom = root.descendants().find(|n| n.has_tag_name("geom")).unwrap();
        assert_eq!(defaults.get(geom, "main", "size"), None);
    }
}
