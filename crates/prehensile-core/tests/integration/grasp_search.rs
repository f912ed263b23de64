//! The pose search end to end: what a grasp must be (no capsule enters the object by more than
//! 1 mm; power touches with ≥ 3 fingers, precision with thumb and index; the palm faces the hook),
//! checked from the result's own capsules with the exact collision path.

use crate::common;
use prehensile_core::object::Repair;

use std::time::Duration;

use prehensile_core::hand::Joint;
use prehensile_core::math::Rotation;
use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::initial_approximation::{
    sample_rotation, InitialApproximation, SAMPLE_COUNT,
};
use prehensile_core::search::translate_to_free::translate_to_free;
use prehensile_core::search::{
    fdist_floor, finger_fdist_floor, Evaluation, GraspPlanner, GraspResult, PlannerStatus,
    SearchError, SearchParams, SearchSink, SearchStats, StopRule, TranslateMode, ValidityRule,
    SAMPLES_PER_SLICE,
};
use prehensile_core::shapes::{self, BUILTIN_OBJECTS};
use prehensile_core::{HandModel, ObjectModel, Workspace};

/// Closed fixture meshes with the scale that makes them hand-sized (metres).
const FIXTURES: [(&str, f64); 9] = [
    ("robosuite_lemon.stl", 1.0),
    ("robosuite_milk.stl", 1.0),
    ("robosuite_bread.stl", 1.0),
    ("robosuite_cereal.stl", 1.0),
    ("robosuite_can.obj", 1.0),
    ("pybullet_bunny.obj", 0.06),
    ("pybullet_duck.obj", 0.06),
    ("pybullet_soccerball.obj", 0.08),
    ("pybullet_torus.obj", 0.06),
];

const SHOULDERS: [[f64; 3]; 3] = [[-0.35, -0.2, 0.35], [0.1, -0.45, 0.3], [-0.3, 0.3, 0.2]];

fn fixture(name: &str, scale: f64) -> ObjectModel {
    let path = common::repo_path(&format!("assets/objects/{name}"));
    prehensile_formats::load_object(&path, scale).unwrap()
}

fn search(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &str,
    shoulder: [f64; 3],
    seed: u64,
) -> GraspResult {
    let params = SearchParams {
        seed,
        ..Default::default()
    };
    search_with(hand, object, movement, shoulder, params)
}

/// [`search`] with other parameters.
fn search_with(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &str,
    shoulder: [f64; 3],
    params: SearchParams,
) -> GraspResult {
    let m = hand.movement(movement).unwrap();
    let shoulder = object.center_of_mass() + Vec3::from(shoulder);
    let mut planner = GraspPlanner::new(hand, object, m, shoulder, params).unwrap();
    planner.run_to_end();
    GraspResult::from_planner(&planner, &mut Workspace::new(hand))
}

/// The narrowest cone, degrees, about any of 20,000 spread directions that holds every contact
/// normal (90 when none is narrower than a hemisphere): an independent, sampled check of the
/// search's exact one-sidedness test.
fn sampled_normal_cap(r: &GraspResult) -> f64 {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let n = 20_000;
    (0..n)
        .map(|k| {
            // Fibonacci sphere.
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let (s, phi) = ((1.0 - z * z).sqrt(), golden * k as f64);
            let u = Vec3::new(s * phi.cos(), s * phi.sin(), z);
            let worst = r
                .contacts
                .iter()
                .map(|c| u.dot(&Vec3::from(c.normal)))
                .fold(1.0, f64::min);
            worst.clamp(0.0, 1.0).acos().to_degrees()
        })
        .fold(90.0, f64::min)
}

/// Checks a result against the definition of a grasp, independently of the search's own flags:
/// nothing enters the object, enough fingers touch, the contacts are in force closure by the hull
/// (the search decides by a linear program) and push from more than one side (their normals not
/// all within 78° of one direction), a precision grasp's thumb and index pads oppose.
fn assert_grasp(object: &ObjectModel, r: &GraspResult, what: &str) {
    assert!(r.valid, "{what}: {:?}", r.invalid_reason);
    assert!(r.stability.force_closure, "{what}: not in force closure");
    assert!(r.stability.epsilon > 0.0, "{what}: epsilon 0");
    let cap = sampled_normal_cap(r);
    assert!(
        cap >= 77.9,
        "{what}: every normal within {cap:.1}° of one direction"
    );
    let exact = object.collider().exact();
    let mut touching: Vec<&str> = Vec::new();
    for c in &r.capsules {
        let (a, b) = (Point3::from(c.a), Point3::from(c.b));
        assert!(
            !exact.capsule_touches(&a, &b, c.radius - 0.001),
            "{what}: capsule of {} enters the object by more than 1 mm",
            c.bone
        );
        if c.finger != "palm"
            && exact.segment_within(&a, &b, c.radius + 0.001)
            && !touching.contains(&c.finger.as_str())
        {
            touching.push(&c.finger);
        }
    }
    if r.movement.starts_with("precision") {
        assert!(
            touching.contains(&"thumb") && touching.contains(&"index"),
            "{what}: touching {touching:?}"
        );
        let pad = |finger: &str| {
            let c = r
                .contacts
                .iter()
                .rev()
                .find(|c| c.finger == finger)
                .unwrap();
            Vec3::from(c.normal)
        };
        let angle = pad("thumb").angle(&pad("index")).to_degrees();
        assert!(angle >= 119.9, "{what}: pads {angle:.0} degrees apart");
    } else {
        assert!(touching.len() >= 3, "{what}: touching {touching:?}");
    }
    // The palm faces the hook: the hook lies on the palm side (+y) of the wrist.
    let q = r.wrist.rotation_xyzw;
    let rotation = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q[3], q[0], q[1], q[2],
    ));
    let palm_normal = rotation * Vec3::y();
    let to_hook = Point3::from(r.hook) - Point3::from(r.wrist.position);
    assert!(
        palm_normal.dot(&to_hook) > 0.0,
        "{what}: the palm faces away from the hook"
    );
}

/// A valid result meets the definition; an invalid one says which test failed and still enters
/// nothing. Returns whether it was valid.
fn check_result(object: &ObjectModel, r: &GraspResult, what: &str) -> bool {
    if r.valid {
        assert_grasp(object, r, what);
        return true;
    }
    // The best attempt names the test it failed (opposition, force closure, a finger short).
    let reason = r.invalid_reason.as_deref().unwrap_or_default();
    assert!(!reason.is_empty(), "{what}: invalid without a reason");
    let exact = object.collider().exact();
    for c in &r.capsules {
        let (a, b) = (Point3::from(c.a), Point3::from(c.b));
        assert!(!exact.capsule_touches(&a, &b, c.radius - 0.001), "{what}");
    }
    false
}

/// Valid grasps found by power and precision searches from each shoulder with seeds 1 and 2.
#[derive(Debug, Default)]
struct Found {
    power: usize,
    precision: usize,
    /// The power searches that found no valid grasp, with the test they failed.
    power_failures: Vec<String>,
}

