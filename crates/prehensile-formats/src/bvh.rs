//! BVH export of a hand's motion: the bone hierarchy with offsets (centimetres, as BVH tools
//! expect) and, per frame, every bone's local rotation as Z, X, Y Euler angles in degrees.

use std::fmt::Write as _;

use prehensile_core::animation::Keyframe;
use prehensile_core::math::{Rotation, Transform};
use prehensile_core::HandModel;

/// Centimetres per metre.
const CM: f64 = 100.0;

/// Z, X, Y Euler angles (radians) with R = Rz(a)·Rx(b)·Ry(c), BVH's usual channel order.
pub fn euler_zxy(r: &Rotation) -> [f64; 3] {
    let m = r.to_rotation_matrix();
    let m = m.matrix();
    let b = m[(2, 1)].clamp(-1.0, 1.0).asin();
    let a = (-m[(0, 1)]).atan2(m[(1, 1)]);
    let c = (-m[(2, 0)]).atan2(m[(2, 2)]);
    [a, b, c]
}

/// The motion as BVH text at `fps` frames per second (keyframes are resampled by index).
pub fn write_bvh(hand: &HandModel, keyframes: &[Keyframe], fps: f64) -> String {
    let mut out = String::from("HIERARCHY\n");
    let bones = hand.bones();
    let children = |k: usize| {
        bones
            .iter()
            .enumerate()
            .filter(move |(_, b)| b.parent == Some(k))
            .map(|(i, _)| i)
    };
    // Depth-first, as BVH nests; parents-first storage makes bone 0 the root.
    fn emit(
        out: &mut String,
        hand: &HandModel,
        k: usize,
        depth: usize,
        kids: &dyn Fn(usize) -> Vec<usize>,
    ) {
        let b = &hand.bones()[k];
        let pad = "  ".repeat(depth);
        let offset = if b.parent.is_some() {
            b.rest.translation.vector * CM
        } else {
            Default::default()
        };
        let keyword = if b.parent.is_none() { "ROOT" } else { "JOINT" };
        let _ = writeln!(
            out,
            "{pad}{keyword} {}",
            b.name.replace(char::is_whitespace, "_")
        );
        let _ = writeln!(out, "{pad}{{");
        let _ = writeln!(
            out,
            "{pad}  OFFSET {:.6} {:.6} {:.6}",
            offset.x, offset.y, offset.z
        );
        if b.parent.is_none() {
            let _ = writeln!(
                out,
                "{pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
            );
        } else {
            let _ = writeln!(out, "{pad}  CHANNELS 3 Zrotation Xrotation Yrotation");
        }
        let children = kids(k);
        if children.is_empty() {
            let tip = hand
                .fingers()
                .iter()
                .find(|f| f.bones.last() == Some(&k))
                .map_or(Default::default(), |f| f.tip.coords * CM);
            let _ = writeln!(
                out,
                "{pad}  End Site\n{pad}  {{\n{pad}    OFFSET {:.6} {:.6} {:.6}\n{pad}  }}",
                tip.x, tip.y, tip.z
            );
        }
        for c in children {
            emit(out, hand, c, depth + 1, kids);
        }
        let _ = writeln!(out, "{pad}}}");
    }
    let kids = |k: usize| children(k).collect::<Vec<_>>();
    emit(&mut out, hand, 0, 0, &kids);
    let _ = writeln!(
        out,
        "MOTION\nFrames: {}\nFrame Time: {:.6}",
        keyframes.len(),
        1.0 / fps
    );
    let mut order = Vec::new();
    fn depth_first(k: usize, kids: &dyn Fn(usize) -> Vec<usize>, order: &mut Vec<usize>) {
        order.push(k);
        for c in kids(k) {
            depth_first(c, kids, order);
        }
    }
    depth_first(0, &kids, &mut order);
    for frame in keyframes {
        let mut line = Vec::new();
        for &k in &order {
            let b = &bones[k];
            let mut local = b.rest * Transform::from_parts(Default::default(), frame.rotations[k]);
            if b.parent.is_none() {
                local = frame.root * local;
                let p = local.translation.vector * CM;
                line.extend([p.x, p.y, p.z]);
            }
            line.extend(euler_zxy(&local.rotation).map(f64::to_degrees));
        }
        let text: Vec<String> = line.iter().map(|v| format!("{v:.5}")).collect();
        let _ = writeln!(out, "{}", text.join(" "));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use prehensile_core::math::Vec3;

    #[test]
    fn zxy_angles_rebuild_the_rotation() {
        for (a, b, c) in [(0.3, -0.4, 1.1), (-2.0, 0.2, 0.5), (0.0, 1.2, -0.7)] {
            let r = Rotation::from_axis_angle(&Vec3::z_axis(), a)
                * Rotation::from_axis_angle(&Vec3::x_axis(), b)
                * Rotation::from_axis_angle(&Vec3::y_axis(), c);
            let [a2, b2, c2] = euler_zxy(&r);
            let back = Rotation::from_axis_angle(&Vec3::z_axis(), a2)
                * Rotation::from_axis_angle(&Vec3::x_axis(), b2)
                * Rotation::from_axis_angle(&Vec3::y_axis(), c2);
            assert!(back.angle_to(&r) < 1e-12);
        }
    }
}
