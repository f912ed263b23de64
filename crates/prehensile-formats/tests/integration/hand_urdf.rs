//! Hands from URDF: the oracle hand tree, and bad files.

use std::path::PathBuf;

use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::{GraspPlanner, GraspResult, SearchParams};
use prehensile_core::shapes::builtin_object;
use prehensile_core::{ObjectModel, Workspace};
use prehensile_formats::{load_hand, parse_hand_urdf};

fn urdf_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/hands/urdf/hand_tree_public.urdf")
}

#[test]
fn the_oracle_hand_tree_imports_with_its_joint_names() {
    let hand = load_hand(&urdf_path()).unwrap();
    assert_eq!(hand.bones().len(), 21);
    assert_eq!(hand.dof_count(), 20);
    let mut fingers: Vec<&str> = hand.fingers().iter().map(|f| f.name.as_str()).collect();
    fingers.sort();
    assert_eq!(fingers, ["index", "little", "middle", "ring", "thumb"]);
    assert!(hand.dof_names().iter().any(|d| d == "thumb_cmc_abduction"));
    assert!(hand.dof_names().iter().any(|d| d == "index_distal_flexion"));
    // Knuckles are zero-length links: no capsule. Phalanges get one each, the palm one per finger.
    let knuckle = hand.bone_index("index_knuckle").unwrap();
    assert!(hand.bone_capsules(knuckle).is_empty());
    let proximal = hand.bone_index("index_proximal").unwrap();
    let c = hand.bone_capsules(proximal)[0];
    assert!(((c.b - c.a).norm() - 0.0451539).abs() < 1e-9);
    // Radius from mass at the density of water: sqrt(0.0126392857 / (1000 π 0.0451539)).
    assert!(
        (c.radius - (0.0126392857f64 / (1000.0 * std::f64::consts::PI * 0.0451539)).sqrt()).abs()
            < 1e-12
    );
    assert_eq!(hand.bone_capsules(0).len(), 5);
    // Inertials as the file gives them, in the link frame.
    let palm = hand.bones()[0].inertial.unwrap();
    assert_eq!(palm.mass, 0.35);
    assert_eq!(palm.center_of_mass, Point3::new(0.0, 0.0, 0.045));
    assert_eq!(palm.inertia[(0, 0)], 3.2e-4);
    assert_eq!(palm.inertia[(2, 2)], 1.1e-4);
    let mass: f64 = hand
        .bones()
        .iter()
        .filter_map(|b| b.inertial)
        .map(|i| i.mass)
        .sum();
    assert!(mass > 0.35 && mass < 0.6, "{mass}");
}

#[test]
fn the_oracle_hand_closes_toward_its_palm_and_grasps_a_box() {
    let hand = load_hand(&urdf_path()).unwrap();
    // In our hand frame the fingers run along +z and curl toward +y.
    let close = hand.movement("close").unwrap();
    let tips = |f: f64| {
        let r: Vec<_> = (0..hand.bones().len())
            .map(|b| close.rotation_at(b, f))
            .collect();
        let w = hand.pose_transforms(&prehensile_core::math::Transform::identity(), &r);
        let i = hand.finger_index("middle").unwrap();
        let finger = &hand.fingers()[i];
        w[*finger.bones.last().unwrap()] * finger.tip
    };
    // Half-way through `close` (3 × 46°) the middle fingertip has moved toward the palm, +y.
    let (open, half) = (tips(0.0), tips(0.5));
    assert!(open.z > 0.1, "{open:?}");
    assert!(half.y - open.y > 0.03, "{open:?} -> {half:?}");
    // Abduction hinges stay open in `close`; flexion hinges move.
    let dof = |name: &str| hand.dof_names().iter().position(|d| d == name).unwrap();
    assert_eq!(close.end_angles()[dof("middle_abduction")], 0.0);
    assert_eq!(close.end_angles()[dof("middle_proximal_flexion")], 1.6);
    let object = ObjectModel::new("box", builtin_object("box").unwrap(), None).unwrap();
    // A box: the grasp `close` found on a 3.2 cm sphere had every contact normal within 66° of
    // one direction, no longer a valid grasp (docs/QUALITY.md).
    let mut planner = GraspPlanner::new(
        &hand,
        &object,
        close,
        Point3::new(-0.3, -0.2, 0.3),
        SearchParams::default(),
    )
    .unwrap();
    planner.run_to_end();
    let result = GraspResult::from_planner(&planner, &mut Workspace::new(&hand));
    assert!(result.valid, "{:?}", result.invalid_reason);
    assert!(result
        .joints
        .iter()
        .any(|j| j.name == "index_proximal_flexion"));
    let _ = Vec3::zeros();
}