/// Power and precision searches from each shoulder with seeds 1 and 2: every valid grasp meets the
/// definition, every invalid result says why.
fn grasps_power_and_precision(
    hand: &HandModel,
    object: &ObjectModel,
    name: &str,
    shoulders: &[[f64; 3]],
    found: &mut Found,
) {
    for movement in ["power", "precision"] {
        for (i, shoulder) in shoulders.iter().enumerate() {
            for seed in [1, 2] {
                let r = search(hand, object, movement, *shoulder, seed);
                let what = format!("{name} {movement} shoulder {i} seed {seed}");
                match (check_result(object, &r, &what), movement) {
                    (true, "power") => found.power += 1,
                    (true, _) => found.precision += 1,
                    (false, "power") => found
                        .power_failures
                        .push(format!("{what}: {:?}", r.invalid_reason)),
                    (false, _) => {}
                }
            }
        }
    }
}

#[test]
fn human_grasps_every_builtin_object_from_several_shoulders_and_seeds() {
    let hand = common::hand("human");
    let mut found = Found::default();
    for name in BUILTIN_OBJECTS {
        let object = common::object(name);
        grasps_power_and_precision(&hand, &object, name, &SHOULDERS, &mut found);
    }
    assert_eq!(found.power_failures, Vec::<String>::new());
    // Opposed pinches of most objects: 17 of 30 precision searches (4 with the thesis's start of
    // the precision movement, thumb extended at the side).
    assert!(found.precision >= 12, "{found:?}");
}

/// The human hand's wide precision start (its thumb nearer straight) closes thumb and index pads
/// in opposition around the built-in objects its curled start pinches least: the 8 cm sphere (all
/// contacts one way), the torus (the thumb passes through the hole) and the mug (not in force
/// closure) — until the search moves its hook into the ring or the cup's wall — from each test
/// shoulder with seeds 1 and 2.
#[test]
fn the_wide_precision_start_pinches_what_the_curled_one_cannot() {
    let hand = common::hand("human");
    let (mut wide, mut curled) = (0, 0);
    for name in ["sphere", "torus", "mug"] {
        let object = common::object(name);
        for (i, shoulder) in SHOULDERS.iter().enumerate() {
            for seed in [1, 2] {
                for (movement, count) in [("precision-wide", &mut wide), ("precision", &mut curled)]
                {
                    let r = search(&hand, &object, movement, *shoulder, seed);
                    let what = format!("{name} {movement} shoulder {i} seed {seed}");
                    if check_result(&object, &r, &what) {
                        *count += 1;
                    }
                }
            }
        }
    }
    // Of 18 searches each: 18 valid with the wide start, 5 with the curled one;
    // 12 with the curled one since its searches of the torus and the mug, finding no pinch
    // from the centre of mass in the hole or the cup, move their hook into the material and
    // pinch the ring or the wall.
    assert!(
        wide >= 16 && wide >= curled + 4,
        "wide {wide}, curled {curled}"
    );
}

/// Searches `close` from every shoulder with seed 1 on every built-in object: every valid grasp
/// meets the definition and every invalid result says why. Returns the objects grasped from every
/// shoulder.
fn closes_on_builtin_objects(
    hand: &HandModel,
    what: &str,
    shoulders: &[[f64; 3]],
) -> Vec<&'static str> {
    let mut grasped = Vec::new();
    for name in BUILTIN_OBJECTS {
        let object = common::object(name);
        let mut all = true;
        for (i, shoulder) in shoulders.iter().enumerate() {
            let r = search(hand, &object, "close", *shoulder, 1);
            all &= check_result(&object, &r, &format!("{what} {name} shoulder {i}"));
        }
        if all {
            grasped.push(name);
        }
    }
    grasped
}

#[test]
fn non_human_hands_grasp_the_builtin_objects() {
    let robot3 = closes_on_builtin_objects(&common::hand("robot3"), "robot3", &SHOULDERS);
    assert_eq!(robot3, BUILTIN_OBJECTS);
    // The cartoon hand's four fingers meet the sphere on its near side only (every normal within
    // 66–67° of one direction, or no force closure): no valid grasp, and the result says so.
    let cartoon4 = closes_on_builtin_objects(&common::hand("cartoon4"), "cartoon4", &SHOULDERS);
    for name in ["box", "cylinder", "torus"] {
        assert!(
            cartoon4.contains(&name),
            "cartoon4 grasped only {cartoon4:?}"
        );
    }
}

#[test]
fn a_hand_with_only_ball_joints_closes_them_and_grasps_the_builtin_objects() {
    // robot3 with every finger joint a ball joint: the generic `close` flexes each about its
    // bone's −x axis, as a hinge flexes, to its x component's limit.
    let path = common::repo_path("assets/hands/robot3_ball.toml");
    let hand = prehensile_formats::load_hand(&path).unwrap();
    let close = hand.movement("close").unwrap();
    for bone in hand.bones().iter().skip(1) {
        assert!(matches!(bone.joint, Joint::Ball { .. }), "{}", bone.name);
        let end = &close.end_angles()[bone.first_dof..bone.first_dof + 3];
        assert_eq!(end, [-60f64.to_radians(), 0.0, 0.0], "{}", bone.name);
    }
    // Its fingertips meet the sphere on the near side (every normal within 73–76° of one
    // direction): no valid grasp of the sphere; every other object from the first shoulder.
    let grasped = closes_on_builtin_objects(&hand, "ball-jointed robot3", &SHOULDERS[..1]);
    assert_eq!(grasped, ["box", "cylinder", "torus", "mug"]);
}

#[test]
fn human_grasps_the_fixture_meshes() {
    let hand = common::hand("human");
    let mut found = Found::default();
    for (name, scale) in FIXTURES {
        let object = fixture(name, scale);
        grasps_power_and_precision(&hand, &object, name, &SHOULDERS[..2], &mut found);
    }
    // 36 power searches (9 meshes, 2 shoulders, 2 seeds). From the first shoulder the lemon is
    // held with the fingers on one side only (every normal within 70° of one direction), and from
    // the second the cereal box finds no grasp in force closure with contacts on more than one
    // side; every other search finds a power grasp.
    assert!(found.power >= 32, "{found:#?}");
}

#[test]
fn milk_carton_slivers_are_repaired_and_reported() {
    let object = fixture("robosuite_milk.stl", 1.0);
    assert_eq!(object.repairs().len(), 1, "{:?}", object.repairs());
    assert!(object.report().defects.is_empty());
}

#[test]
fn same_seed_same_grasp_and_threads_do_not_change_it() {
    let hand = common::hand("human");
    let object = common::object("mug");
    let m = hand.movement("power").unwrap();
    let shoulder = Point3::new(-0.35, -0.2, 0.4);
    let run = |threads: usize, seed: u64| {
        let params = SearchParams {
            seed,
            threads,
            ..Default::default()
        };
        let mut p = GraspPlanner::new(&hand, &object, m, shoulder, params).unwrap();
        p.run_to_end();
        p.best().cloned().unwrap()
    };
    let one = run(1, 5);
    assert_eq!(one, run(1, 5));
    assert_eq!(one, run(3, 5));
}

