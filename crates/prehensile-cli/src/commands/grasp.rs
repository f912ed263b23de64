//! `prehensile grasp`: one hand, one object, one grasp.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::default_shoulder;
use prehensile_core::search::{
    find_grasp, Evaluation, GraspRequest, GraspResult, PlannerStatus, QualityWeights, SearchParams,
    SearchSink, SearchStats,
};
use prehensile_core::stability::ContactModel;
use prehensile_core::{HandModel, ObjectModel};

use crate::args::GraspArgs;
use crate::{picture, sources, CliError};

/// The largest `--budget-ms`: a day.
const MAX_BUDGET_MS: f64 = 86_400_000.0;

/// Shows the search's progress on a spinner.
struct SpinnerSink {
    bar: ProgressBar,
    /// The movement the events are about.
    movement: String,
    /// The best valid quality of each movement so far (movements searched side by side
    /// interleave their events).
    best: std::collections::HashMap<String, f64>,
}

impl SearchSink for SpinnerSink {
    fn movement_started(&mut self, name: &str) {
        self.movement = name.to_string();
    }

    fn step(&mut self, stats: &SearchStats, _current: &Evaluation) {
        let best = self
            .best
            .get(&self.movement)
            .map_or("none yet".to_string(), |q| format!("{q:.4}"));
        self.bar.set_message(format!(
            "{}: step {}, {} poses, best valid quality {best}",
            self.movement, stats.steps, stats.evaluations
        ));
        self.bar.tick();
    }

    fn improved(&mut self, best: &Evaluation) {
        self.best.insert(self.movement.clone(), best.quality);
    }
}

/// Runs the request (every movement for `auto`, see [`find_grasp`](fn@find_grasp)) with a spinner on the
/// terminal when `progress`, and returns the chosen result with the wall time it took.
pub fn search(
    hand: &HandModel,
    object: &ObjectModel,
    request: &GraspRequest,
    progress: bool,
) -> Result<(GraspResult, Duration), CliError> {
    let began = Instant::now();
    let bar = if progress {
        ProgressBar::new_spinner()
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(ProgressStyle::with_template("{spinner} {msg}").expect("valid template"));
    let mut sink = SpinnerSink {
        bar,
        movement: String::new(),
        best: Default::default(),
    };
    let result = find_grasp(hand, object, request, &mut sink).map_err(CliError::from);
    sink.bar.finish_and_clear();
    Ok((result?, began.elapsed()))
}

/// Keyframes of the result: approach from 10 cm back over one second, close over one second.
fn keyframes(
    hand: &HandModel,
    result: &GraspResult,
) -> Result<Vec<prehensile_core::animation::Keyframe>, CliError> {
    let movement = hand.movement(&result.movement).ok_or_else(|| {
        CliError::Usage(format!(
            "the result names movement '{}', which the hand lacks",
            result.movement
        ))
    })?;
    let q = result.hook_rotation_xyzw;
    let hook = prehensile_core::math::Transform::from_parts(
        Point3::from(result.hook).coords.into(),
        nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            q[3], q[0], q[1], q[2],
        )),
    );
    let fractions: Vec<f64> = result.bones.iter().map(|b| b.fraction).collect();
    Ok(prehensile_core::animation::approach_and_close(
        hand,
        movement,
        &hook,
        result.offset,
        &fractions,
        0.1,
        12,
    ))
}

/// The grasp as a glTF binary scene with the approach-and-close animation.
pub fn glb_bytes(
    hand: &HandModel,
    object: &ObjectModel,
    result: &GraspResult,
    skin: Option<&prehensile_formats::SkinnedMesh>,
) -> Result<Vec<u8>, CliError> {
    Ok(prehensile_formats::grasp_glb(
        object.mesh(),
        hand,
        &keyframes(hand, result)?,
        skin,
    ))
}

/// Parses `--up`.
pub fn up_axis(s: &str) -> Result<Vec3, CliError> {
    match s {
        "x" => Ok(Vec3::x()),
        "y" => Ok(Vec3::y()),
        "z" => Ok(Vec3::z()),
        other => Err(CliError::Usage(format!("--up {other}: use x, y or z"))),
    }
}

