//! Times blocks of simulation steps on request, for side-by-side timing with another engine
//! that takes turns with it block by block (tools/benchmark/mujoco_side_by_side.py).
//!
//! `cargo run --release -p prehensile-sim --example step_timing -- [--engine ENGINE] HAND DT...`
//! builds, for every step length DT (seconds), the hand HAND (a hand file or built-in name)
//! holding the built-in sphere still ([`prehensile_sim::scenarios::held_still`], the default
//! solver for DT; ENGINE `reduced`, the default, or `rapier`), prints `ready`,
//! then answers each line `DT STEPS` on standard input with the median microseconds per step of
//! that many steps, timed in blocks of 100. The published numbers come from the criterion
//! benchmark (`cargo bench -p prehensile-bench --bench simulation`); this only lets the two
//! engines alternate closely enough that the machine's drift cancels in their ratio.

use std::io::BufRead;
use std::time::Instant;

use prehensile_core::{shapes, ObjectModel};
use prehensile_sim::scenarios::held_still;
use prehensile_sim::{Engine, Settings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let engine = if args.first().is_some_and(|a| a == "--engine") && args.len() > 1 {
        let name = args.drain(..2).nth(1).unwrap_or_default();
        name.parse::<Engine>().map_err(|e| e.to_string())?
    } else {
        Engine::default()
    };
    let Some((hand, steps)) = args.split_first() else {
        return Err(
            "usage: step_timing [--engine reduced|rapier] HAND DT... (e.g. human 0.0002 0.001)"
                .into(),
        );
    };
    let hand = prehensile_formats::builtin_hand(hand).map_or_else(
        || prehensile_formats::load_hand(std::path::Path::new(hand)),
        Ok,
    )?;
    let sphere = ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None)?;
    let mut scenes = Vec::new();
    for dt in steps {
        let dt: f64 = dt
            .parse()
            .map_err(|_| format!("step length '{dt}' is not a number"))?;
        let settings = Settings {
            engine,
            ..Settings::for_step(dt)
        };
        scenes.push((dt, held_still(&hand, &sphere, settings)?));
    }
    println!("ready");
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let mut words = line.split_whitespace();
        let (Some(dt), Some(count)) = (words.next(), words.next()) else {
            return Err(format!("expected 'DT STEPS', got '{line}'").into());
        };
        let (dt, count): (f64, usize) = (dt.parse()?, count.parse()?);
        let Some((_, sim)) = scenes.iter_mut().find(|(d, _)| (*d - dt).abs() < 1e-12) else {
            return Err(format!("no scene for step length {dt}").into());
        };
        let mut blocks = Vec::new();
        for _ in 0..count.div_ceil(100) {
            let start = Instant::now();
            for _ in 0..100 {
                sim.step()?;
            }
            blocks.push(start.elapsed().as_secs_f64() * 1e6 / 100.0);
        }
        blocks.sort_by(f64::total_cmp);
        println!("{}", blocks[blocks.len() / 2]);
    }
    Ok(())
}
