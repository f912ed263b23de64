//! Hands from MJCF: the Shadow hand, and bad files.

use std::path::PathBuf;

use prehensile_core::math::Vec3;
use prehensile_core::search::{GraspPlanner, GraspResult, SearchParams, ValidityRule};
use prehensile_core::shapes::builtin_object;
use prehensile_core::{ObjectModel, Workspace};
use prehensile_formats::{load_hand, load_object, parse_hand_mjcf};

fn assets(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(path)
}

fn shadow(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/hands/shadow_hand")
        .join(file)
}

/// The Shadow hand's `shared.xml` defaults block.
fn shadow_defaults() -> String {
    let shared = std::fs::read_to_string(shadow("shared.xml")).unwrap();
    shared[shared.find("<default>").unwrap()..shared.rfind("</default>").unwrap() + 10].to_string()
}

/// `robot.xml` with `defaults` in front of it, as `reach.xml` includes them.
fn robot_with(defaults: &str) -> String {
    let robot = std::fs::read_to_string(shadow("robot.xml")).unwrap();
    robot.replacen(
        "<mujoco>",
        &format!("<mujoco><compiler angle=\"radian\"/>{defaults}"),
        1,
    )
}

#[test]
fn the_shadow_hand_imports_from_its_scene_with_joint_names_and_tendons() {
    let hand = load_hand(&shadow("reach.xml")).unwrap();
    // Palm + index/middle/ring (knuckle, proximal, middle, distal) + little (metacarpal + 4)
    // + thumb (base, proximal, hub, middle, distal) = 1 + 12 + 5 + 5.
    assert_eq!(hand.bones().len(), 23);
    assert_eq!(
        hand.dof_count(),
        22,
        "24 hinges less the two wrist joints above the palm"
    );
    let mut fingers: Vec<&str> = hand.fingers().iter().map(|f| f.name.as_str()).collect();
    fingers.sort();
    assert_eq!(fingers, ["index", "little", "middle", "ring", "thumb"]);
    // A right hand, named after its file (the MJCF names no model), with the derived movements.
    assert!(!hand.is_left());
    assert_eq!(hand.name(), "reach");
    for m in ["close", "power", "precision"] {
        assert!(hand.movement(m).is_some(), "{m}");
    }
    // The derived precision pinches with thumb and index and turns the thumb's base (THJ4).
    let precision = hand.movement("precision").unwrap();
    let thj4 = hand
        .dof_names()
        .iter()
        .position(|n| n == "robot0:THJ4")
        .unwrap();
    assert!(precision.end_angles()[thj4].abs() > 0.3);
    let contact: Vec<&str> = precision
        .contact_fingers()
        .iter()
        .map(|&f| hand.fingers()[f].name.as_str())
        .collect();
    assert_eq!(contact, ["thumb", "index"]);
    assert!(hand.dof_names().iter().any(|d| d == "robot0:FFJ3"));
    assert!(!hand.dof_names().iter().any(|d| d.starts_with("robot0:WRJ")));
    assert!(
        hand.description().contains("robot0:wrist"),
        "{}",
        hand.description()
    );
    assert!(
        hand.description().contains("robot0:WRJ0"),
        "{}",
        hand.description()
    );
    // Collision capsules from the file: the index proximal's is radius 1 cm, 4.5 cm long.
    let proximal = hand.bone_index("robot0:ffproximal").unwrap();
    let c = hand.bone_capsules(proximal)[0];
    assert!((c.radius - 0.01).abs() < 1e-12 && ((c.b - c.a).norm() - 0.045).abs() < 1e-9);
    let inertial = hand.bones()[proximal].inertial.unwrap();
    assert_eq!(inertial.mass, 0.014);
    assert!((inertial.center_of_mass.z - 0.023).abs() < 1e-12);
    assert!((inertial.inertia.trace() - 3e-5).abs() < 1e-15);
    // The distal tendons couple J0 to J1 in each of the four fingers.
    assert_eq!(hand.couplings().len(), 4);
    let ff0 = hand
        .dof_names()
        .iter()
        .position(|d| d == "robot0:FFJ0")
        .unwrap();
    let ff1 = hand
        .dof_names()
        .iter()
        .position(|d| d == "robot0:FFJ1")
        .unwrap();
    let coupling = hand.couplings().iter().find(|c| c.follower == ff0).unwrap();
    assert_eq!(coupling.leader, ff1);
    assert!((coupling.ratio - 0.00805 / 0.00705).abs() < 1e-12);
}

#[test]
fn the_shadow_hand_grasps_a_cylinder() {
    // Its derived power movement: the generic `close` (the thumb barely turning) found a grasp
    // with every contact normal within 77° of one direction, no longer valid.
    let object = ObjectModel::new("cylinder", builtin_object("cylinder").unwrap(), None).unwrap();
    let result = shadow_power(&object, ValidityRule::Holds, 1);
    assert!(result.valid, "{:?}", result.invalid_reason);
    assert!(result.joints.iter().any(|j| j.name == "robot0:FFJ2"));
}

