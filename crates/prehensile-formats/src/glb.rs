//! glTF 2.0 binary (GLB) export of a grasp: the object, the hand as a hierarchy of bone nodes
//! carrying capsule meshes, and an animation of the hand approaching and closing.
//!
//! Written by hand: the `gltf` crate reads glTF but does not build files, and a GLB is a JSON
//! header plus one binary buffer. Checked in tests by reading it back with the `gltf` crate and
//! in CI with the Khronos glTF validator.

use prehensile_core::animation::Keyframe;
use prehensile_core::math::{Point3, Transform, Vec3};
use prehensile_core::{HandModel, TriangleMesh};

use crate::SkinnedMesh;
use serde_json::{json, Value};

/// Segments around a capsule, and rings per hemisphere.
const AROUND: usize = 12;
const RINGS: usize = 3;

#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    fn floats(
        &mut self,
        values: &[f32],
        kind: &str,
        width: usize,
        target: Option<u32>,
        bounds: bool,
    ) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let mut a = json!({"bufferView": view, "componentType": 5126, "count": values.len() / width, "type": kind});
        if bounds {
            let (mut lo, mut hi) = (vec![f32::INFINITY; width], vec![f32::NEG_INFINITY; width]);
            for chunk in values.chunks(width) {
                for (k, v) in chunk.iter().enumerate() {
                    lo[k] = lo[k].min(*v);
                    hi[k] = hi[k].max(*v);
                }
            }
            a["min"] = json!(lo);
            a["max"] = json!(hi);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    fn indices(&mut self, values: &[u32]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(34963));
        self.accessors
            .push(json!({"bufferView": view, "componentType": 5125, "count": values.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    fn mesh(&mut self, positions: &[Point3], triangles: &[[u32; 3]], material: usize) -> Value {
        let p: Vec<f32> = positions
            .iter()
            .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32])
            .collect();
        let position = self.floats(&p, "VEC3", 3, Some(34962), true);
        let idx: Vec<u32> = triangles.iter().flatten().copied().collect();
        let indices = self.indices(&idx);
        json!({"primitives": [{"attributes": {"POSITION": position}, "indices": indices, "material": material}]})
    }
}

/// Triangles of a capsule from `a` to `b` with `radius`, appended to `positions`/`triangles`.
fn capsule_triangles(
    a: &Point3,
    b: &Point3,
    radius: f64,
    positions: &mut Vec<Point3>,
    triangles: &mut Vec<[u32; 3]>,
) {
    let axis = b - a;
    let w = if axis.norm() > 1e-12 {
        axis.normalize()
    } else {
        Vec3::z()
    };
    let helper = if w.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let u = w.cross(&helper).normalize();
    let v = w.cross(&u);
    let first = positions.len() as u32;
    // Rings from the bottom pole to the top pole: hemisphere at a, hemisphere at b.
    let mut rings: Vec<(Point3, f64, f64)> = Vec::new(); // (centre, ring radius, axial offset)
    for k in 0..=RINGS {
        let phi = std::f64::consts::FRAC_PI_2 * (1.0 - k as f64 / RINGS as f64);
        rings.push((*a, radius * phi.cos(), -radius * phi.sin()));
    }
    for k in 0..=RINGS {
        let phi = std::f64::consts::FRAC_PI_2 * (k as f64 / RINGS as f64);
        rings.push((*b, radius * phi.cos(), radius * phi.sin()));
    }
    for (centre, r, dz) in &rings {
        for i in 0..AROUND {
            let t = std::f64::consts::TAU * i as f64 / AROUND as f64;
            positions.push(centre + w * *dz + (u * t.cos() + v * t.sin()) * *r);
        }
    }
    let id = |ring: usize, i: usize| first + (ring * AROUND + i % AROUND) as u32;
    for ring in 0..rings.len() - 1 {
        for i in 0..AROUND {
            triangles.push([id(ring, i), id(ring, i + 1), id(ring + 1, i + 1)]);
            triangles.push([id(ring, i), id(ring + 1, i + 1), id(ring + 1, i)]);
        }
    }
}

/// Translation and rotation quaternion (x, y, z, w) of `t`. A unit quaternion's component can
/// exceed 1 by a rounding (1.0000000000000002), which glTF forbids: each is clamped to [−1, 1].
fn trs(t: &Transform) -> (Vec<f64>, Vec<f64>) {
    let q = t.rotation.quaternion();
    (
        t.translation.vector.iter().copied().collect(),
        [q.i, q.j, q.k, q.w]
            .iter()
            .map(|c| c.clamp(-1.0, 1.0))
            .collect(),
    )
}

/// A GLB with the object mesh, the hand's bones (capsule meshes) and their animation over the
/// keyframes (none: the hand in its rest pose at the origin). Coordinates are the object's
/// frame, metres.
///
/// With `skin`, the hand's own skinned mesh is added too, bound to the bone nodes, so it follows
/// the animation.
pub fn grasp_glb(
    object: &TriangleMesh,
    hand: &HandModel,
    keyframes: &[Keyframe],
    skin: Option<&SkinnedMesh>,
) -> Vec<u8> {
    animated_glb(
        Some(object),
        &[],
        &[(hand, keyframes)],
        skin,
        "approach and close",
    )
}

/// A GLB of a simulation run: every hand with its keyframes and, with an object, its pose at
/// every keyframe of the first hand (`object_track`, one per keyframe) — the object moves with
/// the run. With several hands their bone nodes are named `hand 1: …`, `hand 2: …`.
pub fn simulation_glb(
    object: Option<(&TriangleMesh, &[Transform])>,
    hands: &[(&HandModel, &[Keyframe])],
) -> Vec<u8> {
    let (mesh, track) = match object {
        Some((m, t)) => (Some(m), t),
        None => (None, &[][..]),
    };
    animated_glb(mesh, track, hands, None, "simulation")
}

/// A bone's transform in its parent node at `frame` (the root's includes the hand's placement).
fn bone_local(hand: &HandModel, frame: &Keyframe, k: usize) -> Transform {
    let bone = &hand.bones()[k];
    let local = bone.rest * Transform::from_parts(Default::default(), frame.rotations[k]);
    if bone.parent.is_none() {
        frame.root * local
    } else {
        local
    }
}

/// The scene: the object (node 0, if any), then each hand's bones as nodes with capsule meshes,
/// then the skinned mesh bound to the first hand; one animation with every hand's keyframes and
/// the object's track.
fn animated_glb(
    object: Option<&TriangleMesh>,
    object_track: &[Transform],
    hands: &[(&HandModel, &[Keyframe])],
    skin: Option<&SkinnedMesh>,
    animation_name: &str,
) -> Vec<u8> {
    let mut scene = Scene::default();
    if let Some(object) = object {
        scene.add_object(object);
    }
    // Each hand's keyframes (its rest pose at the origin when it has none) and first node.
    let mut tracks: Vec<(&HandModel, Vec<Keyframe>, usize)> = Vec::new();
    for (h, (hand, keyframes)) in hands.iter().enumerate() {
        let keyframes = if keyframes.is_empty() {
            vec![Keyframe {
                time: 0.0,
                root: Transform::identity(),
                rotations: vec![Default::default(); hand.bones().len()],
            }]
        } else {
            keyframes.to_vec()
        };
        let prefix = if hands.len() > 1 {
            format!("hand {}: ", h + 1)
        } else {
            String::new()
        };
        let first_bone = scene.add_hand(hand, &keyframes[0], &prefix);
        tracks.push((hand, keyframes, first_bone));
    }
    if let (Some(skin), Some((hand, _, first_bone))) =
        (skin.filter(|s| !s.positions.is_empty()), tracks.first())
    {
        scene.add_skin(skin, hand, *first_bone);
    }
    for (h, (hand, keyframes, first_bone)) in tracks.iter().enumerate() {
        if keyframes.len() < 2 {
            continue;
        }
        let times: Vec<f32> = keyframes.iter().map(|k| k.time as f32).collect();
        let input = scene.b.floats(&times, "SCALAR", 1, None, true);
        scene.animate_hand(hand, keyframes, *first_bone, input);
        if h == 0 && object.is_some() && object_track.len() == keyframes.len() {
            scene.animate_object(object_track, input);
        }
    }
    scene.finish(animation_name)
}

/// A glTF scene being built: the binary buffer and the JSON arrays that point into it.
#[derive(Default)]
struct Scene {
    b: Builder,
    meshes: Vec<serde_json::Value>,
    nodes: Vec<serde_json::Value>,
    scene_nodes: Vec<usize>,
    skins: Vec<serde_json::Value>,
    samplers: Vec<serde_json::Value>,
    channels: Vec<serde_json::Value>,
}

impl Scene {
    /// The object's mesh as node 0.
    fn add_object(&mut self, object: &TriangleMesh) {
        self.meshes
            .push(self.b.mesh(&object.vertices, &object.triangles, 0));
        self.nodes.push(json!({"name": "object", "mesh": 0}));
        self.scene_nodes.push(self.nodes.len() - 1);
    }

    /// The hand's bones as nodes posed at `first`, each with its capsules' mesh; returns the
    /// first bone's node.
    fn add_hand(&mut self, hand: &HandModel, first: &Keyframe, prefix: &str) -> usize {
        let first_bone = self.nodes.len();
        for (k, bone) in hand.bones().iter().enumerate() {
            let (translation, rotation) = trs(&bone_local(hand, first, k));
            let mut node = json!({"name": format!("{prefix}{}", bone.name), "translation": translation, "rotation": rotation});
            let children: Vec<usize> = hand
                .bones()
                .iter()
                .enumerate()
                .filter(|(_, c)| c.parent == Some(k))
                .map(|(i, _)| first_bone + i)
                .collect();
            if !children.is_empty() {
                node["children"] = json!(children);
            }
            let capsules = hand.bone_capsules(k);
            if !capsules.is_empty() {
                let (mut p, mut t) = (Vec::new(), Vec::new());
                for c in capsules {
                    capsule_triangles(&c.a, &c.b, c.radius, &mut p, &mut t);
                }
                node["mesh"] = json!(self.meshes.len());
                self.meshes.push(self.b.mesh(&p, &t, 1));
            }
            self.nodes.push(node);
        }
        self.scene_nodes.push(first_bone);
        first_bone
    }

    /// The hand's own skinned mesh, bound to its bone nodes from `first_bone`.
    fn add_skin(&mut self, skin: &SkinnedMesh, hand: &HandModel, first_bone: usize) {
        let b = &mut self.b;
        let p: Vec<f32> = skin
            .positions
            .iter()
            .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32])
            .collect();
        let position = b.floats(&p, "VEC3", 3, Some(34962), true);
        let j: Vec<u8> = skin
            .joints
            .iter()
            .flatten()
            .flat_map(|k| k.to_le_bytes())
            .collect();
        let view = b.view(&j, Some(34962));
        b.accessors.push(json!({"bufferView": view, "componentType": 5123, "count": skin.joints.len(), "type": "VEC4"}));
        let joints = b.accessors.len() - 1;
        let w: Vec<f32> = skin.weights.iter().flatten().copied().collect();
        let weights = b.floats(&w, "VEC4", 4, Some(34962), false);
        let idx: Vec<u32> = skin.triangles.iter().flatten().copied().collect();
        let indices = b.indices(&idx);
        self.meshes.push(json!({"name": "skinned hand", "primitives": [{"attributes": {"POSITION": position, "JOINTS_0": joints, "WEIGHTS_0": weights}, "indices": indices, "material": 1}]}));
        // Inverse bind matrices: the bones' rest frames, which the mesh is posed in.
        let inverse_bind = b.floats(&inverse_bind_matrices(hand), "MAT4", 16, None, false);
        self.skins.push(json!({"joints": (0..hand.bones().len()).map(|k| first_bone + k).collect::<Vec<_>>(), "inverseBindMatrices": inverse_bind}));
        self.nodes
            .push(json!({"name": "skinned hand", "mesh": self.meshes.len() - 1, "skin": 0}));
        self.scene_nodes.push(self.nodes.len() - 1);
    }

    /// A linear sampler of `values` (`kind`, `width` numbers each) at the times of accessor
    /// `input`, driving `path` of `node`.
    fn channel(
        &mut self,
        input: usize,
        values: &[f32],
        (kind, width): (&str, usize),
        node: usize,
        path: &str,
    ) {
        let output = self.b.floats(values, kind, width, None, false);
        self.samplers
            .push(json!({"input": input, "output": output, "interpolation": "LINEAR"}));
        self.channels.push(
            json!({"sampler": self.samplers.len() - 1, "target": {"node": node, "path": path}}),
        );
    }

    /// Every bone's rotation over the keyframes, and the root's translation.
    fn animate_hand(
        &mut self,
        hand: &HandModel,
        keyframes: &[Keyframe],
        first_bone: usize,
        input: usize,
    ) {
        for k in 0..hand.bones().len() {
            let locals: Vec<Transform> = keyframes.iter().map(|f| bone_local(hand, f, k)).collect();
            let rotations: Vec<f32> = locals
                .iter()
                .flat_map(|t| trs(t).1.into_iter().map(|v| v as f32))
                .collect();
            self.channel(input, &rotations, ("VEC4", 4), first_bone + k, "rotation");
            if hand.bones()[k].parent.is_none() {
                let translations: Vec<f32> = locals
                    .iter()
                    .flat_map(|t| trs(t).0.into_iter().map(|v| v as f32))
                    .collect();
                self.channel(
                    input,
                    &translations,
                    ("VEC3", 3),
                    first_bone + k,
                    "translation",
                );
            }
        }
    }

    /// The object's pose over the keyframes (node 0).
    fn animate_object(&mut self, track: &[Transform], input: usize) {
        let (translations, rotations): (Vec<Vec<f64>>, Vec<Vec<f64>>) =
            track.iter().map(trs).unzip();
        for (path, values, kind) in [
            ("translation", translations.concat(), ("VEC3", 3)),
            ("rotation", rotations.concat(), ("VEC4", 4)),
        ] {
            let values: Vec<f32> = values.iter().map(|v| *v as f32).collect();
            self.channel(input, &values, kind, 0, path);
        }
    }

    /// The GLB container of the scene, with the animation named `animation_name`.
    fn finish(mut self, animation_name: &str) -> Vec<u8> {
        let materials = json!([
            {"name": "object", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.78, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8}},
            {"name": "hand", "pbrMetallicRoughness": {"baseColorFactor": [0.86, 0.55, 0.42, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6}}
        ]);
        while !self.b.bin.len().is_multiple_of(4) {
            self.b.bin.push(0);
        }
        let mut doc = json!({
            "asset": {"version": "2.0", "generator": concat!("prehensile ", env!("CARGO_PKG_VERSION"))},
            "scene": 0,
            "scenes": [{"nodes": self.scene_nodes}],
            "nodes": self.nodes,
            "meshes": self.meshes,
            "materials": materials,
            "accessors": self.b.accessors,
            "bufferViews": self.b.views,
            "buffers": [{"byteLength": self.b.bin.len()}],
        });
        if !self.channels.is_empty() {
            doc["animations"] = json!([{"name": animation_name, "samplers": self.samplers, "channels": self.channels}]);
        }
        if !self.skins.is_empty() {
            doc["skins"] = json!(self.skins);
        }
        glb_container(
            &serde_json::to_vec(&doc).expect("JSON values serialize"),
            &self.b.bin,
        )
    }
}

