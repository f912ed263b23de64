//! Capsule–object collision (§6.4.1): "does this capsule touch the surface or lie inside?"
//!
//! Two paths: [`TriangleBvh::capsule_touches`] is exact; [`MeshCollider::capsule_touches`] first
//! asks a [`SignedDistanceGrid`] and falls back to the exact path only when the grid's bounds do
//! not decide, so both always give the same answer. The simulation's contacts read a second,
//! finer grid ([`MeshCollider::contact_grid`]): a coarse grid costs the search fewer
//! nearest-triangle queries, a fine one the contacts less interpolation error. A mesh that is
//! not a clean closed manifold
//! has its inside from winding numbers (`fast_winding_number`). With holes it has only the exact
//! path: a signed distance whose sign flips across a hole, away from any triangle, is not the
//! Lipschitz function the grid's bounds need. Closed parts that overlap keep the search's grid
//! for its yes/no tests (their winding number changes only across triangles), but not its
//! distance bounds, nor the contact grid (see [`MeshCollider::from_exact`]).

mod boundary_fan;
mod capsule_contact;
mod fast_winding_number;
mod inside_volume;
mod node_slab;
mod signed_distance_grid;
mod triangle_bvh;
mod winding_cost;

pub use boundary_fan::BoundaryFan;
pub use capsule_contact::CapsuleContact;
pub use fast_winding_number::{triangle_solid_angle, WindingNumberTree};
pub use inside_volume::{inside_volume_and_centroid, overlaps_itself, InsideVolume};
pub use signed_distance_grid::{Decision, SignedDistanceGrid, SEARCH_SPACING};
pub use triangle_bvh::{SurfacePoint, TriangleBvh};
pub use winding_cost::{WindingCost, MOST_WINDING_TERMS};

use std::sync::OnceLock;

use crate::math::Point3;

/// An unfilled distance grid around `exact`'s mesh, `margin` metres past it, nodes at least
/// `least_spacing` apart.
fn grid_around(exact: &TriangleBvh, margin: f64, least_spacing: f64) -> SignedDistanceGrid {
    let (lo, hi) = exact.bounds();
    SignedDistanceGrid::new(lo, hi, margin, least_spacing)
}

/// A capsule in world coordinates: the segment `a–b` swept by a sphere of `radius`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Capsule {
    /// First segment end.
    pub a: Point3,
    /// Second segment end.
    pub b: Point3,
    /// Radius in metres.
    pub radius: f64,
}

/// Counts of collision queries and the tests built on them, to report what a search cost.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct CollisionCounters {
    /// Capsule queries asked.
    pub queries: u64,
    /// Queries the distance grid could not decide and the exact path answered.
    pub exact_fallbacks: u64,
    /// Hand placements checked by TranslateToFree (the thesis's v, summed).
    pub placements: u64,
    /// Poses whose contacts were found and tested for force closure.
    pub stability_tests: u64,
}

/// Both collision paths for one object.
#[derive(Debug, Clone)]
pub struct MeshCollider {
    exact: TriangleBvh,
    /// The grid of the search's yes/no tests, at least [`SEARCH_SPACING`] apart.
    fast: Option<SignedDistanceGrid>,
    /// The finer grid a simulation's contacts interpolate (64 nodes a side), whose error
    /// shrinks with the square of its spacing: made on a simulation's first contact query
    /// (a search never reads it), filled only where read.
    contact: OnceLock<Option<SignedDistanceGrid>>,
    /// How far both grids reach past the mesh (metres).
    margin: f64,
}

