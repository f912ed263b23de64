//! The stages of [`super::ObjectModel::new`]: exact repairs that leave the shape unchanged, the
//! inside of a clean closed surface or from winding numbers, and the default hook.

use crate::collision::{
    inside_volume_and_centroid, BoundaryFan, MeshCollider, TriangleBvh, WindingCost,
};
use crate::math::Point3;
use crate::mesh::{MeshReport, TriangleMesh};

use super::repair::{Repair, Unclean};
use super::{ObjectError, ENCLOSED_FRACTION, VOLUME_CELLS};

/// How far the distance grid reaches past the mesh, metres: far enough to cover a hand closing
/// on it.
const GRID_REACH: f64 = 0.03;

/// What an object's inside is: its collider, volume and centre of mass.
pub(super) struct Inside {
    /// The collider, signed by that inside.
    pub collider: MeshCollider,
    /// Volume, m³.
    pub volume: f64,
    /// Centre of mass (uniform density), object frame.
    pub center_of_mass: Point3,
}

/// The repairs that leave the shape unchanged: collapsed, cancelling and duplicate triangles
/// dropped; triangles facing against their neighbours turned; slivers of a closed mesh split
/// away; an inside-out closed mesh turned. Returns the mesh and its report.
pub(super) fn exact_repairs(
    mesh: TriangleMesh,
    repairs: &mut Vec<Repair>,
) -> (TriangleMesh, MeshReport) {
    let (mut mesh, dropped) = mesh.drop_cancelling_triangles();
    let counted = [
        (dropped.collapsed, Repair::Collapsed as fn(usize) -> Repair),
        (dropped.cancelling_pairs, Repair::CancellingPairs),
        (dropped.duplicates, Repair::Duplicates),
    ];
    repairs.extend(
        counted
            .into_iter()
            .filter(|(n, _)| *n > 0)
            .map(|(n, r)| r(n)),
    );
    let mut report = mesh.report();
    if report.inconsistent_edges > 0 && report.boundary_edges + report.non_manifold_edges == 0 {
        if let Some((oriented, turned)) = mesh.oriented() {
            repairs.push(Repair::Turned(turned));
            mesh = oriented;
            report = mesh.report();
        }
    }
    let edges_clean =
        report.boundary_edges + report.non_manifold_edges + report.inconsistent_edges == 0;
    if edges_clean && report.degenerate_triangles > 0 {
        let (fixed, removed) = mesh.remove_degenerate_triangles();
        let fixed_report = fixed.report();
        if fixed_report.degenerate_triangles == 0 {
            repairs.push(Repair::SliversSplit(removed));
            mesh = fixed;
            report = fixed_report;
        }
    }
    if edges_clean && report.degenerate_triangles == 0 && report.volume < 0.0 {
        mesh = mesh.flipped();
        repairs.push(Repair::InsideOut);
        report = mesh.report();
    }
    (mesh, report)
}

/// A clean closed surface: pseudo-normal signs, the distance grid, and the divergence
/// theorem's volume and centroid.
pub(super) fn closed_surface_inside(mesh: &TriangleMesh, exact: TriangleBvh) -> Inside {
    let (volume, center_of_mass) = mesh.volume_and_centroid();
    Inside {
        collider: MeshCollider::from_exact(exact, GRID_REACH),
        volume,
        center_of_mass,
    }
}

/// Any other mesh: inside is where the generalized winding number exceeds ½, volume and centre
/// of mass integrated over that inside. Refuses a mesh that encloses nothing (a flat or
/// single-sided sheet) or whose winding numbers would each sum nearly every triangle.
pub(super) fn winding_number_inside(
    mesh: &TriangleMesh,
    exact: TriangleBvh,
    report: &MeshReport,
    why: Unclean,
    dropped: usize,
    repairs: &mut Vec<Repair>,
) -> Result<Inside, ObjectError> {
    // A mesh flat along an axis bounds nothing, however its winding numbers would come out:
    // say so before spending anything on them.
    if report.size.contains(&0.0) {
        return Err(ObjectError::NoInside { why });
    }
    // Closed parts that overlap keep the distance grids; holes leave the exact path.
    let whole = mesh.unbalanced_edges().is_empty();
    // Zero-area triangles, dropped before, change no crossing count; the fan is over the
    // boundary the winding tree sees, without them (none when every edge is balanced).
    let fan = if whole {
        Some(BoundaryFan::default())
    } else {
        BoundaryFan::new(mesh)
    };
    let exact = if whole {
        exact.into_whole_winding_numbers()
    } else {
        exact.into_winding_numbers()
    };
    let cost = WindingCost::probe(&exact, mesh);
    if !cost.affordable() {
        let WindingCost { costly, probes } = cost;
        return Err(ObjectError::CostlyInside {
            why,
            costly,
            probes,
        });
    }
    let collider = MeshCollider::from_exact(exact, GRID_REACH);
    let cells = if fan.as_ref().is_some_and(BoundaryFan::is_empty) {
        VOLUME_CELLS
    } else {
        VOLUME_CELLS / 4
    };
    let inside = inside_volume_and_centroid(collider.exact(), cells, fan.as_ref());
    let encloses = inside.volume > ENCLOSED_FRACTION * report.size.iter().product::<f64>();
    if !encloses {
        return Err(ObjectError::NoInside { why });
    }
    if dropped > 0 {
        repairs.push(Repair::ZeroAreaDropped(dropped));
    }
    repairs.push(Repair::WindingInside {
        why,
        volume: inside.volume,
        keeps_grid: whole,
    });
    Ok(Inside {
        collider,
        volume: inside.volume,
        center_of_mass: inside.centroid,
    })
}

/// The default hook: the centre of mass, or, for separate parts with the centre of mass
/// between them, the largest part's centre instead of empty space. (One part with its centre
/// of mass outside its material, as a mug's, keeps it: the hand closes around the cavity.)
pub(super) fn default_hook(
    mesh: &TriangleMesh,
    inside: &Inside,
    repairs: &mut Vec<Repair>,
) -> Point3 {
    let parts = mesh.components();
    if parts.len() > 1 && !inside.collider.exact().inside(&inside.center_of_mass) {
        let largest = TriangleMesh {
            vertices: mesh.vertices.clone(),
            triangles: parts[0].iter().map(|&t| mesh.triangles[t]).collect(),
        };
        repairs.push(Repair::HookOnLargestPart { parts: parts.len() });
        largest.volume_and_centroid().1
    } else {
        inside.center_of_mass
    }
}
