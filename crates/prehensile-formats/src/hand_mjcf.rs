//! Hands from MuJoCo MJCF: `<include>` files, default classes (with `childclass`), bodies with
//! `pos`/`quat`/`euler`/`axisangle`, hinge joints (two in one body become a two-axis joint),
//! collision geoms (capsule, cylinder, sphere, box; meshes and non-colliding geoms are skipped),
//! fingertip sites and two-joint fixed tendons as couplings. The hand's root is the first body
//! where the kinematic tree branches (the palm); the bodies above it (forearm, wrist) are
//! dropped and named in the hand's description.

use std::collections::HashMap;
use std::path::Path;

use prehensile_core::hand::{Axis, HandParts, Inertial, Joint};
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::HandModel;
use roxmltree::{Document, Node};

use crate::hand_import::{
    bone, box_capsules, build_in_hand_frame, file_stem, finger_name, Sidecar,
};
use crate::FormatError;

/// Most nested `<include>` levels.
const MAX_INCLUDE_DEPTH: usize = 8;

/// Reads an MJCF hand, following `<include>` files relative to it.
pub fn load_hand_mjcf(path: &Path) -> Result<HandModel, FormatError> {
    let name = path.display().to_string();
    let text = expand_includes(path, 0, &mut IncludeBudget::new(), &Includes::Disk)?;
    parse_hand_mjcf_with(&text, &name, Sidecar::beside(path)?.as_ref())
}

/// Reads an MJCF hand from named files held in memory (files dropped on a web page, which come
/// without their folders): `main` is the hand's file, and an `<include file="…"/>` names another
/// of `files` by its file name. The same bounds as on disk apply.
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
    parse_hand_mjcf(&text, main)
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

