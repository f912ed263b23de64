//! The graspable object (§3.2, §5.2.2): a checked closed mesh, its mass properties, hooks and
//! collision structures, built once and shared read-only.

use crate::collision::{
    overlaps_itself, Capsule, CollisionCounters, MeshCollider, TriangleBvh, MOST_WINDING_TERMS,
};
use crate::math::Point3;
use crate::mesh::{MeshError, MeshReport, TriangleMesh};

mod repair;
mod setup_stages;

pub use repair::{Repair, Unclean};
use setup_stages::{closed_surface_inside, default_hook, exact_repairs, winding_number_inside};

/// Smallest object size accepted (largest side), metres.
pub const MIN_OBJECT_SIZE: f64 = 1e-3;
/// Largest object size accepted (largest side), metres.
pub const MAX_OBJECT_SIZE: f64 = 100.0;

/// Lines along the longer horizontal side when the inside's volume is integrated
/// ([`crate::collision::inside_volume_and_centroid`]): within 1% on the shapes tested. A quarter as many when the
/// winding number varies between crossings (open or inconsistent meshes), where each line near
/// the boundary samples the fan's winding number at several points instead of counting alone.
const VOLUME_CELLS: usize = 256;
/// Lines along the longer horizontal side scanned for space a closed mesh covers twice.
const OVERLAP_SCAN_CELLS: usize = 64;
/// Below this fraction of its bounding box, an inside counts as no volume at all (a flat card,
/// a single-sided sheet).
const ENCLOSED_FRACTION: f64 = 1e-4;

/// Why a mesh cannot become a graspable object.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ObjectError {
    /// The mesh itself is malformed or not closed.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The object is implausibly small or large, usually a units mistake.
    #[error("the object is {size:.3e} m across; expected between {MIN_OBJECT_SIZE} m and {MAX_OBJECT_SIZE} m. {}", units_hint(*size))]
    AbsurdSize {
        /// Largest side in metres.
        size: f64,
    },
    /// The mesh bounds no volume: a flat or single-sided sheet.
    #[error("the mesh encloses no volume ({why}); a flat or single-sided sheet cannot be grasped as a solid: give it thickness (e.g. Blender's Solidify modifier) or close it")]
    NoInside {
        /// What is wrong with the surface.
        why: Unclean,
    },
    /// The mesh's triangles crowd so closely around every point that each winding-number
    /// inside test would sum nearly all of them (see [`crate::collision::WindingCost`]).
    #[error("deciding what is inside this mesh would take too long ({why}): at {costly} of {probes} points in and around it, one winding number needs more than {MOST_WINDING_TERMS} triangle terms, because a great many triangles lie close to every point (e.g. thousands of faces sharing one edge, or a polygon of thousands of sides fanned from one corner); remove the extra faces or close the mesh, so that its inside comes from distances")]
    CostlyInside {
        /// What is wrong with the surface.
        why: Unclean,
        /// Probe points whose query exceeded the cap.
        costly: usize,
        /// Points probed.
        probes: usize,
    },
    /// A hook is not a finite point.
    #[error("hook {0} is not a finite point")]
    BadHook(usize),
}

/// What to change so that an object `size` metres across gets a plausible size.
pub fn units_hint(size: f64) -> String {
    let plausible = |s: f64| (MIN_OBJECT_SIZE..=MAX_OBJECT_SIZE).contains(&s);
    if plausible(size * 0.001) {
        return "Is it in millimetres? Use --units mm".into();
    }
    if plausible(size * 0.01) {
        return "Is it in centimetres? Use --units cm".into();
    }
    if !(size.is_finite() && size > 0.0) {
        return "Check its coordinates".into();
    }
    // The power of ten that makes it about 10 cm across.
    let factor = 10f64.powf((0.1 / size).log10().round());
    format!(
        "Check its units; --scale {factor:e} would make it {:.3} m across",
        size * factor
    )
}

/// A closed triangle mesh ready for grasping: mass properties, hooks, colliders.
#[derive(Debug, Clone)]
pub struct ObjectModel {
    name: String,
    mesh: TriangleMesh,
    report: MeshReport,
    center_of_mass: Point3,
    hooks: Vec<Point3>,
    collider: MeshCollider,
    repairs: Vec<Repair>,
}