/// The Shadow hand's power grasp of `object` under `validity` from the CLI's default shoulder.
fn shadow_power(object: &ObjectModel, validity: ValidityRule, seed: u64) -> GraspResult {
    let hand = load_hand(&shadow("reach.xml")).unwrap();
    let params = SearchParams {
        validity,
        seed,
        ..SearchParams::default()
    };
    let shoulder = object.center_of_mass() + Vec3::new(-0.35, -0.2, 0.35);
    let mut planner = GraspPlanner::new(
        &hand,
        object,
        hand.movement("power").unwrap(),
        shoulder,
        params,
    )
    .unwrap();
    planner.run_to_end();
    GraspResult::from_planner(&planner, &mut Workspace::new(&hand))
}

#[test]
fn the_shadow_hands_sphere_grasp_wraps_past_the_equator() {
    // Its derived power thumb swings out of the palm and comes down the ball's near side. Aimed
    // at the grasp center it folded under the knuckles, met the 8 cm sphere at its equator, and every
    // grasp had all its normals within 69–73° of one direction, refused by `strict` on every
    // seed. Now the normals share no open half-space, at the default friction, under `strict`
    // and under the default rule, which prefers such grasps (a rule taking the first valid wrap
    // returned one with the normals within 78–90° of one direction).
    let object = ObjectModel::new("sphere", builtin_object("sphere").unwrap(), None).unwrap();
    for validity in [ValidityRule::Strict, ValidityRule::Holds] {
        let result = shadow_power(&object, validity, 1);
        assert_wraps_past_the_equator(&result);
    }
}

#[test]
fn the_shadow_hands_power_thumb_comes_onto_an_object_narrower_than_the_hand() {
    // Aimed only far out of the palm, the thumb passed beside the 4.5 cm lemon:
    // seeds 2 and 4 found grasps of the four fingers alone. It now swings out half-way through
    // the closing (the movement's via pose) and folds in toward the grasp center after.
    let hand = load_hand(&shadow("reach.xml")).unwrap();
    let power = hand.movement("power").unwrap();
    let via = power
        .via()
        .expect("the derived power movement has a via pose");
    assert_eq!(via.fraction(), 0.5);
    // Only the thumb leaves the straight way from start to end.
    let mut off_the_straight_way = 0;
    for bone in hand.bones() {
        for k in bone.first_dof..bone.first_dof + bone.joint.dofs() {
            let straight = 0.5 * (power.start_angles()[k] + power.end_angles()[k]);
            if (via.angles()[k] - straight).abs() > 1e-9 {
                let finger = bone.finger.map(|f| hand.fingers()[f].name.as_str());
                assert_eq!(finger, Some("thumb"), "{} turns off its way", bone.name);
                off_the_straight_way += 1;
            }
        }
    }
    assert!(off_the_straight_way >= 2);
    let lemon = load_object(&assets("objects/robosuite_lemon.stl"), 1.0).unwrap();
    for seed in [2, 4] {
        let result = shadow_power(&lemon, ValidityRule::Holds, seed);
        assert!(result.valid, "seed {seed}: {:?}", result.invalid_reason);
        assert!(
            result.fingers_touching.iter().any(|f| f == "thumb"),
            "seed {seed}: {:?}",
            result.fingers_touching
        );
    }
}

/// A power grasp whose contact normals share no open half-space, the thumb against the fingers.
fn assert_wraps_past_the_equator(result: &GraspResult) {
    assert!(result.valid, "{:?}", result.invalid_reason);
    assert!(result.fingers_touching.iter().any(|f| f == "thumb"));
    // Independently of the rule's own test: over a dense set of directions, every one has a
    // normal at least 90° from it, i.e. no direction sees every normal in front of it.
    let normals: Vec<Vec3> = result
        .contacts
        .iter()
        .map(|c| Vec3::from(c.normal))
        .collect();
    let cap = (0..20_000)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / 20_000.0;
            let phi = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let r = (1.0 - z * z).sqrt();
            let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            normals
                .iter()
                .map(|n| n.dot(&d).clamp(-1.0, 1.0).acos())
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
        .to_degrees();
    assert!(cap >= 90.0, "cone {cap}°");
    // The thumb opposes the fingers: its push and theirs (mean normal) point apart.
    let mean = |finger: &str| {
        result
            .contacts
            .iter()
            .filter(|c| (c.finger == "thumb") == (finger == "thumb") && c.finger != "palm")
            .fold(Vec3::zeros(), |s, c| s + Vec3::from(c.normal))
            .normalize()
    };
    let opposition = mean("thumb").dot(&mean("fingers")).acos().to_degrees();
    assert!(
        opposition > 90.0,
        "thumb against the fingers: {opposition}°"
    );
}

