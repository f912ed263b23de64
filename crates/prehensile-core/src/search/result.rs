//! The search's output (§3.5) as plain data with a documented, versioned JSON form
//! (`docs/RESULT_SCHEMA.md`). Everything is in metres and radians in the object's frame.

use crate::math::{Rotation, Transform};
use crate::stability::{narrowest_normal_cap, Stability};
use crate::workspace::Workspace;

use super::planner::{GraspPlanner, PlannerStatus, SearchStats};
use super::quality::{Evaluation, EvaluationContext, QualityTerms, CONTACT_TOLERANCE};

/// Name and version of the result format.
pub const RESULT_SCHEMA: &str = "prehensile.grasp/3";

/// A rigid pose: position and unit quaternion `[x, y, z, w]`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PoseRecord {
    /// Position, metres.
    pub position: [f64; 3],
    /// Rotation as a unit quaternion `[x, y, z, w]`.
    pub rotation_xyzw: [f64; 4],
}

impl From<&Transform> for PoseRecord {
    fn from(t: &Transform) -> Self {
        let q = t.rotation.quaternion();
        Self {
            position: t.translation.vector.into(),
            rotation_xyzw: [q.i, q.j, q.k, q.w],
        }
    }
}

/// One bone of the grasp pose.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BoneRecord {
    /// Bone name.
    pub name: String,
    /// Finger name, none for the root.
    pub finger: Option<String>,
    /// World pose of the bone's frame.
    pub pose: PoseRecord,
    /// Interpolation reached in finger closing (0..=N).
    pub reached: u32,
    /// Fraction of the movement reached (refined, 0..=1).
    pub fraction: f64,
    /// Whether the bone stopped because it touched the object.
    pub stopped_by_contact: bool,
}

/// One capsule of the hand in the grasp pose.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CapsuleRecord {
    /// Bone it belongs to.
    pub bone: String,
    /// Finger, `"palm"` for the root's capsules.
    pub finger: String,
    /// First end, world.
    pub a: [f64; 3],
    /// Second end, world.
    pub b: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Within 1 mm of the object's surface.
    pub touching: bool,
}

/// One contact between the hand and the object.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ContactRecord {
    /// Bone whose capsule touches.
    pub bone: String,
    /// Finger, `"palm"` for the root.
    pub finger: String,
    /// Contact point on the object's surface, world.
    pub point: [f64; 3],
    /// Unit normal pointing into the object (the direction the hand pushes).
    pub normal: [f64; 3],
    /// Gap between capsule and surface, metres (negative: it enters the object).
    pub gap: f64,
    /// Radius of the touching capsule (its soft pad's torsion scales with it), metres.
    pub radius: f64,
}

/// One joint degree of freedom.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct JointRecord {
    /// `bone.flexion`, `bone.abduction`, or `bone.x|y|z` for ball joints.
    pub name: String,
    /// Angle, radians.
    pub angle: f64,
}

/// A grasp found by the search, or the best attempt with the reason it is not valid.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GraspResult {
    /// Always [`RESULT_SCHEMA`].
    pub schema: &'static str,
    /// Hand name.
    pub hand: String,
    /// Object name.
    pub object: String,
    /// Movement name.
    pub movement: String,
    /// Whether this is a valid grasp (see `docs/RESULT_SCHEMA.md`).
    pub valid: bool,
    /// Why not, when not.
    pub invalid_reason: Option<String>,
    /// Planner status when the result was taken.
    pub status: PlannerStatus,
    /// The hook, world.
    pub hook: [f64; 3],
    /// The shoulder, world.
    pub shoulder: [f64; 3],
    /// Hook rotation `[x, y, z, w]`.
    pub hook_rotation_xyzw: [f64; 4],
    /// Back-off of the grasp center from the hook along the hook's −y, metres (= gDist).
    pub offset: f64,
    /// Quality; absent when −∞.
    pub quality: Option<f64>,
    /// Every quality term.
    pub terms: QualityTerms,
    /// Names of the fingers touching the object.
    pub fingers_touching: Vec<String>,
    /// Wrist (root bone) pose.
    pub wrist: PoseRecord,
    /// Every bone.
    pub bones: Vec<BoneRecord>,
    /// Every joint angle by name.
    pub joints: Vec<JointRecord>,
    /// Every capsule.
    pub capsules: Vec<CapsuleRecord>,
    /// The object's centre of mass, about which `stability` takes torques.
    pub center_of_mass: [f64; 3],
    /// Friction coefficient of the contact model.
    pub friction: f64,
    /// Every contact, with its normal.
    pub contacts: Vec<ContactRecord>,
    /// Force closure, ε and the load held along each axis, for these contacts (computed whatever
    /// the validity rule).
    pub stability: Stability,
    /// Half-angle, degrees, of the narrowest cone holding every contact normal: 90 when the
    /// contacts push from every side, less when they all push the object one way and friction
    /// alone keeps it in the hand.
    pub normal_cone_degrees: f64,
    /// Search statistics.
    pub stats: SearchStats,
}

