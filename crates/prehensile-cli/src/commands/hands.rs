//! `prehensile hands`: the built-in hands, or one hand file described.

use prehensile_core::hand::Joint;
use prehensile_core::HandModel;
use prehensile_formats::{builtin_hand, BUILTIN_HANDS};

use crate::args::HandsArgs;
use crate::CliError;

#[derive(serde::Serialize)]
struct HandSummary {
    name: String,
    description: String,
    bones: usize,
    capsules: usize,
    degrees_of_freedom: usize,
    fingers: Vec<String>,
    movements: Vec<String>,
    /// Each movement: grasp center (hand frame), contact fingers, end angles by name.
    movement_details: Vec<MovementSummary>,
    /// Each finger: its chain's bones and its fingertip (last bone's frame).
    finger_details: Vec<FingerSummary>,
    /// The palm's side: true when the thumb lies on +x (a left hand).
    left: bool,
    /// The hand frame as derived (for an imported hand) or authored, seen from the root bone.
    frame: FrameSummary,
    joints: Vec<JointSummary>,
}

/// The hand frame's axes in the root bone's frame (for an imported hand, the file's palm body):
/// what importing derived, and what to check when grasps come out on the wrong side.
#[derive(serde::Serialize)]
struct FrameSummary {
    /// z: along the fingers, from the palm toward the mean fingertip.
    fingers_along: [f64; 3],
    /// y: out of the palm, the side the fingers close toward.
    palm_normal: [f64; 3],
}

#[derive(serde::Serialize)]
struct MovementSummary {
    name: String,
    grasp_center: [f64; 3],
    contact_fingers: Vec<String>,
    end_angles_deg: std::collections::BTreeMap<String, f64>,
}

#[derive(serde::Serialize)]
struct FingerSummary {
    name: String,
    bones: Vec<String>,
    tip: [f64; 3],
}

#[derive(serde::Serialize)]
struct JointSummary {
    bone: String,
    kind: &'static str,
    limits_deg: Vec<[f64; 2]>,
}

fn summary(h: &HandModel) -> HandSummary {
    HandSummary {
        name: h.name().into(),
        description: h.description().into(),
        bones: h.bones().len(),
        capsules: h.capsules().len(),
        degrees_of_freedom: h.dof_count(),
        fingers: h.fingers().iter().map(|f| f.name.clone()).collect(),
        movements: h.movements().iter().map(|m| m.name().to_string()).collect(),
        movement_details: h
            .movements()
            .iter()
            .map(|m| MovementSummary {
                name: m.name().to_string(),
                grasp_center: m.grasp_center().into(),
                contact_fingers: m
                    .contact_fingers()
                    .iter()
                    .map(|&f| h.fingers()[f].name.clone())
                    .collect(),
                end_angles_deg: h
                    .dof_names()
                    .iter()
                    .zip(m.end_angles())
                    .map(|(n, a)| (n.clone(), a.to_degrees()))
                    .collect(),
            })
            .collect(),
        finger_details: h
            .fingers()
            .iter()
            .map(|f| FingerSummary {
                name: f.name.clone(),
                bones: f.bones.iter().map(|&b| h.bones()[b].name.clone()).collect(),
                tip: f.tip.into(),
            })
            .collect(),
        left: h.is_left(),
        frame: {
            let to_root = h.bones()[0].rest.rotation.inverse();
            FrameSummary {
                fingers_along: (to_root * prehensile_core::math::Vec3::z()).into(),
                palm_normal: (to_root * prehensile_core::math::Vec3::y()).into(),
            }
        },
        joints: h
            .bones()
            .iter()
            .map(|b| JointSummary {
                bone: b.name.clone(),
                kind: match b.joint {
                    Joint::Fixed => "fixed",
                    Joint::Hinge(_) => "hinge",
                    Joint::TwoAxis { .. } => "two-axis",
                    Joint::Ball { .. } => "ball",
                },
                limits_deg: (0..b.joint.dofs())
                    .map(|k| b.joint.limits(k).map(f64::to_degrees))
                    .collect(),
            })
            .collect(),
    }
}

/// Lists or describes hands.
pub fn run(args: &HandsArgs) -> Result<i32, CliError> {
    let hands: Vec<HandModel> = match &args.file {
        Some(path) => vec![prehensile_formats::load_hand(path)?],
        None => BUILTIN_HANDS
            .iter()
            .filter_map(|n| builtin_hand(n))
            .collect(),
    };
    let summaries: Vec<HandSummary> = hands.iter().map(summary).collect();
    if args.json {
        out!("{}", serde_json::to_string_pretty(&summaries)?);
        return Ok(0);
    }
    out!(
        "{:<10} {:>5} {:>8} {:>4}  {:<34} movements",
        "hand",
        "bones",
        "capsules",
        "dofs",
        "fingers"
    );
    for s in &summaries {
        out!(
            "{:<10} {:>5} {:>8} {:>4}  {:<34} {}",
            s.name,
            s.bones,
            s.capsules,
            s.degrees_of_freedom,
            s.fingers.join(","),
            s.movements.join(",")
        );
    }
    if args.file.is_some() {
        for j in &summaries[0].joints {
            let limits: Vec<String> = j
                .limits_deg
                .iter()
                .map(|[a, b]| format!("[{a:.0}°, {b:.0}°]"))
                .collect();
            out!("  {:<22} {:<9} {}", j.bone, j.kind, limits.join(" "));
        }
    }
    Ok(0)
}