/// What a request's sink hears: the movements started (each once, in order), how many times the
/// events switched movement, and each movement's steps (checked to come one by one, in order).
#[derive(Default)]
struct Heard {
    started: Vec<String>,
    switches: u32,
    steps: std::collections::HashMap<String, u32>,
    movement: String,
}
impl SearchSink for Heard {
    fn movement_started(&mut self, name: &str) {
        self.switches += 1;
        self.movement = name.to_string();
        if !self.started.iter().any(|s| s == name) {
            self.started.push(name.to_string());
        }
    }
    fn step(&mut self, stats: &SearchStats, _current: &Evaluation) {
        let last = self.steps.entry(self.movement.clone()).or_default();
        assert_eq!(
            stats.steps,
            *last + 1,
            "{}: a step lost or out of order",
            self.movement
        );
        *last = stats.steps;
    }
}

/// The human hand's `auto` request on the built-in sphere on `threads` threads within `budget`,
/// and what its sink heard; the result's time zeroed, so that results compare.
fn auto_on_sphere(threads: usize, budget: Option<Duration>) -> (GraspResult, Heard) {
    let request = prehensile_core::search::GraspRequest {
        movement: prehensile_core::search::AUTO_MOVEMENT.into(),
        shoulder: Point3::new(-0.35, -0.2, 0.35),
        params: SearchParams {
            threads,
            ..Default::default()
        },
        budget,
    };
    let (hand, object) = (common::hand("human"), common::object("sphere"));
    let mut heard = Heard::default();
    let mut result =
        prehensile_core::search::find_grasp(&hand, &object, &request, &mut heard).unwrap();
    result.stats.seconds = 0.0;
    (result, heard)
}

#[test]
fn movements_searched_side_by_side_give_the_same_result_and_every_event() {
    // `auto` on several threads searches the human hand's movements each on a thread of its
    // own, passing their events on to the caller's sink; on one thread a step each in turn.
    let hand = common::hand("human");
    let object = common::object("sphere");
    let (one, heard_one) = auto_on_sphere(1, None);
    let (side_by_side, heard) = auto_on_sphere(2, None);
    assert_eq!(one, side_by_side);
    let movements: Vec<&str> =
        prehensile_core::search::movements_to_try(&hand, prehensile_core::search::AUTO_MOVEMENT)
            .unwrap()
            .iter()
            .map(|m| m.name())
            .collect();
    assert!(movements.len() > 1, "{movements:?}");
    let mut started = heard.started.clone();
    started.sort();
    let mut expected: Vec<String> = movements.iter().map(|m| m.to_string()).collect();
    expected.sort();
    assert_eq!(started, expected);
    assert_eq!(heard.steps, heard_one.steps);
    // The patience rule: the power grasp ends valid within AUTO_PATIENCE steps, the precision
    // search finds nothing valid on the sphere and stops at AUTO_PATIENCE, not at the step
    // limit, on one thread and on two.
    let patience = prehensile_core::search::AUTO_PATIENCE;
    assert!(one.valid && one.movement == "power", "{}", one.movement);
    assert!(heard.steps["power"] <= patience, "{:?}", heard.steps);
    assert_eq!(heard.steps["precision"], patience, "{:?}", heard.steps);
    let precision_alone = prehensile_core::search::find_grasp(
        &hand,
        &object,
        &prehensile_core::search::GraspRequest {
            movement: "precision".into(),
            shoulder: Point3::new(-0.35, -0.2, 0.35),
            params: SearchParams::default(),
            budget: None,
        },
        &mut (),
    )
    .unwrap();
    assert!(!precision_alone.valid && precision_alone.stats.steps > patience);
}

#[test]
fn a_budget_is_the_whole_requests_and_keeps_the_patience_rule() {
    // A budget used to be each movement's: on one thread `auto`'s three movements of the human
    // hand searched one after another, each for the whole budget, and none stopped for the
    // patience rule. Now the movements share it, in turn or side by side.
    let (unbudgeted, _) = auto_on_sphere(SearchParams::default().threads, None);
    // A budget far beyond the search: the same result, searched in slices, and the precision
    // search still stops at the patience rule, on one thread and on two.
    let patience = prehensile_core::search::AUTO_PATIENCE;
    for threads in [1, 2] {
        let (result, heard) = auto_on_sphere(threads, Some(Duration::from_secs(3600)));
        assert_eq!(result, unbudgeted, "{threads} thread(s)");
        assert_eq!(heard.steps["precision"], patience, "{:?}", heard.steps);
    }
    // With a budget on one thread the movements take turns (the sink hears the events switch
    // back and forth), not each the whole budget one after another.
    let (_, heard) = auto_on_sphere(1, Some(Duration::from_millis(300)));
    assert_eq!(heard.started.len(), 3, "{:?}", heard.started);
    assert!(heard.switches > 3, "switched {} times", heard.switches);
}

#[test]
fn anytime_planner_resumes_and_its_best_only_improves() {
    let hand = common::hand("human");
    let object = common::object("torus");
    let m = hand.movement("power").unwrap();
    let shoulder = Point3::new(-0.35, -0.2, 0.35);
    let mut stepped =
        GraspPlanner::new(&hand, &object, m, shoulder, SearchParams::default()).unwrap();
    let mut last = f64::NEG_INFINITY;
    while stepped.step() == PlannerStatus::Searching {
        let q = stepped.best().map_or(f64::NEG_INFINITY, |b| b.quality);
        assert!(q >= last, "the best pose got worse");
        last = q;
    }
    // The same search in time slices ends in the same place.
    let mut sliced =
        GraspPlanner::new(&hand, &object, m, shoulder, SearchParams::default()).unwrap();
    while sliced.run_for(Duration::from_micros(200)) == PlannerStatus::Searching {}
    assert_eq!(sliced.best(), stepped.best());
    assert_eq!(sliced.stats().steps, stepped.stats().steps);
}

#[test]
fn thesis_stop_rule_and_fixed_translate_steps_still_find_grasps() {
    let hand = common::hand("human");
    let object = common::object("sphere");
    let params = SearchParams {
        stop: StopRule::ThesisLocalMaximum,
        translate: TranslateMode::Steps { step: 0.002 },
        ..Default::default()
    };
    let mut p = GraspPlanner::new(
        &hand,
        &object,
        hand.movement("power").unwrap(),
        Point3::new(-0.3, 0.0, 0.3),
        params,
    )
    .unwrap();
    let status = p.run_to_end();
    assert_ne!(status, PlannerStatus::Searching);
    assert!(p.stats().steps >= 1);
}

