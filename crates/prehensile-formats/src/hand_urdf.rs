//! Hands from URDF: links become bones, revolute and continuous joints hinges (fixed joints
//! fixed), `<mimic>` couplings, collision cylinders, capsules, spheres and boxes capsules, and
//! collision meshes capsules inside their convex hull (files below the URDF's folder;
//! `package://name/path` is looked up as `path` there).
//! Links without collision geometry get a capsule to their child's joint with a radius guessed
//! from their mass; a last link without geometry gets its tip at twice its centre of mass.

use std::collections::HashMap;

use prehensile_core::hand::{Axis, BonePart, HandParts, Inertial, Joint};
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::HandModel;
use roxmltree::{Document, Node};

use crate::collision_mesh::{MeshFiles, MAX_HAND_MESH_VERTICES};
use crate::hand_import::{
    bone, box_capsules, build_in_hand_frame, farthest_capsule_end, file_stem, name_fingers,
    radius_from_mass, Sidecar,
};
use crate::FormatError;

/// A `<link>` as read: its mass and centre of mass (for guessed radii and tips), its inertial
/// if it has an inertia tensor, and its collision capsules.
struct Link {
    mass: f64,
    com: Point3,
    inertial: Option<Inertial>,
    capsules: Vec<(Point3, Point3, f64)>,
}

/// Parses URDF text into a hand. `source` names the file in errors. Collision meshes are
/// skipped (and named): [`load_hand_urdf`] reads them from the file's folder.
pub fn parse_hand_urdf(text: &str, source: &str) -> Result<HandModel, FormatError> {
    parse_hand_urdf_with(text, source, None)
}

/// As [`parse_hand_urdf`], with a sidecar's overrides.
pub fn parse_hand_urdf_with(
    text: &str,
    source: &str,
    sidecar: Option<&Sidecar>,
) -> Result<HandModel, FormatError> {
    parse_urdf(text, source, sidecar, MeshFiles::None)
}

/// URDF text into a hand, its collision meshes read from `meshes`.
fn parse_urdf(
    text: &str,
    source: &str,
    sidecar: Option<&Sidecar>,
    meshes: MeshFiles,
) -> Result<HandModel, FormatError> {
    let doc = Document::parse(text)
        .map_err(|e| FormatError::at(source, format!("line {}", e.pos().row), e.to_string()))?;
    let mut reader = UrdfReader {
        doc: &doc,
        source,
        mesh_files: meshes,
        meshes: Vec::new(),
        skipped: Vec::new(),
        mesh_budget: MAX_HAND_MESH_VERTICES,
    };
    let robot = doc.root_element();
    if robot.tag_name().name() != "robot" {
        return Err(reader.error(robot, "a URDF file's root element is <robot>"));
    }
    let mut links: HashMap<String, Link> = HashMap::new();
    let mut order = Vec::new();
    for link in robot.children().filter(|n| n.has_tag_name("link")) {
        let name = reader.attr(link, "name")?.to_string();
        if links.insert(name.clone(), reader.one_link(link)?).is_some() {
            return Err(reader.error(
                link,
                format!("two links are named '{name}'; link names must be unique"),
            ));
        }
        order.push(name);
    }
    let mut parts = HandParts {
        rigid_couplings: true,
        name: robot
            .attribute("name")
            .map(str::to_string)
            .unwrap_or_else(|| file_stem(source)),
        ..Default::default()
    };
    let mut bones = HashMap::new();
    for joint in robot.children().filter(|n| n.has_tag_name("joint")) {
        let part = reader.one_joint(joint, &links, &mut parts)?;
        let child_link = part.name.clone();
        if bones.insert(child_link.clone(), part).is_some() {
            return Err(reader.error(joint, format!("link '{child_link}' has two parent joints")));
        }
    }
    // The root: the link no joint moves.
    let roots: Vec<&String> = order.iter().filter(|l| !bones.contains_key(*l)).collect();
    let [root] = roots.as_slice() else {
        return Err(FormatError::new(
            source,
            format!("a hand needs exactly one root link; found {roots:?}"),
        ));
    };
    bones.insert(root.to_string(), bone(root, None, Transform::identity()));
    parts.bones = order
        .iter()
        .map(|l| bones.remove(l).expect("every link is a bone"))
        .collect();
    // Where each bone's children's joints are, in its frame (indexed once: linear in the links).
    let mut ends: HashMap<String, Vec<Point3>> = HashMap::new();
    for b in &parts.bones {
        if let Some(p) = &b.parent {
            ends.entry(p.clone())
                .or_default()
                .push(Point3::from(b.rest.translation.vector));
        }
    }
    for part in parts.bones.iter_mut() {
        let link = links.remove(&part.name).expect("every bone is a link");
        link_shapes(part, link, ends.get(&part.name).map_or(&[], Vec::as_slice));
    }
    name_fingers(&mut parts);
    parts.description = reader.description();
    build_in_hand_frame(parts, source, sidecar)
}