#[test]
fn robot_xml_alone_asks_for_its_defaults() {
    let e = load_hand(&shadow("robot.xml")).unwrap_err();
    assert!(
        e.reason.contains("robot0:asset_class") && e.reason.contains("reach.xml"),
        "{e}"
    );
}

#[test]
fn bad_mjcf_is_named() {
    // robot.xml with the defaults of shared.xml in front of it, as reach.xml includes them.
    let text = robot_with(&shadow_defaults());
    assert!(parse_hand_mjcf(&text, "robot.xml").is_ok());
    let slide = text.replace(
        "name=\"robot0:FFJ2\" type=\"hinge\"",
        "name=\"robot0:FFJ2\" type=\"slide\"",
    );
    let e = parse_hand_mjcf(&slide, "robot.xml").unwrap_err();
    assert!(
        e.reason.contains("slide") && e.reason.contains("robot0:FFJ2"),
        "{e}"
    );
    assert!(
        e.location.as_deref().is_some_and(|l| l.contains("line")),
        "{e}"
    );
    let e = parse_hand_mjcf(
        &text.replace("pos=\"0 0 0.045\"", "pos=\"0 0 nan\""),
        "robot.xml",
    )
    .unwrap_err();
    assert!(e.reason.contains("not a list of finite numbers"), "{e}");
    assert!(parse_hand_mjcf("<mujoco>", "x.xml").is_err());
    assert!(parse_hand_mjcf("<mujoco></mujoco>", "x.xml")
        .unwrap_err()
        .reason
        .contains("no <body>"));
}

#[test]
fn a_ball_joint_becomes_three_named_degrees_of_freedom() {
    let text = robot_with(&shadow_defaults()).replace(
        "name=\"robot0:THJ4\" type=\"hinge\" pos=\"0 0 0\" axis=\"0 0 -1\" range=\"-1.047 1.047\"",
        "name=\"robot0:THJ4\" type=\"ball\" range=\"0 0.8\"",
    );
    let hand = parse_hand_mjcf(&text, "ball.xml").unwrap();
    assert!(hand.dof_names().iter().any(|d| d == "robot0:THJ4.y"));
    let base = hand.bone_index("robot0:thbase").unwrap();
    assert_eq!(hand.bones()[base].joint.limits(2), [-0.8, 0.8]);
}

#[test]
fn the_shadow_hands_derived_movements_keep_side_by_side_fingers_apart() {
    use prehensile_core::geometry::distance_squared_segment_segment;
    use prehensile_core::math::{Rotation, Transform};
    let hand = load_hand(&shadow("reach.xml")).unwrap();
    // Deepest overlap between capsules of two different non-thumb fingers, in metres.
    let deepest_overlap = |angles: &[f64]| {
        let mut rotations = vec![Rotation::identity(); hand.bones().len()];
        hand.joint_rotations(angles, &mut rotations);
        let world = hand.pose_transforms(&Transform::identity(), &rotations);
        let placed: Vec<_> = hand
            .capsules()
            .iter()
            .filter_map(|c| {
                let finger = hand
                    .fingers()
                    .iter()
                    .position(|f| f.bones.contains(&c.bone))?;
                (hand.fingers()[finger].name != "thumb")
                    .then(|| (finger, world[c.bone] * c.a, world[c.bone] * c.b, c.radius))
            })
            .collect();
        let mut deepest = 0.0f64;
        for (i, (f1, a1, b1, r1)) in placed.iter().enumerate() {
            for (f2, a2, b2, r2) in &placed[i + 1..] {
                if f1 != f2 {
                    let d = distance_squared_segment_segment(a1, b1, a2, b2).sqrt();
                    deepest = deepest.max(r1 + r2 - d);
                }
            }
        }
        deepest
    };
    let rest = deepest_overlap(&vec![0.0; hand.dof_count()]);
    // MuJoCo collides the Shadow hand's fingers with each other: a derived pose that sinks the
    // ring finger into the little finger pushes both, and the object, aside.
    for m in ["power", "precision"] {
        let end = hand.movement(m).unwrap().end_angles();
        let overlap = deepest_overlap(end);
        assert!(
            overlap <= rest + 1e-3,
            "{m}: fingers overlap {:.1} mm (at rest {:.1} mm)",
            overlap * 1e3,
            rest * 1e3
        );
    }
}