#[test]
fn turning_the_character_restarts_the_search() {
    let hand = common::hand("human");
    let object = common::object("cylinder");
    let m = hand.movement("power").unwrap();
    let mut p = GraspPlanner::new(
        &hand,
        &object,
        m,
        Point3::new(-0.4, 0.0, 0.3),
        SearchParams::default(),
    )
    .unwrap();
    p.run_to_end();
    // 5° around the vertical: no restart, the search goes on from where it was.
    let small = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), 5f64.to_radians())
        * Point3::new(-0.4, 0.0, 0.3);
    assert!(!p.set_shoulder(small).unwrap());
    assert_eq!(p.stats().restarts, 0);
    // 30°: restart from the new starting position.
    let large = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), 30f64.to_radians())
        * Point3::new(-0.4, 0.0, 0.3);
    assert!(p.set_shoulder(large).unwrap());
    assert_eq!(p.stats().restarts, 1);
    // The restart's work runs in slices, so a game frame that works in slices keeps to its
    // budget: 64 initial-approximation samples, SAMPLES_PER_SLICE a slice, then one slice
    // evaluating the start.
    // Until then the current pose is not evaluated and nothing is best.
    let steps_before = p.stats().steps;
    let mut slices = 0;
    while p.restarting() {
        assert!(p.best().is_none());
        assert!(matches!(
            p.current().validity,
            Err(prehensile_core::search::Invalid::NotEvaluated)
        ));
        let placements = p.stats().placements;
        p.slice();
        slices += 1;
        // One TranslateToFree per sample: a few dozen placements each at most.
        assert!(
            p.stats().placements - placements < SAMPLES_PER_SLICE as u64 * 200,
            "slice {slices}"
        );
    }
    assert_eq!(slices, 64usize.div_ceil(SAMPLES_PER_SLICE) + 1);
    assert_eq!(
        p.stats().steps,
        steps_before,
        "slices are not optimization steps"
    );
    assert!(p.current().validity != Err(prehensile_core::search::Invalid::NotEvaluated));
    // With one thread, a step's slices are its candidates, one each (seven-pose: six), and the
    // stability test of at most one candidate each: with the last candidate, then in slices of
    // their own until the step's outcome is decided.
    for lazy_stability in [false, true] {
        let single = SearchParams {
            threads: 1,
            lazy_stability,
            ..Default::default()
        };
        let mut q =
            GraspPlanner::new(&hand, &object, m, Point3::new(-0.4, 0.0, 0.3), single).unwrap();
        while q.restarting() {
            q.slice();
        }
        for _ in 0..8 {
            assert_eq!(q.status(), PlannerStatus::Searching);
            let (steps, evaluations) = (q.stats().steps, q.stats().evaluations);
            let tests = q.stats().stability_tests;
            for _ in 0..5 {
                q.slice();
                assert_eq!(
                    q.stats().steps,
                    steps,
                    "a step ends after its last candidate"
                );
            }
            let mut slices = 0;
            while q.stats().steps == steps {
                let before = q.stats().stability_tests;
                q.slice();
                slices += 1;
                if lazy_stability {
                    assert!(q.stats().stability_tests <= before + 1);
                }
            }
            let judged = q.stats().stability_tests - tests;
            assert_eq!(
                slices,
                1 + judged.saturating_sub(1) as usize * usize::from(lazy_stability)
            );
            assert_eq!(q.stats().evaluations, evaluations + 6);
        }
    }
    p.run_to_end();
    let r = GraspResult::from_planner(&p, &mut Workspace::new(&hand));
    assert_grasp(&object, &r, "after restart");
}

#[test]
fn bad_search_input_is_refused_with_a_reason() {
    let hand = common::hand("human");
    let m = hand.movement("power").unwrap();
    let sphere = common::object("sphere");
    let new = |object: &ObjectModel, shoulder: Point3, params: SearchParams| {
        GraspPlanner::new(&hand, object, m, shoulder, params).map(|_| ())
    };
    let far = common::object("sphere")
        .with_hooks(vec![Point3::new(2.0, 0.0, 0.0)])
        .unwrap();
    assert!(matches!(
        new(&far, Point3::new(2.0, 0.0, 1.0), SearchParams::default()),
        Err(SearchError::HookOutside { .. })
    ));
    let on_hook = sphere.center_of_mass();
    assert!(matches!(
        new(&sphere, on_hook, SearchParams::default()),
        Err(SearchError::ShoulderOnHook(_))
    ));
    let big = ObjectModel::new(
        "crate",
        prehensile_core::shapes::cuboid(Vec3::new(1.0, 1.0, 1.0)),
        None,
    )
    .unwrap();
    assert!(matches!(
        new(&big, Point3::new(-2.0, 0.0, 2.0), SearchParams::default()),
        Err(SearchError::TooBig { .. })
    ));
    let shoulder = Point3::new(-0.3, 0.0, 0.3);
    for params in [
        SearchParams {
            max_angle: f64::NAN,
            ..Default::default()
        },
        SearchParams {
            max_angle: -1.0,
            ..Default::default()
        },
        SearchParams {
            translate: TranslateMode::Steps { step: 0.0 },
            ..Default::default()
        },
        SearchParams {
            translate: TranslateMode::Bisection {
                coarse: 0.001,
                precision: 0.01,
            },
            ..Default::default()
        },
        SearchParams {
            up: Vec3::zeros(),
            ..Default::default()
        },
        SearchParams {
            max_steps: 0,
            ..Default::default()
        },
    ] {
        assert!(matches!(
            new(&sphere, shoulder, params),
            Err(SearchError::BadParameter(_))
        ));
    }
    assert!(matches!(
        new(
            &sphere,
            Point3::new(f64::NAN, 0.0, 0.0),
            SearchParams::default()
        ),
        Err(SearchError::BadParameter(_))
    ));
}

#[test]
fn a_hook_beside_the_object_gives_an_invalid_result_with_a_reason_not_a_penetrating_pose() {
    let hand = common::hand("human");
    // 12 cm from the sphere's centre: 8 cm outside its surface, within the hand's reach.
    let object = common::object("sphere")
        .with_hooks(vec![Point3::new(0.12, 0.0, 0.0)])
        .unwrap();
    let r = search(&hand, &object, "precision", [-0.3, -0.2, 0.3], 1);
    let exact = object.collider().exact();
    for c in &r.capsules {
        assert!(!exact.capsule_touches(&Point3::from(c.a), &Point3::from(c.b), c.radius - 0.001));
    }
    if !r.valid {
        assert!(r.invalid_reason.is_some());
    }
}

#[test]
fn a_sink_hears_every_step_and_every_improvement() {
    #[derive(Default)]
    struct Recorder {
        steps: u32,
        improvements: Vec<f64>,
    }
    impl SearchSink for Recorder {
        fn step(&mut self, stats: &SearchStats, _current: &Evaluation) {
            self.steps = stats.steps;
        }
        fn improved(&mut self, best: &Evaluation) {
            self.improvements.push(best.quality);
        }
    }
    let hand = common::hand("human");
    let object = common::object("box");
    let m = hand.movement("power").unwrap();
    let mut planner = GraspPlanner::new(
        &hand,
        &object,
        m,
        Point3::new(-0.35, -0.2, 0.35),
        SearchParams::default(),
    )
    .unwrap();
    let mut sink = Recorder::default();
    planner.run_to_end_into(&mut sink);
    assert_eq!(sink.steps, planner.stats().steps);
    assert!(
        sink.improvements.windows(2).all(|w| w[1] > w[0]),
        "{:?}",
        sink.improvements
    );
    // The power grasp of the box is found, so the sink must have heard of it.
    assert!(!sink.improvements.is_empty());
    assert_eq!(
        sink.improvements.last().copied(),
        planner.best().map(|b| b.quality)
    );
}

