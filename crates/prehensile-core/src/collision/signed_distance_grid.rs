//! The fast path for capsule tests: exact signed distances sampled on a regular grid once per
//! object, queried with conservative bounds.
//!
//! The signed distance `s` is 1-Lipschitz, so a node value `s(g)` bounds every nearby point:
//! `s(g) - |p - g| <= s(p) <= s(g) + |p - g|`. A query answers from these bounds alone when they
//! decide it — a capsule far away costs one bounding-box test or one lookup — and otherwise
//! returns [`Decision::Unsure`] so the caller asks the exact path. The fast path therefore never
//! disagrees with the exact one: its error bound is zero, at the price of an exact query for
//! capsules within about one grid spacing of touching.

use crate::math::{Point3, Vec3};

use super::TriangleGrid;

/// Most nodes along the longest axis of the grid.
const MAX_NODES_PER_AXIS: usize = 64;

/// What the grid alone can say about a capsule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Decision {
    /// The capsule touches the surface or lies inside.
    Touches,
    /// The capsule is clear of the object.
    Free,
    /// The bounds do not decide; ask the exact path.
    Unsure,
}

/// Signed distances on a regular grid covering the object's bounds plus a margin.
#[derive(Debug, Clone)]
pub struct SignedDistanceGrid {
    origin: Point3,
    spacing: f64,
    dims: [usize; 3],
    values: Vec<f32>,
    mesh_min: Point3,
    mesh_max: Point3,
}

impl SignedDistanceGrid {
    /// Samples the exact signed distance of `exact` on a grid around bounds `(lo, hi)` padded by
    /// `margin` metres.
    pub fn new(exact: &TriangleGrid, lo: Point3, hi: Point3, margin: f64) -> Self {
        let origin = lo - Vec3::repeat(margin);
        let extent = (hi - lo) + Vec3::repeat(2.0 * margin);
        let spacing = (extent.max() / (MAX_NODES_PER_AXIS - 1) as f64).max(1e-9);
        let dims = [0, 1, 2].map(|i| ((extent[i] / spacing).ceil() as usize + 1).max(2));
        let mut values = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    let p = origin + Vec3::new(x as f64, y as f64, z as f64) * spacing;
                    values.push(exact.signed_distance(&p) as f32);
                }
            }
        }
        Self {
            origin,
            spacing,
            dims,
            values,
            mesh_min: lo,
            mesh_max: hi,
        }
    }

    /// Grid spacing in metres.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Node whose value bounds `p`, and the distance from `p` to it; `None` outside the grid.
    fn nearest_node(&self, p: &Point3) -> Option<(f64, f64)> {
        let mut idx = [0usize; 3];
        let mut offset = Vec3::zeros();
        for i in 0..3 {
            let f = ((p[i] - self.origin[i]) / self.spacing).round();
            if f < 0.0 || f >= self.dims[i] as f64 {
                return None;
            }
            idx[i] = f as usize;
            offset[i] = p[i] - (self.origin[i] + f * self.spacing);
        }
        let v = self.values[(idx[2] * self.dims[1] + idx[1]) * self.dims[0] + idx[0]] as f64;
        // Stored as f32: widen the distance by the rounding error of the value.
        let rounding = v.abs() * 1e-7 + 1e-9;
        Some((v, offset.norm() + rounding))
    }

    /// Lower bound on the distance from the segment's bounding box to the mesh's bounding box.
    fn box_gap(&self, a: &Point3, b: &Point3) -> f64 {
        let lo = a.inf(b);
        let hi = a.sup(b);
        let gap = Vec3::from_fn(|i, _| {
            (self.mesh_min[i] - hi[i]).max(lo[i] - self.mesh_max[i]).max(0.0)
        });
        gap.norm()
    }

    /// Decides from the grid whether capsule `a–b` with `radius` touches or is inside the object.
    pub fn decide(&self, a: &Point3, b: &Point3, radius: f64) -> Decision {
        if self.box_gap(a, b) > radius {
            return Decision::Free;
        }
        let mid = nalgebra::center(a, b);
        let half = (b - a).norm() * 0.5;
        if let Some((s, d)) = self.nearest_node(&mid) {
            if s + d <= radius {
                return Decision::Touches;
            }
            if s - d - half > radius {
                return Decision::Free;
            }
        }
        // Sample the segment at about the grid spacing.
        let pieces = ((2.0 * half / self.spacing).ceil() as usize).max(1);
        let reach = half / pieces as f64;
        let mut all_free = true;
        for k in 0..=pieces {
            let p = a + (b - a) * (k as f64 / pieces as f64);
            match self.nearest_node(&p) {
                Some((s, d)) => {
                    if s + d <= radius {
                        return Decision::Touches;
                    }
                    if s - d - reach <= radius {
                        all_free = false;
                    }
                }
                None => {
                    // Outside the grid: only the gap to the mesh's box bounds the distance.
                    if self.box_gap(&p, &p) - reach <= radius {
                        all_free = false;
                    }
                }
            }
        }
        if all_free {
            Decision::Free
        } else {
            Decision::Unsure
        }
    }
}