/// A bone's capsules, inertial and tip from its link: the link's collision capsules, or where
/// it has none a capsule to each child's joint (the palm: to every finger's first joint) with a
/// radius guessed from its mass; at the end of a finger the capsule end farthest from the
/// joint, else twice the centre of mass, as the tip.
fn link_shapes(part: &mut BonePart, link: Link, ends: &[Point3]) {
    let is_root = part.parent.is_none();
    part.inertial = link.inertial;
    part.capsules = link.capsules;
    if part.capsules.is_empty() {
        if is_root {
            for end in ends {
                let length = end.coords.norm();
                let radius =
                    radius_from_mass(link.mass / ends.len().max(1) as f64, length).min(0.015);
                if length > 1e-6 {
                    part.capsules.push((Point3::origin(), *end, radius));
                }
            }
        } else {
            let end = ends
                .first()
                .copied()
                .unwrap_or_else(|| Point3::from(link.com.coords * 2.0));
            let length = end.coords.norm();
            if length > 1e-6 {
                part.capsules
                    .push((Point3::origin(), end, radius_from_mass(link.mass, length)));
            }
        }
    }
    if ends.is_empty() && !is_root {
        part.tip = Some(
            farthest_capsule_end(&part.capsules)
                .unwrap_or_else(|| Point3::from(link.com.coords * 2.0)),
        );
    }
}

/// Reads the elements of one URDF document, one method per element, and notes what its
/// collision meshes became.
struct UrdfReader<'d, 'i> {
    doc: &'d Document<'i>,
    source: &'d str,
    /// Where collision meshes are read from.
    mesh_files: MeshFiles<'d>,
    /// Collision meshes and what they became.
    meshes: Vec<String>,
    /// Collision meshes not read, with the reason.
    skipped: Vec<String>,
    /// Vertices the collision meshes may still have.
    mesh_budget: usize,
}

impl UrdfReader<'_, '_> {
    /// An error at `node`.
    fn error(&self, node: Node, message: impl Into<String>) -> FormatError {
        FormatError::at(
            self.source,
            format!("line {}", self.doc.text_pos_at(node.range().start).row),
            message,
        )
    }

    /// One `<link>`: its inertial and collision geometry.
    fn one_link(&mut self, link: Node) -> Result<Link, FormatError> {
        let mut read = Link {
            mass: 0.0,
            com: Point3::origin(),
            inertial: None,
            capsules: Vec::new(),
        };
        if let Some(inertial) = child(link, "inertial") {
            self.one_inertial(inertial, &mut read)?;
        }
        for collision in link.children().filter(|n| n.has_tag_name("collision")) {
            self.one_collision(collision, &mut read.capsules)?;
        }
        Ok(read)
    }

    /// One `<inertial>`: mass, centre of mass and, with an `<inertia>`, the whole inertial in
    /// the link's frame.
    fn one_inertial(&self, inertial: Node, link: &mut Link) -> Result<(), FormatError> {
        if let Some(m) = child(inertial, "mass") {
            link.mass = self.number(m, "value")?;
        }
        let frame = self.origin_of(inertial)?;
        link.com = Point3::from(frame.translation.vector);
        if let Some(i) = child(inertial, "inertia") {
            let v = |n: &str| i.attribute(n).map_or(Ok(0.0), |_| self.number(i, n));
            let (xx, xy, xz, yy, yz, zz) = (
                v("ixx")?,
                v("ixy")?,
                v("ixz")?,
                v("iyy")?,
                v("iyz")?,
                v("izz")?,
            );
            let tensor = nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
            let r = frame.rotation.to_rotation_matrix().into_inner();
            link.inertial = Some(Inertial {
                mass: link.mass,
                center_of_mass: link.com,
                inertia: r * tensor * r.transpose(),
            });
        }
        Ok(())
    }