#[test]
fn the_mirrored_human_hand_is_a_left_hand_that_grasps() {
    let right = common::hand("human");
    let left = common::hand("human-left");
    let thumb_x = |h: &HandModel| {
        let t = h.finger_index("thumb").unwrap();
        h.pose_transforms(
            &prehensile_core::math::Transform::identity(),
            &vec![Default::default(); h.bones().len()],
        )[*h.fingers()[t].bones.last().unwrap()]
        .translation
        .x
    };
    assert!(thumb_x(&right) < 0.0 && thumb_x(&left) > 0.0);
    assert!(left.is_left() && !right.is_left());
    // Every movement's poses are mirror images, joint by joint and tip by tip, all the way
    // through: abduction (the thumb's turn toward the palm's heel at the power grasp's end)
    // turns the mirrored way.
    let mirror = |p: Point3| Point3::new(-p.x, p.y, p.z);
    for m_right in right.movements() {
        let m_left = left.movement(m_right.name()).unwrap();
        for f in [0.0, 0.5, 1.0] {
            let points = |h: &HandModel, m: &prehensile_core::GraspMovement| {
                let r: Vec<_> = (0..h.bones().len()).map(|b| m.rotation_at(b, f)).collect();
                let world = h.pose_transforms(&prehensile_core::math::Transform::identity(), &r);
                let joints = world.iter().map(|t| Point3::from(t.translation.vector));
                let tips = h
                    .fingers()
                    .iter()
                    .map(|fi| world[*fi.bones.last().unwrap()] * fi.tip);
                joints.chain(tips).collect::<Vec<_>>()
            };
            let (r, l) = (points(&right, m_right), points(&left, m_left));
            for (k, (r, l)) in r.iter().zip(&l).enumerate() {
                let gap = (mirror(*r) - l).norm();
                assert!(gap < 1e-12, "{} at {f}: point {k} {gap} m", m_right.name());
            }
        }
    }
    // The default shoulder is mirrored with the hand: beside the hand's own side.
    let hook = Point3::origin();
    let s_right = prehensile_core::search::default_shoulder(&right, &hook, &Vec3::z());
    let s_left = prehensile_core::search::default_shoulder(&left, &hook, &Vec3::z());
    assert!((s_right.y + s_left.y).abs() < 1e-12 && s_right.y < 0.0);
    for name in BUILTIN_OBJECTS {
        let object = common::object(name);
        for movement in ["power", "precision"] {
            let r = search(&left, &object, movement, SHOULDERS[0], 1);
            check_result(&object, &r, &format!("left {name} {movement}"));
        }
    }
}

#[test]
fn the_left_hand_searches_the_mirror_image_of_the_right_hands_search() {
    // On an object symmetric about the plane y = 0 through its centre, the left hand reaching
    // from the mirrored shoulder meets the mirror image of everything the right hand meets:
    // its wrist turns within the mirror image of the right wrist's range (145° one way about
    // the fingers, 70° the other), so it takes the same steps to the mirrored grasp. Within
    // the right hand's own range it took other paths, and from shoulders turned 60° found
    // only one-sided grasps of the cereal box where the right hand's push from every side.
    let (right, left) = (common::hand("human"), common::hand("human-left"));
    let mirror = |p: [f64; 3]| [p[0], -p[1], p[2]];
    for name in ["box", "cylinder", "sphere", "torus"] {
        let object = common::object(name);
        for seed in 1..=3 {
            let r = search(&right, &object, "power", SHOULDERS[0], seed);
            let l = search(&left, &object, "power", mirror(SHOULDERS[0]), seed);
            let what = format!("{name} seed {seed}");
            assert!(r.valid && l.valid, "{what}");
            assert_eq!(r.stats.steps, l.stats.steps, "{what}");
            // Alike to rounding on the sphere and torus; on the box and cylinder, whose faces
            // are not split into triangles symmetrically, within 0.02 mm at the wrist.
            let (qr, ql) = (r.quality.unwrap(), l.quality.unwrap());
            assert!((qr - ql).abs() < 1e-3, "{what}: quality {qr} and {ql}");
            let gap = (Vec3::from(mirror(r.wrist.position)) - Vec3::from(l.wrist.position)).norm();
            assert!(gap < 1e-4, "{what}: wrists {gap} m from mirror images");
        }
    }
}

#[test]
fn human_power_grasps_hold_open_and_non_manifold_meshes() {
    // Their insides come from winding numbers; the results must meet the same definition.
    let hand = common::hand("human");
    let cup_path = common::repo_path("crates/prehensile-core/tests/data/winding/open_cup.obj");
    let open_cup = prehensile_formats::load_object(&cup_path, 1.0).unwrap();
    let objects = [
        ("open cup", open_cup),
        ("pybullet_mug.obj", fixture("pybullet_mug.obj", 1.0)),
        (
            "can with holes",
            fixture("robosuite_can_with_holes.stl", 1.0),
        ),
        ("bottle", fixture("robosuite_bottle.stl", 1.0)),
    ];
    for (name, object) in &objects {
        assert!(object.collider().exact().uses_winding_numbers(), "{name}");
        for shoulder in &SHOULDERS[..2] {
            let r = search(&hand, object, "power", *shoulder, 1);
            assert_grasp(object, &r, &format!("{name} from {shoulder:?}"));
        }
    }
}

/// Giving up on samples that cannot beat the best changes nothing: the same start as
/// backing every sample off in full.
#[test]
fn giving_up_early_keeps_the_start_of_the_full_sampling() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    for name in ["mug", "torus", "box"] {
        let object = ObjectModel::new(name, shapes::builtin_object(name).unwrap(), None).unwrap();
        for shoulder in [Point3::new(-0.35, -0.2, 0.35), Point3::new(0.3, 0.1, 0.2)] {
            let planner = GraspPlanner::new(
                &hand,
                &object,
                hand.movement("power").unwrap(),
                shoulder,
                SearchParams::default(),
            )
            .unwrap();
            let ctx = planner.context();
            let mut ws = Workspace::new(&hand);
            let mut sampling = InitialApproximation::new();
            assert!(sampling.advance(ctx, &mut ws, SAMPLE_COUNT));
            let mut full: Option<(Rotation, f64)> = None;
            for k in 0..SAMPLE_COUNT {
                let rotation = sample_rotation(ctx, k);
                let freed = translate_to_free(
                    ctx.hand,
                    ctx.object,
                    ctx.movement,
                    &ctx.hook_frame(&rotation),
                    ctx.translate,
                    ctx.max_offset,
                    f64::INFINITY,
                    &mut ws,
                );
                if let Some(o) = freed.filter(|&o| full.is_none_or(|(_, b)| o < b)) {
                    full = Some((rotation, o));
                }
            }
            assert_eq!(sampling.best(), full, "{name} from {shoulder:?}");
            assert!(full.is_some());
        }
    }
}

