//! `prehensile simulate`: one of the paper's scenarios on rapier or the reduced engine, with a
//! progress bar, a JSON report and optional animations.

use indicatif::{ProgressBar, ProgressStyle};
use prehensile_formats::Outputs;
use prehensile_sim::scenarios::{self, Options, Recording, RunReport};
use prehensile_sim::{Engine, RapierSettings, Settings};

use crate::args::SimulateArgs;
use crate::{sources, CliError};

/// The run as the user gave it: the library checks it.
fn options(args: &SimulateArgs) -> Result<Options, CliError> {
    if args.engine == Engine::Reduced
        && (args.iterations.is_some() || args.inner_iterations.is_some())
    {
        return Err(CliError::Usage(
            "--iterations and --inner-iterations set rapier's solver, and the reduced engine has \
             none (it sweeps its contacts until they settle): drop them, or add --engine rapier"
                .into(),
        ));
    }
    let hand = sources::hand(&args.hand)?;
    let objects = args
        .object
        .iter()
        .map(|spec| {
            sources::object(
                spec.trim(),
                args.mesh_options.factor(),
                args.mesh_options.weld,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let step = RapierSettings::for_step(args.dt);
    Ok(Options {
        hand,
        objects,
        alpha: args.alpha,
        settings: Settings {
            friction: args.friction,
            object_density: args.density,
            engine: args.engine,
            rapier: RapierSettings {
                solver_iterations: args.iterations.unwrap_or(step.solver_iterations),
                inner_iterations: args.inner_iterations.unwrap_or(step.inner_iterations),
                ..step
            },
            ..Settings::for_step(args.dt)
        },
        seconds: args.seconds,
        candidates: args.candidates,
    })
}

/// Runs the command; exit code 0, or 1 when the run diverged.
pub fn run(args: &SimulateArgs) -> Result<i32, CliError> {
    let mut outputs = Outputs::reading(std::iter::once(&args.hand).chain(&args.object));
    for path in [Some(&args.out), args.glb.as_ref(), args.bvh.as_ref()]
        .into_iter()
        .flatten()
    {
        outputs.claim(path)?;
    }
    let options = options(args)?;
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{msg:28} [{bar:30}] {percent:>3}%")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let mut progress = |label: &str, fraction: f64| {
        bar.set_message(label.to_string());
        bar.set_position((fraction * 1000.0) as u64);
    };
    let (report, recording) = scenarios::run(args.scenario, &options, &mut progress)?;
    bar.finish_and_clear();
    outputs.write(&args.out, serde_json::to_string_pretty(&report)?.as_bytes())?;
    print_cases(&report)?;
    out!("wrote {}", args.out.display());
    write_animations(args, &outputs, &options, &recording)?;
    Ok(if report.finite { 0 } else { 1 })
}

/// A line per case with its outcome, and its metrics.
fn print_cases(report: &RunReport) -> Result<(), CliError> {
    for case in &report.cases {
        let held = case.held.map_or(String::new(), |h| format!(", held {h}"));
        let slip = case
            .object_slip_m
            .map_or(String::new(), |s| format!(", slip {:.1} mm", s * 1e3));
        let force = case
            .mean_contact_force_n
            .map_or(String::new(), |f| format!(", contact force {f:.2} N"));
        out!(
            "{}: finite {}{held}{slip}{force}, penetration {:.2} mm, {:.1}× real time",
            case.label,
            case.finite,
            case.max_penetration_m * 1e3,
            case.realtime_factor
        );
        for (name, value) in &case.metrics {
            out!("    {name} = {value:.4}");
        }
        if let Some(d) = &case.diverged {
            out!("    stopped: {d}");
        }
    }
    Ok(())
}

/// The first case as an animated glTF scene (every hand and the object) and its first hand as
/// BVH, when asked for.
fn write_animations(
    args: &SimulateArgs,
    outputs: &Outputs,
    options: &Options,
    recording: &Recording,
) -> Result<(), CliError> {
    if let Some(path) = &args.glb {
        let object = recording
            .object
            .as_ref()
            .map(|(o, track)| (o.mesh(), &track[..]));
        let hands: Vec<_> = recording
            .hands
            .iter()
            .map(|(hand, frames)| (hand, &frames[..]))
            .collect();
        outputs.write(path, &prehensile_formats::simulation_glb(object, &hands))?;
        out!("wrote {}", path.display());
    }
    if let (Some(path), Some((hand, frames))) = (&args.bvh, recording.hands.first()) {
        let fps = options.settings.record_fps;
        outputs.write(
            path,
            prehensile_formats::write_bvh(hand, frames, fps).as_bytes(),
        )?;
        out!("wrote {}", path.display());
    }
    Ok(())
}
