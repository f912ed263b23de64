//! The fast path for capsule tests: exact signed distances sampled on a regular grid once per
//! object, queried with conservative bounds.
//!
//! The signed distance `s` is 1-Lipschitz, so a node value `s(g)` bounds every nearby point:
//! `s(g) - |p - g| <= s(p) <= s(g) + |p - g|`. A query answers from these bounds alone when they
//! decide it — a capsule far away costs one bounding-box test or one lookup — and otherwise
//! returns [`Decision::Unsure`] so the caller asks the exact path. The fast path therefore never
//! disagrees with the exact one: its error bound is zero, at the price of an exact query for
//! capsules within about one grid spacing of touching.
//!
//! Building it computes exact distances only for nodes within a band of the surface. Farther
//! nodes store ±band: a lower bound on the distance outside, an upper bound on the (negative)
//! distance inside, which is all the bounds above need. Their sign comes from a flood fill: two
//! neighbouring nodes both farther than the band from the surface (band > spacing) cannot have
//! the surface between them, so each connected far region has one sign, found by a single exact
//! query (regions touching the grid's border are outside, as the grid extends past the mesh).

use crate::geometry::closest_point_on_triangle;
use crate::math::{Point3, Vec3};

use super::TriangleBvh;

/// Most nodes along the longest axis of the grid.
const MAX_NODES_PER_AXIS: usize = 64;
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

/// Signed distances on a regular grid covering the object's bounds plus a margin.
#[derive(Debug, Clone)]
pub struct SignedDistanceGrid {
    origin: Point3,
    spacing: f64,
    dims: [usize; 3],
    values: Vec<f32>,
    band: f32,
    mesh_min: Point3,
    mesh_max: Point3,
}

impl SignedDistanceGrid {
    /// Samples the exact signed distance of `exact` on a grid around bounds `(lo, hi)` padded by
    /// `margin` metres.
    pub fn new(exact: &TriangleBvh, lo: Point3, hi: Point3, margin: f64) -> Self {
        let origin = lo - Vec3::repeat(margin);
        let extent = (hi - lo) + Vec3::repeat(2.0 * margin);
        let spacing = (extent.max() / (MAX_NODES_PER_AXIS - 1) as f64).max(1e-9);
        let dims = [0, 1, 2].map(|i| ((extent[i] / spacing).ceil() as usize + 1).max(2));
        let band = (2.5 * spacing).max(BAND_MIN).min(margin.max(2.5 * spacing));
        let node = |x: usize, y: usize, z: usize| {
            origin + Vec3::new(x as f64, y as f64, z as f64) * spacing
        };
        let count = dims[0] * dims[1] * dims[2];
        let index = |x: usize, y: usize, z: usize| (z * dims[1] + y) * dims[0] + x;
        // Each triangle updates the nodes within the band of its bounding box with its distance.
        let mut nearest = vec![(band * band, u32::MAX); count];
        let to_node =
            |v: f64, i: usize| ((v - origin[i]) / spacing).clamp(0.0, (dims[i] - 1) as f64);
        for t in 0..exact.triangle_count() {
            let [a, b, c] = exact.triangle(t);
            let lo = a.inf(b).inf(c) - Vec3::repeat(band);
            let hi = a.sup(b).sup(c) + Vec3::repeat(band);
            let first: [usize; 3] = std::array::from_fn(|i| to_node(lo[i], i).ceil() as usize);
            let last: [usize; 3] = std::array::from_fn(|i| to_node(hi[i], i).floor() as usize);
            for z in first[2]..=last[2] {
                for y in first[1]..=last[1] {
                    for x in first[0]..=last[0] {
                        let p = node(x, y, z);
                        let d2 = (closest_point_on_triangle(&p, a, b, c).0 - p).norm_squared();
                        let slot = &mut nearest[index(x, y, z)];
                        if d2 <= slot.0 {
                            *slot = (d2, t as u32);
                        }
                    }
                }
            }
        }
        let mut values: Vec<f32> = (0..count)
            .map(|i| {
                let (_, t) = nearest[i];
                if t == u32::MAX {
                    return f32::NAN;
                }
                let (x, y, z) = (
                    i % dims[0],
                    (i / dims[0]) % dims[1],
                    i / (dims[0] * dims[1]),
                );
                exact.signed_distance_to_triangle(&node(x, y, z), t as usize) as f32
            })
            .collect();
        // Flood-fill the far nodes (NaN) region by region.
        let mut stack = Vec::new();
        for start in 0..count {
            if !values[start].is_nan() {
                continue;
            }
            let (sx, sy, sz) = (
                start % dims[0],
                (start / dims[0]) % dims[1],
                start / (dims[0] * dims[1]),
            );
            let on_border = |x: usize, y: usize, z: usize| {
                x == 0
                    || y == 0
                    || z == 0
                    || x + 1 == dims[0]
                    || y + 1 == dims[1]
                    || z + 1 == dims[2]
            };
            let inside = !on_border(sx, sy, sz) && exact.signed_distance(&node(sx, sy, sz)) < 0.0;
            let fill = if inside { -band } else { band } as f32;
            values[start] = fill;
            stack.push((sx, sy, sz));
            while let Some((x, y, z)) = stack.pop() {
                let mut visit = |nx: usize, ny: usize, nz: usize| {
                    let i = index(nx, ny, nz);
                    if values[i].is_nan() {
                        values[i] = fill;
                        stack.push((nx, ny, nz));
                    }
                };
                if x > 0 {
                    visit(x - 1, y, z);
                }
                if y > 0 {
                    visit(x, y - 1, z);
                }
                if z > 0 {
                    visit(x, y, z - 1);
                }
                if x + 1 < dims[0] {
                    visit(x + 1, y, z);
                }
                if y + 1 < dims[1] {
                    visit(x, y + 1, z);
                }
                if z + 1 < dims[2] {
                    visit(x, y, z + 1);
                }
            }
        }
        Self {
            origin,
            spacing,
            dims,
            values,
            band: band as f32,
            mesh_min: lo,
            mesh_max: hi,
        }
    }

