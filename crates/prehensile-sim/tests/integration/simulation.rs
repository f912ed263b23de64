//! The simulated hand: passive settling, joint-limit springs, divergence detection, bad input.

use prehensile_control::Setpoint;
use prehensile_core::math::{Transform, Vec3};
use prehensile_sim::scenarios::{self, Options, PlannedGrasp, Scenario};
use prehensile_sim::{
    ArmTrajectory, DistanceTo, Divergence, Engine, HandSetup, RapierSettings, ReducedSettings,
    Settings, SimError, Simulation, Waypoint,
};

fn human() -> prehensile_core::HandModel {
    prehensile_formats::builtin_hand("human").unwrap()
}

fn passive_setup(hand: &prehensile_core::HandModel, gravity: Vec3) -> (HandSetup, Vec<f64>) {
    let poses = PlannedGrasp::without_object(hand).unwrap();
    let mut controller = poses.controller(hand, &gravity).unwrap();
    controller.active = false;
    let neutral = controller.setpoints.neutral.clone();
    (
        HandSetup {
            hand: hand.clone(),
            controller,
            arm: ArmTrajectory::new(vec![Waypoint {
                time: 0.0,
                root: Transform::identity(),
            }]),
            start: poses.open.clone(),
            distance: DistanceTo::Constant(1.0),
            release_at: None,
            compensate_gravity: false,
            compensate_arm: false,
            manual: Vec::new(),
        },
        neutral,
    )
}

#[test]
fn without_gravity_the_passive_hand_settles_at_its_neutral_pose() {
    let hand = human();
    let settings = Settings {
        gravity: Vec3::zeros(),
        ..Settings::default()
    };
    let (setup, neutral) = passive_setup(&hand, settings.gravity);
    let start_error = setup
        .start
        .iter()
        .zip(&neutral)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let mut sim = Simulation::new(settings).unwrap();
    sim.add_hand(setup).unwrap();
    for _ in 0..2000 {
        sim.step().unwrap();
    }
    let error = sim
        .joint_angles(0)
        .iter()
        .zip(&neutral)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(start_error > 0.3, "the test must start away from neutral");
    assert!(error < 0.02, "{error} rad from neutral after 2 s");
}

