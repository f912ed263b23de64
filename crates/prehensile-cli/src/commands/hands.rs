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
    start_angles_deg: std::collections::BTreeMap<String, f64>,
    end_angles_deg: std::collections::BTreeMap<String, f64>,
    /// The pose the movement passes through on the way, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    via_angles_deg: Option<std::collections::BTreeMap<String, f64>>,
    /// Fraction of the closing at the via pose.
    #[serde(skip_serializing_if = "Option::is_none")]
    via_fraction: Option<f64>,
}

#[derive(serde::Serialize)]
struct FingerSummary {
    name: String,
    bones: Vec<String>,
    tip: [f64; 3],
}

/// A bone's joint, with what it takes to rebuild the hand in another program (e.g. an MJCF for
/// MuJoCo, `tools/mujoco/hand_mjcf.py`): the bone's rest frame in its parent's, the joint's axes
/// and its capsules in the bone's frame.
#[derive(serde::Serialize)]
struct JointSummary {
    bone: String,
    /// The parent bone, `None` for the root.
    parent: Option<String>,
    kind: &'static str,
    limits_deg: Vec<[f64; 2]>,
    /// The degrees of freedom's names, in the order of a joint-angle vector.
    dofs: Vec<String>,
    /// Each degree of freedom's axis, bone frame: a hinge's axis; a two-axis joint's flexion
    /// (inner) then abduction (outer) axis, R = R(abduction)·R(flexion); a ball joint's x, y, z
    /// (its angles are a rotation vector).
    axes: Vec<[f64; 3]>,
    /// The bone frame at rest, in the parent's frame (the root's: in the hand frame).
    rest_position: [f64; 3],
    rest_rotation_xyzw: [f64; 4],
    /// The bone's capsules, bone frame: end points and radius, metres.
    capsules: Vec<CapsuleSummary>,
}

#[derive(serde::Serialize)]
struct CapsuleSummary {
    a: [f64; 3],
    b: [f64; 3],
    radius: f64,
}

/// Joint angles (radians, one per degree of freedom) in degrees under the joints' names.
fn degrees_by_name(h: &HandModel, angles: &[f64]) -> std::collections::BTreeMap<String, f64> {
    h.dof_names()
        .iter()
        .zip(angles)
        .map(|(n, a)| (n.clone(), a.to_degrees()))
        .collect()
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
                start_angles_deg: degrees_by_name(h, m.start_angles()),
                end_angles_deg: degrees_by_name(h, m.end_angles()),
                via_angles_deg: m.via().map(|v| degrees_by_name(h, v.angles())),
                via_fraction: m.via().map(|v| v.fraction()),
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
            .enumerate()
            .map(|(k, b)| JointSummary {
                bone: b.name.clone(),
                parent: b.parent.map(|p| h.bones()[p].name.clone()),
                dofs: h.dof_names()[b.first_dof..b.first_dof + b.joint.dofs()].to_vec(),
                axes: match &b.joint {
                    Joint::Fixed => vec![],
                    Joint::Hinge(a) => vec![a.axis.into_inner().into()],
                    Joint::TwoAxis { flexion, abduction } => vec![
                        flexion.axis.into_inner().into(),
                        abduction.axis.into_inner().into(),
                    ],
                    Joint::Ball { .. } => vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                },
                rest_position: b.rest.translation.vector.into(),
                rest_rotation_xyzw: b.rest.rotation.coords.into(),
                capsules: h
                    .bone_capsules(k)
                    .iter()
                    .map(|c| CapsuleSummary {
                        a: c.a.into(),
                        b: c.b.into(),
                        radius: c.radius,
                    })
                    .collect(),
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
        // Where the hand came from and what its collision geoms became, a clause a line.
        for clause in summaries[0].description.split("; ") {
            out!("  {clause}");
        }
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