/// Runs `prehensile grasp`.
pub fn run(args: &GraspArgs) -> Result<i32, CliError> {
    let setup = Instant::now();
    let hold_engine = prehensile_sim::Engine::from_name(&args.hold_engine).ok_or_else(|| {
        CliError::Usage(format!(
            "unknown --hold-engine '{}'; choose one of {}",
            args.hold_engine,
            prehensile_sim::Engine::NAMES.join(", ")
        ))
    })?;
    // The hand and the object need nothing of each other: read and set up side by side (a
    // scan's setup and a robot hand's file each take milliseconds).
    let (hand, object) = rayon::join(
        || sources::hand(&args.hand),
        || {
            sources::object(
                &args.object,
                args.mesh_options.factor(),
                args.mesh_options.weld,
            )
        },
    );
    let (hand, mut object) = (hand?, object?);
    if let Some(h) = args.hook {
        object = object.with_hooks(vec![Point3::from(h)])?;
    }
    let up = up_axis(&args.up)?;
    let hook = object.hooks()[0];
    let shoulder = args
        .shoulder
        .map(Point3::from)
        .unwrap_or_else(|| default_shoulder(&hand, &hook, &up));
    let budget = match args.budget_ms {
        Some(ms) if ms.is_finite() && ms > 0.0 && ms <= MAX_BUDGET_MS => {
            Some(Duration::from_secs_f64(ms / 1000.0))
        }
        Some(ms) => {
            return Err(CliError::Usage(format!(
                "--budget-ms {ms:e} must be a positive number of milliseconds, at most {MAX_BUDGET_MS} (a day)"
            )))
        }
        None => None,
    };
    if args.threads == Some(0) {
        return Err(CliError::Usage(
            "--threads 0: use 1 or more (the default is one per core)".into(),
        ));
    }
    let request = GraspRequest {
        movement: args.movement.clone(),
        shoulder,
        params: SearchParams {
            seed: args.seed,
            up,
            weights: args
                .weights
                .map(|[gdist, fdist, tdist, wdist, stability]| QualityWeights {
                    gdist,
                    fdist,
                    tdist,
                    wdist,
                    stability,
                }),
            validity: args.validity,
            one_sided_patience: args.one_sided_patience,
            contact_model: ContactModel {
                friction: args.friction,
                ..ContactModel::default()
            },
            threads: args
                .threads
                .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from)),
            ..SearchParams::default()
        },
        budget,
    };
    if args.fill_grid {
        object.collider().fill_grid();
    }
    let setup_ms = setup.elapsed().as_secs_f64() * 1e3;
    let (result, took) = search(&hand, &object, &request, true)?;
    let hold = if args.hold {
        Some(prehensile_sim::scenarios::hold_test_of_result(
            &hand,
            &object,
            &result,
            hold_engine,
        )?)
    } else {
        None
    };
    let mut record = serde_json::to_value(&result)?;
    if let (Some(h), Some(map)) = (&hold, record.as_object_mut()) {
        map.insert("hold".into(), serde_json::to_value(h)?);
    }
    let json = serde_json::to_string_pretty(&record)?;
    match &args.out {
        Some(path) => std::fs::write(path, &json).map_err(crate::CliError::file("write", path))?,
        None if args.svg.is_none() && args.glb.is_none() && args.bvh.is_none() => {
            out!("{json}")
        }
        None => {}
    }
    if let Some(path) = &args.glb {
        // A skinned glTF hand also brings its own mesh, posed by the bones.
        let is_gltf = [".glb", ".gltf"]
            .iter()
            .any(|e| args.hand.to_ascii_lowercase().ends_with(e));
        let skin = if is_gltf {
            Some(prehensile_formats::load_hand_gltf_skinned(std::path::Path::new(&args.hand))?.1)
        } else {
            None
        };
        std::fs::write(path, glb_bytes(&hand, &object, &result, skin.as_ref())?)
            .map_err(crate::CliError::file("write", path))?;
    }
    if let Some(path) = &args.bvh {
        let text = prehensile_formats::write_bvh(&hand, &keyframes(&hand, &result)?, 12.0);
        std::fs::write(path, text).map_err(crate::CliError::file("write", path))?;
    }
    if let Some(path) = &args.svg {
        std::fs::write(path, picture::grasp_svg(&object, &result))
            .map_err(crate::CliError::file("write", path))?;
    }
    let status = if result.valid {
        "valid grasp".to_string()
    } else {
        format!(
            "no valid grasp: {}",
            result.invalid_reason.as_deref().unwrap_or("unknown")
        )
    };
    eprintln!(
        "{} on {}: {} ({}), fingers touching: {}, search {:.1} ms (reading and setting up hand and object: {:.1} ms)",
        hand.name(),
        object.name(),
        status,
        result.movement,
        if result.fingers_touching.is_empty() {
            "none".to_string()
        } else {
            result.fingers_touching.join(", ")
        },
        took.as_secs_f64() * 1e3,
        setup_ms
    );
    // A search the budget stopped says so: a larger budget may find a (better) grasp.
    if let (PlannerStatus::Searching, Some(ms)) = (result.status, args.budget_ms) {
        eprintln!(
            "--budget-ms {ms} ended the search after {} step(s), before its stop rule",
            result.stats.steps
        );
    }
    if let Some(h) = &hold {
        let held: Vec<&str> = h
            .directions
            .iter()
            .filter(|d| d.held)
            .map(|d| d.direction)
            .collect();
        eprintln!(
            "hold test ({} engine, alpha {}, {:.1} g object): held against gravity along {} of 6 directions ({})",
            h.engine.name(),
            h.alpha,
            h.object_mass_kg * 1e3,
            h.held,
            if held.is_empty() { "none".to_string() } else { held.join(" ") }
        );
    }
    Ok(if result.valid { 0 } else { 1 })
}