#[test]
fn compensated_gravity_leaves_a_tilted_hand_where_it_is() {
    let hand = human();
    let settings = Settings::default();
    let sag = |compensate: bool| {
        let (mut setup, _) = passive_setup(&hand, settings.gravity);
        // Hold the planned closed pose, palm turned so gravity bends every finger sideways.
        let poses = PlannedGrasp::without_object(&hand).unwrap();
        setup.controller.setpoints.neutral = poses.closed.clone();
        setup.start = poses.closed.clone();
        setup.compensate_gravity = compensate;
        setup.arm = ArmTrajectory::new(vec![Waypoint {
            time: 0.0,
            root: Transform::from_parts(
                Vec3::zeros().into(),
                prehensile_core::math::Rotation::from_euler_angles(1.57, 0.3, 0.0),
            ),
        }]);
        let mut sim = Simulation::new(settings).unwrap();
        sim.add_hand(setup).unwrap();
        for _ in 0..1000 {
            sim.step().unwrap();
        }
        sim.joint_angles(0)
            .iter()
            .zip(&poses.closed)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (without, with) = (sag(false), sag(true));
    assert!(
        without > 0.2,
        "gravity must bend the weak fingers: {without} rad"
    );
    assert!(with < 0.02, "compensated, the hand still sagged {with} rad");
}

#[test]
fn joint_limit_springs_keep_the_dropped_fingers_near_their_range() {
    let options = Options {
        hand: human(),
        objects: Vec::new(),
        alpha: 0.0,
        settings: Settings::default(),
        seconds: Some(1.0),
        candidates: scenarios::CANDIDATES,
    };
    let (report, recording) = scenarios::run(Scenario::Drop, &options, &mut |_, _| {}).unwrap();
    assert!(report.finite);
    let violation = |k: usize| report.cases[k].metrics["max_limit_violation_rad"];
    assert!(
        violation(0) < 0.5 * violation(1),
        "with limits {} rad, without {} rad",
        violation(0),
        violation(1)
    );
    assert!(recording.hands[0].1.len() >= 59, "60 fps recording");
}

#[test]
fn absurd_gains_are_caught_as_divergence_naming_the_bone() {
    for engine in [Engine::Rapier, Engine::Reduced] {
        let hand = human();
        let settings = Settings {
            engine,
            ..Settings::default()
        };
        let (mut setup, _) = passive_setup(&hand, settings.gravity);
        setup.controller.gains.k_s = 1e12;
        setup.controller.gains.k_d = 0.0;
        // A force this large overwhelms any integrator: give it by scaling gravity
        // (uncompensated) instead of the (implicit, stable) springs. The reduced engine's
        // implicit springs of these gains still held the fingers under 1e10 m/s².
        let mut sim = Simulation::new(Settings {
            gravity: Vec3::new(0.0, 0.0, -9.81e12),
            ..settings
        })
        .unwrap();
        sim.add_hand(setup).unwrap();
        let mut outcome = Ok(());
        for _ in 0..2000 {
            outcome = sim.step();
            if outcome.is_err() {
                break;
            }
        }
        match outcome {
            Err(SimError::Diverged { time, what }) => {
                assert!(time.is_finite() && time < 2.0);
                assert!(
                    matches!(what, Divergence::Bone { .. } | Divergence::JointGap { .. }),
                    "{engine:?}: {what}"
                );
            }
            other => panic!("{engine:?}: expected divergence, got {other:?}"),
        }
    }
}

#[test]
fn a_bone_pulled_off_its_joint_is_found_with_its_gap() {
    use prehensile_sim::ArticulatedHand;
    use rapier3d_f64::prelude::{Group, PhysicsWorld, Vector};
    let hand = human();
    let mut world = PhysicsWorld::new();
    let q = vec![0.0; hand.dof_count()];
    let body = ArticulatedHand::insert(
        &hand,
        &mut world,
        &Transform::identity(),
        &q,
        Group::GROUP_2,
        1.0,
    );
    let (_, gap) = body.widest_joint_gap(&world).unwrap();
    assert!(
        gap < 1e-9,
        "as built, every bone sits on its joint ({gap} m)"
    );
    let tip = hand.bones().len() - 1;
    let handle = body.bone_bodies()[tip];
    let mut pose = *world.bodies[handle].position();
    pose.translation += Vector::new(0.0, 0.006, 0.008);
    world.bodies[handle].set_position(pose, true);
    let (bone, gap) = body.widest_joint_gap(&world).unwrap();
    assert_eq!(bone, tip);
    assert!((gap - 0.010).abs() < 1e-9, "{gap} m");
}

#[test]
fn the_solver_follows_the_step_length() {
    let solver = |dt: f64| {
        let s = Settings::for_step(dt);
        (s.rapier.solver_iterations, s.rapier.inner_iterations)
    };
    assert_eq!(solver(0.0002), (1, 3), "the paper's step");
    assert_eq!(solver(0.0005), (1, 4));
    assert_eq!(solver(0.001), (1, 8));
    assert_eq!(solver(0.0025), (3, 7), "substeps of 0.83 ms");
    assert_eq!(solver(0.01), (10, 8));
    assert_eq!(solver(f64::NAN), (1, 3));
    assert_eq!(RapierSettings::iterations_for(1.0), 100, "capped");
    assert_eq!(Settings::default(), Settings::for_step(0.001));
}

#[test]
fn bad_settings_and_setpoints_are_refused_with_reasons() {
    for (settings, word) in [
        (
            Settings {
                dt: 0.5,
                ..Settings::default()
            },
            "dt = 0.5 is outside",
        ),
        (
            Settings {
                dt: f64::NAN,
                ..Settings::default()
            },
            "dt = NaN",
        ),
        (
            Settings {
                friction: -1.0,
                ..Settings::default()
            },
            "friction",
        ),
        (
            Settings {
                rapier: RapierSettings {
                    solver_iterations: 0,
                    ..RapierSettings::default()
                },
                ..Settings::default()
            },
            "rapier.solver_iterations",
        ),
        (
            Settings {
                rapier: RapierSettings {
                    inner_iterations: 0,
                    ..RapierSettings::default()
                },
                ..Settings::default()
            },
            "rapier.inner_iterations",
        ),
        (
            Settings {
                reduced: ReducedSettings {
                    sweeps: 0,
                    ..ReducedSettings::default()
                },
                ..Settings::default()
            },
            "reduced.sweeps",
        ),
        (
            Settings {
                reduced: ReducedSettings {
                    softness: f64::NAN,
                    ..ReducedSettings::default()
                },
                ..Settings::default()
            },
            "reduced.softness",
        ),
    ] {
        let e = Simulation::new(settings).err().expect("refused");
        assert!(e.to_string().contains(word), "{e}");
    }
    let hand = human();
    let (mut setup, _) = passive_setup(&hand, Vec3::zeros());
    setup.controller.setpoints.positions[prehensile_control::Setpoint::Grip][3] = f64::NAN;
    let mut sim = Simulation::new(Settings::default()).unwrap();
    let e = sim.add_hand(setup).unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");
    let (mut setup, _) = passive_setup(&hand, Vec3::zeros());
    setup.start.pop();
    assert!(sim.add_hand(setup).is_err());
}

#[test]
fn two_hands_shake_with_contact_and_without_driving_their_palms_into_each_other() {
    for engine in [Engine::Rapier, Engine::Reduced] {
        let options = Options {
            hand: human(),
            objects: Vec::new(),
            alpha: 0.5,
            settings: Settings {
                engine,
                ..Settings::default()
            },
            seconds: Some(2.0),
            candidates: scenarios::CANDIDATES,
        };
        let (report, recording) =
            scenarios::run(Scenario::Handshake, &options, &mut |_, _| {}).unwrap();
        let case = &report.cases[0];
        assert!(case.finite);
        assert_eq!(recording.hands.len(), 2, "both hands are recorded");
        // Each controller grips the other hand: both reach GRIPPING.
        for hand in 0..2 {
            assert!(
                case.timeline
                    .iter()
                    .any(|c| c.hand == hand && c.state == "Gripping"),
                "{:?}",
                case.timeline
            );
        }
        let force = case.mean_contact_force_n.unwrap();
        assert!(
            force > 0.1,
            "{engine:?}: the hands touch while gripping: {force} N"
        );
        // The palms are placed apart by their own thickness: only the fingers press in, a little
        // (the palms are kinematic, so nothing could push overlapping palms apart).
        assert!(
            case.max_penetration_m < 0.005,
            "{engine:?}: penetration {} m",
            case.max_penetration_m
        );
    }
}

#[test]
fn the_run_report_never_contains_nan() {
    let options = Options {
        hand: human(),
        objects: Vec::new(),
        alpha: 0.0,
        settings: Settings::default(),
        seconds: Some(0.6),
        candidates: scenarios::CANDIDATES,
    };
    let (report, _) = scenarios::run(Scenario::Shake, &options, &mut |_, _| {}).unwrap();
    // serde_json writes a NaN as null: every measured number must be a number.
    let json: serde_json::Value = serde_json::to_value(&report).unwrap();
    for case in json["cases"].as_array().unwrap() {
        for key in ["max_penetration_m", "realtime_factor"] {
            assert!(case[key].as_f64().is_some_and(f64::is_finite), "{case}");
        }
        for (name, value) in case["metrics"].as_object().unwrap() {
            assert!(
                value.as_f64().is_some_and(f64::is_finite),
                "{name}: {value}"
            );
        }
    }
    assert!(report.finite);
    assert!(report.realtime_factor > 0.0);
    let bad = Options {
        alpha: f64::NAN,
        ..options
    };
    assert!(scenarios::run(Scenario::Shake, &bad, &mut |_, _| {}).is_err());
}

fn options(objects: &[&str], alpha: f64) -> Options {
    Options {
        hand: human(),
        objects: objects
            .iter()
            .map(|name| {
                let mesh = prehensile_core::shapes::builtin_object(name).unwrap();
                prehensile_core::ObjectModel::new(name, mesh, None).unwrap()
            })
            .collect(),
        alpha,
        settings: Settings::default(),
        seconds: None,
        candidates: scenarios::CANDIDATES,
    }
}

/// [`options`] (grip 0.5) for the hand in the repository file `path`.
fn hand_file_options(path: &str, objects: &[&str]) -> Options {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    Options {
        hand: prehensile_formats::load_hand(&dir.join("../..").join(path)).unwrap(),
        ..options(objects, 0.5)
    }
}

#[test]
fn the_hand_lifts_a_light_sphere_and_carries_it() {
    // The slip on each engine: reduced 10.2 mm (14.9 mm when its friction held each tangent
    // to ±μλ on its own), rapier 7.0 mm. Rapier's figure depends on the mass
    // it gives the intermediate body of each two-axis joint, which the hand model does not have
    // (2.7 mm at 0.3 of the bone's mass), the reduced engine's on nothing outside the model.
    for (engine, most_slip) in [(Engine::Reduced, 0.013), (Engine::Rapier, 0.01)] {
        let mut options = options(&["sphere"], 0.5);
        options.settings.engine = engine;
        let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
        let case = &report.cases[0];
        assert!(case.finite);
        assert_eq!(case.held, Some(true), "{engine:?}: {case:?}");
        assert!(case.metrics["object_rise_m"] > 0.08, "{engine:?}: {case:?}");
        assert!(
            case.object_slip_m.unwrap() < most_slip,
            "{engine:?}: {case:?}"
        );
    }
}

/// `prehensile simulate`'s default run (Fig. 6) with `hand`: one controller, fitted to the
/// sphere's grasp, lifts the sphere, the box and the cylinder. Each grasp is searched at half
/// the world's friction (searched at the whole of it, the human's cylinder grasp lies along the
/// cylinder with straight fingers and the hand drops it), the box and the cylinder along the
/// controller's own closing.
fn the_default_run_holds_all_three(hand: prehensile_core::HandModel, engine: Engine) {
    let objects = ["sphere", "box", "cylinder"];
    let mut options = Options {
        hand,
        ..options(&objects, 0.5)
    };
    options.settings.engine = engine;
    let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
    assert_eq!(report.cases.len(), 3);
    for (case, name) in report.cases.iter().zip(objects) {
        assert_eq!(case.label, name);
        assert_eq!(case.held, Some(true), "{case:?}");
        assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
        assert_eq!(case.metrics["search_friction"], 0.5, "{case:?}");
        assert_eq!(
            case.metrics["searched_along_example_closing"], 1.0,
            "{case:?}"
        );
    }
}

#[test]
fn one_controller_fitted_to_the_sphere_lifts_the_box_and_the_cylinder_too() {
    the_default_run_holds_all_three(human(), Engine::Rapier);
}

#[test]
fn the_left_hands_controller_fitted_to_the_sphere_lifts_the_box_too() {
    // Searched along the left hand's own power movement, the box was placed where that
    // movement's fingers stop; the sphere's grip did not close on it and the box fell.
    the_default_run_holds_all_three(
        prehensile_formats::builtin_hand("human-left").unwrap(),
        Engine::default(),
    );
}

#[test]
fn on_the_reduced_engine_the_cartoon_hands_sphere_controller_lifts_the_box_too() {
    // Penetration pushed out by a fifth of it a step (a 5 ms time constant at 1 ms), the box
    // failed the hold check of every candidate grasp and slipped 33 mm.
    the_default_run_holds_all_three(
        prehensile_formats::builtin_hand("cartoon4").unwrap(),
        Engine::Reduced,
    );
}

#[test]
fn on_the_reduced_engine_the_ball_jointed_claw_lifts_the_box_with_bones_flat_on_it() {
    // With one contact per bone (its point nearest the box), the box slipped 30.8 mm; with
    // each end of a bone lying along a face touching too, 27.3 mm (close to the 30 mm that
    // count as held: a change that moves it should be judged with the survey,
    // tools/quality/simulate_survey.py --engine reduced).
    let mut options = hand_file_options("assets/hands/robot3_ball.toml", &["box"]);
    options.settings.engine = Engine::Reduced;
    let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
    let case = &report.cases[0];
    assert_eq!(case.held, Some(true), "{case:?}");
    assert!(case.object_slip_m.unwrap() < 0.03, "{case:?}");
}

#[test]
fn a_joint_the_search_left_at_its_start_still_squeezes() {
    // The human hand's cylinder grasp touches with the index's first phalanx at the start of
    // the closing, so that joint stays where the movement starts. The example's grip presses
    // past the found pose along the movement's closing; without that the grip setpoint there
    // equals the open one and α's squeeze (Eq. 15–16) adds nothing.
    let options = options(&["cylinder"], 0.5);
    let grasp = options.plan_grasp(&options.objects[0]).unwrap();
    let hand = &options.hand;
    let power = hand.movement("power").unwrap();
    let closing: Vec<f64> = power
        .end_angles()
        .iter()
        .zip(power.start_angles())
        .map(|(end, start)| end - start)
        .collect();
    let unmoved: Vec<usize> = (0..hand.dof_count())
        .filter(|&k| closing[k] > 0.1 && (grasp.closed[k] - grasp.open[k]).abs() < 1e-9)
        .collect();
    assert!(
        !unmoved.is_empty(),
        "the grasp no longer leaves a closing joint at its start; pick another object"
    );
    let controller = grasp.controller(hand, &options.settings.gravity).unwrap();
    let positions = &controller.setpoints.positions;
    for k in unmoved {
        let squeeze = positions[Setpoint::Grip][k] - positions[Setpoint::Open][k];
        assert!(
            squeeze > 0.05 * closing[k],
            "{}: grip − open setpoint {squeeze}, closing {}",
            hand.dof_names()[k],
            closing[k]
        );
    }
}

#[test]
fn the_controller_fitted_to_the_cylinders_own_grasp_lifts_it() {
    // `prehensile simulate --object cylinder`: it dropped the cylinder (slip 5.25 m) before
    // the example's grip pressed past the found pose.
    let (report, _) = scenarios::run(
        Scenario::Grasp,
        &options(&["cylinder"], 0.5),
        &mut |_, _| {},
    )
    .unwrap();
    let case = &report.cases[0];
    assert_eq!(case.held, Some(true), "{case:?}");
    assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
}

#[test]
fn the_cartoon_hand_lifts_the_cylinder_with_its_derived_power_grasp() {
    // cartoon4's file writes only `close`, a fingertip grasp on the cylinder's top that dropped
    // it; its derived power movement wraps it, thumb opposite the fingers.
    let mut options = options(&["cylinder"], 0.5);
    options.hand = prehensile_formats::builtin_hand("cartoon4").unwrap();
    let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
    let case = &report.cases[0];
    assert_eq!(case.held, Some(true), "{case:?}");
    assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
}

#[test]
fn the_grip_force_grows_with_grip_strength() {
    let (report, _) = scenarios::run(
        Scenario::GripSweep,
        &options(&["sphere"], 0.0),
        &mut |_, _| {},
    )
    .unwrap();
    let grip: Vec<f64> = report
        .cases
        .iter()
        .map(|c| c.metrics["grip_force_n"])
        .collect();
    assert_eq!(grip.len(), 6);
    assert!(grip[5] > 3.0 * grip[0], "{grip:?}");
    // The grip on the fixed object (the last 0.2 s before let-go) is noisy: a bone that touches
    // or chatters moves it by ±0.04 N, and since the example's grip presses past the found pose
    // α = 0.1 reads 0.60 N between α = 0's 0.17 and α = 0.2's 0.41. The force that holds the
    // lifted object, averaged over the whole hold, grows step by step.
    let held: Vec<f64> = report
        .cases
        .iter()
        .map(|c| c.mean_contact_force_n.unwrap())
        .collect();
    assert!(
        held.windows(2).all(|w| w[1] > w[0]),
        "contact force while held by α 0, 0.1, …, 0.5: {held:?}"
    );
    assert!(held[5] > 2.0 * held[0], "{held:?}");
}

#[test]
fn the_sweeps_cases_run_side_by_side_as_they_run_one_after_another() {
    let mut options = options(&["sphere"], 0.0);
    options.seconds = Some(0.5);
    let mut heard = Vec::new();
    let (side_by_side, _) = scenarios::run(Scenario::GripSweep, &options, &mut |label, _| {
        heard.push(label.to_string())
    })
    .unwrap();
    let (one_after_another, _) = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| scenarios::run(Scenario::GripSweep, &options, &mut |_, _| {}))
        .unwrap();
    // Everything but the wall-clock speeds.
    let without_speeds = |report: &scenarios::RunReport| {
        let mut value = serde_json::to_value(report).unwrap();
        value.as_object_mut().unwrap().remove("realtime_factor");
        for case in value["cases"].as_array_mut().unwrap() {
            case.as_object_mut().unwrap().remove("realtime_factor");
        }
        value
    };
    assert_eq!(
        without_speeds(&side_by_side),
        without_speeds(&one_after_another)
    );
    let labels: Vec<&str> = side_by_side
        .cases
        .iter()
        .map(|c| c.label.as_str())
        .collect();
    assert_eq!(
        labels,
        [
            "alpha 0.0",
            "alpha 0.1",
            "alpha 0.2",
            "alpha 0.3",
            "alpha 0.4",
            "alpha 0.5"
        ]
    );
    for label in labels {
        assert!(
            heard.iter().any(|h| h == label),
            "no progress heard from {label}"
        );
    }
}

