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
use prehensile_core::math::{Point3, Vec3};
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
    let err = |e: String| FormatError::new(name, e);
    if sidecar.is_some_and(|s| {
        !s.tips.is_empty() || !s.close.is_empty() || !s.movements.is_empty() || s.frame.is_some()
    }) {
        return Err(err("a skinned hand's sidecar may only name fingers ([fingers]); fingertips come from joints named …tip or …end, movements from the human hand, the frame from the skin".into()));
    }
    let gltf = crate::gltf_accessors::parse_gltf(bytes).map_err(err)?;
    let blob = gltf.blob.clone().unwrap_or_default();
    let buffer = |b: gltf::Buffer| (b.index() == 0 && !blob.is_empty()).then_some(&blob[..]);
    let skin = gltf.document.skins().next().ok_or_else(|| {
        err("the file has no skin; a hand must be a skinned (rigged) mesh".into())
    })?;
    // Only the GLB's binary chunk is read: every accessor must lie in it.
    let slices: Vec<&[u8]> = if blob.is_empty() {
        vec![]
    } else {
        vec![&blob[..]]
    };
    if let Some(a) = skin.inverse_bind_matrices() {
        let matrices = [(
            gltf::accessor::Dimensions::Mat4,
            gltf::accessor::DataType::F32,
        )];
        crate::gltf_accessors::check_accessor(&a, "inverse bind matrices", &matrices, &slices)
            .map_err(err)?;
    }
    for mesh in gltf.document.meshes() {
        for primitive in mesh.primitives() {
            crate::gltf_accessors::check_primitive(&primitive, true, &slices).map_err(err)?;
        }
    }
    let skeleton = Skeleton::read(&skin, buffer).map_err(err)?;
    let vertices = SkinVertices::read(&gltf.document, buffer);
    let fingers = skeleton.fingers(sidecar).map_err(err)?;
    let frame = HandFrame::new(&skeleton, &fingers).map_err(err)?;
    let stem = Path::new(name)
        .file_stem()
        .map_or("gltf hand".into(), |s| s.to_string_lossy().into_owned());
    let desc = HandDescription {
        name: stem,
        description: format!(
            "skinned hand from {name}, joints and movements mapped from the human hand"
        ),
        ..human_mapping(&skeleton, &fingers, &frame, &skeleton.radii(&vertices))
    };
    let hand = HandModel::from_description(&desc).map_err(|e| FormatError::caused_by(name, e))?;
    let skinned = vertices.in_hand(&hand, &skeleton, &frame);
    Ok((hand, skinned))
}

/// The skin's joints in their bind pose: names, positions (skin space), parents, children, which
/// are fingertips, and the root (the wrist).
struct Skeleton {
    names: Vec<String>,
    position: Vec<Point3>,
    parent: Vec<Option<usize>>,
    children: Vec<Vec<usize>>,
    /// Leaf joints named `…tip` or `…end`: fingertips, not bones.
    tip: Vec<bool>,
    root: usize,
}