#[test]
fn bad_urdf_is_named() {
    let text = std::fs::read_to_string(urdf_path()).unwrap();
    let e = parse_hand_urdf(
        &text.replace(
            "type=\"revolute\"><parent link=\"palm\"/><child link=\"index_knuckle\"/>",
            "type=\"prismatic\"><parent link=\"palm\"/><child link=\"index_knuckle\"/>",
        ),
        "h.urdf",
    )
    .unwrap_err();
    assert!(
        e.reason.contains("prismatic") && e.reason.contains("index_abduction"),
        "{e}"
    );
    assert!(
        e.location
            .as_deref()
            .is_some_and(|l| l.starts_with("line ")),
        "{e}"
    );
    let e = parse_hand_urdf(
        &text.replace("<mass value=\"0.35\"/>", "<mass value=\"abc\"/>"),
        "h.urdf",
    )
    .unwrap_err();
    assert!(e.reason.contains("abc"), "{e}");
    let e = parse_hand_urdf("<robot><link name=\"a\"/>", "h.urdf").unwrap_err();
    assert!(e.location.is_some(), "{e}");
    let e = parse_hand_urdf(
        &text.replace(
            "<parent link=\"index_middle\"/>",
            "<parent link=\"nowhere\"/>",
        ),
        "h.urdf",
    )
    .unwrap_err();
    assert!(e.reason.contains("not defined"), "{e}");
}

#[test]
fn a_sidecar_overrides_fingers_tips_and_close() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-sidecar-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("claw.urdf");
    std::fs::copy(urdf_path(), &urdf).unwrap();
    std::fs::write(
        dir.join("claw.prehensile.toml"),
        "[fingers]\nthumb_cmc_link = \"opposer\"\n[tips]\nindex_distal = [0.0, 0.0, 0.03]\n[close]\nindex_proximal_flexion = 1.0\nmiddle_proximal_flexion = 1.2\n",
    )
    .unwrap();
    let hand = load_hand(&urdf).unwrap();
    assert!(hand.finger_index("opposer").is_some() && hand.finger_index("thumb").is_none());
    let index = &hand.fingers()[hand.finger_index("index").unwrap()];
    assert!((index.tip.z - 0.03).abs() < 1e-12);
    let close = hand.movement("close").unwrap();
    let dof = |n: &str| hand.dof_names().iter().position(|d| d == n).unwrap();
    assert_eq!(close.end_angles()[dof("index_proximal_flexion")], 1.0);
    assert_eq!(
        close.end_angles()[dof("ring_proximal_flexion")],
        0.0,
        "only the sidecar's targets"
    );
    std::fs::write(
        dir.join("claw.prehensile.toml"),
        "[tips]\nnobody = [0.0, 0.0, 0.1]\n",
    )
    .unwrap();
    let e = load_hand(&urdf).unwrap_err();
    assert!(e.reason.contains("nobody"), "{e}");
    std::fs::write(dir.join("claw.prehensile.toml"), "[tipz]\n").unwrap();
    assert!(load_hand(&urdf)
        .unwrap_err()
        .source_name
        .ends_with("claw.prehensile.toml"));
}