#[test]
fn arm_compensation_removes_most_of_the_finger_lag_of_a_shake() {
    let (report, _) = scenarios::run(Scenario::Shake, &options(&[], 0.0), &mut |_, _| {}).unwrap();
    let lag = |k: usize| report.cases[k].metrics["finger_lag_rms_rad"];
    assert!(
        lag(0) < 0.2 * lag(1),
        "with τARM {} rad, without {} rad",
        lag(0),
        lag(1)
    );
}

#[test]
fn the_benchmark_scene_holds_its_object_still() {
    let sphere = prehensile_core::ObjectModel::new(
        "sphere",
        prehensile_core::shapes::builtin_object("sphere").unwrap(),
        None,
    )
    .unwrap();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let shadow =
        prehensile_formats::load_hand(&dir.join("../../assets/hands/shadow_hand/reach.xml"))
            .unwrap();
    for (hand, engine) in [
        (human(), Engine::Rapier),
        (human(), Engine::Reduced),
        (shadow, Engine::Reduced),
    ] {
        let settings = Settings {
            engine,
            ..Settings::for_step(1e-3)
        };
        let mut sim = scenarios::held_still(&hand, &sphere, settings).unwrap();
        let before = sim.object_pose().unwrap().translation.vector;
        let mut settled = before;
        for step in 0..600 {
            if step == 400 {
                settled = sim.object_pose().unwrap().translation.vector;
            }
            sim.step().unwrap();
        }
        let after = sim.object_pose().unwrap().translation.vector;
        let (settling, still) = ((settled - before).norm(), (after - settled).norm());
        let touching = sim.contacts(0).touching;
        let what = format!("{} on {engine:?}", hand.name());
        assert!(
            touching >= 3,
            "{what}: {touching} capsules touch the sphere"
        );
        // Settling in the hand moves it millimetres (rapier 5, the reduced engine 4–17: its
        // fingers do not sink into the sphere); falling would take it 20 cm in 0.2 s. Then it
        // stays.
        assert!(
            settling < 0.02,
            "{what}: the sphere moved {settling} m in 0.2 s"
        );
        assert!(still < 0.002, "{what}: then {still} m in the next 0.2 s");
    }
}

