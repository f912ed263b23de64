//! `prehensile check MESH`: is this mesh a usable object?

use prehensile_formats::read_mesh;

use crate::args::CheckArgs;
use crate::CliError;

/// Prints the mesh report; exit code 2 when the mesh has defects.
pub fn run(args: &CheckArgs) -> Result<i32, CliError> {
    let mut mesh =
        read_mesh(&args.mesh, args.mesh_options.factor()).map_err(CliError::from_display)?;
    if let Some(w) = args.mesh_options.weld {
        if !(w.is_finite() && w > 0.0) {
            return Err(CliError(format!(
                "--weld {w} must be a positive number of metres"
            )));
        }
        let (welded, merged) = mesh.weld_within(w);
        eprintln!("note: merged {merged} vertices closer than {w:.1e} m");
        mesh = welded;
    }
    let report = mesh.report();
    let parts = mesh.components().len();
    // What `grasp` will do with it: the same exact repairs and checks (plausible size too).
    let name = args.mesh.display().to_string();
    let verdict = prehensile_core::ObjectModel::new(&name, mesh, None);
    let repairs: Vec<String> = verdict
        .as_ref()
        .map(|o| o.repairs().to_vec())
        .unwrap_or_default();
    if args.json {
        let mut value = serde_json::to_value(&report).map_err(CliError::from_display)?;
        if let Some(map) = value.as_object_mut() {
            map.insert("repairs".into(), serde_json::json!(repairs));
            map.insert("parts".into(), serde_json::json!(parts));
            map.insert("grasp_accepts".into(), serde_json::json!(verdict.is_ok()));
            map.insert(
                "grasp_error".into(),
                serde_json::json!(verdict.as_ref().err().map(|e| e.to_string())),
            );
        }
        out!(
            "{}",
            serde_json::to_string_pretty(&value).map_err(CliError::from_display)?
        );
    } else {
        out!("{}", args.mesh.display());
        out!("  triangles           {}", report.triangles);
        out!("  vertices (welded)   {}", report.vertices);
        out!("  separate parts      {parts}");
        out!(
            "  closed              {}",
            if report.boundary_edges == 0 {
                "yes"
            } else {
                "no"
            }
        );
        out!("  boundary edges      {}", report.boundary_edges);
        out!("  non-manifold edges  {}", report.non_manifold_edges);
        out!("  flipped edges       {}", report.inconsistent_edges);
        out!("  degenerate triangles {}", report.degenerate_triangles);
        out!("  volume              {:.6e} m³", report.volume);
        out!(
            "  size                {:.4} x {:.4} x {:.4} m",
            report.size[0],
            report.size[1],
            report.size[2]
        );
    }
    // Within what an object may be, but not what one hand holds: say so, with the likely units.
    let size = report.size.iter().copied().fold(0.0, f64::max);
    if verdict.is_ok() && !(0.005..=2.0).contains(&size) {
        eprintln!(
            "note: {name}: {size:.3} m across is {} for an object held in one hand. {}",
            if size > 2.0 { "large" } else { "small" },
            prehensile_core::object::units_hint(size)
        );
    }
    match verdict {
        Ok(_) => {
            for d in &report.defects {
                eprintln!("note: {name}: {d}");
            }
            for r in &repairs {
                eprintln!("repair: {name}: {r}");
            }
            eprintln!(
                "{name}: prehensile grasp accepts this mesh{}",
                if repairs.is_empty() {
                    ""
                } else {
                    " after the repairs above"
                }
            );
            Ok(0)
        }
        Err(e) => {
            for d in &report.defects {
                eprintln!("error: {name}: {d}");
            }
            if report.defects.is_empty() {
                eprintln!("error: {name}: {e}");
            }
            eprintln!("{name}: prehensile grasp refuses this mesh");
            Ok(2)
        }
    }
}