#[test]
fn default_classes_that_would_inherit_from_themselves_are_refused() {
    // Found by `cargo fuzz run hand_mjcf` (10 min): a nested <default> without a class was
    // "main" again, its own parent, and attribute lookup looped forever.
    let defaults = shadow_defaults();
    let unnamed = defaults.replacen("<default class=\"robot0:D_Touch\">", "<default>", 1);
    let e = parse_hand_mjcf(&robot_with(&unnamed), "robot.xml").unwrap_err();
    assert!(e.reason.contains("needs a class attribute"), "{e}");
    assert!(e.location.is_some(), "{e}");
    let twice = defaults.replacen(
        "<default class=\"robot0:D_Touch\">",
        "<default class=\"robot0:asset_class\">",
        1,
    );
    let e = parse_hand_mjcf(&robot_with(&twice), "robot.xml").unwrap_err();
    assert!(e.reason.contains("defined twice"), "{e}");
}

#[test]
fn closing_keeps_the_shadow_hands_tendon_couplings() {
    // The Shadow hand's fixed tendons tie each finger's distal joint (J1) to its middle one (J2).
    // Closing used to let the distal bone go on after the middle one touched, breaking the
    // coupling the real hand (and MuJoCo) enforces.
    let hand = load_hand(&shadow("reach.xml")).unwrap();
    assert!(!hand.couplings().is_empty());
    let limits = hand.dof_limits();
    let mut checked = 0;
    for object in ["sphere", "box", "cylinder", "mug"] {
        let object = ObjectModel::new(object, builtin_object(object).unwrap(), None).unwrap();
        for movement in ["power", "precision"] {
            for seed in [1, 2] {
                let params = SearchParams {
                    seed,
                    ..SearchParams::default()
                };
                let m = hand.movement(movement).unwrap();
                let shoulder = object.center_of_mass() + Vec3::new(-0.35, -0.2, 0.35);
                let mut planner = GraspPlanner::new(&hand, &object, m, shoulder, params).unwrap();
                planner.run_to_end();
                let result = GraspResult::from_planner(&planner, &mut Workspace::new(&hand));
                let angles: Vec<f64> = result.joints.iter().map(|j| j.angle).collect();
                for c in hand.couplings() {
                    let wanted = (c.ratio * angles[c.leader])
                        .clamp(limits[c.follower][0], limits[c.follower][1]);
                    assert!(
                        (angles[c.follower] - wanted).abs() < 1e-6,
                        "{} on {}, seed {seed}: {} = {:.4} but {} × {} = {:.4}",
                        movement,
                        object.name(),
                        result.joints[c.follower].name,
                        angles[c.follower],
                        c.ratio,
                        result.joints[c.leader].name,
                        wanted
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 0);
}

#[test]
fn an_mjcf_hand_and_its_includes_from_memory_equal_the_files_on_disk() {
    // Files dropped on a web page come by name only, without their folder.
    let files: Vec<(String, Vec<u8>)> =
        ["reach.xml", "shared.xml", "shared_asset.xml", "robot.xml"]
            .iter()
            .map(|n| (n.to_string(), std::fs::read(shadow(n)).unwrap()))
            .collect();
    let from_memory = prehensile_formats::parse_hand_mjcf_files("reach.xml", &files).unwrap();
    let from_disk = load_hand(&shadow("reach.xml")).unwrap();
    assert_eq!(from_memory.dof_names(), from_disk.dof_names());
    assert_eq!(from_memory.capsules(), from_disk.capsules());
    // An include not given is named, with what was given.
    let e = prehensile_formats::parse_hand_mjcf_files("reach.xml", &files[..2]).unwrap_err();
    assert!(
        e.to_string().contains("shared_asset.xml") && e.reason.contains("not given"),
        "{e}"
    );
    // What an attacker would drop: a cycle, a path out of the folder, a fan-out.
    let file = |name: &str, text: String| (name.to_string(), text.into_bytes());
    let cycle = [
        file(
            "a.xml",
            r#"<mujoco><include file="b.xml"/></mujoco>"#.into(),
        ),
        file(
            "b.xml",
            r#"<mujoco><include file="a.xml"/></mujoco>"#.into(),
        ),
    ];
    let e = prehensile_formats::parse_hand_mjcf_files("a.xml", &cycle).unwrap_err();
    assert!(e.reason.contains("cycle"), "{e}");
    let escape = [file(
        "a.xml",
        r#"<mujoco><include file="../../etc/passwd"/></mujoco>"#.into(),
    )];
    let e = prehensile_formats::parse_hand_mjcf_files("a.xml", &escape).unwrap_err();
    assert!(
        e.to_string().contains("passwd") && e.reason.contains("not given"),
        "{e}"
    );
    let fan = format!(
        "<mujoco>{}</mujoco>",
        r#"<include file="b.xml"/>"#.repeat(300)
    );
    let fan_out = [file("a.xml", fan), file("b.xml", "<mujoco/>".into())];
    let e = prehensile_formats::parse_hand_mjcf_files("a.xml", &fan_out).unwrap_err();
    assert!(e.reason.contains("included files in all"), "{e}");
}