#[test]
fn the_reduced_engine_lifts_what_rapier_lifts_without_sinking_into_it() {
    let objects = ["sphere", "box", "cylinder"];
    let mut options = options(&objects, 0.5);
    options.settings.engine = Engine::Reduced;
    let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
    for (case, name) in report.cases.iter().zip(objects) {
        assert_eq!(case.label, name);
        assert_eq!(case.held, Some(true), "{case:?}");
        assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
        assert!(case.object_slip_m.unwrap() < 0.03, "{case:?}");
        // Contacts are solved as constraints, not springs: rapier lets the fingers sink
        // 0.4–0.6 mm into these objects.
        assert!(case.max_penetration_m < 2e-4, "{case:?}");
    }
}

#[test]
fn the_grasp_scenario_plans_with_the_worlds_friction_and_the_simulation_judges_the_hold() {
    // The search judges a grasp by the friction it assumes: half the world's (and the whole of
    // it when that finds nothing). The Shadow hand's sphere grasp wraps the ball past its
    // equator, so it is planned at 0.5 in the default world and at 0.25 in a world of 0.5, and
    // the hand lifts the ball in both. In a world of 0.2 the plan at 0.1 is in force closure
    // on paper, but the hand's squeeze does not keep the ball: the simulation, not the plan,
    // says whether it holds.
    let options = hand_file_options("assets/hands/shadow_hand/reach.xml", &["sphere"]);
    let world = |friction: f64| Options {
        settings: Settings {
            friction,
            ..Settings::default()
        },
        ..options.clone()
    };
    for (friction, held) in [(1.0, true), (0.5, true), (0.2, false)] {
        let (report, _) =
            scenarios::run(Scenario::Grasp, &world(friction), &mut |_, _| {}).unwrap();
        let case = &report.cases[0];
        assert!(case.finite, "{case:?}");
        assert_eq!(case.metrics["search_friction"], friction / 2.0, "{case:?}");
        assert_eq!(case.held, Some(held), "world friction {friction}: {case:?}");
        if held {
            assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
        }
    }

    // A ball of 20 cm, wider than the hand closes around: the scenario says why at both
    // frictions it tried, instead of simulating.
    let boulder = prehensile_core::ObjectModel::new(
        "boulder",
        prehensile_core::shapes::sphere(0.1, 32, 16),
        None,
    )
    .unwrap();
    let e = scenarios::run(
        Scenario::Grasp,
        &Options {
            objects: vec![boulder],
            ..options
        },
        &mut |_, _| {},
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("no valid power grasp of 'boulder' was found for hand 'reach'"),
        "{e}"
    );
}