impl Skeleton {
    /// The skin's joints: positions from the inverse bind matrices, parents from the node
    /// hierarchy, or for a flat skin (the WebXR hands) each finger's joints chained by distance
    /// from the wrist.
    fn read<'a>(
        skin: &gltf::Skin,
        buffer: impl Clone + Fn(gltf::Buffer) -> Option<&'a [u8]>,
    ) -> Result<Self, String> {
        let joints: Vec<gltf::Node> = skin.joints().collect();
        let inverse_bind: Vec<[[f32; 4]; 4]> = skin
            .reader(buffer)
            .read_inverse_bind_matrices()
            .ok_or("the skin has no inverse bind matrices")?
            .collect();
        if inverse_bind.len() != joints.len() {
            return Err("the skin's inverse bind matrices do not match its joints".into());
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
            chain_flat_skin(&names, &position, &mut parent)?;
        }
        let children: Vec<Vec<usize>> = (0..joints.len())
            .map(|i| {
                (0..joints.len())
                    .filter(|&k| parent[k] == Some(i))
                    .collect()
            })
            .collect();
        let tip = (0..joints.len())
            .map(|i| {
                let n = names[i].to_ascii_lowercase();
                children[i].is_empty() && (n.ends_with("tip") || n.ends_with("end"))
            })
            .collect();
        let roots: Vec<usize> = (0..joints.len()).filter(|&i| parent[i].is_none()).collect();
        let [root] = roots[..] else {
            return Err(format!(
                "the skin has {} root joints; a hand has one (the wrist)",
                roots.len()
            ));
        };
        Ok(Self {
            names,
            position,
            parent,
            children,
            tip,
            root,
        })
    }

    /// Per bone, the 25th percentile of its dominant vertices' distances to its segment (to its
    /// first child), within 4–30 mm; 8 mm with fewer than five vertices.
    fn radii(&self, vertices: &SkinVertices) -> Vec<f64> {
        let n = self.names.len();
        let mut distances: Vec<Vec<f64>> = vec![Vec::new(); n];
        for (v, j, w) in &vertices.raw {
            let k = (0..4).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
            let bone = j[k] as usize;
            let Some(&end) = self.children.get(bone).and_then(|c| c.first()) else {
                continue;
            };
            let (a, b) = (self.position[bone], self.position[end]);
            let ab = b - a;
            let t = ((v - a).dot(&ab) / ab.norm_squared().max(1e-18)).clamp(0.0, 1.0);
            distances[bone].push((a + ab * t - v).norm());
        }
        distances
            .into_iter()
            .map(|mut d| {
                if d.len() < 5 {
                    return 0.008;
                }
                d.sort_by(f64::total_cmp);
                d[d.len() / 4].clamp(0.004, 0.03)
            })
            .collect()
    }

    /// Per joint, the finger it belongs to, its role (0 = the chain's first bone) and the
    /// chain's length: chains from the root, named by the sidecar or by their joints' names.
    fn fingers(&self, sidecar: Option<&crate::Sidecar>) -> Result<Vec<Option<FingerRole>>, String> {
        let mut finger_of = vec![None; self.names.len()];
        for &c in &self.children[self.root] {
            let mut chain = vec![c];
            while let Some(&next) = self.children[*chain.last().expect("non-empty")]
                .iter()
                .find(|&&k| !self.tip[k])
            {
                chain.push(next);
            }
            let finger = sidecar
                .and_then(|s| s.fingers.get(&self.names[c]).map(String::as_str))
                .or_else(|| chain.iter().find_map(|&i| finger_name(&self.names[i])))
                .ok_or_else(|| format!("cannot tell which finger joint '{}' belongs to; name it thumb, index, middle, ring or little", self.names[c]))?;
            for (role, &i) in chain.iter().enumerate() {
                finger_of[i] = Some((finger.to_string(), role, chain.len()));
            }
        }
        Ok(finger_of)
    }
}

/// A joint's finger, its role in the finger (0 = first bone) and the finger's bone count.
type FingerRole = (String, usize, usize);

