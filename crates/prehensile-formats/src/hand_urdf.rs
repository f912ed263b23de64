//! Hands from URDF: links become bones, revolute and continuous joints hinges (fixed joints
//! fixed), `<mimic>` couplings, collision cylinders, capsules, spheres and boxes capsules.
//! Links without collision geometry get a capsule to their child's joint with a radius guessed
//! from their mass; a last link without geometry gets its tip at twice its centre of mass.

use std::collections::HashMap;

use prehensile_core::hand::{Axis, HandParts, Inertial, Joint};
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::HandModel;
use roxmltree::{Document, Node};

use crate::hand_import::{
    bone, box_capsules, build_in_hand_frame, file_stem, finger_name, radius_from_mass, Sidecar,
};
use crate::FormatError;

struct Link {
    mass: f64,
    com: Point3,
    inertial: Option<Inertial>,
    capsules: Vec<(Point3, Point3, f64)>,
}

/// Parses URDF text into a hand. `source` names the file in errors.
pub fn parse_hand_urdf(text: &str, source: &str) -> Result<HandModel, FormatError> {
    parse_hand_urdf_with(text, source, None)
}

/// As [`parse_hand_urdf`], with a sidecar's overrides.
pub fn parse_hand_urdf_with(
    text: &str,
    source: &str,
    sidecar: Option<&Sidecar>,
) -> Result<HandModel, FormatError> {
    let doc = Document::parse(text)
        .map_err(|e| FormatError::at(source, format!("line {}", e.pos().row), e.to_string()))?;
    let at = |node: Node| format!("line {}", doc.text_pos_at(node.range().start).row);
    let robot = doc.root_element();
    if robot.tag_name().name() != "robot" {
        return Err(FormatError::at(
            source,
            at(robot),
            "a URDF file's root element is <robot>",
        ));
    }
    let mut links: HashMap<String, Link> = HashMap::new();
    let mut order = Vec::new();
    for link in robot.children().filter(|n| n.has_tag_name("link")) {
        let name = attr(link, "name", source, &at)?.to_string();
        let mut mass = 0.0;
        let mut com = Point3::origin();
        let mut full = None;
        if let Some(inertial) = child(link, "inertial") {
            if let Some(m) = child(inertial, "mass") {
                mass = number(m, "value", source, &at)?;
            }
            let frame = match child(inertial, "origin") {
                Some(o) => origin(o, source, &at)?,
                None => Transform::identity(),
            };
            com = Point3::from(frame.translation.vector);
            if let Some(i) = child(inertial, "inertia") {
                let v = |n: &str| {
                    i.attribute(n)
                        .map_or(Ok(0.0), |_| number(i, n, source, &at))
                };
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
                full = Some(Inertial {
                    mass,
                    center_of_mass: com,
                    inertia: r * tensor * r.transpose(),
                });
            }
        }
        let mut capsules = Vec::new();
        for collision in link.children().filter(|n| n.has_tag_name("collision")) {
            let frame = match child(collision, "origin") {
                Some(o) => origin(o, source, &at)?,
                None => Transform::identity(),
            };
            let Some(geometry) =
                child(collision, "geometry").and_then(|g| g.children().find(|n| n.is_element()))
            else {
                continue;
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
                    number(geometry, "length", source, &at)? / 2.0,
                    number(geometry, "radius", source, &at)?,
                )),
                "sphere" => capsules.push(segment(0.0, number(geometry, "radius", source, &at)?)),
                "box" => {
                    let size = vector(geometry, "size", source, &at)?;
                    capsules.extend(box_capsules(&frame, (size / 2.0).into()));
                }
                "mesh" => continue,
                other => {
                    return Err(FormatError::at(
                        source,
                        at(geometry),
                        format!("unknown collision geometry <{other}>"),
                    ))
                }
            }
        }
        order.push(name.clone());
        links.insert(
            name,
            Link {
                mass,
                com,
                inertial: full,
                capsules,
            },
        );
    }
    let mut parts = HandParts {
        rigid_couplings: true,
        name: robot
            .attribute("name")
            .map(str::to_string)
            .unwrap_or_else(|| file_stem(source)),
        description: format!("imported from {source}"),
        ..Default::default()
    };
    let mut parent_of: HashMap<String, String> = HashMap::new();
    let mut bones = HashMap::new();
    for joint in robot.children().filter(|n| n.has_tag_name("joint")) {
        let name = attr(joint, "name", source, &at)?;
        let kind = attr(joint, "type", source, &at)?;
        let parent = attr(
            child_req(joint, "parent", source, &at)?,
            "link",
            source,
            &at,
        )?;
        let child_link = attr(child_req(joint, "child", source, &at)?, "link", source, &at)?;
        if !links.contains_key(parent) || !links.contains_key(child_link) {
            return Err(FormatError::at(
                source,
                at(joint),
                format!("joint '{name}' connects links that are not defined"),
            ));
        }
        let rest = match child(joint, "origin") {
            Some(o) => origin(o, source, &at)?,
            None => Transform::identity(),
        };
        let axis = match child(joint, "axis") {
            Some(a) => vector(a, "xyz", source, &at)?,
            None => Vec3::x(),
        };
        let mut part = bone(child_link, Some(parent), rest);
        match kind {
            "revolute" | "continuous" => {
                let limits = match (kind, child(joint, "limit")) {
                    ("revolute", Some(l)) => [number(l, "lower", source, &at)?, number(l, "upper", source, &at)?],
                    ("revolute", None) => {
                        return Err(FormatError::at(source, at(joint), format!("revolute joint '{name}' has no <limit>")))
                    }
                    _ => [-std::f64::consts::PI, std::f64::consts::PI],
                };
                if axis.norm() < 1e-12 {
                    return Err(FormatError::at(source, at(joint), format!("joint '{name}' has a zero axis")));
                }
                part.joint = Joint::Hinge(Axis::new(axis, limits));
                part.dof_names = vec![name.to_string()];
                if let Some(m) = child(joint, "mimic") {
                    let leader = attr(m, "joint", source, &at)?;
                    let ratio = m.attribute("multiplier").map_or(Ok(1.0), |_| number(m, "multiplier", source, &at))?;
                    parts.couplings.push((name.to_string(), leader.to_string(), ratio));
                }
            }
            "fixed" => {}
            other => {
                return Err(FormatError::at(
                    source,
                    at(joint),
                    format!("joint '{name}' is of type '{other}'; hands may use revolute, continuous and fixed joints"),
                ))
            }
        }
        if parent_of
            .insert(child_link.to_string(), parent.to_string())
            .is_some()
        {
            return Err(FormatError::at(
                source,
                at(joint),
                format!("link '{child_link}' has two parent joints"),
            ));
        }
        bones.insert(child_link.to_string(), part);
    }
    // The root: the link no joint moves.
    let roots: Vec<&String> = order
        .iter()
        .filter(|l| !parent_of.contains_key(*l))
        .collect();
    let [root] = roots.as_slice() else {
        return Err(FormatError::new(
            source,
            format!("a hand needs exactly one root link; found {roots:?}"),
        ));
    };
    bones.insert(root.to_string(), bone(root, None, Transform::identity()));
    let root = root.to_string();
    let children_of = |l: &str| -> Vec<String> {
        order
            .iter()
            .filter(|c| parent_of.get(*c).is_some_and(|p| p == l))
            .cloned()
            .collect()
    };
    // Where each link's children's joints are, in the link's frame.
    let child_joints: HashMap<String, Vec<Point3>> = order
        .iter()
        .map(|l| {
            let ends = children_of(l)
                .iter()
                .map(|c| Point3::from(bones[c].rest.translation.vector))
                .collect();
            (l.clone(), ends)
        })
        .collect();
    for name in &order {
        let link = &links[name];
        let ends = &child_joints[name];
        let part = bones.get_mut(name).expect("every link is a bone");
        part.capsules = link.capsules.clone();
        part.inertial = link.inertial;
        if part.capsules.is_empty() {
            if *name == root {
                // The palm: a capsule to each finger's first joint.
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
                    part.capsules.push((
                        Point3::origin(),
                        end,
                        radius_from_mass(link.mass, length),
                    ));
                }
            }
        }
        if ends.is_empty() && *name != root {
            // The fingertip: the capsule end farthest from the joint, else twice the centre of mass.
            let tip = part
                .capsules
                .iter()
                .flat_map(|c| [c.0, c.1])
                .max_by(|a, b| a.coords.norm().total_cmp(&b.coords.norm()))
                .unwrap_or_else(|| Point3::from(link.com.coords * 2.0));
            part.tip = Some(tip);
        }
    }
    for c in children_of(&root) {
        let mut chain = vec![c.clone()];
        while let [next] = children_of(chain.last().expect("non-empty")).as_slice() {
            chain.push(next.clone());
        }
        bones.get_mut(&c).expect("bone").finger = chain
            .iter()
            .find_map(|b| finger_name(b))
            .map(str::to_string);
    }
    parts.bones = order
        .iter()
        .map(|l| bones.remove(l).expect("every link is a bone"))
        .collect();
    build_in_hand_frame(parts, source, sidecar)
}