impl ObjectModel {
    /// Checks the mesh (plausible size, an inside of some volume), computes its mass properties
    /// and builds its colliders. Hooks default to the centre of mass.
    ///
    /// Exact repairs that leave the shape unchanged come first: collapsed triangles,
    /// coincident opposite pairs and same-wound duplicates are dropped, zero-area slivers removed by splitting their
    /// neighbours, an inside-out closed mesh turned the right way, vertices no triangle uses
    /// dropped. A clean closed manifold then
    /// gets pseudo-normal signs and the distance grid. Any other mesh — open, non-manifold,
    /// inconsistently wound, or of overlapping parts — gets its inside from generalized winding
    /// numbers, and its volume and centre of mass from that inside. [`ObjectModel::repairs`]
    /// says what was done.
    pub fn new(
        name: &str,
        mesh: TriangleMesh,
        hooks: Option<Vec<Point3>>,
    ) -> Result<Self, ObjectError> {
        let mut repairs = Vec::new();
        let (mesh, mut report) = exact_repairs(mesh, &mut repairs);
        let size = report.size.iter().copied().fold(0.0, f64::max);
        if !(MIN_OBJECT_SIZE..=MAX_OBJECT_SIZE).contains(&size) {
            return Err(ObjectError::AbsurdSize { size });
        }
        // A mesh with defects takes the winding-number inside; a clean one too if it covers some
        // space twice (overlapping parts, a face pushed through another), which only the
        // hierarchy's crossings can tell.
        let defective = !report.defects.is_empty();
        let (mesh, dropped) = if defective {
            let (kept, dropped) = mesh.without_degenerate_triangles();
            if kept.triangles.is_empty() {
                return Err(MeshError::Empty.into());
            }
            (kept, dropped)
        } else {
            (mesh, 0)
        };
        let (mesh, unused) = mesh.without_unused_vertices();
        if unused > 0 {
            repairs.push(Repair::UnusedVertices(unused));
            report.vertices = mesh.vertices.len();
        }
        let exact = TriangleBvh::new(&mesh);
        let unclean = if defective {
            Some(Unclean::Defects(report.defects.clone()))
        } else {
            overlaps_itself(&exact, OVERLAP_SCAN_CELLS).then_some(Unclean::Overlaps)
        };
        let inside = match unclean {
            None => closed_surface_inside(&mesh, exact),
            Some(why) => winding_number_inside(&mesh, exact, &report, why, dropped, &mut repairs)?,
        };
        let hooks = match hooks {
            Some(hooks) => hooks,
            None => vec![default_hook(&mesh, &inside, &mut repairs)],
        };
        if let Some(i) = hooks.iter().position(|h| !h.iter().all(|c| c.is_finite())) {
            return Err(ObjectError::BadHook(i));
        }
        report.volume = inside.volume;
        Ok(Self {
            name: name.to_string(),
            mesh,
            report,
            center_of_mass: inside.center_of_mass,
            hooks,
            collider: inside.collider,
            repairs,
        })
    }

    /// What was repaired when the object was built (empty when nothing was).
    pub fn repairs(&self) -> &[Repair] {
        &self.repairs
    }

    /// The same object with other hooks.
    pub fn with_hooks(mut self, hooks: Vec<Point3>) -> Result<Self, ObjectError> {
        if let Some(i) = hooks.iter().position(|h| !h.iter().all(|c| c.is_finite())) {
            return Err(ObjectError::BadHook(i));
        }
        self.hooks = hooks;
        Ok(self)
    }

    /// Name of the object.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The welded mesh.
    pub fn mesh(&self) -> &TriangleMesh {
        &self.mesh
    }

    /// The mesh check.
    pub fn report(&self) -> &MeshReport {
        &self.report
    }

    /// Enclosed volume, m³.
    pub fn volume(&self) -> f64 {
        self.report.volume
    }

    /// Centre of mass for uniform density.
    pub fn center_of_mass(&self) -> Point3 {
        self.center_of_mass
    }

    /// Hooks (§5.2.2).
    pub fn hooks(&self) -> &[Point3] {
        &self.hooks
    }

    /// Both collision paths.
    pub fn collider(&self) -> &MeshCollider {
        &self.collider
    }

