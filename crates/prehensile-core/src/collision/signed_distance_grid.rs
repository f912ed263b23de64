//! The fast path for capsule tests: exact signed distances sampled on a regular grid,
//! queried with conservative bounds.
//!
//! The signed distance `s` is 1-Lipschitz, so a node value `s(g)` bounds every nearby point:
//! `s(g) - |p - g| <= s(p) <= s(g) + |p - g|`. A query answers from these bounds alone when they
//! decide it — a capsule far away costs one bounding-box test or one lookup — and otherwise
//! returns [`Decision::Unsure`] so the caller asks the exact path. The fast path therefore never
//! disagrees with the exact one: its error bound is zero, at the price of an exact query for
//! capsules within about one grid spacing of touching.
//!
//! The grid is filled lazily: a node's value is computed the first time a query needs it, and
//! kept. Within a band of the surface it is the exact signed distance (one nearest-triangle query
//! of the BVH bounded by the band; sign from the pseudo-normal of the nearest feature). Farther
//! out it is only a bound: a node outside the mesh's bounding box stores `+band` (a lower bound
//! on its distance, all the bounds below need); a far node inside the box, rarer, gets an
//! unbounded query for its sign and stores its signed distance, read as a one-sided bound. Setting an object up therefore costs no distance queries at
//! all (filling all 64³ nodes of a 16k-triangle mesh up front took 0.6 s, and 85 s for a
//! million triangles, while a search reads a few thousand nodes near the hand's path). The
//! search's grid is coarser still ([`SEARCH_SPACING`]): each node it reads costs a query. Nodes are
//! atomics, so one object serves many threads; two threads filling the same node write the same
//! number.

use std::sync::atomic::{AtomicU32, Ordering};

use crate::math::{Point3, Vec3};

use super::TriangleBvh;

/// Most nodes along the longest axis of the grid.
const MAX_NODES_PER_AXIS: usize = 64;
/// The least spacing of the grid the search's yes/no capsule tests read (metres), about a
/// finger capsule's radius. Its spacing sets a trade: a finer grid decides more capsules
/// alone but costs a nearest-triangle query for every node it fills, and the exact path it
/// leaves undecided is now cheap (it tests only the stretch the grid could not clear). Side by
/// side over ten hand-sized objects, human and Shadow hands, power, seeds 1–3
/// (docs/PERFORMANCE.md): at 8 mm the search took 0.46× (human) and 0.75× (Shadow)
/// of the time it took with 64 nodes a side (2.2 mm on a can); about as fast up to 12 mm,
/// slower again at 16 mm on a 16k-triangle scan, whose exact queries cost more. On a grid
/// already filled the finer one is faster (about 1.1× for the human hand).
pub const SEARCH_SPACING: f64 = 0.008;
/// The bits of a node not filled yet (a NaN no distance computes to).
const UNFILLED: u32 = u32::MAX;
/// Nodes nearer the surface than this (metres, or 2.5 spacings if larger) store exact values.
const BAND_MIN: f64 = 0.02;

/// What the grid alone can say about a capsule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Decision {
    /// The capsule touches the surface or lies inside.
    Touches,
    /// The capsule is clear of the object.
    Free,
    /// The bounds do not decide; ask the exact path about the part of the segment from fraction
    /// `from` to `to` (the rest is proven clear). `outside` tells that some sample was proven
    /// clear, hence outside the object: if the exact path finds no surface within the radius, the
    /// capsule is free without an inside test.
    Unsure {
        /// Start of the unproven part, as a fraction of the segment.
        from: f64,
        /// End of the unproven part.
        to: f64,
        /// Some part of the capsule is proven outside.
        outside: bool,
    },
}

/// Signed distances on a regular grid covering the object's bounds plus a margin, filled on
/// first use.
#[derive(Debug)]
pub struct SignedDistanceGrid {
    origin: Point3,
    spacing: f64,
    dims: [usize; 3],
    values: Vec<AtomicU32>,
    band: f64,
    mesh_min: Point3,
    mesh_max: Point3,
}

impl Clone for SignedDistanceGrid {
    fn clone(&self) -> Self {
        Self {
            values: self
                .values
                .iter()
                .map(|v| AtomicU32::new(v.load(Ordering::Relaxed)))
                .collect(),
            ..*self
        }
    }
}