/// A flat skin (no joint has a parent, as in the WebXR hands): each finger's joints, found by
/// name, chained by distance from the wrist (the joint named `…wrist…`, else the first).
fn chain_flat_skin(
    names: &[String],
    position: &[Point3],
    parent: &mut [Option<usize>],
) -> Result<(), String> {
    let root = names
        .iter()
        .position(|n| n.to_ascii_lowercase().contains("wrist"))
        .unwrap_or(0);
    let mut by_finger: HashMap<&str, Vec<usize>> = HashMap::new();
    for i in (0..names.len()).filter(|&i| i != root) {
        let f = finger_name(&names[i]).ok_or_else(|| {
            format!(
                "joint '{}' has no parent and names no finger; cannot place it in the hand",
                names[i]
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
    Ok(())
}

/// The skinned vertices as the file gives them (skin space): position, joints, weights; and
/// the triangles.
struct SkinVertices {
    raw: Vec<(Point3, [u16; 4], [f32; 4])>,
    triangles: Vec<[u32; 3]>,
}

impl SkinVertices {
    /// Every primitive that has positions, joints and weights; triangles whose indices fall
    /// outside their primitive are left out.
    fn read<'a>(
        document: &gltf::Document,
        buffer: impl Clone + Fn(gltf::Buffer) -> Option<&'a [u8]>,
    ) -> Self {
        let mut out = Self {
            raw: Vec::new(),
            triangles: Vec::new(),
        };
        for mesh in document.meshes() {
            for primitive in mesh.primitives() {
                let reader = primitive.reader(buffer.clone());
                let first = out.raw.len() as u32;
                let (Some(p), Some(j), Some(w)) = (
                    reader.read_positions(),
                    reader.read_joints(0),
                    reader.read_weights(0),
                ) else {
                    continue;
                };
                out.raw.extend(
                    p.zip(j.into_u16()).zip(w.into_f32()).map(|((p, j), w)| {
                        (Point3::new(p[0] as f64, p[1] as f64, p[2] as f64), j, w)
                    }),
                );
                let count = out.raw.len() as u32 - first;
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..count).collect(),
                };
                for t in indices.chunks_exact(3) {
                    if t.iter().all(|&i| i < count) {
                        out.triangles
                            .push([first + t[0], first + t[1], first + t[2]]);
                    }
                }
            }
        }
        out
    }

    /// The mesh in the hand frame, weighted to `hand`'s bones (a fingertip joint gives its
    /// weight to its bone).
    fn in_hand(self, hand: &HandModel, skeleton: &Skeleton, frame: &HandFrame) -> SkinnedMesh {
        let bone_of: Vec<u16> = (0..skeleton.names.len())
            .map(|j| {
                let owner = if skeleton.tip[j] {
                    skeleton.parent[j].unwrap_or(skeleton.root)
                } else {
                    j
                };
                hand.bone_index(&skeleton.names[owner]).unwrap_or(0) as u16
            })
            .collect();
        let mut skinned = SkinnedMesh::default();
        for (p, j, w) in &self.raw {
            skinned.positions.push(Point3::from(frame.to_hand(p)));
            skinned
                .joints
                .push(j.map(|k| bone_of.get(k as usize).copied().unwrap_or(0)));
            skinned.weights.push(*w);
        }
        skinned.triangles = self.triangles;
        skinned
    }
}

/// The hand frame of a skin: z from the wrist toward the middle finger's tip, y out of the palm
/// on the thumb's side, x across; and how far the thumb lies along x.
struct HandFrame {
    wrist: Point3,
    axes: [Vec3; 3],
    thumb_side: f64,
    /// Wrist to the middle finger's end, metres: the hand's length.
    length: f64,
}

impl HandFrame {
    fn new(skeleton: &Skeleton, finger_of: &[Option<FingerRole>]) -> Result<Self, String> {
        let position = &skeleton.position;
        let base = |f: &str| {
            (0..finger_of.len()).find(|&i| {
                finger_of[i]
                    .as_ref()
                    .is_some_and(|(n, r, _)| n == f && *r == 0)
            })
        };
        // A finger's end: its joint farthest from the wrist (file order says nothing).
        let wrist = position[skeleton.root];
        let tip_of = |f: &str| {
            (0..finger_of.len())
                .filter(|&i| finger_of[i].as_ref().is_some_and(|(n, _, _)| n == f))
                .max_by(|&a, &b| {
                    (position[a] - wrist)
                        .norm()
                        .total_cmp(&(position[b] - wrist).norm())
                })
        };
        let (Some(index), Some(little), Some(middle), Some(thumb)) = (
            base("index"),
            base("little"),
            tip_of("middle"),
            tip_of("thumb"),
        ) else {
            return Err("a skinned hand needs thumb, index, middle and little fingers to be mapped onto the human hand".into());
        };
        let z = (position[middle] - wrist).normalize();
        let across = position[little] - position[index];
        let mut y = across.cross(&z);
        if y.dot(&(position[thumb] - wrist)) < 0.0 {
            y = -y;
        }
        let y = (y - z * y.dot(&z)).normalize();
        let x = y.cross(&z);
        Ok(Self {
            wrist,
            axes: [x, y, z],
            thumb_side: position[thumb].coords.dot(&x) - wrist.coords.dot(&x),
            length: (position[middle] - wrist).norm(),
        })
    }

    /// A skin-space point in the hand frame.
    fn to_hand(&self, p: &Point3) -> [f64; 3] {
        let d = p - self.wrist;
        self.axes.map(|a| d.dot(&a))
    }
}

/// The hand description of a skin: its bones at their bind positions (hand frame) with the
/// built-in human hand's joints, limits, couplings and movements, matched by finger and role;
/// the power grasp centre scaled by the hand's length.
fn human_mapping(
    skeleton: &Skeleton,
    finger_of: &[Option<FingerRole>],
    frame: &HandFrame,
    radius: &[f64],
) -> HandDescription {
    let template = human();
    let template_bone = |n: &str| template.bones.iter().find(|b| b.name == n);
    let mut renamed: HashMap<String, String> = HashMap::new();
    let mut bones = Vec::new();
    for i in (0..skeleton.names.len()).filter(|&i| !skeleton.tip[i]) {
        let mut b = BoneDescription {
            name: skeleton.names[i].clone(),
            parent: skeleton.parent[i].map(|p| skeleton.names[p].clone()),
            origin: frame.to_hand(&skeleton.position[i]),
            tip: skeleton.children[i]
                .iter()
                .find(|&&k| skeleton.tip[k])
                .map(|&k| frame.to_hand(&skeleton.position[k])),
            radius: if i == skeleton.root { 0.015 } else { radius[i] },
            joint: JointDescription::Fixed,
            finger: None,
            flexes_toward: None,
        };
        if let Some((finger, role, count)) = &finger_of[i] {
            if let Some(t) = human_role(finger, *role, *count).and_then(|h| {
                renamed.insert(h.clone(), skeleton.names[i].clone());
                template_bone(&h)
            }) {
                b.joint = t.joint.clone();
                // The thumb flexes across the palm toward the fingers, whichever side it is on.
                b.flexes_toward = t
                    .flexes_toward
                    .map(|[hx, hy, hz]| [hx.abs() * -frame.thumb_side.signum(), hy, hz]);
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
    let scale = frame.length / 0.1774;
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
                via: map(&m.via),
                ..m.clone()
            }
        })
        .collect();
    HandDescription {
        name: String::new(),
        description: String::new(),
        bones,
        couplings,
        movements,
    }
}