/// Judging a step's candidates' stability lazily (best quality first, until one holds) takes the
/// search down the same path as judging every candidate: the same current and best pose after
/// every step and the same counts, with fewer than half the stability tests (2.95× fewer in
/// the searches that end with a grasp pushing from every side). On one thread and
/// on two.
#[test]
fn lazy_stability_takes_the_same_path_with_fewer_tests() {
    let scan = fixture("robosuite_can.obj", 1.0);
    let mut objects: Vec<ObjectModel> = BUILTIN_OBJECTS.iter().map(|n| common::object(n)).collect();
    objects.push(scan);
    let cases = [
        ("human", "power", 1),
        ("human", "precision", 1),
        ("robot3", "close", 2),
    ];
    let (mut lazy_tests, mut eager_tests) = (0, 0);
    for (hand, movement, threads) in cases {
        let hand = common::hand(hand);
        let m = hand.movement(movement).unwrap();
        for object in &objects {
            for seed in [1, 2] {
                let shoulder = object.center_of_mass() + Vec3::new(-0.35, -0.2, 0.35);
                let planner = |lazy_stability| {
                    let params = SearchParams {
                        seed,
                        threads,
                        lazy_stability,
                        ..Default::default()
                    };
                    GraspPlanner::new(&hand, object, m, shoulder, params).unwrap()
                };
                let (mut lazy, mut eager) = (planner(true), planner(false));
                let what = format!(
                    "{} {movement} on {} seed {seed}",
                    hand.name(),
                    object.name()
                );
                loop {
                    let (a, b) = (lazy.step(), eager.step());
                    assert_eq!(a, b, "{what}");
                    assert_eq!(lazy.current(), eager.current(), "{what}");
                    assert_eq!(lazy.best(), eager.best(), "{what}");
                    let (s, t) = (lazy.stats(), eager.stats());
                    assert_eq!(
                        (s.steps, s.evaluations, s.collision_queries, s.placements),
                        (t.steps, t.evaluations, t.collision_queries, t.placements),
                        "{what}"
                    );
                    if a != PlannerStatus::Searching {
                        break;
                    }
                }
                assert!(lazy.stats().stability_tests <= eager.stats().stability_tests);
                // A search that never finds a valid grasp has to judge every candidate that
                // passes the other checks: it saves nothing. Nor does one whose best grasp
                // pushes from one side only: any candidate might push from every side. Nor does
                // the first part of one that moved its hook into the material, which found
                // no such grasp from its first hook.
                if eager.stats().hook_moves == 0
                    && eager
                        .best()
                        .is_some_and(|b| eager.context().pushes_from_every_side(b))
                {
                    lazy_tests += lazy.stats().stability_tests;
                    eager_tests += eager.stats().stability_tests;
                }
            }
        }
    }
    // Judging every candidate, a search judges the valid ones that close below the bar of a
    // step too, unless the step's bound stops them while their fingers close: since it stops
    // finger by finger, most are (these searches: 984 stability tests before,
    // 421 after, lazy judging 367 both times), so laziness saves less than it did.
    assert!(
        lazy_tests < eager_tests,
        "searches that found a grasp pushing from every side: lazy judging made {lazy_tests} stability tests, judging \
         every candidate {eager_tests}"
    );
}

#[test]
fn the_default_rule_prefers_wraps_that_push_from_every_side_and_strict_refuses_the_rest() {
    // A rule that took the first valid wrap returned the human hand's torus grasp of seed 2 with
    // every contact normal within 82.5° of one direction (friction 0.5 holds it on paper). The
    // default rule ranks valid wraps that push from every side above one-sided ones, and finds one, as
    // `--validity strict` does. For the four-fingered cartoon hand's sphere (seed 1: the hand
    // over the ball, its fingertips down to the equator) it finds none, and returns the
    // one-sided grasp, saying so in `normal_cone_degrees`; `strict` refuses it, saying why and
    // that `holds` would take it. A pinch keeps the friction-aware test: the human hand's wide
    // pinch of the sphere is valid under `strict` with both pads' normals (and the others') in
    // one open half-space.
    let strict = |hand: &HandModel, object: &ObjectModel, movement: &str, seed: u64| {
        let params = SearchParams {
            validity: ValidityRule::Strict,
            seed,
            ..Default::default()
        };
        search_with(hand, object, movement, SHOULDERS[0], params)
    };
    let (human, cartoon) = (common::hand("human"), common::hand("cartoon4"));
    let (torus, sphere) = (common::object("torus"), common::object("sphere"));
    let default_torus = search(&human, &torus, "power", SHOULDERS[0], 2);
    let default_sphere = search(&cartoon, &sphere, "power", SHOULDERS[0], 1);
    for (r, every_side) in [(&default_torus, true), (&default_sphere, false)] {
        assert!(r.valid, "{:?}", r.invalid_reason);
        let cap = sampled_normal_cap(r);
        // 20,000 sampled directions lie about 1.4° apart: the sampled cap is at most 1° wider.
        assert!(
            (0.0..1.0).contains(&(cap - r.normal_cone_degrees + 1e-9)),
            "sampled {cap:.2}°, reported {:.2}°",
            r.normal_cone_degrees
        );
        assert_eq!(
            cap >= 89.9,
            every_side,
            "the default grasp's normals: {cap:.1}°"
        );
    }
    // With only a one-sided grasp the search went on looking for 120 steps (it would have
    // stopped 12 steps after its last improvement), then stopped (not at the 500-step limit).
    assert_eq!(default_sphere.status, PlannerStatus::Converged);
    assert!(
        (120..500).contains(&default_sphere.stats.steps),
        "{} steps",
        default_sphere.stats.steps
    );
    // `auto` ranks the same way across movements: the cartoon hand's pinch of the sphere,
    // whose pads oppose, beats that one-sided wrap although the wrap's ε is larger.
    let auto = prehensile_core::search::find_grasp(
        &cartoon,
        &sphere,
        &prehensile_core::search::GraspRequest {
            movement: prehensile_core::search::AUTO_MOVEMENT.into(),
            shoulder: sphere.center_of_mass() + Vec3::from(SHOULDERS[0]),
            params: SearchParams::default(),
            budget: None,
        },
        &mut (),
    )
    .unwrap();
    assert_eq!(auto.movement, "precision");
    assert!(auto.valid && auto.stability.epsilon < default_sphere.stability.epsilon);
    // Without that patience it stops sooner, with a one-sided grasp.
    let params = SearchParams {
        one_sided_patience: 0,
        ..Default::default()
    };
    let quick = search_with(&cartoon, &sphere, "power", SHOULDERS[0], params);
    assert!(quick.valid && quick.normal_cone_degrees < 89.9);
    assert_eq!(quick.status, PlannerStatus::Converged);
    assert!(quick.stats.steps < 120, "{} steps", quick.stats.steps);
    let wrap = strict(&human, &torus, "power", 2);
    assert!(wrap.valid, "{:?}", wrap.invalid_reason);
    let cap = sampled_normal_cap(&wrap);
    assert!(
        cap >= 89.9,
        "the strict grasp's normals lie within {cap:.1}°"
    );
    let refused = strict(&cartoon, &sphere, "power", 2);
    assert!(!refused.valid);
    let reason = refused.invalid_reason.unwrap_or_default();
    assert!(
        reason.contains("90° needed") && reason.contains("the `holds` validity rule accepts it"),
        "{reason}"
    );
    let pinch = strict(&human, &sphere, "precision-wide", 1);
    assert!(pinch.valid, "{:?}", pinch.invalid_reason);
    let cap = sampled_normal_cap(&pinch);
    assert!(
        (77.9..89.0).contains(&cap),
        "the pinch's normals lie within {cap:.1}°"
    );
    assert_grasp(&sphere, &pinch, "strict wide pinch of the sphere");
}