impl SignedDistanceGrid {
    /// A grid around bounds `(lo, hi)` padded by `margin` metres, every node unfilled: 64
    /// nodes along the longest side, or fewer where that would space them closer than
    /// `least_spacing` metres.
    pub fn new(lo: Point3, hi: Point3, margin: f64, least_spacing: f64) -> Self {
        let extent = (hi - lo) + Vec3::repeat(2.0 * margin);
        let spacing = (extent.max() / (MAX_NODES_PER_AXIS - 1) as f64)
            .max(least_spacing)
            .max(1e-9);
        let dims = [0, 1, 2].map(|i| ((extent[i] / spacing).ceil() as usize + 1).max(2));
        // Centred on the bounds, so that a mirror-symmetric object gets a mirror-symmetric grid
        // (and a mirrored hand the mirror image of a search's steps).
        let origin =
            nalgebra::center(&lo, &hi) - Vec3::from_fn(|i, _| 0.5 * (dims[i] - 1) as f64 * spacing);
        let count = dims[0] * dims[1] * dims[2];
        Self {
            origin,
            spacing,
            dims,
            values: (0..count).map(|_| AtomicU32::new(UNFILLED)).collect(),
            band: (2.5 * spacing).max(BAND_MIN).min(margin.max(2.5 * spacing)),
            mesh_min: lo,
            mesh_max: hi,
        }
    }

    /// How many nodes the grid has.
    pub fn node_count(&self) -> usize {
        self.values.len()
    }

    /// How many nodes have been filled so far.
    pub fn filled_nodes(&self) -> usize {
        self.values
            .iter()
            .filter(|v| v.load(Ordering::Relaxed) != UNFILLED)
            .count()
    }

    /// Fills every node not filled yet, on rayon's pool (the global one, or the one the call
    /// runs in), with the values a search would have filled them with as it read them: done
    /// once, e.g. while a game loads its level, it leaves later searches only reads. Returns how
    /// many nodes it filled.
    pub fn fill_all(&self, exact: &TriangleBvh) -> usize {
        use rayon::prelude::*;
        let [nx, ny, _] = self.dims;
        self.values
            .par_iter()
            .enumerate()
            .filter(|(_, slot)| slot.load(Ordering::Relaxed) == UNFILLED)
            .map(|(i, slot)| self.fill(exact, [i % nx, i / nx % ny, i / (nx * ny)], slot))
            .count()
    }

    /// The exact signed distance at node `idx`, filled now if it was not.
    #[inline]
    fn node_value(&self, exact: &TriangleBvh, idx: [usize; 3]) -> f32 {
        let slot = &self.values[(idx[2] * self.dims[1] + idx[1]) * self.dims[0] + idx[0]];
        let bits = slot.load(Ordering::Relaxed);
        if bits != UNFILLED {
            return f32::from_bits(bits);
        }
        self.fill(exact, idx, slot)
    }

    /// Fills node `idx`, whose value lives in `slot`: the first read of a node, kept out of
    /// line so that the many reads of filled nodes stay short.
    #[cold]
    #[inline(never)]
    fn fill(&self, exact: &TriangleBvh, idx: [usize; 3], slot: &AtomicU32) -> f32 {
        let node =
            self.origin + Vec3::new(idx[0] as f64, idx[1] as f64, idx[2] as f64) * self.spacing;
        let value = match exact.closest_point_within(&node, self.band) {
            Some(s) => s.signed_distance,
            None if self.box_gap(&node, &node) > 0.0 => self.band,
            None => exact.signed_distance(&node),
        } as f32;
        slot.store(value.to_bits(), Ordering::Relaxed);
        value
    }

    /// Grid spacing in metres.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The signed distance at `p` interpolated trilinearly from its cell's eight nodes, and its
    /// gradient (not normalized), for contact generation; `None` outside the grid or where a
    /// corner is beyond the band (farther than `band − √3·spacing` from the surface). Within the
    /// band the nodes are exact, so the value is off the true distance by at most the
    /// interpolation error: about `spacing² / (8 R)` on a surface of curvature radius `R`, up to
    /// half a spacing at a sharp edge.
    pub fn sample(&self, exact: &TriangleBvh, p: &Point3) -> Option<(f64, Vec3)> {
        let mut cell = [0usize; 3];
        let mut f = [0.0f64; 3];
        for i in 0..3 {
            let x = (p[i] - self.origin[i]) / self.spacing;
            // NaN fails the test.
            if !(x >= 0.0 && x <= (self.dims[i] - 1) as f64) {
                return None;
            }
            cell[i] = (x as usize).min(self.dims[i] - 2);
            f[i] = x - cell[i] as f64;
        }
        let band = self.band as f32;
        let mut corner = [0.0f64; 8];
        for (k, value) in corner.iter_mut().enumerate() {
            let v = self.node_value(exact, [0, 1, 2].map(|i| cell[i] + (k >> i & 1)));
            if v.abs() >= band {
                return None;
            }
            *value = v as f64;
        }
        // Interpolate along x, then y, then z, carrying the derivatives.
        let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
        let x = [0, 1, 2, 3].map(|k| lerp(corner[2 * k], corner[2 * k + 1], f[0]));
        let dx = [0, 1, 2, 3].map(|k| corner[2 * k + 1] - corner[2 * k]);
        let y = [lerp(x[0], x[1], f[1]), lerp(x[2], x[3], f[1])];
        let dxy = [lerp(dx[0], dx[1], f[1]), lerp(dx[2], dx[3], f[1])];
        let dy = [x[1] - x[0], x[3] - x[2]];
        let value = lerp(y[0], y[1], f[2]);
        let gradient = Vec3::new(
            lerp(dxy[0], dxy[1], f[2]),
            lerp(dy[0], dy[1], f[2]),
            y[1] - y[0],
        ) / self.spacing;
        Some((value, gradient))
    }

