//! Gravity torques and the joint-space mass matrix of the Shadow hand, read from its MJCF through
//! the formats crate, against MuJoCo 4.0 to 1e-9 relative.
//!
//! The oracle covers all 24 hinges of the file; our import roots the hand at the palm and leaves
//! the two wrist joints above it out, so the 22 finger joints are compared. Their block of the
//! mass matrix does not depend on the wrist; their gravity torques do, through the palm's
//! orientation, which the test builds from the file's mount and wrist frames.

use prehensile_control::{gravity_torques, mass_matrix};
use prehensile_core::math::Vec3;

#[derive(serde::Deserialize)]
struct Sample {
    qpos: Vec<f64>,
    gravity_torques: Vec<f64>,
    mass_matrix_without_armature: Vec<Vec<f64>>,
}

#[derive(serde::Deserialize)]
struct Oracle {
    joint_names: Vec<String>,
    gravity: [f64; 3],
    samples: Vec<Sample>,
}

/// The palm's orientation in the world for wrist angles `wrj1` and `wrj0`, from `robot.xml`:
/// the hand mount's `euler="1.5708 0 3.14159"` (MuJoCo's default intrinsic x-y-z sequence),
/// then WRJ1 about the wrist's y axis and WRJ0 about the palm's x axis (no other body rotations).
#[allow(clippy::approx_constant, reason = "the file's numbers, not π/2 and π")]
fn palm_orientation(wrj1: f64, wrj0: f64) -> nalgebra::Rotation3<f64> {
    let about = |axis: Vec3, angle: f64| {
        nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
    };
    let mount = about(Vec3::x(), 1.5708) * about(Vec3::y(), 0.0) * about(Vec3::z(), 3.14159);
    mount * about(Vec3::y(), wrj1) * about(Vec3::x(), wrj0)
}

fn close(ours: f64, theirs: f64, scale: f64) -> bool {
    (ours - theirs).abs() <= 1e-9 * scale.max(1e-12)
}

#[test]
fn shadow_hand_dynamics_match_mujoco() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let oracle: Oracle = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tests/data/shadow_hand_mujoco_public.json")).unwrap(),
    )
    .unwrap();
    let hand = prehensile_formats::load_hand(&dir.join("../../assets/hands/shadow_hand/reach.xml"))
        .unwrap();
    let (wrj1, wrj0) = (
        oracle
            .joint_names
            .iter()
            .position(|n| n == "robot0:WRJ1")
            .unwrap(),
        oracle
            .joint_names
            .iter()
            .position(|n| n == "robot0:WRJ0")
            .unwrap(),
    );
    // For each of our degrees of freedom, its column in the oracle.
    let theirs: Vec<usize> = hand
        .dof_names()
        .iter()
        .map(|d| oracle.joint_names.iter().position(|n| n == d).unwrap())
        .collect();
    assert_eq!(theirs.len(), 22);
    assert_eq!(oracle.samples.len(), 10);
    for (s, sample) in oracle.samples.iter().enumerate() {
        let q: Vec<f64> = theirs.iter().map(|&k| sample.qpos[k]).collect();
        let palm = palm_orientation(sample.qpos[wrj1], sample.qpos[wrj0]);
        let gravity_in_palm = palm.inverse() * Vec3::from(oracle.gravity);

        let gravity = gravity_torques(&hand, &q, gravity_in_palm).unwrap();
        let scale = theirs
            .iter()
            .fold(0.0f64, |m, &k| m.max(sample.gravity_torques[k].abs()));
        for (i, &k) in theirs.iter().enumerate() {
            assert!(
                close(gravity[i], sample.gravity_torques[k], scale),
                "sample {s} gravity {}: {} vs {}",
                oracle.joint_names[k],
                gravity[i],
                sample.gravity_torques[k]
            );
        }

        let m = mass_matrix(&hand, &q).unwrap();
        let full = &sample.mass_matrix_without_armature;
        let scale = theirs
            .iter()
            .flat_map(|&r| theirs.iter().map(move |&c| full[r][c].abs()))
            .fold(0.0f64, f64::max);
        for (i, &r) in theirs.iter().enumerate() {
            for (j, &c) in theirs.iter().enumerate() {
                assert!(
                    close(m[(i, j)], full[r][c], scale),
                    "sample {s} M[{}][{}]: {} vs {}",
                    oracle.joint_names[r],
                    oracle.joint_names[c],
                    m[(i, j)],
                    full[r][c]
                );
            }
        }
    }
}
