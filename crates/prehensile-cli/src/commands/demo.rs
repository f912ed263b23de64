//! `prehensile demo`: every built-in hand on every built-in object, on defaults.

use std::fmt::Write as _;

use indicatif::{ProgressBar, ProgressStyle};
use prehensile_core::math::Vec3;
use prehensile_core::shapes::BUILTIN_OBJECTS;
use prehensile_formats::BUILTIN_HANDS;

use crate::args::DemoArgs;
use crate::commands::grasp::{glb_bytes, search};
use crate::{picture, sources, CliError};
use prehensile_core::search::{default_shoulder, GraspRequest, SearchParams, AUTO_MOVEMENT};

/// Copies the built viewer's page (`index.html`, and `main.js` with the core inlined) into
/// `out/viewer`; false when `viewer` holds no built viewer.
fn copy_viewer(viewer: &std::path::Path, out: &std::path::Path) -> Result<bool, CliError> {
    let files = ["index.html", "main.js"];
    if !files.iter().all(|f| viewer.join(f).is_file()) {
        return Ok(false);
    }
    let to = out.join("viewer");
    std::fs::create_dir_all(&to).map_err(CliError::file("create", &to))?;
    for f in files {
        std::fs::copy(viewer.join(f), to.join(f)).map_err(CliError::file("write", &to.join(f)))?;
    }
    Ok(true)
}

/// Runs the demo and writes `<hand>-<object>.json`, `.svg` and an `index.html` gallery.
pub fn run(args: &DemoArgs) -> Result<i32, CliError> {
    std::fs::create_dir_all(&args.out).map_err(crate::CliError::file("create", &args.out))?;
    let hands: Vec<_> = BUILTIN_HANDS
        .iter()
        .map(|h| sources::hand(h))
        .collect::<Result<_, _>>()?;
    let objects: Vec<_> = BUILTIN_OBJECTS
        .iter()
        .map(|o| sources::object(o, 1.0, None))
        .collect::<Result<_, _>>()?;
    let bar = ProgressBar::new((hands.len() * objects.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("valid template"),
    );
    // Columns as wide as their longest entry (`human-left`, `precision-wide`).
    let hand_width = hands.iter().map(|h| h.name().len()).fold(4, usize::max);
    let movement_width = hands
        .iter()
        .flat_map(|h| h.movements().iter().map(|m| m.name().len()))
        .fold("movement".len(), usize::max);
    let mut table = vec![format!(
        "{:<hand_width$} {:<9} {:<movement_width$} {:>8} {:<6} {:<32} {:>8}",
        "hand", "object", "movement", "quality", "valid", "fingers touching", "time ms"
    )];
    let mut gallery = String::from("<!doctype html><meta charset=utf-8><title>Prehensile demo</title><style>body{font-family:sans-serif;background:#fafafa}figure{display:inline-block;margin:8px;background:#fff;border:1px solid #ddd}figcaption{padding:4px 8px;font-size:13px}</style><h1>Prehensile demo</h1>\n");
    if copy_viewer(&args.viewer, &args.out)? {
        let _ = writeln!(
            gallery,
            "<p>In 3D, live: <a href=\"viewer/index.html\">the browser viewer</a> (opens from this folder; drag the object and the hand re-grasps, drop your own meshes and hands on it). Each result below opens in it with the command under its picture, or drop its .json on the page.</p>"
        );
    } else {
        let _ = writeln!(
            gallery,
            "<p>In 3D, live: <code>bash tools/viewer/build.sh &amp;&amp; prehensile view</code> serves the browser viewer on http://127.0.0.1:8000/ (drag the object and the hand re-grasps); built before the demo, it is copied into this folder too. Each result below opens in it with the command under its picture.</p>"
        );
    }
    let mut invalid = 0;
    for hand in &hands {
        for object in &objects {
            bar.set_message(format!("{} on {}", hand.name(), object.name()));
            let up = Vec3::z();
            let request = GraspRequest {
                movement: AUTO_MOVEMENT.into(),
                shoulder: default_shoulder(hand, &object.hooks()[0], &up),
                params: SearchParams {
                    seed: args.seed,
                    up,
                    threads: std::thread::available_parallelism().map_or(1, usize::from),
                    ..SearchParams::default()
                },
                budget: None,
            };
            let (result, took) = search(hand, object, &request, false)?;
            let stem = format!("{}-{}", hand.name(), object.name());
            let json = serde_json::to_string_pretty(&result)?;
            write(&args.out.join(format!("{stem}.json")), &json)?;
            write(
                &args.out.join(format!("{stem}.svg")),
                &picture::grasp_svg(object, &result),
            )?;
            let glb = args.out.join(format!("{stem}.glb"));
            std::fs::write(&glb, glb_bytes(hand, object, &result, None)?)
                .map_err(crate::CliError::file("write", &glb))?;
            if !result.valid {
                invalid += 1;
            }
            table.push(format!(
                "{:<hand_width$} {:<9} {:<movement_width$} {:>8} {:<6} {:<32} {:>8.1}",
                hand.name(),
                object.name(),
                result.movement,
                result.quality.map_or("-inf".into(), |q| format!("{q:.4}")),
                if result.valid { "yes" } else { "no" },
                result.fingers_touching.join(","),
                took.as_secs_f64() * 1e3
            ));
            let _ = writeln!(
                gallery,
                "<figure><img src=\"{stem}.svg\" width=520><figcaption>{} on {}: {} grasp, {}, fingers touching: {} (<a href=\"{stem}.glb\">glTF scene</a>)<br><code>prehensile view {}</code></figcaption></figure>",
                hand.name(),
                object.name(),
                result.movement,
                if result.valid { "valid" } else { "not valid" },
                result.fingers_touching.join(", "),
                [".json", ".glb"]
                    .map(|e| args.out.join(format!("{stem}{e}")).display().to_string())
                    .join(" ")
            );
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    write(&args.out.join("index.html"), &gallery)?;
    for line in &table {
        out!("{line}");
    }
    out!(
        "\nwrote {} results (JSON, SVG picture, animated glTF scene) and {}; open it in a browser",
        hands.len() * objects.len(),
        args.out.join("index.html").display()
    );
    if invalid > 0 {
        out!("{invalid} combination(s) found no valid grasp; their JSON says why");
    }
    Ok(0)
}

fn write(path: &std::path::Path, text: &str) -> Result<(), CliError> {
    super::write_file(path, text.as_bytes())
}