    /// Lower and upper bounds of the signed distance at `p` from its nearest node; `None`
    /// outside the grid. Far nodes bound only one side.
    fn bounds_at(&self, exact: &TriangleBvh, p: &Point3) -> Option<(f64, f64)> {
        let mut idx = [0usize; 3];
        let mut offset = Vec3::zeros();
        for i in 0..3 {
            // The nearest node: ⌊x + ½⌋ by truncation, which is cheaper than `f64::round` (a libm
            // call without SSE4.1). NaN fails the first test. A grid has at most 65 nodes a side,
            // so the conversions go through `i32`: one instruction each, where `usize`'s take
            // several (x86-64 has no unsigned conversions before AVX-512).
            let shifted = (p[i] - self.origin[i]) / self.spacing + 0.5;
            if !(shifted >= 0.0 && shifted < f64::from(self.dims[i] as i32)) {
                return None;
            }
            let node = shifted as i32;
            idx[i] = node as usize;
            offset[i] = p[i] - (self.origin[i] + f64::from(node) * self.spacing);
        }
        let v = self.node_value(exact, idx) as f64;
        // Stored as f32: widen by the rounding error of the value. Values at or beyond the band
        // bound one side only.
        let d = offset.norm() + v.abs() * 1e-7 + 1e-9;
        let band = self.band as f32 as f64;
        Some(if v >= band {
            (v - d, f64::INFINITY)
        } else if v <= -band {
            (f64::NEG_INFINITY, v + d)
        } else {
            (v - d, v + d)
        })
    }

    /// Lower bound on the distance from the segment's bounding box to the mesh's bounding box.
    fn box_gap(&self, a: &Point3, b: &Point3) -> f64 {
        let lo = a.inf(b);
        let hi = a.sup(b);
        let gap = Vec3::from_fn(|i, _| {
            (self.mesh_min[i] - hi[i])
                .max(lo[i] - self.mesh_max[i])
                .max(0.0)
        });
        gap.norm()
    }

    /// An upper bound on the smallest signed distance along segment `a–b` (+∞ when the grid
    /// cannot bound it): a capsule of radius `r` around the segment needs to move at least
    /// `r − bound` to be free of the object. Only a bound below `below` is asked for: when the
    /// segment's bound is at least `below`, the answer is some number at least `below`, and
    /// the samples that cannot go lower are skipped without reading (filling) their nodes.
    pub fn segment_clearance_upper_bound(
        &self,
        exact: &TriangleBvh,
        a: &Point3,
        b: &Point3,
        below: f64,
    ) -> f64 {
        // Outside the mesh's box, every point of the segment is at least this far from it.
        let gap = self.box_gap(a, b);
        if gap > 0.0 && gap >= below {
            return f64::INFINITY;
        }
        let length = (b - a).norm();
        let pieces = ((length / self.spacing).ceil() as usize).max(1);
        let step = length / pieces as f64;
        let mut lowest = f64::INFINITY;
        let mut k = 0;
        while k <= pieces {
            let p = a + (b - a) * (k as f64 / pieces as f64);
            let Some((lower, upper)) = self.bounds_at(exact, &p) else {
                k += 1;
                continue;
            };
            lowest = lowest.min(upper);
            // A sample within `reach` of this one is at least `lower − reach` from the surface
            // (1-Lipschitz), so its upper bound is no lower than the threshold: skip it.
            let reach = lower - lowest.min(below) - 1e-9;
            k += if step > 0.0 && reach >= step {
                (reach / step) as usize + 1
            } else {
                1
            };
        }
        lowest
    }

    /// Decides from the grid (filled from `exact` where needed) whether capsule `a–b` with
    /// `radius` touches or is inside the object.
    pub fn decide(&self, exact: &TriangleBvh, a: &Point3, b: &Point3, radius: f64) -> Decision {
        // A NaN capsule bounds nothing (and its walk would never end): the exact path answers.
        if a.coords.iter().chain(b.coords.iter()).any(|x| x.is_nan()) || radius.is_nan() {
            return Decision::Unsure {
                from: 0.0,
                to: 1.0,
                outside: false,
            };
        }
        if self.box_gap(a, b) > radius {
            return Decision::Free;
        }
        let mid = nalgebra::center(a, b);
        let half = (b - a).norm() * 0.5;
        if let Some((lower, upper)) = self.bounds_at(exact, &mid) {
            if upper <= radius {
                return Decision::Touches;
            }
            if lower - half > radius {
                return Decision::Free;
            }
        }
        self.walk(exact, a, b, radius)
    }

