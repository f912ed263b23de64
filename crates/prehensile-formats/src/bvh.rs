//! BVH: export of a hand's motion (the bone hierarchy with offsets in centimetres, as BVH tools
//! expect, and per frame every bone's local rotation as Z, X, Y Euler angles in degrees), and
//! import of hand motions as joint-angle trajectories of a hand model, matched by bone name.

use std::fmt::Write as _;

use prehensile_core::animation::Keyframe;
use prehensile_core::math::{Rotation, Transform};
use prehensile_core::HandModel;

use crate::FormatError;

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

/// One joint of a BVH hierarchy.
#[derive(Debug, Clone, PartialEq)]
pub struct BvhJoint {
    /// Name.
    pub name: String,
    /// Parent joint index.
    pub parent: Option<usize>,
    /// Channel names in file order (`Xposition`, `Zrotation`, ...).
    pub channels: Vec<String>,
}

/// A parsed BVH file.
#[derive(Debug, Clone, PartialEq)]
pub struct BvhMotion {
    /// Joints in file order.
    pub joints: Vec<BvhJoint>,
    /// Seconds per frame.
    pub frame_time: f64,
    /// Channel values per frame, joints' channels concatenated in file order.
    pub frames: Vec<Vec<f64>>,
}

/// The channels a BVH joint may have.
const CHANNELS: [&str; 6] = [
    "Xposition",
    "Yposition",
    "Zposition",
    "Xrotation",
    "Yrotation",
    "Zrotation",
];

/// Most frames or channels accepted, to bound memory on absurd headers.
const MAX_VALUES: usize = 50_000_000;

/// The lines of a BVH text, numbered from 0.
type Lines<'a> = std::iter::Enumerate<std::str::Lines<'a>>;

/// An error at line `n` (0-based) of `source`.
fn at_line(source: &str, n: usize, reason: String) -> FormatError {
    FormatError::at(source, format!("line {}", n + 1), reason)
}

/// Parses BVH text. Errors name the line.
pub fn parse_bvh(text: &str, source: &str) -> Result<BvhMotion, FormatError> {
    let mut lines = text.lines().enumerate();
    let joints = parse_hierarchy(&mut lines, source)?;
    let (frame_time, frames) = parse_motion(&mut lines, &joints, source)?;
    Ok(BvhMotion {
        joints,
        frame_time,
        frames,
    })
}

/// The joints of the HIERARCHY section, up to and including its MOTION line.
fn parse_hierarchy(lines: &mut Lines, source: &str) -> Result<Vec<BvhJoint>, FormatError> {
    let mut joints: Vec<BvhJoint> = Vec::new();
    let mut stack: Vec<Option<usize>> = Vec::new();
    let err = |n: usize, reason: String| at_line(source, n, reason);
    let mut in_end_site = 0usize;
    for (n, raw) in lines.by_ref() {
        let words: Vec<&str> = raw.split_whitespace().collect();
        match words.as_slice() {
            ["HIERARCHY"] | [] | ["OFFSET", ..] => {}
            ["ROOT" | "JOINT", name] => {
                joints.push(BvhJoint {
                    name: name.to_string(),
                    parent: stack.last().copied().flatten(),
                    channels: Vec::new(),
                });
            }
            ["End", "Site"] => in_end_site += 1,
            ["{"] => stack.push(if in_end_site > 0 {
                None
            } else {
                Some(joints.len().saturating_sub(1))
            }),
            ["}"] => {
                let popped = stack
                    .pop()
                    .ok_or_else(|| err(n, "a '}' closes nothing".into()))?;
                if popped.is_none() && in_end_site > 0 {
                    in_end_site -= 1;
                }
            }
            ["CHANNELS", count, names @ ..] => {
                let joint = joints
                    .last_mut()
                    .ok_or_else(|| err(n, "CHANNELS before any joint".into()))?;
                joint.channels = parse_channels(count, names).map_err(|e| err(n, e))?;
            }
            ["MOTION"] if stack.is_empty() => return Ok(joints),
            ["MOTION"] => return Err(err(n, "the hierarchy's braces are not balanced".into())),
            other => return Err(err(n, format!("unexpected '{}'", other.join(" ")))),
        }
    }
    Err(FormatError::new(source, "no MOTION section"))
}

/// A CHANNELS line's names, checked against its count and the channels BVH has.
fn parse_channels(count: &str, names: &[&str]) -> Result<Vec<String>, String> {
    let count: usize = count
        .parse()
        .map_err(|_| format!("'{count}' is not a channel count"))?;
    if names.len() != count {
        return Err(format!("CHANNELS says {count} but lists {}", names.len()));
    }
    if let Some(bad) = names.iter().find(|c| !CHANNELS.contains(c)) {
        return Err(format!(
            "unknown channel '{bad}'; BVH channels are {}",
            CHANNELS.join(", ")
        ));
    }
    Ok(names.iter().map(|s| s.to_string()).collect())
}

