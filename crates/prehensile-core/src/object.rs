//! The graspable object (§3.2, §5.2.2): a checked closed mesh, its mass properties, hooks and
//! collision structures, built once and shared read-only.

use crate::collision::{Capsule, CollisionCounters, MeshCollider};
use crate::math::Point3;
use crate::mesh::{MeshError, MeshReport, TriangleMesh};

/// Smallest object size accepted (largest side), metres.
pub const MIN_OBJECT_SIZE: f64 = 1e-3;
/// Largest object size accepted (largest side), metres.
pub const MAX_OBJECT_SIZE: f64 = 100.0;

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
    repairs: Vec<String>,
}

impl ObjectModel {
    /// Checks the mesh (closed, manifold, consistent, no degenerate triangles, plausible size),
    /// computes its mass properties and builds its colliders. Hooks default to the centre of mass.
    ///
    /// Zero-area triangles are removed without changing the shape when they are the only defect
    /// (see [`TriangleMesh::remove_degenerate_triangles`]); [`ObjectModel::repairs`] says so.
    pub fn new(
        name: &str,
        mesh: TriangleMesh,
        hooks: Option<Vec<Point3>>,
    ) -> Result<Self, ObjectError> {
        let (mut mesh, collapsed, pairs) = mesh.drop_cancelling_triangles();
        let mut repairs = Vec::new();
        if collapsed > 0 {
            repairs.push(format!(
                "dropped {collapsed} collapsed triangle(s) (a vertex repeated); the shape is unchanged"
            ));
        }
        if pairs > 0 {
            repairs.push(format!(
                "dropped {pairs} pair(s) of coincident triangles wound opposite ways (they cancel); the shape is unchanged"
            ));
        }
        let mut report = mesh.report();
        let only_slivers = report.degenerate_triangles > 0
            && report.boundary_edges + report.non_manifold_edges + report.inconsistent_edges == 0;
        if only_slivers {
            let (fixed, removed) = mesh.remove_degenerate_triangles();
            let fixed_report = fixed.report();
            if fixed_report.defects.is_empty() {
                repairs.push(format!(
                    "removed {removed} zero-area triangle(s) by splitting their neighbours; the shape is unchanged"
                ));
                mesh = fixed;
                report = fixed_report;
            }
        }
        let size = report.size.iter().copied().fold(0.0, f64::max);
        if !(MIN_OBJECT_SIZE..=MAX_OBJECT_SIZE).contains(&size) {
            return Err(ObjectError::AbsurdSize { size });
        }
        if !report.defects.is_empty() {
            return Err(MeshError::Defective(Box::new(report)).into());
        }
        let (_, center_of_mass) = mesh.volume_and_centroid();
        // The collider first: the default hook must be on the object.
        // The distance grid reaches 3 cm past the mesh: far enough to cover a hand closing on it.
        let collider = MeshCollider::new(&mesh, 0.03);
        let parts = mesh.components();
        let hooks = hooks.unwrap_or_else(|| {
            // Several separate parts with the centre of mass between them: hook the largest
            // part's centre instead of empty space. (One part with its centre of mass outside
            // its material, as a mug's, keeps it: the hand closes around the cavity.)
            if parts.len() > 1 && collider.exact().signed_distance(&center_of_mass) > 0.0 {
                let largest = TriangleMesh {
                    vertices: mesh.vertices.clone(),
                    triangles: parts[0].iter().map(|&t| mesh.triangles[t]).collect(),
                };
                repairs.push(format!(
                    "the mesh has {} separate parts and its centre of mass lies between them; the hook is the largest part's centre",
                    parts.len()
                ));
                vec![largest.volume_and_centroid().1]
            } else {
                vec![center_of_mass]
            }
        });
        for (i, h) in hooks.iter().enumerate() {
            if !h.iter().all(|c| c.is_finite()) {
                return Err(ObjectError::BadHook(i));
            }
        }
        Ok(Self {
            name: name.to_string(),
            mesh,
            report,
            center_of_mass,
            hooks,
            collider,
            repairs,
        })
    }

    /// What was repaired when the object was built (empty when nothing was).
    pub fn repairs(&self) -> &[String] {
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
            .any(|r| r.contains("2 separate parts")));
        // One part whose centre of mass lies outside its material (the mug) keeps it.
        let mug =
            ObjectModel::new("mug", crate::shapes::builtin_object("mug").unwrap(), None).unwrap();
        assert_eq!(mug.hooks()[0], mug.center_of_mass());
    }
}

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
    pub repairs: Vec<String>,
    /// Whether the search accepts the mesh.
    pub grasp_accepts: bool,
    /// Why not, when not.
    pub grasp_error: Option<String>,
}

impl MeshCheck {
    /// Checks `mesh` (named `name` in messages).
    pub fn new(name: &str, mesh: TriangleMesh) -> Self {
        let report = mesh.report();
        let parts = mesh.components().len();
        let verdict = ObjectModel::new(name, mesh, None);
        Self {
            report,
            parts,
            repairs: verdict
                .as_ref()
                .map(|o| o.repairs().to_vec())
                .unwrap_or_default(),
            grasp_accepts: verdict.is_ok(),
            grasp_error: verdict.err().map(|e| e.to_string()),
        }
    }
}