    /// Does the capsule touch or lie inside the object? (fast path, exact answer)
    #[inline]
    pub fn capsule_touches(&self, capsule: &Capsule, counters: &mut CollisionCounters) -> bool {
        self.collider.capsule_touches(capsule, counters)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn two_separate_cubes_are_hooked_on_the_larger_not_in_the_gap() {
        let small = crate::shapes::cuboid(Vec3::new(0.04, 0.04, 0.04));
        let large = crate::shapes::cuboid(Vec3::new(0.05, 0.05, 0.05));
        // The small cube 3 cm beyond the large one along x.
        let offset = Vec3::new(0.075, 0.0, 0.0);
        let n = large.vertices.len() as u32;
        let mut vertices = large.vertices.clone();
        vertices.extend(small.vertices.iter().map(|p| p + offset));
        let mut triangles = large.triangles.clone();
        triangles.extend(small.triangles.iter().map(|t| t.map(|v| v + n)));
        let mesh = TriangleMesh {
            vertices,
            triangles,
        };
        assert_eq!(mesh.components().len(), 2);
        let object = ObjectModel::new("two cubes", mesh, None).unwrap();
        let hook = object.hooks()[0];
        assert!(
            object.collider().exact().signed_distance(&hook) < 0.0,
            "{hook}"
        );
        assert!(hook.coords.norm() < 1e-9, "the large cube's centre: {hook}");
        assert!(object
            .repairs()
            .iter()
            .any(|r| matches!(r, Repair::HookOnLargestPart { parts: 2 })));
        // One part whose centre of mass lies outside its material (the mug) keeps it.
        let mug =
            ObjectModel::new("mug", crate::shapes::builtin_object("mug").unwrap(), None).unwrap();
        assert_eq!(mug.hooks()[0], mug.center_of_mass());
    }
}

/// Weld tolerances `check` tries on a mesh with holes, metres: hairline seams of exported scans.
const WELD_TRIALS: [f64; 3] = [1e-7, 1e-6, 1e-5];

/// What `check` says about a mesh: its topology report, and what the grasp search will do with
/// it (the same exact repairs and checks as [`ObjectModel::new`]).
#[derive(Debug, Clone, serde::Serialize)]
pub struct MeshCheck {
    /// Counts of triangles, vertices, open, non-manifold and flipped edges; volume and size.
    #[serde(flatten)]
    pub report: MeshReport,
    /// Separate connected parts.
    pub parts: usize,
    /// Repairs the search makes before it accepts the mesh.
    pub repairs: Vec<Repair>,
    /// Whether the search accepts the mesh.
    pub grasp_accepts: bool,
    /// How the search decides inside from outside, when it accepts the mesh:
    /// `"closed surface"` (pseudo-normals and the distance grid) or `"winding number"`.
    pub inside_rule: Option<&'static str>,
    /// The volume the search uses (after repairs; of the winding-number inside), m³.
    pub object_volume: Option<f64>,
    /// For a mesh with holes: the smallest `--weld` tolerance (metres) that closes it into a
    /// clean surface, which the search handles on its fast path.
    pub weld_closes_at: Option<f64>,
    /// Why not, when not.
    pub grasp_error: Option<String>,
}

impl MeshCheck {
    /// Checks `mesh` (named `name` in messages).
    pub fn new(name: &str, mesh: TriangleMesh) -> Self {
        let report = mesh.report();
        let parts = mesh.components().len();
        let weld_closes_at = (report.boundary_edges > 0)
            .then(|| {
                WELD_TRIALS
                    .into_iter()
                    .find(|&w| mesh.weld_within(w).0.report().defects.is_empty())
            })
            .flatten();
        let verdict = ObjectModel::new(name, mesh, None);
        Self {
            report,
            parts,
            repairs: verdict
                .as_ref()
                .map(|o| o.repairs().to_vec())
                .unwrap_or_default(),
            grasp_accepts: verdict.is_ok(),
            inside_rule: verdict.as_ref().ok().map(|o| {
                if o.collider().exact().uses_winding_numbers() {
                    "winding number"
                } else {
                    "closed surface"
                }
            }),
            object_volume: verdict.as_ref().ok().map(|o| o.volume()),
            weld_closes_at,
            grasp_error: verdict.err().map(|e| e.to_string()),
        }
    }
}