    /// The cheap half of [`Self::decide`]: true when the mesh's bounding box or the node nearest
    /// the segment's middle proves capsule `a–b` with `radius` clear of the object (one lookup
    /// at most); false says nothing.
    pub fn proves_clear(&self, exact: &TriangleBvh, a: &Point3, b: &Point3, radius: f64) -> bool {
        self.box_gap(a, b) > radius
            || self
                .bounds_at(exact, &nalgebra::center(a, b))
                .is_some_and(|(lower, _)| lower - (b - a).norm() * 0.5 > radius)
    }

    /// The walk of [`Self::decide`] along the segment, once the middle did not decide it.
    fn walk(&self, exact: &TriangleBvh, a: &Point3, b: &Point3, radius: f64) -> Decision {
        let half = (b - a).norm() * 0.5;
        // Walk the segment. A sample whose lower bound exceeds the radius by g clears every point
        // within g of it (the distance is 1-Lipschitz), so the walk leaps g ahead (sphere
        // tracing); an undecided sample moves one grid spacing on.
        let length = 2.0 * half;
        let direction = if length > 0.0 {
            (b - a) / length
        } else {
            Vec3::zeros()
        };
        let mut all_free = true;
        let mut outside = false;
        let (mut first_unsure, mut last_unsure) = (f64::INFINITY, 0.0f64);
        let mut t = 0.0;
        loop {
            let p = a + direction * t;
            // Outside the grid only the gap to the mesh's box bounds the distance.
            let (lower, upper) = self
                .bounds_at(exact, &p)
                .unwrap_or_else(|| (self.box_gap(&p, &p), f64::INFINITY));
            if upper <= radius {
                return Decision::Touches;
            }
            let clear = lower - radius;
            let advance = if clear > 0.25 * self.spacing {
                outside = true;
                clear
            } else {
                all_free = false;
                first_unsure = first_unsure.min(t);
                last_unsure = t;
                self.spacing
            };
            if t >= length {
                break;
            }
            t = (t + advance).min(length);
        }
        if all_free {
            Decision::Free
        } else {
            // Everything before the first unsure sample is covered by the clear samples before
            // it; after the last one, the next sample (one spacing on) takes over.
            let fraction = |t: f64| {
                if length > 0.0 {
                    (t / length).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            };
            Decision::Unsure {
                from: fraction(first_unsure),
                to: fraction(last_unsure + self.spacing),
                outside,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::builtin_object;
    use crate::ObjectModel;
    use proptest::prelude::*;

    /// Every sample's upper bound, as the walk would read them without skipping any.
    fn every_sample(grid: &SignedDistanceGrid, exact: &TriangleBvh, a: &Point3, b: &Point3) -> f64 {
        let pieces = (((b - a).norm() / grid.spacing).ceil() as usize).max(1);
        (0..=pieces)
            .filter_map(|k| grid.bounds_at(exact, &(a + (b - a) * (k as f64 / pieces as f64))))
            .map(|(_, upper)| upper)
            .fold(f64::INFINITY, f64::min)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]

        /// Skipping samples that cannot go below the threshold changes no answer below it.
        #[test]
        fn the_clearance_bound_skips_only_samples_that_cannot_lower_it(
            object in prop::sample::select(vec!["mug", "torus"]),
            a in prop::array::uniform3(-0.1f64..0.1),
            b in prop::array::uniform3(-0.1f64..0.1),
            below in prop::sample::select(vec![-0.01, 0.0, 0.004, 0.01, f64::INFINITY]),
        ) {
            thread_local! {
                static OBJECTS: std::collections::HashMap<&'static str, ObjectModel> =
                    ["mug", "torus"].into_iter()
                        .map(|n| (n, ObjectModel::new(n, builtin_object(n).unwrap(), None).unwrap()))
                        .collect();
            }
            let lift = Vec3::new(0.0, 0.0, 0.04);
            let (a, b) = (Point3::from(a) + lift, Point3::from(b) + lift);
            OBJECTS.with(|objects| {
                let collider = objects[object].collider();
                let (grid, exact) = (collider.grid().unwrap(), collider.exact());
                let all = every_sample(grid, exact, &a, &b);
                let found = grid.segment_clearance_upper_bound(exact, &a, &b, below);
                if all < below {
                    prop_assert_eq!(found, all);
                } else {
                    prop_assert!(found >= below, "{} against {} (all samples {})", found, below, all);
                }
                Ok(())
            })?;
        }
    }
}