/// Reads a URDF hand file.
pub fn load_hand_urdf(path: &std::path::Path) -> Result<HandModel, FormatError> {
    let name = path.display().to_string();
    let text = crate::read_input_text(path, crate::MAX_TEXT_BYTES)?;
    parse_hand_urdf_with(&text, &name, Sidecar::beside(path)?.as_ref())
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    node.children().find(|n| n.has_tag_name(tag))
}

fn child_req<'a, 'i>(
    node: Node<'a, 'i>,
    tag: &str,
    source: &str,
    at: &dyn Fn(Node) -> String,
) -> Result<Node<'a, 'i>, FormatError> {
    child(node, tag).ok_or_else(|| {
        FormatError::at(
            source,
            at(node),
            format!("<{}> needs a <{tag}>", node.tag_name().name()),
        )
    })
}

fn attr<'a>(
    node: Node<'a, '_>,
    name: &str,
    source: &str,
    at: &dyn Fn(Node) -> String,
) -> Result<&'a str, FormatError> {
    node.attribute(name).ok_or_else(|| {
        FormatError::at(
            source,
            at(node),
            format!("<{}> needs a '{name}' attribute", node.tag_name().name()),
        )
    })
}

fn numbers(
    node: Node,
    name: &str,
    source: &str,
    at: &dyn Fn(Node) -> String,
) -> Result<Vec<f64>, FormatError> {
    attr(node, name, source, at)?
        .split_whitespace()
        .map(|w| {
            w.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    FormatError::at(
                        source,
                        at(node),
                        format!("'{w}' in '{name}' is not a finite number"),
                    )
                })
        })
        .collect()
}

