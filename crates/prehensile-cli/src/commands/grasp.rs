//! `prehensile grasp`: one hand, one object, one grasp.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use prehensile_core::animation::{result_keyframes, Keyframe};
use prehensile_core::search::{
    find_grasp, Evaluation, GraspOptions, GraspRequest, GraspResult, PlannerStatus, SearchSink,
    SearchStats,
};
use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::Outputs;
use prehensile_sim::scenarios::{hold_test_of_result, HoldReport};

use crate::args::GraspArgs;
use crate::{picture, sources, CliError};

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

/// Keyframes of the result ([`result_keyframes`]).
fn keyframes(hand: &HandModel, result: &GraspResult) -> Result<Vec<Keyframe>, CliError> {
    Ok(result_keyframes(hand, result)?)
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

/// The request as the user gave it: the library checks and resolves it.
fn grasp_options(args: &GraspArgs) -> GraspOptions {
    GraspOptions {
        movement: args.movement.clone(),
        hook: args.hook,
        shoulder: args.shoulder,
        up: args.up,
        seed: args.seed,
        threads: args.threads,
        weights: args.weights.clone(),
        friction: args.friction,
        validity: args.validity,
        one_sided_patience: args.one_sided_patience,
        budget_ms: args.budget_ms,
    }
}

/// The output files, checked against the inputs before anything is searched.
fn claim_outputs(args: &GraspArgs) -> Result<Outputs, CliError> {
    let mut outputs = Outputs::reading([&args.hand, &args.object]);
    for path in [&args.out, &args.svg, &args.glb, &args.bvh]
        .into_iter()
        .flatten()
    {
        outputs.claim(path)?;
    }
    Ok(outputs)
}

/// The hand and the object, read and set up side by side (a scan's setup and a robot hand's
/// file each take milliseconds), the object hung from the requested hook.
fn load_inputs(
    args: &GraspArgs,
    options: &GraspOptions,
) -> Result<(HandModel, ObjectModel), CliError> {
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
    if let Some(hook) = options.hook_point()? {
        object = object.with_hooks(vec![hook])?;
    }
    if args.fill_grid {
        object.collider().fill_grid();
    }
    Ok((hand, object))
}

/// Writes every output asked for: the JSON (to standard output when no file is asked for), the
/// glTF scene, the BVH motion and the SVG picture.
fn write_outputs(
    args: &GraspArgs,
    outputs: &Outputs,
    (hand, object): (&HandModel, &ObjectModel),
    result: &GraspResult,
    hold: Option<&HoldReport>,
) -> Result<(), CliError> {
    let mut record = serde_json::to_value(result)?;
    if let (Some(h), Some(map)) = (hold, record.as_object_mut()) {
        map.insert("hold".into(), serde_json::to_value(h)?);
    }
    let json = serde_json::to_string_pretty(&record)?;
    match &args.out {
        Some(path) => outputs.write(path, json.as_bytes())?,
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
        outputs.write(path, &glb_bytes(hand, object, result, skin.as_ref())?)?;
    }
    if let Some(path) = &args.bvh {
        let text = prehensile_formats::write_bvh(hand, &keyframes(hand, result)?, 12.0);
        outputs.write(path, text.as_bytes())?;
    }
    if let Some(path) = &args.svg {
        outputs.write(path, picture::grasp_svg(object, result).as_bytes())?;
    }
    Ok(())
}

/// Runs `prehensile grasp`.
pub fn run(args: &GraspArgs) -> Result<i32, CliError> {
    let setup = Instant::now();
    let outputs = claim_outputs(args)?;
    let options = grasp_options(args);
    let (hand, object) = load_inputs(args, &options)?;
    let request = options.request(&hand, &object)?;
    let setup_ms = setup.elapsed().as_secs_f64() * 1e3;
    let (result, took) = search(&hand, &object, &request, true)?;
    let hold = if args.hold {
        Some(hold_test_of_result(
            &hand,
            &object,
            &result,
            args.hold_engine,
        )?)
    } else {
        None
    };
    write_outputs(args, &outputs, (&hand, &object), &result, hold.as_ref())?;
    print_summary(args, (&hand, &object), &result, (took, setup_ms));
    if let Some(h) = &hold {
        print_hold(h);
    }
    Ok(if result.valid { 0 } else { 1 })
}

/// One line on standard error: the grasp, its fingers and the time it took.
fn print_summary(
    args: &GraspArgs,
    (hand, object): (&HandModel, &ObjectModel),
    result: &GraspResult,
    (took, setup_ms): (Duration, f64),
) {
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
}

/// One line on standard error: what the hold test held.
fn print_hold(h: &HoldReport) {
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
