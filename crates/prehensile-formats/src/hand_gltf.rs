//! Hands from glTF 2.0 skins (e.g. the WebXR hand): the skin's joint hierarchy and bind pose,
//! capsule radii measured from the skinned mesh, and — as a skin carries no joint limits — the
//! built-in human hand's joints, limits, couplings and movements mapped by finger and by role in
//! the finger (metacarpal, proximal, middle, distal). Leaf joints named `…tip` or `…end` become
//! fingertips. The palm side is where the thumb is, so left and right hands both work.

use std::collections::HashMap;
use std::path::Path;

use prehensile_core::hand::{
    BoneDescription, CouplingDescription, HandDescription, JointDescription, MovementDescription,
};
use prehensile_core::math::Point3;
use prehensile_core::HandModel;

use crate::hand_import::finger_name;
use crate::FormatError;

/// The human hand's description: the source of joints, limits and movements for skins.
fn human() -> HandDescription {
    toml::from_str(include_str!("../../../assets/hands/human.toml"))
        .expect("the built-in human hand parses")
}

/// The human bone with the same finger and role, e.g. ("index", 1) -> "index_proximal".
fn human_role(finger: &str, role: usize, bones_in_finger: usize) -> Option<String> {
    let roles: &[&str] = if finger == "thumb" {
        &["metacarpal", "proximal", "distal"]
    } else {
        &["metacarpal", "proximal", "middle", "distal"]
    };
    // Align from the fingertip: a finger with fewer bones loses its metacarpal first.
    let offset = roles.len() as isize - bones_in_finger as isize;
    let k = role as isize + offset;
    (0..roles.len() as isize)
        .contains(&k)
        .then(|| format!("{finger}_{}", roles[k as usize]))
}

/// A hand's skinned mesh in the hand frame, weighted to the hand model's bones (a skin joint
/// that became a fingertip gives its weight to the fingertip's bone).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SkinnedMesh {
    /// Vertex positions in the hand frame at the rest pose.
    pub positions: Vec<Point3>,
    /// Triangles.
    pub triangles: Vec<[u32; 3]>,
    /// Up to four bone indices per vertex.
    pub joints: Vec<[u16; 4]>,
    /// Their weights.
    pub weights: Vec<[f32; 4]>,
}

/// Reads a skinned glTF/GLB hand.
pub fn load_hand_gltf(path: &Path) -> Result<HandModel, FormatError> {
    load_hand_gltf_skinned(path).map(|(hand, _)| hand)
}

/// Reads a skinned glTF/GLB hand and its skinned mesh, with the sidecar beside it.
pub fn load_hand_gltf_skinned(path: &Path) -> Result<(HandModel, SkinnedMesh), FormatError> {
    let name = path.display().to_string();
    let sidecar = crate::Sidecar::beside(path)?;
    let bytes = crate::read_input(path, crate::MAX_MESH_BYTES)?;
    parse_hand_gltf_skinned(&bytes, &name, sidecar.as_ref())
}