#[test]
fn a_ring_the_hand_cannot_pinch_from_its_hole_is_pinched_by_its_rim() {
    // The human hand's precision grasp (thumb curled across the palm at the start) of the
    // built-in torus (9 cm across, lying flat), seed 1: hung from the centre of mass, in the
    // hole, no pose brings thumb and index pads onto the ring in opposition in 120 steps (without a
    // second hang it ran to the 500-step limit and returned nothing valid). It then moves its
    // hook into the tube on the shoulder's side and pinches the rim there.
    let (major, minor) = (0.045, 0.014);
    let hand = common::hand("human");
    let torus = common::object("torus");
    let r = search(&hand, &torus, "precision", SHOULDERS[0], 1);
    assert!(r.valid, "{:?}", r.invalid_reason);
    assert_eq!(r.stats.hook_moves, 1);
    for finger in ["thumb", "index"] {
        assert!(r.fingers_touching.iter().any(|f| f == finger), "{finger}");
    }
    // The reported hook is the one the grasp hangs from: on the tube's centre line, toward the
    // shoulder seen from above.
    let hook = Point3::from(r.hook);
    let across = Vec3::new(hook.x, hook.y, 0.0);
    assert!(
        (across.norm() - major).abs() < 1e-3 && hook.z.abs() < 1e-3,
        "{hook:?}"
    );
    assert!(torus.collider().exact().signed_distance(&hook) < -0.9 * minor);
    let toward = Vec3::new(SHOULDERS[0][0], SHOULDERS[0][1], 0.0).normalize();
    assert!(across.normalize().dot(&toward) > 0.999, "{hook:?}");
    // A search that finds its grasp from the first hook keeps it (the power grasp of the same
    // torus), as does one whose centre of mass is in the material.
    let power = search(&hand, &torus, "power", SHOULDERS[0], 1);
    let sphere = common::object("sphere");
    let ball = search(&hand, &sphere, "precision", SHOULDERS[0], 1);
    for (r, object) in [(&power, &torus), (&ball, &sphere)] {
        assert_eq!(r.stats.hook_moves, 0);
        assert_eq!(Point3::from(r.hook), object.center_of_mass());
    }
}

#[test]
fn a_small_object_the_first_hang_cages_is_grasped_hung_nearer_the_palm() {
    // The Shadow hand's power grasp of the 4.5 cm lemon scan, seed 1: hung from its derived
    // grasp center, 4.8 cm out of the palm, the lemon sits between the curling fingertips and
    // no valid grasp is found in 120 steps (nor in 500, hung there alone). The search then
    // hangs the hand again, nearer its palm, and closes on the lemon from every side with the
    // thumb on it.
    let hand = prehensile_formats::load_hand_mjcf(&common::repo_path(
        "assets/hands/shadow_hand/reach.xml",
    ))
    .unwrap();
    let lemon = fixture("robosuite_lemon.stl", 1.0);
    let r = search(&hand, &lemon, "power", SHOULDERS[0], 1);
    assert!(r.valid, "{:?}", r.invalid_reason);
    assert_eq!((r.stats.hung_again, r.stats.hook_moves), (1, 0));
    assert!(r.normal_cone_degrees >= 89.9, "{}", r.normal_cone_degrees);
    assert!(r.fingers_touching.iter().any(|f| f == "thumb"));
    assert_eq!(Point3::from(r.hook), lemon.center_of_mass());
    // The result's offset is from the hook itself: the hook frame moved `offset` along −y, less
    // the grasp center, is the wrist the result reports.
    let movement = hand.movement("power").unwrap();
    let q = r.hook_rotation_xyzw;
    let hook = prehensile_core::math::Transform::from_parts(
        Point3::from(r.hook).coords.into(),
        Rotation::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2])),
    );
    let root = prehensile_core::search::translate_to_free::hand_root(&hook, movement, r.offset);
    let wrist = Vec3::from(r.wrist.position);
    assert!(
        (root.translation.vector - wrist).norm() < 1e-9,
        "{root:?} {wrist:?}"
    );
    assert!(r.offset < r.terms.gdist, "{} {}", r.offset, r.terms.gdist);
}

/// The human hand's power grasp of the 3 cm thick cereal box scan, seed `seed`, from the first
/// test shoulder turned 60° about the vertical.
fn human_cereal_power_from_a_turned_shoulder(seed: u64) -> (HandModel, GraspResult) {
    let hand = common::hand("human");
    let cereal = fixture("robosuite_cereal.stl", 1.0);
    let turned = Rotation::from_axis_angle(&Vec3::z_axis(), 60f64.to_radians());
    let shoulder = turned * Vec3::from(SHOULDERS[0]);
    let r = search(&hand, &cereal, "power", shoulder.into(), seed);
    (hand, r)
}

#[test]
fn a_thin_box_that_pushes_the_hand_back_is_grasped_hung_farther_out() {
    // The human hand's power grasp of the 3 cm thick cereal box scan from a shoulder turned 60°
    // about the vertical, seed 1: the box pushes the open hand back off the hook, its top edge
    // ends against the palm with the fingers over it, every contact pushing one way, and
    // nothing better turns up in 120 steps. Hung nearer, the hand would back off to the same
    // place; the second hang takes it farther out, the edge in the fingers, which close round it
    // from every side.
    let (hand, r) = human_cereal_power_from_a_turned_shoulder(1);
    assert!(r.valid, "{:?}", r.invalid_reason);
    assert_eq!((r.stats.hung_again, r.stats.hook_moves), (1, 0));
    assert!(r.normal_cone_degrees >= 89.9, "{}", r.normal_cone_degrees);
    // Hung farther: the result's offset from the hook exceeds the back-off from the hang by the
    // grasp center's height out of the palm.
    let height = hand.movement("power").unwrap().grasp_center().y;
    assert!(
        (r.offset - r.terms.gdist - height).abs() < 1e-12,
        "{} {}",
        r.offset,
        r.terms.gdist
    );
}

#[test]
fn a_search_whose_second_hang_finds_only_one_sided_grasps_searches_once_more() {
    // The same box and shoulder, seed 3: from its second hang, farther out, the search found
    // only a grasp whose contacts all push one way. Searched once more from that hang,
    // along the random angles that follow, it finds one that pushes from every side.
    let (_, r) = human_cereal_power_from_a_turned_shoulder(3);
    assert!(r.valid, "{:?}", r.invalid_reason);
    assert_eq!((r.stats.hung_again, r.stats.searched_again), (1, 1));
    assert!(r.normal_cone_degrees >= 89.9, "{}", r.normal_cone_degrees);
    assert!(r.stats.steps <= SearchParams::default().max_steps);
}