/// As [`parse_hand_mjcf`], with a sidecar's overrides.
pub fn parse_hand_mjcf_with(
    text: &str,
    source: &str,
    sidecar: Option<&Sidecar>,
) -> Result<HandModel, FormatError> {
    let doc = Document::parse(text)
        .map_err(|e| FormatError::at(source, format!("line {}", e.pos().row), e.to_string()))?;
    let at = |node: Node| {
        format!(
            "<{}> at line {}",
            node.tag_name().name(),
            doc.text_pos_at(node.range().start).row
        )
    };
    let root = doc.root_element();
    let degrees = root
        .descendants()
        .find(|n| n.has_tag_name("compiler"))
        .and_then(|c| c.attribute("angle"))
        .is_none_or(|a| a != "radian");
    let angle = |v: f64| if degrees { v.to_radians() } else { v };
    let mut classes = HashMap::new();
    for d in root.children().filter(|n| n.has_tag_name("default")) {
        Defaults::collect(d, None, &mut classes, source)?;
    }
    let defaults = Defaults { classes };
    for node in root
        .descendants()
        .filter(|n| n.is_element() && !n.has_tag_name("default"))
    {
        for name in ["class", "childclass"] {
            if let Some(c) = node.attribute(name) {
                if !defaults.classes.contains_key(c) {
                    return Err(FormatError::at(
                        source,
                        at(node),
                        format!("default class '{c}' is not defined; load the model file that includes its defaults (for the Shadow hand: reach.xml, which includes shared.xml)"),
                    ));
                }
            }
        }
    }
    // The body tree with the most joints is the hand.
    let tops: Vec<Node> = root
        .descendants()
        .filter(|n| n.has_tag_name("body") && n.parent().is_some_and(|p| !p.has_tag_name("body")))
        .collect();
    let joints_in = |n: Node| n.descendants().filter(|d| d.has_tag_name("joint")).count();
    let Some(mut palm) = tops.into_iter().max_by_key(|n| joints_in(*n)) else {
        return Err(FormatError::new(
            source,
            "no <body> found; is this an MJCF model?",
        ));
    };

    let mut dropped = Vec::new();
    // What became of the collision geoms that are not one capsule.
    let mut boxes = Vec::new();
    let mut skipped = Vec::new();
    while let [only] = bodies(palm).as_slice() {
        dropped.push(palm.attribute("name").unwrap_or("?").to_string());
        palm = *only;
    }
    let numbers = |node: Node, value: &str, what: &str| -> Result<Vec<f64>, FormatError> {
        value
            .split_whitespace()
            .map(|w| w.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| {
                FormatError::at(
                    source,
                    at(node),
                    format!("{what} '{value}' is not a list of finite numbers"),
                )
            })
    };
    let class_of = |node: Node| -> String {
        if let Some(c) = node.attribute("class") {
            return c.to_string();
        }
        node.ancestors()
            .find_map(|a| a.attribute("childclass"))
            .unwrap_or("main")
            .to_string()
    };
    let frame_of = |node: Node| -> Result<Transform, FormatError> {
        let class = class_of(node);
        let get = |name: &str| defaults.get(node, &class, name);
        let pos = match get("pos") {
            Some(p) => match numbers(node, &p, "pos")?.as_slice() {
                [x, y, z] => Vec3::new(*x, *y, *z),
                _ => return Err(FormatError::at(source, at(node), "pos needs three numbers")),
            },
            None => Vec3::zeros(),
        };
        let rotation = if let Some(q) = get("quat") {
            match numbers(node, &q, "quat")?.as_slice() {
                [w, x, y, z] => {
                    Rotation::from_quaternion(nalgebra::Quaternion::new(*w, *x, *y, *z))
                }
                _ => return Err(FormatError::at(source, at(node), "quat needs four numbers")),
            }
        } else if let Some(e) = get("euler") {
            match numbers(node, &e, "euler")?.as_slice() {
                // MuJoCo's default eulerseq "xyz": rotations about the moving x, then y, then z.
                [a, b, c] => {
                    Rotation::from_axis_angle(&Vec3::x_axis(), angle(*a))
                        * Rotation::from_axis_angle(&Vec3::y_axis(), angle(*b))
                        * Rotation::from_axis_angle(&Vec3::z_axis(), angle(*c))
                }
                _ => {
                    return Err(FormatError::at(
                        source,
                        at(node),
                        "euler needs three numbers",
                    ))
                }
            }
        } else if let Some(aa) = get("axisangle") {
            match numbers(node, &aa, "axisangle")?.as_slice() {
                [x, y, z, a] => Rotation::from_axis_angle(
                    &nalgebra::Unit::new_normalize(Vec3::new(*x, *y, *z)),
                    angle(*a),
                ),
                _ => {
                    return Err(FormatError::at(
                        source,
                        at(node),
                        "axisangle needs four numbers",
                    ))
                }
            }
        } else if get("xyaxes").is_some() || get("zaxis").is_some() {
            return Err(FormatError::at(
                source,
                at(node),
                "xyaxes and zaxis orientations are not supported yet; use quat or euler",
            ));
        } else {
            Rotation::identity()
        };
        Ok(Transform::from_parts(pos.into(), rotation))
    };
    let mut parts = HandParts {
        rigid_couplings: true,
        name: root
            .attribute("model")
            .map(str::to_string)
            .unwrap_or_else(|| file_stem(source)),
        description: if dropped.is_empty() {
            format!("imported from {source}")
        } else {
            format!(
                "imported from {source}; bodies above the palm dropped: {}",
                dropped.join(", ")
            )
        },
        ..Default::default()
    };
    let mut stack = vec![(palm, None::<String>)];
    while let Some((body, parent)) = stack.pop() {
        let name = body
            .attribute("name")
            .map(str::to_string)
            .unwrap_or_else(|| format!("body@{}", at(body)));
        // MuJoCo requires unique body names; the bone tree is linked by name.
        if parts.bones.iter().any(|b| b.name == name) {
            return Err(FormatError::at(
                source,
                at(body),
                format!("two bodies are named '{name}'; body names must be unique"),
            ));
        }
        let rest = if parent.is_some() {
            frame_of(body)?
        } else {
            Transform::identity()
        };
        let mut part = bone(&name, parent.as_deref(), rest);
        if let Some(i) = body.children().find(|c| c.has_tag_name("inertial")) {
            let frame = frame_of(i)?;
            let mass = i
                .attribute("mass")
                .map_or(Ok(vec![0.0]), |m| numbers(i, m, "mass"))?;
            let tensor = if let Some(d) = i.attribute("diaginertia") {
                match numbers(i, d, "diaginertia")?.as_slice() {
                    [a, b, c] => nalgebra::Matrix3::from_diagonal(&Vec3::new(*a, *b, *c)),
                    _ => {
                        return Err(FormatError::at(
                            source,
                            at(i),
                            "diaginertia needs three numbers",
                        ))
                    }
                }
            } else if let Some(f) = i.attribute("fullinertia") {
                match numbers(i, f, "fullinertia")?.as_slice() {
                    [xx, yy, zz, xy, xz, yz] => {
                        nalgebra::Matrix3::new(*xx, *xy, *xz, *xy, *yy, *yz, *xz, *yz, *zz)
                    }
                    _ => {
                        return Err(FormatError::at(
                            source,
                            at(i),
                            "fullinertia needs six numbers",
                        ))
                    }
                }
            } else {
                nalgebra::Matrix3::zeros()
            };
            let r = frame.rotation.to_rotation_matrix().into_inner();
            part.inertial = Some(Inertial {
                mass: mass.first().copied().unwrap_or(0.0),
                center_of_mass: Point3::from(frame.translation.vector),
                inertia: r * tensor * r.transpose(),
            });
        }
        let joints: Vec<Node> = body
            .children()
            .filter(|c| c.has_tag_name("joint"))
            .collect();
        let mut axes = Vec::new();
        for j in &joints {
            let jclass = class_of(*j);
            let get = |n: &str| defaults.get(*j, &jclass, n);
            let jname = j.attribute("name").unwrap_or("?").to_string();
            match get("type").as_deref().unwrap_or("hinge") {
                "hinge" => {}
                "ball" => {
                    // MuJoCo limits a ball joint by one cone angle: each rotation-vector
                    // component within ±that angle.
                    let limited = get("limited").is_none_or(|l| l != "false");
                    let max = match (get("range"), limited) {
                        (Some(r), true) => match numbers(*j, &r, "range")?.as_slice() {
                            [_, hi] => angle(*hi).abs(),
                            _ => return Err(FormatError::at(source, at(*j), "range needs two numbers")),
                        },
                        _ => std::f64::consts::PI,
                    };
                    if joints.len() != 1 {
                        return Err(FormatError::at(source, at(body), format!("body '{name}' mixes a ball joint with others; not supported")));
                    }
                    part.joint = Joint::Ball { limits: [[-max, max]; 3] };
                    part.dof_names = ["x", "y", "z"].iter().map(|a| format!("{jname}.{a}")).collect();
                    continue;
                }
                other => {
                    return Err(FormatError::at(
                        source,
                        at(*j),
                        format!("joint '{jname}' is of type '{other}'; hand bodies may use hinge and ball joints"),
                    ))
                }
            }
            if let Some(p) = get("pos") {
                if numbers(*j, &p, "pos")?.iter().any(|v| v.abs() > 1e-9) {
                    return Err(FormatError::at(source, at(*j), format!("joint '{jname}' is not at its body's origin; this is not supported yet")));
                }
            }
            let axis = match get("axis") {
                Some(a) => match numbers(*j, &a, "axis")?.as_slice() {
                    [x, y, z] if Vec3::new(*x, *y, *z).norm() > 1e-12 => Vec3::new(*x, *y, *z),
                    _ => {
                        return Err(FormatError::at(
                            source,
                            at(*j),
                            format!("joint '{jname}' needs a non-zero axis"),
                        ))
                    }
                },
                None => Vec3::z(),
            };
            let limited = get("limited").is_none_or(|l| l != "false");
            let limits = match (get("range"), limited) {
                (Some(r), true) => match numbers(*j, &r, "range")?.as_slice() {
                    [lo, hi] => [angle(*lo), angle(*hi)],
                    _ => return Err(FormatError::at(source, at(*j), "range needs two numbers")),
                },
                _ => [-std::f64::consts::PI, std::f64::consts::PI],
            };
            axes.push((jname, Axis::new(axis, limits)));
        }
        if parent.is_none() && !axes.is_empty() {
            // The palm's own joints move the whole hand, as the hook's rotations do: dropped.
            dropped.extend(axes.drain(..).map(|(n, _)| n));
        }
        match axes.as_slice() {
            [] if matches!(part.joint, Joint::Ball { .. }) => {}
            [] => {}
            [(n, a)] => {
                part.joint = Joint::Hinge(*a);
                part.dof_names = vec![n.clone()];
            }
            // MuJoCo applies a body's joints in order: the first is outermost.
            [(n0, outer), (n1, inner)] => {
                part.joint = Joint::TwoAxis {
                    flexion: *inner,
                    abduction: *outer,
                };
                part.dof_names = vec![n1.clone(), n0.clone()];
            }
            _ => {
                return Err(FormatError::at(
                    source,
                    at(body),
                    format!("body '{name}' has more than two joints; not supported"),
                ))
            }
        }
        for g in body.children().filter(|c| c.has_tag_name("geom")) {
            let gclass = class_of(g);
            let get = |n: &str| defaults.get(g, &gclass, n);
            let collides = get("contype").is_none_or(|c| c != "0")
                || get("conaffinity").is_none_or(|c| c != "0");
            let kind = get("type").unwrap_or_else(|| "sphere".into());
            if !collides {
                continue;
            }
            let geom_name = g.attribute("name").unwrap_or("unnamed").to_string();
            if kind == "mesh" || kind == "plane" || g.has_attribute("mesh") {
                skipped.push(format!("{geom_name} ({kind})"));
                continue;
            }
            let size = numbers(g, &get("size").unwrap_or_default(), "size")?;
            if let (Some(ft), Some(r)) = (get("fromto"), size.first()) {
                match numbers(g, &ft, "fromto")?.as_slice() {
                    [a, b, c, d, e, f] => {
                        part.capsules
                            .push((Point3::new(*a, *b, *c), Point3::new(*d, *e, *f), *r))
                    }
                    _ => {
                        return Err(FormatError::at(
                            source,
                            at(g),
                            "fromto needs six numbers and size a radius",
                        ))
                    }
                }
                continue;
            }
            let frame = frame_of(g)?;
            let half = match (kind.as_str(), size.as_slice()) {
                ("capsule" | "cylinder", [r, h, ..]) => (Vec3::new(0.0, 0.0, *h), *r),
                ("sphere", [r, ..]) => (Vec3::zeros(), *r),
                ("box", [x, y, z]) => {
                    let capsules = box_capsules(&frame, [*x, *y, *z]);
                    boxes.push(format!("{geom_name} ({})", capsules.len()));
                    part.capsules.extend(capsules);
                    continue;
                }
                (other, _) => {
                    return Err(FormatError::at(
                        source,
                        at(g),
                        format!("geom type '{other}' with size {size:?} is not supported"),
                    ))
                }
            };
            let (half, radius) = half;
            part.capsules.push((
                frame * Point3::from(-half),
                frame * Point3::from(half),
                radius,
            ));
        }
        let children = bodies(body);
        if children.is_empty() {
            let site_tip = body
                .children()
                .filter(|c| {
                    c.has_tag_name("site") && c.attribute("name").is_some_and(|n| n.contains("tip"))
                })
                .find_map(|s| frame_of(s).ok())
                .map(|f| Point3::from(f.translation.vector));
            let farthest = part
                .capsules
                .iter()
                .flat_map(|c| [c.0, c.1])
                .max_by(|a, b| a.coords.norm().total_cmp(&b.coords.norm()));
            part.tip = site_tip.or(farthest);
            if part.tip.is_none() {
                return Err(FormatError::at(
                    source,
                    at(body),
                    format!("body '{name}' ends a finger but has no tip site or collision geom"),
                ));
            }
        }
        for c in children.iter().rev() {
            stack.push((*c, Some(name.clone())));
        }
        parts.bones.push(part);
    }
    // Finger names from each chain's bodies.
    let first_bones: Vec<usize> = (0..parts.bones.len())
        .filter(|&i| parts.bones[i].parent.as_deref() == Some(parts.bones[0].name.as_str()))
        .collect();
    for i in first_bones {
        let mut names = vec![parts.bones[i].name.clone()];
        let mut at_name = parts.bones[i].name.clone();
        while let Some(next) = parts
            .bones
            .iter()
            .find(|b| b.parent.as_deref() == Some(at_name.as_str()))
        {
            names.push(next.name.clone());
            at_name = next.name.clone();
        }
        parts.bones[i].finger = names
            .iter()
            .find_map(|n| finger_name(n))
            .map(str::to_string);
    }
    // Two-joint fixed tendons with a tight range hold c1·q1 + c2·q2 ≈ 0: q1 = −(c2/c1)·q2.
    for t in root.descendants().filter(|n| n.has_tag_name("fixed")) {
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
            .and_then(|r| numbers(t, r, "range").ok())
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
    parts.description = format!("imported from {source}");
    if !dropped.is_empty() {
        parts.description += &format!("; dropped above the palm: {}", dropped.join(", "));
    }
    if !boxes.is_empty() {
        parts.description += &format!(
            "; boxes as capsules within 1 mm of their two largest faces, edges rounded: {}",
            boxes.join(", ")
        );
    }
    if !skipped.is_empty() {
        parts.description += &format!(
            "; collision geoms skipped (meshes and planes are not supported): {}",
            skipped.join(", ")
        );
    }
    build_in_hand_frame(parts, source, sidecar)
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