#[test]
fn the_shadow_hand_holds_sphere_box_and_cylinder_once_each_grasp_is_checked() {
    // The default run's box grasp from the default shoulder (the only one its seeds give)
    // seated the box 30 mm toward the palm in the first second after let-go, and the run's slip
    // was 32.3 mm (30 allowed). Each grasp is now held against gravity in the simulation before
    // its run, and the next shoulder's grasp is searched when it does not hold. (With friction
    // the same in every direction, the default shoulder's box grasp holds; the
    // robot3_ball test below has a first shoulder that does not.)
    let objects = ["sphere", "box", "cylinder"];
    let options = hand_file_options("assets/hands/shadow_hand/reach.xml", &objects);
    let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
    for (case, name) in report.cases.iter().zip(objects) {
        assert_eq!(case.label, name);
        assert_eq!(case.held, Some(true), "{case:?}");
        assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
        let tried = case.metrics["hold_check_tried"];
        assert!((1.0..=3.0).contains(&tried), "{case:?}");
    }
    let box_case = &report.cases[1];
    assert_eq!(box_case.metrics["hold_check_held"], 1.0, "{box_case:?}");

    // One candidate: the default shoulder's grasp, run unchecked.
    let unchecked = Options {
        candidates: 1,
        ..options
    };
    let (report, _) = scenarios::run(Scenario::Grasp, &unchecked, &mut |_, _| {}).unwrap();
    for case in &report.cases {
        assert_eq!(case.metrics["hold_check_tried"], 0.0, "{case:?}");
        assert_eq!(
            case.metrics["hold_check_shoulder_turn_deg"], 0.0,
            "{case:?}"
        );
        assert!(!case.metrics.contains_key("hold_check_held"), "{case:?}");
    }
}

