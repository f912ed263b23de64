//! `prehensile fit`: a grasp controller (setpoints, neutral pose, limits) fitted to one example
//! motion (Pollard & Zordan §4–5.1), written as TOML.

use std::path::Path;

use prehensile_control::{
    fit_controller, BaseMotion, ControllerFile, Gains, Motion, MOTION_SCHEMA,
};
use prehensile_core::math::Vec3;
use prehensile_core::HandModel;

use prehensile_formats::Outputs;

use crate::args::FitArgs;
use crate::{sources, CliError};

/// Runs the command.
pub fn run(args: &FitArgs) -> Result<i32, CliError> {
    let mut outputs = Outputs::reading(
        [Some(args.hand.as_ref()), args.motion.as_deref()]
            .into_iter()
            .flatten()
            .map(std::path::Path::new),
    );
    outputs.claim(&args.out)?;
    let example_path = args.out.with_extension("motion.json");
    if args.motion.is_none() {
        outputs.claim(&example_path)?;
    }
    let hand = sources::hand(&args.hand)?;
    let gains = Gains::grasp();
    let (motion, open_while_closing) = match &args.motion {
        Some(path) => (read_motion(&hand, path)?, false),
        None => {
            let object = sources::object(&args.object, 1.0, None)?;
            let grasp = prehensile_sim::scenarios::plan_grasp(&hand, &object)?;
            let motion = grasp.example(&hand, &gains);
            let json = serde_json::to_string_pretty(&motion)?;
            outputs.write(&example_path, json.as_bytes())?;
            out!(
                "wrote {} (the synthetic example of a grasp of '{}')",
                example_path.display(),
                object.name()
            );
            (motion, true)
        }
    };
    // The example's wrist is upright: gravity along the palm frame's −z by default.
    let base = BaseMotion::at_rest(Vec3::new(0.0, 0.0, -9.81));
    let controller = fit_controller(&hand, &motion, gains, open_while_closing, &base)?;
    let text = ControllerFile::new(&hand, &controller).to_toml();
    outputs.write(&args.out, text.as_bytes())?;
    out!(
        "fitted {} frames ({:.2} s) for hand '{}'; wrote {}",
        motion.frames.len(),
        motion.frames.len() as f64 * motion.frame_time,
        hand.name(),
        args.out.display()
    );
    Ok(0)
}

/// A motion from JSON (`prehensile.motion/1`) or BVH.
fn read_motion(hand: &HandModel, path: &Path) -> Result<Motion, CliError> {
    let text = std::fs::read_to_string(path).map_err(crate::CliError::file("read", path))?;
    let source = path.display().to_string();
    let is_bvh = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("bvh"));
    if !is_bvh {
        let motion: Motion = serde_json::from_str(&text).map_err(|e| {
            CliError::Usage(format!("{source}: {e} (expected {MOTION_SCHEMA} JSON)"))
        })?;
        motion.check(hand.dof_names())?;
        return Ok(motion);
    }
    let bvh = prehensile_formats::parse_bvh(&text, &source)?;
    let frames = bvh.joint_angles(hand, &source)?;
    // Distance: how far the root is from where it is at the most closed frame.
    let closed = (0..frames.len())
        .max_by(|&a, &b| {
            let sum = |t: usize| frames[t].iter().sum::<f64>();
            sum(a).total_cmp(&sum(b))
        })
        .unwrap_or(0);
    let root_channels: Vec<usize> = ["Xposition", "Yposition", "Zposition"]
        .iter()
        .filter_map(|c| bvh.joints.first()?.channels.iter().position(|n| n == c))
        .collect();
    if root_channels.len() != 3 {
        return Err(CliError::Usage(format!(
            "{source}: the root joint has no X/Y/Z position channels, so the hand–object distance is unknown; write a {MOTION_SCHEMA} JSON with distances instead"
        )));
    }
    let at = |t: usize| Vec3::from_iterator(root_channels.iter().map(|&c| bvh.frames[t][c]));
    let distances = (0..frames.len())
        .map(|t| (at(t) - at(closed)).norm())
        .collect();
    let motion = Motion {
        schema: MOTION_SCHEMA.into(),
        dof_names: hand.dof_names().to_vec(),
        frame_time: bvh.frame_time,
        frames,
        distances,
        release_frame: None,
    };
    motion.check(hand.dof_names())?;
    Ok(motion)
}