#[test]
fn a_sidecar_changes_a_derived_movement_and_adds_one() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-movements-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("claw.urdf");
    std::fs::copy(urdf_path(), &urdf).unwrap();
    let derived = load_hand(&urdf).unwrap();
    let dof = |n: &str| derived.dof_names().iter().position(|d| d == n).unwrap();
    let power = derived.movement("power").unwrap();
    let sidecar = dir.join("claw.prehensile.toml");
    std::fs::write(
        &sidecar,
        "[movements.power]\nend = { index_proximal_flexion = 0.5 }\n\
         [movements.hook]\nend = { index_proximal_flexion = 1.0, middle_proximal_flexion = 1.1 }\n\
         grasp_center = [0.0, 0.03, 0.1]\ncontact_fingers = [\"index\", \"middle\"]\n",
    )
    .unwrap();
    let hand = load_hand(&urdf).unwrap();
    // power: the named joint changed, every other joint and the centre as derived.
    let changed = hand.movement("power").unwrap();
    assert_eq!(changed.end_angles()[dof("index_proximal_flexion")], 0.5);
    assert_ne!(power.end_angles()[dof("index_proximal_flexion")], 0.5);
    for k in (0..hand.dof_count()).filter(|&k| k != dof("index_proximal_flexion")) {
        assert_eq!(changed.end_angles()[k], power.end_angles()[k], "joint {k}");
    }
    assert_eq!(changed.grasp_center(), power.grasp_center());
    // The derived thumb's swing out of the palm (the via pose) is kept; the index, whose end
    // changed, goes straight to it.
    let (fraction, detour) = power
        .via_detour()
        .expect("the derived power has a via pose");
    assert_eq!(changed.via_detour(), Some((fraction, detour.clone())));
    assert!(detour.iter().any(Option::is_some));
    assert_eq!(detour[dof("index_proximal_flexion")], None);
    // hook: a new movement from the open pose.
    let hook = hand.movement("hook").unwrap();
    assert_eq!(hook.end_angles()[dof("middle_proximal_flexion")], 1.1);
    assert_eq!(hook.end_angles()[dof("ring_proximal_flexion")], 0.0);
    assert_eq!(hook.grasp_center().y, 0.03);
    let names: Vec<&str> = hook
        .contact_fingers()
        .iter()
        .map(|&f| hand.fingers()[f].name.as_str())
        .collect();
    assert_eq!(names, ["index", "middle"]);
    // Mistakes are named.
    for (text, expected) in [
        ("[movements.power]\nend = { nojoint = 0.5 }\n", "nojoint"),
        (
            "[movements.power]\nend = { index_proximal_flexion = 2.5 }\n",
            "outside its limits",
        ),
        (
            "[movements.new]\nend = { index_proximal_flexion = 1.0 }\n",
            "without a grasp_center",
        ),
        (
            "[movements.power]\ncontact_fingers = [\"sixth\"]\n",
            "sixth",
        ),
        ("[movements.power]\nends = {}\n", "ends"),
    ] {
        std::fs::write(&sidecar, text).unwrap();
        let e = load_hand(&urdf).unwrap_err().to_string();
        assert!(e.contains(expected), "{text}: {e}");
    }
}

#[test]
fn a_sidecar_frame_replaces_the_derived_one() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-frame-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("claw.urdf");
    std::fs::copy(urdf_path(), &urdf).unwrap();
    let axes = |hand: &prehensile_core::HandModel| {
        let to_root = hand.bones()[0].rest.rotation.inverse();
        (to_root * Vec3::z(), to_root * Vec3::y())
    };
    let (z, y) = axes(&load_hand(&urdf).unwrap());
    let sidecar = dir.join("claw.prehensile.toml");
    let write = |along: Vec3, normal: Vec3| {
        let f = |v: Vec3| format!("[{}, {}, {}]", v.x, v.y, v.z);
        std::fs::write(
            &sidecar,
            format!(
                "[frame]\nfingers_along = {}\npalm_normal = {}\n",
                f(along),
                f(normal)
            ),
        )
        .unwrap();
    };
    // The frame given turned 20° about the fingers, its normal not yet square to them.
    let turned = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(z), 0.35) * y;
    write(z * 2.0, turned + z * 0.3);
    let (z2, y2) = axes(&load_hand(&urdf).unwrap());
    assert!((z2 - z).norm() < 1e-9, "{z2} vs {z}");
    assert!((y2 - turned).norm() < 1e-9, "{y2} vs {turned}");
    for (along, normal, expected) in [
        (Vec3::zeros(), y, "fingers_along"),
        (z, z * 3.0, "palm_normal"),
    ] {
        write(along, normal);
        let e = load_hand(&urdf).unwrap_err().to_string();
        assert!(e.contains(expected) && e.contains("[frame]"), "{e}");
    }
}
