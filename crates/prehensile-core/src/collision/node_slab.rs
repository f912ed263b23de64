//! Slabs around the triangles of a hierarchy's nodes: the two planes, across the patch's mean
//! normal, between which all of its triangles lie. On a finely triangulated smooth surface (a
//! scan of tens of thousands of triangles) a node's box is nearly as tall as it is wide, but its
//! patch of surface is nearly flat, so the slab is thin. A capsule hovering just clear of such a
//! surface comes within its radius of many boxes and of none of their slabs: the slab ends the
//! visit where the box alone would open every leaf below. A node's distance bound is the larger
//! of the two, so answers stay the same and only the work shrinks.

use crate::math::{Point3, Vec3};

/// Nodes over more triangles than this get no slab: their patches curve too much for a thin
/// slab, and each slab costs a pass over its node's corners when the tree is built. Whole
/// `prehensile grasp` runs on a 15k-triangle can (one thread, instructions counted by
/// cachegrind, seeds 1–2) took 1% more instructions than without slabs with slabs up to 16
/// triangles, and 2.3%, 2.9% and 2.8% fewer up to 64, 128 and 256 (a first, dearer build of
/// the slabs; the one here saves 3.8% at 128; docs/PERFORMANCE.md).
pub(super) const SLAB_MOST_TRIANGLES: usize = 128;

/// The region `lo ≤ axis·x ≤ hi` (unit `axis`), holding every point of a node's triangles.
#[derive(Debug, Clone, Copy)]
pub(super) struct Slab {
    axis: Vec3,
    lo: f64,
    hi: f64,
}

impl Slab {
    /// The slab that bounds nothing: every point is in it.
    pub(super) const EVERYWHERE: Slab = Slab {
        axis: Vec3::new(0.0, 0.0, 0.0),
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// The slab across `normal_sum` (the sum of the triangles' `(b − a) × (c − a)`, their
    /// area-weighted mean normal) around `triangles`, widened by far more than the rounding of
    /// any height, so that a test that prunes by it never prunes a triangle the exact kernels
    /// would find within reach; [`Slab::EVERYWHERE`] when the normals cancel.
    pub(super) fn around(normal_sum: Vec3, triangles: &[[Point3; 3]]) -> Self {
        let Some(axis) = normal_sum
            .try_normalize(1e-300)
            .filter(|axis| axis.iter().all(|x| x.is_finite()))
        else {
            return Self::EVERYWHERE;
        };
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in triangles.iter().flatten() {
            let h = axis.x * p.x + axis.y * p.y + axis.z * p.z;
            // Plain comparisons: `f64::min` also orders NaNs, and this runs on every corner of
            // every node with a slab; a NaN height leaves the bounds infinite, checked below.
            if h < lo {
                lo = h;
            }
            if h > hi {
                hi = h;
            }
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return Self::EVERYWHERE;
        }
        let slack = 1e-9 + 1e-12 * lo.abs().max(hi.abs());
        Self {
            axis,
            lo: lo - slack,
            hi: hi + slack,
        }
    }

    /// A lower bound on the distance from segment `a–b` to the slab, so to the node's triangles
    /// (zero or less when the segment meets the slab).
    #[inline]
    pub(super) fn segment_gap(&self, a: &Point3, b: &Point3) -> f64 {
        let (ha, hb) = (self.axis.dot(&a.coords), self.axis.dot(&b.coords));
        (self.lo - ha.max(hb)).max(ha.min(hb) - self.hi)
    }
}

/// A triangle's `(b − a) × (c − a)`: its normal times twice its area.
pub(super) fn area_normal([a, b, c]: &[Point3; 3]) -> Vec3 {
    (b - a).cross(&(c - a))
}