#[test]
fn the_default_rule_walks_as_strict_does_and_keeps_one_sided_grasps_in_reserve() {
    // Under the default rule a one-sided wrap is valid but ranks, for where the search moves
    // next, among the invalid poses: the search takes `--validity strict`'s path and returns its
    // grasp wherever that finds one; elsewhere the one-sided grasp it met on the way. (A search
    // that moved onto a one-sided wrap circled it: the Shadow hand's can scan, seed 2, ended
    // one-sided where `strict` wraps it at step 55.)
    let mut same = 0;
    for (hand, name, seed) in [
        ("human", "torus", 2),
        ("human", "mug", 1),
        ("cartoon4", "box", 1),
        ("cartoon4", "cylinder", 2),
        ("cartoon4", "sphere", 1),
    ] {
        let hand = common::hand(hand);
        let object = common::object(name);
        let strict = SearchParams {
            validity: ValidityRule::Strict,
            seed,
            ..Default::default()
        };
        let a = search(&hand, &object, "power", SHOULDERS[0], seed);
        let b = search_with(&hand, &object, "power", SHOULDERS[0], strict);
        let what = format!("{} on {name} seed {seed}", hand.name());
        if b.valid {
            assert_eq!(
                (a.hook_rotation_xyzw, a.stats.steps, a.valid),
                (b.hook_rotation_xyzw, b.stats.steps, true),
                "{what}"
            );
            same += 1;
        } else {
            assert!(a.valid && a.normal_cone_degrees < 89.9, "{what}");
        }
    }
    assert_eq!(same, 4);
}

#[test]
fn the_fdist_floor_bounds_every_valid_pose() {
    // The bound that stops a step's candidates early (`evaluate_pose_to_beat`): every pose
    // valid so far has an fDist at least the floor, and a pose is stopped only when its quality
    // is at most the bar it was given. Hook rotations scattered around the start, human and
    // Shadow hands, power grasps of objects whose hook lies inside them.
    let shadow = prehensile_formats::load_hand_mjcf(&common::repo_path(
        "assets/hands/shadow_hand/reach.xml",
    ))
    .unwrap();
    let objects = [
        common::object("sphere"),
        common::object("cylinder"),
        common::object("box"),
        fixture("robosuite_can.obj", 1.0),
        fixture("robosuite_bread.stl", 1.0),
    ];
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for hand in [common::hand("human"), shadow] {
        let movement = hand.movement("power").unwrap();
        let (mut valid, mut stopped) = (0, 0);
        for object in &objects {
            let shoulder = Point3::from(SHOULDERS[0]);
            let planner =
                GraspPlanner::new(&hand, object, movement, shoulder, SearchParams::default())
                    .unwrap();
            let ctx = *planner.context();
            let floor = fdist_floor(&hand, object, &ctx.hook);
            assert!(floor > 0.0, "{}: the hook lies inside", object.name());
            let mut ws = Workspace::new(&hand);
            for _ in 0..60 {
                let axis = Vec3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5);
                let turn = Rotation::from_scaled_axis(axis.normalize() * uniform());
                let rotation = ctx.start * turn;
                let e = ctx.evaluate_pose(&rotation, &mut ws);
                if e.validity.is_err() {
                    continue;
                }
                valid += 1;
                assert!(
                    e.terms.fdist >= floor,
                    "{} {}: fDist {} below the floor {floor}",
                    hand.name(),
                    object.name(),
                    e.terms.fdist
                );
                // Finger by finger too: a closed finger's term replaces its floor in the bound.
                for (f, finger) in hand.fingers().iter().enumerate() {
                    let (term, floor) = (
                        ctx.finger_fdist(finger, &ws),
                        finger_fdist_floor(&hand, f, ctx.hook_depth),
                    );
                    assert!(
                        term >= floor,
                        "{} {} finger {f}: {term} below its floor {floor}",
                        hand.name(),
                        object.name()
                    );
                }
                // Just below its quality the pose counts and is evaluated to the end, with
                // the same outcome; well above, the bound may stop it.
                let below = ctx.evaluate_pose_to_beat(&rotation, &mut ws, e.quality - 1e-7);
                assert_eq!(below.quality, e.quality);
                assert_eq!(below.validity, e.validity);
                let above = ctx.evaluate_pose_to_beat(&rotation, &mut ws, e.quality + 0.2);
                if above.validity == Err(prehensile_core::search::Invalid::Outranked) {
                    stopped += 1;
                }
            }
        }
        assert!(valid >= 40, "{}: only {valid} valid poses", hand.name());
        assert!(
            stopped >= valid / 2,
            "{}: {stopped} of {valid} stopped",
            hand.name()
        );
    }
}

/// A distance grid filled up front (`MeshCollider::fill_grid`) holds the values a search fills
/// as it reads them, so searches on it find the same grasps; every node is filled once.
#[test]
fn a_grid_filled_up_front_gives_the_same_grasps() {
    let hand = common::hand("human");
    let objects = [
        (common::object("mug"), common::object("mug")),
        (
            fixture("robosuite_can.obj", 1.0),
            fixture("robosuite_can.obj", 1.0),
        ),
    ];
    for (lazy, filled) in &objects {
        let grid = filled.collider().grid().expect("a closed mesh has a grid");
        assert_eq!(grid.filled_nodes(), 0);
        assert_eq!(filled.collider().fill_grid(), grid.node_count());
        assert_eq!(grid.filled_nodes(), grid.node_count());
        assert_eq!(
            filled.collider().fill_grid(),
            0,
            "a second fill has nothing to do"
        );
        for seed in 1..=2 {
            let on_lazy = search(&hand, lazy, "power", SHOULDERS[0], seed);
            let mut on_filled = search(&hand, filled, "power", SHOULDERS[0], seed);
            on_filled.stats.seconds = on_lazy.stats.seconds;
            assert_eq!(on_lazy, on_filled, "{} seed {seed}", lazy.name());
        }
        let lazy_grid = lazy.collider().grid().unwrap();
        // Two searches read part of the grid: on the mug 2,712 of its 4,275 nodes.
        let (filled, all) = (lazy_grid.filled_nodes(), lazy_grid.node_count());
        assert!(
            filled < all * 3 / 4,
            "{} filled {filled} of {all}",
            lazy.name()
        );
    }
}

#[test]
fn a_vertex_no_triangle_uses_changes_no_grasp() {
    // A stray vertex 170 m away in a 5 cm cube's file made every power search of it fail: the
    // search's widths were taken over the vertices. It is dropped, and the grasp is the cube's.
    let cube = shapes::cuboid(Vec3::new(0.05, 0.05, 0.05));
    let mut stray = cube.clone();
    stray.vertices.insert(3, Point3::new(100.0, 100.0, 100.0));
    for t in &mut stray.triangles {
        for i in t.iter_mut() {
            if *i >= 3 {
                *i += 1;
            }
        }
    }
    let (clean, with_stray) = (
        ObjectModel::new("cube", cube, None).unwrap(),
        ObjectModel::new("cube", stray, None).unwrap(),
    );
    assert!(clean.repairs().is_empty(), "{:?}", clean.repairs());
    assert!(
        with_stray.repairs().contains(&Repair::UnusedVertices(1)),
        "{:?}",
        with_stray.repairs()
    );
    assert_eq!(clean.mesh(), with_stray.mesh());
    let hand = common::hand("human");
    let m = hand.movement("power").unwrap();
    let shoulder = Point3::new(-0.35, -0.2, 0.4);
    let best = |object: &ObjectModel| {
        let params = SearchParams {
            seed: 1,
            ..Default::default()
        };
        let mut p = GraspPlanner::new(&hand, object, m, shoulder, params).unwrap();
        p.run_to_end();
        p.best().cloned()
    };
    let grasp = best(&clean);
    assert!(grasp.is_some());
    assert_eq!(grasp, best(&with_stray));
}