/// The MOTION section after its MOTION line: the frame time and every frame's values.
fn parse_motion(
    lines: &mut Lines,
    joints: &[BvhJoint],
    source: &str,
) -> Result<(f64, Vec<Vec<f64>>), FormatError> {
    let err = |n: usize, reason: String| at_line(source, n, reason);
    let mut next_value = |prefix: &str| -> Result<(usize, String), FormatError> {
        let (n, line) = lines
            .next()
            .ok_or_else(|| FormatError::new(source, format!("missing '{prefix}' line")))?;
        let value = line
            .trim()
            .strip_prefix(prefix)
            .ok_or_else(|| err(n, format!("expected '{prefix}'")))?;
        Ok((n, value.trim().to_string()))
    };
    let (n, frames_text) = next_value("Frames:")?;
    let count: usize = frames_text
        .parse()
        .map_err(|_| err(n, format!("'{frames_text}' is not a frame count")))?;
    let (n, time_text) = next_value("Frame Time:")?;
    let frame_time: f64 = time_text
        .parse()
        .ok()
        .filter(|t: &f64| t.is_finite() && *t > 0.0)
        .ok_or_else(|| err(n, format!("'{time_text}' is not a positive frame time")))?;
    let width: usize = joints.iter().map(|j| j.channels.len()).sum();
    if count.saturating_mul(width.max(1)) > MAX_VALUES {
        return Err(FormatError::new(
            source,
            format!("{count} frames of {width} channels is more than this reader accepts"),
        ));
    }
    let mut frames = Vec::with_capacity(count.min(100_000));
    for (n, line) in lines.by_ref().take(count) {
        let values: Vec<f64> = line
            .split_whitespace()
            .map(|w| w.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<_>>()
            .ok_or_else(|| err(n, "a frame value is not a finite number".into()))?;
        if values.len() != width {
            return Err(err(
                n,
                format!(
                    "{} values, but the hierarchy has {width} channels",
                    values.len()
                ),
            ));
        }
        frames.push(values);
    }
    // More frame lines than the header promises: as wrong as fewer (blank lines at the end are
    // allowed).
    if let Some((n, _)) = lines.find(|(_, l)| !l.trim().is_empty()) {
        return Err(err(
            n,
            format!(
                "the header promises {count} frames, but more frame lines follow; fix 'Frames:'"
            ),
        ));
    }
    if frames.len() != count {
        return Err(FormatError::new(
            source,
            format!(
                "the header promises {count} frames, the file has {}",
                frames.len()
            ),
        ));
    }
    Ok((frame_time, frames))
}

impl BvhMotion {
    /// Each frame as the hand's joint-angle vector: every bone is matched by name to a BVH joint,
    /// its local rotation read from the Z/X/Y rotation channels, the bone's rest rotation taken
    /// off, and the remainder decomposed onto the bone's joint. Couplings and limits are applied.
    pub fn joint_angles(
        &self,
        hand: &HandModel,
        source: &str,
    ) -> Result<Vec<Vec<f64>>, FormatError> {
        let mut first_channel = Vec::with_capacity(self.joints.len());
        let mut at = 0;
        for j in &self.joints {
            first_channel.push(at);
            at += j.channels.len();
        }
        let mut mapping = Vec::new();
        for (k, bone) in hand.bones().iter().enumerate().skip(1) {
            if bone.joint.dofs() == 0 {
                continue;
            }
            let name = bone.name.replace(char::is_whitespace, "_");
            let j = self
                .joints
                .iter()
                .position(|j| j.name == name)
                .ok_or_else(|| {
                    FormatError::new(
                        source,
                        format!(
                            "the hand's bone '{}' has no joint of that name in the motion",
                            bone.name
                        ),
                    )
                })?;
            mapping.push((k, j));
        }
        let mut out = Vec::with_capacity(self.frames.len());
        for frame in &self.frames {
            let mut angles = vec![0.0; hand.dof_count()];
            for &(k, j) in &mapping {
                let mut r = Rotation::identity();
                for (c, name) in self.joints[j].channels.iter().enumerate() {
                    let v = frame[first_channel[j] + c].to_radians();
                    let axis = match name.as_str() {
                        "Xrotation" => prehensile_core::math::Vec3::x_axis(),
                        "Yrotation" => prehensile_core::math::Vec3::y_axis(),
                        "Zrotation" => prehensile_core::math::Vec3::z_axis(),
                        _ => continue,
                    };
                    r *= Rotation::from_axis_angle(&axis, v);
                }
                let bone = &hand.bones()[k];
                let joint_rotation = bone.rest.rotation.inverse() * r;
                let n = bone.joint.dofs();
                bone.joint.angles(
                    &joint_rotation,
                    &mut angles[bone.first_dof..bone.first_dof + n],
                );
            }
            hand.constrain(&mut angles);
            out.push(angles);
        }
        Ok(out)
    }
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