    /// Grid spacing in metres.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Lower and upper bounds of the signed distance at `p` from its nearest node; `None`
    /// outside the grid. Far nodes store ±band, which bounds only one side.
    fn bounds_at(&self, p: &Point3) -> Option<(f64, f64)> {
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
        let v = self.values[(idx[2] * self.dims[1] + idx[1]) * self.dims[0] + idx[0]];
        // Stored as f32: widen by the rounding error of the value.
        let d = offset.norm() + (v.abs() as f64) * 1e-7 + 1e-9;
        let v64 = v as f64;
        Some(if v >= self.band {
            (v64 - d, f64::INFINITY)
        } else if v <= -self.band {
            (f64::NEG_INFINITY, v64 + d)
        } else {
            (v64 - d, v64 + d)
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
    /// `r − bound` to be free of the object.
    pub fn segment_clearance_upper_bound(&self, a: &Point3, b: &Point3) -> f64 {
        let length = (b - a).norm();
        let pieces = ((length / self.spacing).ceil() as usize).max(1);
        (0..=pieces)
            .filter_map(|k| self.bounds_at(&(a + (b - a) * (k as f64 / pieces as f64))))
            .map(|(_, upper)| upper)
            .fold(f64::INFINITY, f64::min)
    }

    /// Decides from the grid whether capsule `a–b` with `radius` touches or is inside the object.
    pub fn decide(&self, a: &Point3, b: &Point3, radius: f64) -> Decision {
        if self.box_gap(a, b) > radius {
            return Decision::Free;
        }
        let mid = nalgebra::center(a, b);
        let half = (b - a).norm() * 0.5;
        if let Some((lower, upper)) = self.bounds_at(&mid) {
            if upper <= radius {
                return Decision::Touches;
            }
            if lower - half > radius {
                return Decision::Free;
            }
        }
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
                .bounds_at(&p)
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
