//! `prehensile grasp`: one hand, one object, one grasp.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::default_shoulder;
use prehensile_core::search::{
    Evaluation, GraspPlanner, GraspResult, QualityWeights, SearchParams, SearchSink, SearchStats,
    ValidityRule,
};
use prehensile_core::stability::ContactModel;
use prehensile_core::{HandModel, ObjectModel, Workspace};

use crate::args::GraspArgs;
use crate::{picture, sources, CliError};

/// The largest `--budget-ms`: a day.
const MAX_BUDGET_MS: f64 = 86_400_000.0;

/// A resolved grasp request.
pub struct Request<'a> {
    /// The hand.
    pub hand: &'a HandModel,
    /// The object (hooks set).
    pub object: &'a ObjectModel,
    /// Movement name or `auto`.
    pub movement: &'a str,
    /// Shoulder, world.
    pub shoulder: Point3,
    /// Up direction.
    pub up: Vec3,
    /// Seed.
    pub seed: u64,
    /// Time budget per movement.
    pub budget: Option<Duration>,
    /// Quality weights, or the movement's defaults.
    pub weights: Option<QualityWeights>,
    /// Which grasps are valid.
    pub validity: ValidityRule,
    /// How contacts resist forces.
    pub contact_model: ContactModel,
    /// Show a spinner with the search's progress on a terminal.
    pub progress: bool,
}

/// Shows the search's progress on a spinner.
struct SpinnerSink {
    bar: ProgressBar,
    movement: String,
    best: Option<f64>,
}

impl SearchSink for SpinnerSink {
    fn step(&mut self, stats: &SearchStats, _current: &Evaluation) {
        let best = self
            .best
            .map_or("none yet".to_string(), |q| format!("{q:.4}"));
        self.bar.set_message(format!(
            "{}: step {}, {} poses, best valid quality {best}",
            self.movement, stats.steps, stats.evaluations
        ));
        self.bar.tick();
    }

    fn improved(&mut self, best: &Evaluation) {
        self.best = Some(best.quality);
    }
}