/// A skinned glTF/GLB hand and its skinned mesh from the file's bytes; `name` names it in errors
/// and, by its stem, names the hand.
pub fn parse_hand_gltf_skinned(
    bytes: &[u8],
    name: &str,
    sidecar: Option<&crate::Sidecar>,
) -> Result<(HandModel, SkinnedMesh), FormatError> {
    let name = name.to_string();
    if sidecar.is_some_and(|s| !s.tips.is_empty() || !s.close.is_empty() || !s.movements.is_empty())
    {
        return Err(FormatError::new(
            &name,
            "a skinned hand's sidecar may only name fingers ([fingers]); fingertips come from joints named …tip or …end, movements from the human hand",
        ));
    }
    let gltf = crate::gltf_accessors::parse_gltf(bytes).map_err(|e| FormatError::new(&name, e))?;
    let blob = gltf.blob.clone().unwrap_or_default();
    let buffer = |b: gltf::Buffer| (b.index() == 0 && !blob.is_empty()).then_some(&blob[..]);
    let skin = gltf.document.skins().next().ok_or_else(|| {
        FormatError::new(
            &name,
            "the file has no skin; a hand must be a skinned (rigged) mesh",
        )
    })?;
    let joints: Vec<gltf::Node> = skin.joints().collect();
    // Only the GLB's binary chunk is read: every accessor must lie in it.
    let slices: Vec<&[u8]> = if blob.is_empty() {
        vec![]
    } else {
        vec![&blob[..]]
    };
    if let Some(a) = skin.inverse_bind_matrices() {
        crate::gltf_accessors::check_accessor(
            &a,
            "inverse bind matrices",
            &[(
                gltf::accessor::Dimensions::Mat4,
                gltf::accessor::DataType::F32,
            )],
            &slices,
        )
        .map_err(|e| FormatError::new(&name, e))?;
    }
    for mesh in gltf.document.meshes() {
        for primitive in mesh.primitives() {
            crate::gltf_accessors::check_primitive(&primitive, true, &slices)
                .map_err(|e| FormatError::new(&name, e))?;
        }
    }
    let inverse_bind: Vec<[[f32; 4]; 4]> = skin
        .reader(buffer)
        .read_inverse_bind_matrices()
        .ok_or_else(|| FormatError::new(&name, "the skin has no inverse bind matrices"))?
        .collect();
    if inverse_bind.len() != joints.len() {
        return Err(FormatError::new(
            &name,
            "the skin's inverse bind matrices do not match its joints",
        ));
    }
    // Bind-pose joint positions (the inverse of each inverse bind matrix), in skin space.
    let position: Vec<Point3> = inverse_bind
        .iter()
        .map(|m| {
            let m = nalgebra::Matrix4::from_fn(|r, c| m[c][r] as f64);
            let inv = m.try_inverse().unwrap_or_else(nalgebra::Matrix4::identity);
            Point3::new(inv[(0, 3)], inv[(1, 3)], inv[(2, 3)])
        })
        .collect();
    let names: Vec<String> = joints
        .iter()
        .map(|j| j.name().unwrap_or("joint").to_string())
        .collect();
    let index_of: HashMap<usize, usize> = joints
        .iter()
        .enumerate()
        .map(|(i, j)| (j.index(), i))
        .collect();
    let mut parent = vec![None; joints.len()];
    for (i, j) in joints.iter().enumerate() {
        for c in j.children() {
            if let Some(&k) = index_of.get(&c.index()) {
                parent[k] = Some(i);
            }
        }
    }
    if parent.iter().all(Option::is_none) {
        // A flat skin (the WebXR hands): chain each finger's joints by distance from the wrist.
        let root = names
            .iter()
            .position(|n| n.to_ascii_lowercase().contains("wrist"))
            .unwrap_or(0);
        let mut by_finger: HashMap<&str, Vec<usize>> = HashMap::new();
        for i in (0..joints.len()).filter(|&i| i != root) {
            let f = finger_name(&names[i]).ok_or_else(|| {
                FormatError::new(
                    &name,
                    format!(
                        "joint '{}' has no parent and names no finger; cannot place it in the hand",
                        names[i]
                    ),
                )
            })?;
            by_finger.entry(f).or_default().push(i);
        }
        for chain in by_finger.values_mut() {
            chain.sort_by(|&a, &b| {
                (position[a] - position[root])
                    .norm()
                    .total_cmp(&(position[b] - position[root]).norm())
            });
            let mut previous = root;
            for &i in chain.iter() {
                parent[i] = Some(previous);
                previous = i;
            }
        }
    }
    let child_lists: Vec<Vec<usize>> = (0..joints.len())
        .map(|i| {
            (0..joints.len())
                .filter(|&k| parent[k] == Some(i))
                .collect()
        })
        .collect();
    let children = |i: usize| child_lists[i].iter().copied();
    let tips: Vec<bool> = (0..joints.len())
        .map(|i| {
            let n = names[i].to_ascii_lowercase();
            child_lists[i].is_empty() && (n.ends_with("tip") || n.ends_with("end"))
        })
        .collect();
    let is_tip = |i: usize| tips[i];
    let roots: Vec<usize> = (0..joints.len()).filter(|&i| parent[i].is_none()).collect();
    let [root] = roots[..] else {
        return Err(FormatError::new(
            &name,
            format!(
                "the skin has {} root joints; a hand has one (the wrist)",
                roots.len()
            ),
        ));
    };
    // Radii: per bone, the 25th percentile of its dominant vertices' distances to its segment.
    let mut distances: Vec<Vec<f64>> = vec![Vec::new(); joints.len()];
    let mut raw: Vec<(Point3, [u16; 4], [f32; 4])> = Vec::new();
    let mut raw_triangles: Vec<[u32; 3]> = Vec::new();
    for mesh in gltf.document.meshes() {
        for primitive in mesh.primitives() {
            let reader = primitive.reader(buffer);
            let first = raw.len() as u32;
            if let (Some(p), Some(j), Some(w)) = (
                reader.read_positions(),
                reader.read_joints(0),
                reader.read_weights(0),
            ) {
                raw.extend(
                    p.zip(j.into_u16()).zip(w.into_f32()).map(|((p, j), w)| {
                        (Point3::new(p[0] as f64, p[1] as f64, p[2] as f64), j, w)
                    }),
                );
                let count = raw.len() as u32 - first;
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..count).collect(),
                };
                for t in indices.chunks_exact(3) {
                    if t.iter().all(|&i| i < count) {
                        raw_triangles.push([first + t[0], first + t[1], first + t[2]]);
                    }
                }
            }
            let (Some(p), Some(j), Some(w)) = (
                reader.read_positions(),
                reader.read_joints(0),
                reader.read_weights(0),
            ) else {
                continue;
            };
            for ((p, j), w) in p.zip(j.into_u16()).zip(w.into_f32()) {
                let k = (0..4).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
                let bone = j[k] as usize;
                let Some(end) = children(bone.min(joints.len() - 1)).next() else {
                    continue;
                };
                if bone >= joints.len() {
                    continue;
                }
                let (a, b) = (position[bone], position[end]);
                let v = Point3::new(p[0] as f64, p[1] as f64, p[2] as f64);
                let ab = b - a;
                let t = ((v - a).dot(&ab) / ab.norm_squared().max(1e-18)).clamp(0.0, 1.0);
                distances[bone].push((a + ab * t - v).norm());
            }
        }
    }
    let radius = |i: usize| -> f64 {
        let mut d = distances[i].clone();
        if d.len() < 5 {
            return 0.008;
        }
        d.sort_by(f64::total_cmp);
        d[d.len() / 4].clamp(0.004, 0.03)
    };
    // Fingers: chains from the root; roles counted from the chain's first bone.
    let mut finger_of = vec![None::<(String, usize, usize)>; joints.len()];
    for c in children(root) {
        let mut chain = vec![c];
        while let Some(next) = children(*chain.last().expect("non-empty")).find(|&k| !is_tip(k)) {
            chain.push(next);
        }
        let finger = sidecar
            .and_then(|s| s.fingers.get(&names[c]).map(String::as_str))
            .or_else(|| chain.iter().find_map(|&i| finger_name(&names[i])))
            .ok_or_else(|| FormatError::new(&name, format!("cannot tell which finger joint '{}' belongs to; name it thumb, index, middle, ring or little", names[c])))?;
        for (role, &i) in chain.iter().enumerate() {
            finger_of[i] = Some((finger.to_string(), role, chain.len()));
        }
    }
    // The hand frame: z from the wrist toward the middle finger's base, y out of the palm on the
    // thumb's side, x across.
    let base = |f: &str| {
        (0..joints.len()).find(|&i| {
            finger_of[i]
                .as_ref()
                .is_some_and(|(n, r, _)| n == f && *r == 0)
        })
    };
    // A finger's end: its joint farthest from the wrist (file order says nothing).
    let tip_of = |f: &str| {
        (0..joints.len())
            .filter(|&i| finger_of[i].as_ref().is_some_and(|(n, _, _)| n == f))
            .max_by(|&a, &b| {
                (position[a] - position[root])
                    .norm()
                    .total_cmp(&(position[b] - position[root]).norm())
            })
    };
    let (Some(index), Some(little), Some(middle), Some(thumb)) = (
        base("index"),
        base("little"),
        tip_of("middle"),
        tip_of("thumb"),
    ) else {
        return Err(FormatError::new(&name, "a skinned hand needs thumb, index, middle and little fingers to be mapped onto the human hand"));
    };
    let wrist = position[root];
    let z = (position[middle] - wrist).normalize();
    let across = position[little] - position[index];
    let mut y = across.cross(&z);
    if y.dot(&(position[thumb] - wrist)) < 0.0 {
        y = -y;
    }
    let y = (y - z * y.dot(&z)).normalize();
    let x = y.cross(&z);
    let to_hand = |p: &Point3| -> [f64; 3] {
        let d = p - wrist;
        [d.dot(&x), d.dot(&y), d.dot(&z)]
    };
    let thumb_side = position[thumb].coords.dot(&x) - wrist.coords.dot(&x);
    let template = human();
    let template_bone = |n: &str| template.bones.iter().find(|b| b.name == n);
    let mut renamed: HashMap<String, String> = HashMap::new();
    let mut bones = Vec::new();
    for i in 0..joints.len() {
        if is_tip(i) {
            continue;
        }
        let mut b = BoneDescription {
            name: names[i].clone(),
            parent: parent[i].map(|p| names[p].clone()),
            origin: to_hand(&position[i]),
            tip: children(i)
                .find(|&k| is_tip(k))
                .map(|k| to_hand(&position[k])),
            radius: if i == root { 0.015 } else { radius(i) },
            joint: JointDescription::Fixed,
            finger: None,
            flexes_toward: None,
        };
        if let Some((finger, role, count)) = &finger_of[i] {
            if let Some(t) = human_role(finger, *role, *count).and_then(|h| {
                renamed.insert(h.clone(), names[i].clone());
                template_bone(&h)
            }) {
                b.joint = t.joint.clone();
                // The thumb flexes across the palm toward the fingers, whichever side it is on.
                b.flexes_toward = t
                    .flexes_toward
                    .map(|[hx, hy, hz]| [hx.abs() * -thumb_side.signum(), hy, hz]);
            }
            if *role == 0 {
                b.finger = Some(finger.clone());
            }
        }
        bones.push(b);
    }
    let rename = |h: &String| renamed.get(h).cloned();
    let couplings = template
        .couplings
        .iter()
        .filter_map(|c| {
            Some(CouplingDescription {
                follower: rename(&c.follower)?,
                leader: rename(&c.leader)?,
                ..c.clone()
            })
        })
        .collect();
    // Movements: the human's, on the mapped bones; the power grasp center scaled by hand length.
    let scale = (position[middle] - wrist).norm() / 0.1774;
    let movements = template
        .movements
        .iter()
        .map(|m| {
            let map = |pose: &std::collections::BTreeMap<String, Vec<f64>>| {
                pose.iter()
                    .filter_map(|(k, v)| Some((rename(k)?, v.clone())))
                    .collect()
            };
            MovementDescription {
                grasp_center: m.grasp_center.map(|c| c.map(|v| v * scale)),
                start: map(&m.start),
                end: map(&m.end),
                ..m.clone()
            }
        })
        .collect();
    let desc = HandDescription {
        name: Path::new(&name)
            .file_stem()
            .map_or("gltf hand".into(), |s| s.to_string_lossy().into_owned()),
        description: format!(
            "skinned hand from {name}, joints and movements mapped from the human hand"
        ),
        bones,
        couplings,
        movements,
    };
    let hand = HandModel::from_description(&desc).map_err(|e| FormatError::caused_by(&name, e))?;
    // The skinned mesh in the hand frame, weighted to the model's bones.
    let bone_of: Vec<u16> = (0..joints.len())
        .map(|j| {
            let owner = if is_tip(j) {
                parent[j].unwrap_or(root)
            } else {
                j
            };
            hand.bone_index(&names[owner]).unwrap_or(0) as u16
        })
        .collect();
    let mut skinned = SkinnedMesh::default();
    for (p, j, w) in &raw {
        skinned.positions.push(Point3::from(to_hand(p)));
        skinned
            .joints
            .push(j.map(|k| bone_of.get(k as usize).copied().unwrap_or(0)));
        skinned.weights.push(*w);
    }
    skinned.triangles = raw_triangles;
    Ok((hand, skinned))
}
