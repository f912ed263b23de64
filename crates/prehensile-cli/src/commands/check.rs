//! `prehensile check MESH`: is this mesh a usable object?

use prehensile_formats::read_mesh;

use crate::args::CheckArgs;
use crate::CliError;

/// Prints the mesh report; exit code 2 when the mesh has defects.
pub fn run(args: &CheckArgs) -> Result<i32, CliError> {
    let mut mesh = read_mesh(&args.mesh, args.mesh_options.factor())?;
    if let Some(w) = args.mesh_options.weld {
        if !(w.is_finite() && w > 0.0) {
            return Err(CliError::Usage(format!(
                "--weld {w} must be a positive number of metres"
            )));
        }
        let (welded, merged) = mesh.weld_within(w);
        eprintln!("note: merged {merged} vertices closer than {w:.1e} m");
        mesh = welded;
    }
    let name = args.mesh.display().to_string();
    let check = prehensile_core::object::MeshCheck::new(&name, mesh);
    let (report, parts, repairs) = (&check.report, check.parts, &check.repairs);
    if args.json {
        out!("{}", serde_json::to_string_pretty(&check)?);
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
        out!("  volume (signed)     {:.6e} m³", report.volume);
        if let (Some(rule), Some(volume)) = (check.inside_rule, check.object_volume) {
            out!("  inside from         {rule}");
            out!("  object volume       {volume:.6e} m³");
        }
        out!(
            "  size                {:.4} x {:.4} x {:.4} m",
            report.size[0],
            report.size[1],
            report.size[2]
        );
    }
    // Within what an object may be, but not what one hand holds: say so, with the likely units.
    let size = report.size.iter().copied().fold(0.0, f64::max);
    if check.grasp_accepts && !(0.005..=2.0).contains(&size) {
        eprintln!(
            "note: {name}: {size:.3} m across is {} for an object held in one hand. {}",
            if size > 2.0 { "large" } else { "small" },
            prehensile_core::object::units_hint(size)
        );
    }
    if check.grasp_accepts {
        for d in &report.defects {
            eprintln!("note: {name}: {d}");
        }
        for r in repairs {
            eprintln!("repair: {name}: {r}");
        }
        if let Some(w) = check.weld_closes_at {
            eprintln!(
                "hint: {name}: --weld {w:e} closes the holes exactly (a clean closed surface: the search runs on its fast path)"
            );
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
    } else {
        // The defects, then what made the search refuse the mesh (a defective mesh may still
        // be accepted by its winding number, so the defects alone do not say why).
        for d in &report.defects {
            eprintln!("note: {name}: {d}");
        }
        eprintln!(
            "error: {name}: {}",
            check.grasp_error.as_deref().unwrap_or("refused")
        );
        eprintln!("{name}: prehensile grasp refuses this mesh");
        Ok(2)
    }
}