/// A skin's inverse bind matrices for `hand`: per bone the inverse of its rest frame in the hand
/// frame (the frame a [`SkinnedMesh`] is given in), 16 numbers column-major each.
pub fn inverse_bind_matrices(hand: &HandModel) -> Vec<f32> {
    let rest = hand.pose_transforms(
        &Transform::identity(),
        &vec![Default::default(); hand.bones().len()],
    );
    rest.iter()
        .flat_map(|t| t.inverse().to_homogeneous().as_slice().to_vec())
        .map(|v| v as f32)
        .collect()
}

/// A binary glTF (GLB) file of a JSON chunk and a binary chunk, each padded to 4 bytes.
pub fn glb_container(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| n.div_ceil(4) * 4;
    let (json_len, bin_len) = (pad(json.len()), pad(bin.len()));
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.resize(12 + 8 + json_len, b' ');
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rotation_rounded_past_one_is_written_within_the_gltf_range() {
        let q = nalgebra::Quaternion::new(1.0000000000000002, 0.0, 0.0, 0.0);
        let t = Transform::from_parts(
            Vec3::new(0.1, 0.0, 0.0).into(),
            nalgebra::UnitQuaternion::new_unchecked(q),
        );
        let (translation, rotation) = trs(&t);
        assert_eq!(translation, [0.1, 0.0, 0.0]);
        assert_eq!(rotation, [0.0, 0.0, 0.0, 1.0]);
    }
}