#[test]
fn a_grasp_that_fails_the_hold_check_gives_way_to_another_shoulders() {
    // The ball-jointed claw's cylinder grasps from the default shoulder and from 30° one way
    // drop it in the hold check; the one from 30° the other way holds, and the run lifts with it.
    let options = hand_file_options("assets/hands/robot3_ball.toml", &["cylinder"]);
    let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
    let case = &report.cases[0];
    assert_eq!(case.metrics["hold_check_held"], 1.0, "{case:?}");
    assert_eq!(case.metrics["hold_check_tried"], 3.0, "{case:?}");
    assert_eq!(
        case.metrics["hold_check_shoulder_turn_deg"], -30.0,
        "{case:?}"
    );
    assert_eq!(case.held, Some(true), "{case:?}");
    assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
}

#[test]
fn the_webxr_right_hand_holds_the_sphere_its_first_hang_found() {
    // Its power search of the sphere finds only one-sided grasps, from every hang. Hung
    // farther out a second time, it found a fingertip grasp that ranked above the first
    // hang's; the run dropped the sphere (it fell 5.5 m). A search begun again now keeps the
    // first hang's one-sided grasp unless it finds one that pushes from every side.
    let options = hand_file_options("assets/hands/webxr_generic_hand/right.glb", &["sphere"]);
    let (report, _) = scenarios::run(Scenario::Grasp, &options, &mut |_, _| {}).unwrap();
    let case = &report.cases[0];
    assert_eq!(case.held, Some(true), "{case:?}");
    assert!(case.metrics["object_rise_m"] > 0.08, "{case:?}");
}