impl GraspResult {
    /// The planner's best valid pose, or its current pose (marked invalid) if it has none.
    pub fn from_planner(planner: &GraspPlanner, ws: &mut Workspace) -> Self {
        let (chosen, ctx) = planner.chosen();
        let again = ctx.evaluate_pose(&chosen.rotation, ws);
        ctx.find_contacts(ws);
        Self::from_found_contacts(planner, ctx, again, ws)
    }

    /// Builds the result for evaluation `e` (from [`EvaluationContext::evaluate_pose`], its
    /// stability perhaps still to judge) in context `ctx`, whose pose is in `ws` with its
    /// contacts found ([`EvaluationContext::find_contacts`]): the contacts that judge the pose
    /// are those the result reports, found once. [`GraspPlanner::chosen`]'s pose, re-created
    /// (evaluation is deterministic), gives the planner's own result.
    pub(crate) fn from_found_contacts(
        planner: &GraspPlanner,
        ctx: &EvaluationContext,
        mut e: Evaluation,
        ws: &mut Workspace,
    ) -> Self {
        if ctx.stability_pending(&e) {
            ctx.judge_found_contacts(&mut e, ws);
        }
        let stability = ctx.stability_of_found_contacts(ws);
        let normal_cone_degrees =
            narrowest_normal_cap(ws.contacts.iter().map(|c| c.normal)).to_degrees();
        let hand = ctx.hand;
        let finger_name = |b: usize| {
            hand.bones()[b]
                .finger
                .map(|f| hand.fingers()[f].name.clone())
        };
        let q = e.rotation.quaternion();
        let capsules: Vec<CapsuleRecord> = ws
            .capsules
            .iter()
            .zip(hand.capsules())
            .map(|(c, model)| CapsuleRecord {
                bone: hand.bones()[model.bone].name.clone(),
                finger: finger_name(model.bone).unwrap_or_else(|| "palm".into()),
                a: c.a.into(),
                b: c.b.into(),
                radius: c.radius,
                touching: ctx.object.collider().exact().segment_within(
                    &c.a,
                    &c.b,
                    c.radius + CONTACT_TOLERANCE,
                ),
            })
            .collect();
        let mut fingers_touching: Vec<String> = Vec::new();
        for c in &capsules {
            if c.touching && c.finger != "palm" && !fingers_touching.contains(&c.finger) {
                fingers_touching.push(c.finger.clone());
            }
        }
        Self {
            schema: RESULT_SCHEMA,
            hand: hand.name().to_string(),
            object: ctx.object.name().to_string(),
            movement: ctx.movement.name().to_string(),
            valid: e.validity.is_ok(),
            invalid_reason: e.validity.as_ref().err().map(|r| r.to_string()),
            status: planner.status(),
            hook: ctx.hook.into(),
            shoulder: ctx.shoulder.into(),
            hook_rotation_xyzw: [q.i, q.j, q.k, q.w],
            offset: e.offset - ctx.hang_shift,
            quality: e.quality.is_finite().then_some(e.quality),
            terms: e.terms,
            fingers_touching,
            wrist: PoseRecord::from(&ws.world[0]),
            bones: hand
                .bones()
                .iter()
                .enumerate()
                .map(|(i, b)| BoneRecord {
                    name: b.name.clone(),
                    finger: finger_name(i),
                    pose: PoseRecord::from(&ws.world[i]),
                    reached: ws.reached[i],
                    fraction: ws.fraction[i],
                    stopped_by_contact: ws.touching[i],
                })
                .collect(),
            joints: joint_records(hand, &ws.rotations),
            capsules,
            center_of_mass: ctx.object.center_of_mass().into(),
            friction: ctx.contact_model.friction,
            contacts: ws
                .contacts
                .iter()
                .map(|c| ContactRecord {
                    bone: hand.bones()[c.bone].name.clone(),
                    finger: finger_name(c.bone).unwrap_or_else(|| "palm".into()),
                    point: c.point.into(),
                    normal: c.normal.into(),
                    gap: c.gap,
                    radius: c.radius,
                })
                .collect(),
            stability,
            normal_cone_degrees,
            stats: planner.stats(),
        }
    }
}

/// Joint angles recovered from each bone's joint rotation, under the hand's degree-of-freedom
/// names.
fn joint_records(hand: &crate::hand::HandModel, rotations: &[Rotation]) -> Vec<JointRecord> {
    let mut angles = vec![0.0; hand.dof_count()];
    for (bone, r) in hand.bones().iter().zip(rotations) {
        let n = bone.joint.dofs();
        bone.joint
            .angles(r, &mut angles[bone.first_dof..bone.first_dof + n]);
    }
    hand.dof_names()
        .iter()
        .zip(angles)
        .map(|(name, angle)| JointRecord {
            name: name.clone(),
            angle,
        })
        .collect()
}