    /// One `<collision>`: cylinders, capsules and spheres as one capsule, boxes as rows of
    /// capsules, meshes as capsules inside their hull.
    fn one_collision(
        &mut self,
        collision: Node,
        capsules: &mut Vec<(Point3, Point3, f64)>,
    ) -> Result<(), FormatError> {
        let frame = self.origin_of(collision)?;
        let Some(geometry) =
            child(collision, "geometry").and_then(|g| g.children().find(|n| n.is_element()))
        else {
            return Ok(());
        };
        let segment = |half: f64, radius: f64| {
            (
                frame * Point3::new(0.0, 0.0, -half),
                frame * Point3::new(0.0, 0.0, half),
                radius,
            )
        };
        match geometry.tag_name().name() {
            "cylinder" | "capsule" => capsules.push(segment(
                self.number(geometry, "length")? / 2.0,
                self.number(geometry, "radius")?,
            )),
            "sphere" => capsules.push(segment(0.0, self.number(geometry, "radius")?)),
            "box" => {
                let size = self.vector(geometry, "size")?;
                capsules.extend(box_capsules(&frame, (size / 2.0).into()));
            }
            "mesh" => self.one_mesh(collision, geometry, &frame, capsules)?,
            other => {
                return Err(self.error(geometry, format!("unknown collision geometry <{other}>")))
            }
        }
        Ok(())
    }

    /// One collision `<mesh filename scale>`: capsules inside its convex hull, or a note saying
    /// why it was skipped.
    fn one_mesh(
        &mut self,
        collision: Node,
        mesh: Node,
        frame: &Transform,
        capsules: &mut Vec<(Point3, Point3, f64)>,
    ) -> Result<(), FormatError> {
        let filename = self.attr(mesh, "filename")?;
        let scale = match mesh.attribute("scale") {
            Some(_) => self.vector(mesh, "scale")?,
            None => Vec3::repeat(1.0),
        };
        let name = collision
            .attribute("name")
            .map_or_else(|| filename.to_string(), str::to_string);
        // package://name/path: the package's own folder is unknown here; look below ours.
        let reference = filename
            .strip_prefix("package://")
            .map_or(filename, |rest| {
                rest.split_once('/').map_or(rest, |(_, p)| p)
            });
        match self
            .mesh_files
            .capsules(&name, reference, scale, frame, &mut self.mesh_budget)
        {
            Ok(made) => {
                capsules.extend(made.capsules);
                self.meshes.push(made.note);
            }
            Err(note) => self.skipped.push(note),
        }
        Ok(())
    }

    /// The hand's description: its source and what its collision meshes became.
    fn description(&self) -> String {
        let mut d = format!("imported from {}", self.source);
        if !self.meshes.is_empty() {
            d += &format!("; meshes as capsules: {}", self.meshes.join(", "));
        }
        if !self.skipped.is_empty() {
            d += &format!(
                "; collision meshes skipped (links without collision geometry get a capsule \
                 guessed from their mass): {}",
                self.skipped.join(", ")
            );
        }
        d
    }

    /// One `<joint>` as the bone of its child link: revolute and continuous joints are hinges
    /// (a `<mimic>` adds a coupling to `parts`), fixed joints fixed.
    fn one_joint(
        &self,
        joint: Node,
        links: &HashMap<String, Link>,
        parts: &mut HandParts,
    ) -> Result<BonePart, FormatError> {
        let name = self.attr(joint, "name")?;
        let kind = self.attr(joint, "type")?;
        let parent = self.attr(self.child_req(joint, "parent")?, "link")?;
        let child_link = self.attr(self.child_req(joint, "child")?, "link")?;
        if !links.contains_key(parent) || !links.contains_key(child_link) {
            return Err(self.error(
                joint,
                format!("joint '{name}' connects links that are not defined"),
            ));
        }
        let rest = self.origin_of(joint)?;
        let axis = match child(joint, "axis") {
            Some(a) => self.vector(a, "xyz")?,
            None => Vec3::x(),
        };
        let mut part = bone(child_link, Some(parent), rest);
        match kind {
            "revolute" | "continuous" => {
                let limits = match (kind, child(joint, "limit")) {
                    ("revolute", Some(l)) => [self.number(l, "lower")?, self.number(l, "upper")?],
                    ("revolute", None) => {
                        return Err(self.error(
                            joint,
                            format!("revolute joint '{name}' has no <limit>"),
                        ))
                    }
                    _ => [-std::f64::consts::PI, std::f64::consts::PI],
                };
                if axis.norm() < 1e-12 {
                    return Err(self.error(joint, format!("joint '{name}' has a zero axis")));
                }
                part.joint = Joint::Hinge(Axis::new(axis, limits));
                part.dof_names = vec![name.to_string()];
                if let Some(m) = child(joint, "mimic") {
                    let leader = self.attr(m, "joint")?;
                    let ratio = m
                        .attribute("multiplier")
                        .map_or(Ok(1.0), |_| self.number(m, "multiplier"))?;
                    parts
                        .couplings
                        .push((name.to_string(), leader.to_string(), ratio));
                }
            }
            "fixed" => {}
            other => {
                return Err(self.error(
                    joint,
                    format!("joint '{name}' is of type '{other}'; hands may use revolute, continuous and fixed joints"),
                ))
            }
        }
        Ok(part)
    }