#[test]
fn the_candidate_shoulders_turn_both_ways_in_widening_steps() {
    let turns: Vec<f64> = (0..5).map(scenarios::shoulder_turn_degrees).collect();
    assert_eq!(turns, [0.0, 30.0, -30.0, 60.0, -60.0]);
}

/// Hand `hand` let swing under gravity from mid-range for 50 ms with (almost) no springs, the
/// palm held still, on `engine`: its joint angles, and those of the hand model's own equations
/// of motion (`forward_dynamics` stepped at 10 µs) from the same start.
fn free_swing(hand: &prehensile_core::HandModel, engine: Engine) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    use prehensile_control::{
        forward_dynamics, BaseMotion, DynamicsModel, Gains, GraspController, PerSetpoint, Setpoints,
    };
    let n = hand.dof_count();
    let limits = hand.dof_limits();
    let start: Vec<f64> = limits.iter().map(|[lo, hi]| 0.5 * (lo + hi)).collect();
    let gravity = Vec3::new(0.0, -9.81, 0.0);
    let seconds = 0.05;
    let setpoints = Setpoints {
        positions: PerSetpoint::from_fn(|_| start.clone()),
        velocities: PerSetpoint::from_fn(|_| vec![0.0; n]),
        neutral: start.clone(),
        limits,
    };
    // Springs a million times weaker than Table 1's (rapier's motors need some stiffness).
    let gains = Gains {
        k_s: 1e-3,
        k_d: 1e-3,
        k_jl: 0.0,
        ..Gains::grasp()
    };
    let mut controller = GraspController::new(gains, setpoints);
    controller.active = false;
    let settings = Settings {
        gravity,
        engine,
        ..Settings::for_step(1e-4)
    };
    let mut sim = Simulation::new(settings).unwrap();
    sim.add_hand(HandSetup {
        hand: hand.clone(),
        controller,
        arm: ArmTrajectory::new(vec![Waypoint {
            time: 0.0,
            root: Transform::identity(),
        }]),
        start: start.clone(),
        distance: DistanceTo::Constant(1.0),
        release_at: None,
        compensate_gravity: false,
        compensate_arm: false,
        manual: Vec::new(),
    })
    .unwrap();
    while sim.time() < seconds - 1e-9 {
        sim.step().unwrap();
    }
    let model = DynamicsModel::new(hand);
    let mut data = model.data();
    let base = BaseMotion::at_rest(hand.bones()[0].rest.rotation.inverse() * gravity);
    let (mut q, mut qd, zeros) = (start.clone(), vec![0.0; n], vec![0.0; n]);
    let h = 1e-5;
    for _ in 0..(seconds / h).round() as usize {
        let a = forward_dynamics(&model, &mut data, &q, &qd, &zeros, &base).unwrap();
        for k in 0..n {
            qd[k] += h * a[k];
            q[k] += h * qd[k];
        }
    }
    (start, sim.joint_angles(0).to_vec(), q)
}