fn number(
    node: Node,
    name: &str,
    source: &str,
    at: &dyn Fn(Node) -> String,
) -> Result<f64, FormatError> {
    match numbers(node, name, source, at)?.as_slice() {
        [v] => Ok(*v),
        _ => Err(FormatError::at(
            source,
            at(node),
            format!("'{name}' should be one number"),
        )),
    }
}

fn vector(
    node: Node,
    name: &str,
    source: &str,
    at: &dyn Fn(Node) -> String,
) -> Result<Vec3, FormatError> {
    match numbers(node, name, source, at)?.as_slice() {
        [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(FormatError::at(
            source,
            at(node),
            format!("'{name}' should be three numbers"),
        )),
    }
}

/// `<origin xyz rpy>`: URDF's fixed-axis roll, pitch, yaw (R = Rz(yaw)·Ry(pitch)·Rx(roll)).
fn origin(node: Node, source: &str, at: &dyn Fn(Node) -> String) -> Result<Transform, FormatError> {
    let xyz = if node.has_attribute("xyz") {
        vector(node, "xyz", source, at)?
    } else {
        Vec3::zeros()
    };
    let rpy = if node.has_attribute("rpy") {
        vector(node, "rpy", source, at)?
    } else {
        Vec3::zeros()
    };
    Ok(Transform::from_parts(
        xyz.into(),
        Rotation::from_euler_angles(rpy.x, rpy.y, rpy.z),
    ))
}