impl MeshCollider {
    /// The colliders around an exact path: with the distance grids (`margin` metres beyond the
    /// mesh) when its signs come from pseudo-normals, alone when from winding numbers across
    /// holes. A mesh of closed parts that overlap (whole winding numbers,
    /// [`TriangleBvh::signs_change_only_at_the_surface`]) gets the search's grid for its yes/no
    /// tests, which give the exact answers. Its distances are right outside the object but
    /// inside they measure to the nearest triangle, buried ones too, so it gets no contact grid
    /// (whose gradients are contact normals) and no
    /// [clearance bounds](MeshCollider::segment_clearance_upper_bound). Those bounds stay valid,
    /// but they move where TranslateToFree's leaps (at least 4 mm) land, and there the leaps
    /// passed thin free gaps that plain 4 mm steps stop in: on a box overlapped by a sphere,
    /// 4 of 10 Shadow hand grasps held in ≥ 5 directions with them, 10 of 10 without
    /// (docs/PERFORMANCE.md).
    pub fn from_exact(exact: TriangleBvh, margin: f64) -> Self {
        Self {
            fast: exact
                .signs_change_only_at_the_surface()
                .then(|| grid_around(&exact, margin, SEARCH_SPACING)),
            exact,
            contact: OnceLock::new(),
            margin,
        }
    }

    /// The exact path.
    pub fn exact(&self) -> &TriangleBvh {
        &self.exact
    }

    /// The distance grid of the search's capsule tests (none for a mesh with holes, whose inside
    /// is from winding numbers).
    pub fn grid(&self) -> Option<&SignedDistanceGrid> {
        self.fast.as_ref()
    }

    /// The finer distance grid a simulation's contacts are interpolated from
    /// ([`Self::capsule_contact`]); none for a mesh whose inside is from winding numbers.
    pub fn contact_grid(&self) -> Option<&SignedDistanceGrid> {
        self.contact
            .get_or_init(|| {
                (!self.exact.uses_winding_numbers())
                    .then(|| grid_around(&self.exact, self.margin, 0.0))
            })
            .as_ref()
    }

    /// Fills the search's whole distance grid now ([`SignedDistanceGrid::fill_all`]) rather
    /// than node by node as searches read it; returns how many nodes it filled (0 without a
    /// grid). The contact grid stays filled on demand.
    pub fn fill_grid(&self) -> usize {
        self.fast
            .as_ref()
            .map_or(0, |grid| grid.fill_all(&self.exact))
    }

    /// An upper bound on the smallest signed distance along segment `a–b` (+∞ when the grid
    /// cannot bound it, or there is no grid, or the inside is from winding numbers), from the
    /// distance grid; only a bound below
    /// `below` is asked for (at or above it, some number at least `below`; pass `f64::INFINITY`
    /// for the tightest bound the grid gives).
    pub fn segment_clearance_upper_bound(&self, a: &Point3, b: &Point3, below: f64) -> f64 {
        match &self.fast {
            Some(grid) if !self.exact.uses_winding_numbers() => {
                grid.segment_clearance_upper_bound(&self.exact, a, b, below)
            }
            _ => f64::INFINITY,
        }
    }

    /// Fast test, same answer as the exact one: does the capsule touch or lie inside the object?
    /// A capsule with a NaN coordinate or radius touches nothing.
    pub fn capsule_touches(&self, capsule: &Capsule, counters: &mut CollisionCounters) -> bool {
        counters.queries += 1;
        if capsule
            .a
            .coords
            .iter()
            .chain(capsule.b.coords.iter())
            .any(|x| x.is_nan())
            || capsule.radius.is_nan()
        {
            return false;
        }
        let Some(fast) = &self.fast else {
            counters.exact_fallbacks += 1;
            return self
                .exact
                .capsule_touches(&capsule.a, &capsule.b, capsule.radius);
        };
        match fast.decide(&self.exact, &capsule.a, &capsule.b, capsule.radius) {
            Decision::Touches => true,
            Decision::Free => false,
            Decision::Unsure { from, to, outside } => {
                counters.exact_fallbacks += 1;
                let (a, b) = (capsule.a, capsule.b);
                let (p, q) = (a + (b - a) * from, a + (b - a) * to);
                // No surface near the unproven part and the rest proven clear: the capsule is
                // wholly outside or wholly inside, and `outside` or one inside test says which.
                self.exact.segment_within(&p, &q, capsule.radius)
                    || (!outside && self.exact.signed_distance(&a) < 0.0)
            }
        }
    }
}