#[test]
fn a_free_hand_swings_as_its_equations_of_motion_say() {
    // The reduced engine steps the model's own dynamics; rapier builds the hand from bodies
    // and joints and agrees where every joint is a hinge (the Shadow hand). Its two-axis joints
    // (two hinges through an intermediate body carrying the bone's mass, which the model does
    // not have) move the human hand's joints 0.65-6.5 times as far as the model says in this
    // swing (docs/PERFORMANCE.md), so rapier is not held to the model there.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let shadow =
        prehensile_formats::load_hand(&dir.join("../../assets/hands/shadow_hand/reach.xml"))
            .unwrap();
    for (hand, engine) in [
        (human(), Engine::Reduced),
        (
            prehensile_formats::builtin_hand("robot3").unwrap(),
            Engine::Reduced,
        ),
        (shadow.clone(), Engine::Reduced),
        (shadow, Engine::Rapier),
    ] {
        let (start, simulated, model) = free_swing(&hand, engine);
        let moved = start
            .iter()
            .zip(&model)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let off = simulated
            .iter()
            .zip(&model)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let what = format!("{} on {engine:?}", hand.name());
        assert!(moved > 0.2, "{what}: the fingers must swing ({moved} rad)");
        assert!(
            off < 0.01 * moved,
            "{what}: {off} rad off after {moved} rad"
        );
    }
}
