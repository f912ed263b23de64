//! `prehensile demo`: every built-in hand on every built-in object, on defaults.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use prehensile_core::search::{GraspOptions, GraspResult};
use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::{write_file, BUILTIN_HANDS, BUILTIN_OBJECTS};

use crate::args::DemoArgs;
use crate::commands::grasp::{glb_bytes, search};
use crate::{picture, sources, CliError};

/// Copies the built viewer's page (`index.html`, and `main.js` with the core inlined) into
/// `out/viewer`; false when `viewer` holds no built viewer.
fn copy_viewer(viewer: &Path, out: &Path) -> Result<bool, CliError> {
    let files = ["index.html", "main.js"];
    if !files.iter().all(|f| viewer.join(f).is_file()) {
        return Ok(false);
    }
    for f in files {
        let bytes =
            std::fs::read(viewer.join(f)).map_err(CliError::file("read", &viewer.join(f)))?;
        write_file(&out.join("viewer").join(f), &bytes)?;
    }
    Ok(true)
}

/// The gallery's head, with a line on the browser viewer (copied into the folder or not).
fn gallery_head(viewer_copied: bool) -> String {
    let mut gallery = String::from("<!doctype html><meta charset=utf-8><title>Prehensile demo</title><style>body{font-family:sans-serif;background:#fafafa}figure{display:inline-block;margin:8px;background:#fff;border:1px solid #ddd}figcaption{padding:4px 8px;font-size:13px}</style><h1>Prehensile demo</h1>\n");
    let line = if viewer_copied {
        "<p>In 3D, live: <a href=\"viewer/index.html\">the browser viewer</a> (opens from this folder; drag the object and the hand re-grasps, drop your own meshes and hands on it). Each result below opens in it with the command under its picture, or drop its .json on the page.</p>"
    } else {
        "<p>In 3D, live: <code>bash tools/viewer/build.sh &amp;&amp; prehensile view</code> serves the browser viewer on http://127.0.0.1:8000/ (drag the object and the hand re-grasps); built before the demo, it is copied into this folder too. Each result below opens in it with the command under its picture.</p>"
    };
    let _ = writeln!(gallery, "{line}");
    gallery
}

/// The table's columns, as wide as their longest entry (`human-left`, `precision-wide`).
struct Table {
    hand: usize,
    movement: usize,
    lines: Vec<String>,
}

impl Table {
    fn new(hands: &[HandModel]) -> Self {
        let hand = hands.iter().map(|h| h.name().len()).fold(4, usize::max);
        let movement = hands
            .iter()
            .flat_map(|h| h.movements().iter().map(|m| m.name().len()))
            .fold("movement".len(), usize::max);
        let header = format!(
            "{:<hand$} {:<9} {:<movement$} {:>8} {:<6} {:<32} {:>8}",
            "hand", "object", "movement", "quality", "valid", "fingers touching", "time ms"
        );
        Self {
            hand,
            movement,
            lines: vec![header],
        }
    }

    fn add(
        &mut self,
        hand: &HandModel,
        object: &ObjectModel,
        result: &GraspResult,
        took: Duration,
    ) {
        let (hw, mw) = (self.hand, self.movement);
        self.lines.push(format!(
            "{:<hw$} {:<9} {:<mw$} {:>8} {:<6} {:<32} {:>8.1}",
            hand.name(),
            object.name(),
            result.movement,
            result.quality.map_or("-inf".into(), |q| format!("{q:.4}")),
            if result.valid { "yes" } else { "no" },
            result.fingers_touching.join(","),
            took.as_secs_f64() * 1e3
        ));
    }
}

/// Grasps `object` with `hand` on the defaults and writes the result's JSON, SVG picture and
/// glTF scene; returns the result, how long the search took and the gallery's figure.
fn grasp_one(
    args: &DemoArgs,
    hand: &HandModel,
    object: &ObjectModel,
) -> Result<(GraspResult, Duration, String), CliError> {
    let options = GraspOptions {
        seed: args.seed,
        ..GraspOptions::default()
    };
    let request = options.request(hand, object)?;
    let (result, took) = search(hand, object, &request, false)?;
    let stem = format!("{}-{}", hand.name(), object.name());
    let file = |ext: &str| args.out.join(format!("{stem}{ext}"));
    write_file(
        &file(".json"),
        serde_json::to_string_pretty(&result)?.as_bytes(),
    )?;
    write_file(
        &file(".svg"),
        picture::grasp_svg(object, &result).as_bytes(),
    )?;
    write_file(&file(".glb"), &glb_bytes(hand, object, &result, None)?)?;
    let figure = format!(
        "<figure><img src=\"{stem}.svg\" width=520><figcaption>{} on {}: {} grasp, {}, fingers touching: {} (<a href=\"{stem}.glb\">glTF scene</a>)<br><code>prehensile view {}</code></figcaption></figure>",
        hand.name(),
        object.name(),
        result.movement,
        if result.valid { "valid" } else { "not valid" },
        result.fingers_touching.join(", "),
        [".json", ".glb"].map(|e| file(e).display().to_string()).join(" ")
    );
    Ok((result, took, figure))
}

/// Runs the demo and writes `<hand>-<object>.json`, `.svg`, `.glb` and an `index.html` gallery.
pub fn run(args: &DemoArgs) -> Result<i32, CliError> {
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
    let mut table = Table::new(&hands);
    let mut gallery = gallery_head(copy_viewer(&args.viewer, &args.out)?);
    let mut invalid = 0;
    for hand in &hands {
        for object in &objects {
            bar.set_message(format!("{} on {}", hand.name(), object.name()));
            let (result, took, figure) = grasp_one(args, hand, object)?;
            invalid += usize::from(!result.valid);
            table.add(hand, object, &result, took);
            let _ = writeln!(gallery, "{figure}");
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    write_file(&args.out.join("index.html"), gallery.as_bytes())?;
    for line in &table.lines {
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