/// Runs the search for one movement, or for each movement with `auto`, and returns the chosen
/// result with the wall time it took.
///
/// `auto` tries the hand's authored movements (the generic `close` only when there are none) and
/// keeps, among valid results, the one that holds best: the largest Ferrari–Canny ε, then the
/// smallest gDist. Qualities of different movements use different formulas (Eq. 5.1 and 5.2)
/// and are not compared.
pub fn search(req: &Request) -> Result<(GraspResult, Duration), CliError> {
    let names: Vec<&str> = if req.movement == "auto" {
        let authored: Vec<&str> = req
            .hand
            .movements()
            .iter()
            .map(|m| m.name())
            .filter(|n| *n != "close")
            .collect();
        if authored.is_empty() {
            vec!["close"]
        } else {
            authored
        }
    } else {
        vec![req.movement]
    };
    let began = Instant::now();
    let mut best: Option<GraspResult> = None;
    for name in names {
        let movement = req.hand.movement(name).ok_or_else(|| {
            CliError(format!(
                "hand '{}' has no movement '{name}'; it has {}, or use auto",
                req.hand.name(),
                req.hand
                    .movements()
                    .iter()
                    .map(|m| m.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
        let params = SearchParams {
            seed: req.seed,
            up: req.up,
            weights: req.weights,
            validity: req.validity,
            contact_model: req.contact_model,
            ..SearchParams::default()
        };
        let mut planner = GraspPlanner::new(req.hand, req.object, movement, req.shoulder, params)
            .map_err(CliError::from_display)?;
        let bar = if req.progress {
            ProgressBar::new_spinner()
        } else {
            ProgressBar::hidden()
        };
        bar.set_style(ProgressStyle::with_template("{spinner} {msg}").expect("valid template"));
        let mut sink = SpinnerSink {
            bar,
            movement: name.to_string(),
            best: None,
        };
        match req.budget {
            Some(b) => planner.run_for_into(b, &mut sink),
            None => planner.run_to_end_into(&mut sink),
        };
        sink.bar.finish_and_clear();
        let mut ws = Workspace::new(req.hand);
        let result = GraspResult::from_planner(&planner, &mut ws);
        let better = match &best {
            None => true,
            Some(b) => {
                (result.valid, result.stability.epsilon, -result.terms.gdist)
                    > (b.valid, b.stability.epsilon, -b.terms.gdist)
            }
        };
        if better {
            best = Some(result);
        }
    }
    Ok((best.expect("at least one movement"), began.elapsed()))
}

/// Keyframes of the result: approach from 10 cm back over one second, close over one second.
fn keyframes(
    hand: &HandModel,
    result: &GraspResult,
) -> Result<Vec<prehensile_core::animation::Keyframe>, CliError> {
    let movement = hand.movement(&result.movement).ok_or_else(|| {
        CliError(format!(
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
        other => Err(CliError(format!("--up {other}: use x, y or z"))),
    }
}

/// Runs `prehensile grasp`.
pub fn run(args: &GraspArgs) -> Result<i32, CliError> {
    let setup = Instant::now();
    let hand = sources::hand(&args.hand)?;
    let mut object = sources::object(
        &args.object,
        args.mesh_options.factor(),
        args.mesh_options.weld,
    )?;
    if let Some(h) = args.hook {
        object = object
            .with_hooks(vec![Point3::from(h)])
            .map_err(CliError::from_display)?;
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
            return Err(CliError(format!(
                "--budget-ms {ms:e} must be a positive number of milliseconds, at most {MAX_BUDGET_MS} (a day)"
            )))
        }
        None => None,
    };
    let request = Request {
        hand: &hand,
        object: &object,
        movement: &args.movement,
        shoulder,
        up,
        seed: args.seed,
        budget,
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
        contact_model: ContactModel {
            friction: args.friction,
            ..ContactModel::default()
        },
        progress: true,
    };
    let setup_ms = setup.elapsed().as_secs_f64() * 1e3;
    let (result, took) = search(&request)?;
    let hold = if args.hold {
        Some(hold_test(&hand, &object, &result)?)
    } else {
        None
    };
    let mut record = serde_json::to_value(&result).map_err(CliError::from_display)?;
    if let (Some(h), Some(map)) = (&hold, record.as_object_mut()) {
        map.insert(
            "hold".into(),
            serde_json::to_value(h).map_err(CliError::from_display)?,
        );
    }
    let json = serde_json::to_string_pretty(&record).map_err(CliError::from_display)?;
    match &args.out {
        Some(path) => std::fs::write(path, &json)
            .map_err(|e| CliError(format!("cannot write {}: {e}", path.display())))?,
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
            Some(
                prehensile_formats::load_hand_gltf_skinned(std::path::Path::new(&args.hand))
                    .map_err(CliError::from_display)?
                    .1,
            )
        } else {
            None
        };
        std::fs::write(path, glb_bytes(&hand, &object, &result, skin.as_ref())?)
            .map_err(|e| CliError(format!("cannot write {}: {e}", path.display())))?;
    }
    if let Some(path) = &args.bvh {
        let text = prehensile_formats::write_bvh(&hand, &keyframes(&hand, &result)?, 12.0);
        std::fs::write(path, text)
            .map_err(|e| CliError(format!("cannot write {}: {e}", path.display())))?;
    }
    if let Some(path) = &args.svg {
        std::fs::write(path, picture::grasp_svg(&object, &result))
            .map_err(|e| CliError(format!("cannot write {}: {e}", path.display())))?;
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
        result.fingers_touching.join(", "),
        took.as_secs_f64() * 1e3,
        setup_ms
    );
    if let Some(h) = &hold {
        let held: Vec<&str> = h
            .directions
            .iter()
            .filter(|d| d.held)
            .map(|d| d.direction)
            .collect();
        eprintln!(
            "hold test (rapier, alpha {}, {:.1} g object): held against gravity along {} of 6 directions ({})",
            h.alpha,
            h.object_mass_kg * 1e3,
            h.held,
            if held.is_empty() { "none".to_string() } else { held.join(" ") }
        );
    }
    Ok(if result.valid { 0 } else { 1 })
}

/// Runs the rapier hold test of the found grasp (gravity along each axis direction).
fn hold_test(
    hand: &HandModel,
    object: &ObjectModel,
    result: &GraspResult,
) -> Result<prehensile_sim::scenarios::HoldReport, CliError> {
    use prehensile_sim::scenarios::{hold_test, PlannedGrasp, HOLD_ALPHA};
    let grasp = PlannedGrasp::from_result(hand, result).map_err(CliError::from_display)?;
    hold_test(
        hand,
        object,
        &grasp,
        prehensile_sim::Settings::default(),
        HOLD_ALPHA,
    )
    .map_err(CliError::from_display)
}