    /// The `<{tag}>` child of `node`, which must have one.
    fn child_req<'a, 'i>(
        &self,
        node: Node<'a, 'i>,
        tag: &str,
    ) -> Result<Node<'a, 'i>, FormatError> {
        child(node, tag).ok_or_else(|| {
            self.error(
                node,
                format!("<{}> needs a <{tag}>", node.tag_name().name()),
            )
        })
    }

    /// Attribute `name` of `node`, which must have it.
    fn attr<'a>(&self, node: Node<'a, '_>, name: &str) -> Result<&'a str, FormatError> {
        node.attribute(name).ok_or_else(|| {
            self.error(
                node,
                format!("<{}> needs a '{name}' attribute", node.tag_name().name()),
            )
        })
    }

    /// The finite numbers of attribute `name`.
    fn numbers(&self, node: Node, name: &str) -> Result<Vec<f64>, FormatError> {
        self.attr(node, name)?
            .split_whitespace()
            .map(|w| {
                w.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        self.error(node, format!("'{w}' in '{name}' is not a finite number"))
                    })
            })
            .collect()
    }

    /// Attribute `name` as one number.
    fn number(&self, node: Node, name: &str) -> Result<f64, FormatError> {
        match self.numbers(node, name)?.as_slice() {
            [v] => Ok(*v),
            _ => Err(self.error(node, format!("'{name}' should be one number"))),
        }
    }

    /// Attribute `name` as three numbers.
    fn vector(&self, node: Node, name: &str) -> Result<Vec3, FormatError> {
        match self.numbers(node, name)?.as_slice() {
            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
            _ => Err(self.error(node, format!("'{name}' should be three numbers"))),
        }
    }

    /// The `<origin xyz rpy>` child of `node` (identity without one): URDF's fixed-axis roll,
    /// pitch, yaw, R = Rz(yaw)·Ry(pitch)·Rx(roll).
    fn origin_of(&self, node: Node) -> Result<Transform, FormatError> {
        let Some(o) = child(node, "origin") else {
            return Ok(Transform::identity());
        };
        let read = |name| {
            if o.has_attribute(name) {
                self.vector(o, name)
            } else {
                Ok(Vec3::zeros())
            }
        };
        let (xyz, rpy) = (read("xyz")?, read("rpy")?);
        Ok(Transform::from_parts(
            xyz.into(),
            Rotation::from_euler_angles(rpy.x, rpy.y, rpy.z),
        ))
    }
}

/// Reads a URDF hand from named files held in memory (files dropped on a web page, which come
/// without their folders): `main` is the hand's file, and a collision `<mesh filename=…>` names
/// another of `files` by its file name.
pub fn parse_hand_urdf_files(
    main: &str,
    files: &[(String, Vec<u8>)],
) -> Result<HandModel, FormatError> {
    let (_, bytes) = files
        .iter()
        .find(|(n, _)| n == main)
        .ok_or_else(|| FormatError::new(main, "the hand file is not among the files given"))?;
    let text = String::from_utf8(bytes.clone())
        .map_err(|e| FormatError::new(main, format!("the file is not UTF-8 text: {e}")))?;
    parse_urdf(&text, main, None, MeshFiles::Named(files))
}

/// Reads a URDF hand file.
pub fn load_hand_urdf(path: &std::path::Path) -> Result<HandModel, FormatError> {
    let name = path.display().to_string();
    let text = crate::read_input_text(path, crate::MAX_TEXT_BYTES)?;
    parse_urdf(
        &text,
        &name,
        Sidecar::beside(path)?.as_ref(),
        MeshFiles::Disk(path),
    )
}

/// The first `<{tag}>` child of `node`.
fn child<'a, 'i>(node: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    node.children().find(|n| n.has_tag_name(tag))
}
