//! A convex collision mesh as capsules that lie inside it: how an imported hand's mesh geoms
//! (MJCF `type="mesh"`, URDF `<mesh>`) become the capsules every query of Prehensile uses.
//!
//! MuJoCo and most engines collide a mesh geom as its convex hull, so the hull is the shape to
//! stand in for. The capsules run along the hull's longest principal axis (of its solid) on a
//! grid of lines across it; each line carries the capsule of most volume that fits (at most as
//! thick as the one through the middle) over the stretch where it fits, found by clipping the
//! line against the hull's faces moved inward by the radius. So the capsules never leave the hull — a finger is
//! never made fatter than its file says — and lines sit close enough that between two of them
//! a flat face is covered to within the tolerance. Corners and edges come out rounded; how far
//! the hull reaches past the capsules is measured and reported ([`ConvexCapsules`]).
//!
//! Written here because no crate turns a convex polytope into inscribed capsules; the hull
//! itself is [`crate::geometry::ConvexHull`] (checked against Qhull).

use crate::geometry::{ConvexHull, HullError};
use crate::math::{Point3, Vec3};

/// Most lines across the hull; a finer grid than this widens its spacing instead.
const MAX_LINES: usize = 64;

/// Radii tried for each line's capsule, from the thickest that fits down.
const RADIUS_SAMPLES: usize = 48;

/// The thinner capsules tried on each line to fill what the rows leave, as shares of the
/// thickest that fits there.
const FILL_LEVELS: [f64; 4] = [0.8, 0.6, 0.45, 0.3];

/// Most capsules added to fill what the rows leave.
const MAX_FILL_CAPSULES: usize = 6;

/// A filling capsule is added while it brings the samples nearer by at least this share of the
/// tolerance on average.
const FILL_GAIN: f64 = 0.05;

/// A capsule thinner than this share of the middle one adds little and is left out.
const THINNEST_SHARE: f64 = 0.25;

/// Capsules standing in for a convex mesh, and how closely they fill it.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexCapsules {
    /// The capsules, `(a, b, radius)` in the mesh's frame; every one inside the hull.
    pub capsules: Vec<(Point3, Point3, f64)>,
    /// Largest distance from a hull face's centre to the capsules, metres: how far flat faces
    /// stand out of them.
    pub face_gap: f64,
    /// Largest distance from a hull vertex to the capsules, metres: how far corners are cut.
    pub corner_gap: f64,
}

/// A capsule `(a, b, radius)`.
type CapsuleSpec = (Point3, Point3, f64);

/// Capsules inside the convex hull of `points` (a collision mesh's vertices), with adjacent
/// lines close enough that a flat face between them is covered within `tolerance` metres.
/// Fails when the points are too few, not finite, or flat (a plane encloses nothing).
pub fn convex_capsules(points: &[Point3], tolerance: f64) -> Result<ConvexCapsules, HullError> {
    let coordinates: Vec<[f64; 3]> = points.iter().map(|p| [p.x, p.y, p.z]).collect();
    let mut hull = ConvexHull::<3>::new();
    hull.compute(&coordinates)?;
    let solid = Solid::new(&hull, points);
    // The fullest capsule along the long axis through the middle sets the radius.
    let radius = solid
        .fullest(&solid.centre, f64::INFINITY)
        .map_or(0.0, |(r, _, _)| r);
    let (mut capsules, lines) = if radius > 0.0 {
        solid.rows(radius, tolerance)
    } else {
        (Vec::new(), Vec::new())
    };
    // Where the hull reaches past the capsules, sampled at its corners and faces' centres.
    let samples: Vec<Point3> = solid
        .corners
        .iter()
        .copied()
        .chain(hull.facets().iter().map(|f| {
            Point3::from(
                f.vertices
                    .iter()
                    .map(|&i| points[i as usize].coords)
                    .sum::<Vec3>()
                    / 3.0,
            )
        }))
        .collect();
    solid.fill(&lines, &samples, radius, tolerance, &mut capsules);
    drop_contained(&mut capsules);
    let gap_at = |p: &Point3| nearest_gap(p, &capsules);
    let corner_gap = solid.corners.iter().map(gap_at).fold(0.0, f64::max);
    let face_gap = samples[solid.corners.len()..]
        .iter()
        .map(gap_at)
        .fold(0.0, f64::max);
    Ok(ConvexCapsules {
        capsules,
        face_gap,
        corner_gap,
    })
}

/// How far `p` lies outside capsule `(a, b, r)` (negative inside).
fn gap(p: &Point3, (a, b, r): &CapsuleSpec) -> f64 {
    distance_to_segment(p, a, b) - r
}

/// How far `p` lies outside the nearest of `capsules`, 0 inside one.
fn nearest_gap(p: &Point3, capsules: &[CapsuleSpec]) -> f64 {
    capsules
        .iter()
        .map(|c| gap(p, c))
        .fold(f64::INFINITY, f64::min)
        .max(0.0)
}

/// The hull as a solid to fill: its face planes, its corners, its centroid and principal axes,
/// and its extent along the longest.
struct Solid {
    /// Every face's outward normal and offset.
    planes: Vec<(Vec3, f64)>,
    /// The hull's vertices.
    corners: Vec<Point3>,
    /// The solid's centroid.
    centre: Point3,
    /// Its principal axes, longest spread first.
    long: Vec3,
    across: Vec3,
    thin: Vec3,
    /// Its extent along `long` from `centre`.
    along: (f64, f64),
}

impl Solid {
    fn new(hull: &ConvexHull<3>, points: &[Point3]) -> Self {
        let planes = hull
            .facets()
            .iter()
            .map(|f| (Vec3::from(f.normal), f.offset))
            .collect();
        let mut corner_indices: Vec<u32> = hull.facets().iter().flat_map(|f| f.vertices).collect();
        corner_indices.sort_unstable();
        corner_indices.dedup();
        let corners = corner_indices.iter().map(|&i| points[i as usize]).collect();
        let (centre, [long, across, thin]) = solid_axes(hull, points);
        let mut solid = Self {
            planes,
            corners,
            centre,
            long,
            across,
            thin,
            along: (0.0, 0.0),
        };
        solid.along = solid.span(&long);
        solid
    }

    /// The extent of the corners along `axis` from the centre.
    fn span(&self, axis: &Vec3) -> (f64, f64) {
        self.corners
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let s = (p - self.centre).dot(axis);
                (lo.min(s), hi.max(s))
            })
    }

    /// How far inside every face `p` lies.
    fn clearance(&self, p: &Point3) -> f64 {
        self.planes
            .iter()
            .map(|(n, d)| d - n.dot(&p.coords))
            .fold(f64::INFINITY, f64::min)
    }

    /// The thickest capsule's radius on the long line through `origin`.
    fn thickest(&self, origin: &Point3) -> f64 {
        thickest_on_line(
            &|p: &Point3| self.clearance(p),
            origin,
            &self.long,
            self.along,
        )
        .1
    }

    /// The capsule on the long line through `origin`, at most `cap` thick: of the radii up to
    /// the thickest that fits (a hair thinner, so that the faces it touches do not pinch its
    /// line to a point in rounding), the one whose capsule has the most volume — a tapered part
    /// gets a capsule along it rather than a ball at its thickest. `(radius, s0, s1)`.
    fn fullest(&self, origin: &Point3, cap: f64) -> Option<(f64, f64, f64)> {
        let top = (self.thickest(origin) * (1.0 - 1e-7)).min(cap);
        (1..=RADIUS_SAMPLES)
            .filter_map(|k| {
                let r = top * k as f64 / RADIUS_SAMPLES as f64;
                let (s0, s1) = clip_line(&self.planes, origin, &self.long, r)?;
                let volume = r * r * (s1 - s0) + 4.0 / 3.0 * r * r * r;
                Some((volume, r, s0, s1))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, r, s0, s1)| (r, s0, s1))
    }

    /// Across `axis`, the offsets between which a line still holds the whole `radius` (an
    /// interval: the thickest capsule on a line is concave in its offset); the outermost rows
    /// go there, as a box's outer rows go to its faces.
    fn reach(&self, axis: &Vec3, radius: f64) -> (f64, f64) {
        let (lo, hi) = self.span(axis);
        let edge = |end: f64| {
            let (mut inner, mut outer) = (0.0, end);
            for _ in 0..32 {
                let mid = 0.5 * (inner + outer);
                if self.thickest(&(self.centre + axis * mid)) >= radius {
                    inner = mid;
                } else {
                    outer = mid;
                }
            }
            inner
        };
        (edge(lo), edge(hi))
    }

    /// Rows of capsules of `radius` along the long axis, their lines spaced so that a flat face
    /// between two dips at most `tolerance` into the gap, at most [`MAX_LINES`] of them; returns
    /// the capsules and every line's origin.
    fn rows(&self, radius: f64, tolerance: f64) -> (Vec<CapsuleSpec>, Vec<Point3>) {
        let dip = tolerance.clamp(0.0, radius);
        let mut spacing = 2.0 * (radius * radius - (radius - dip) * (radius - dip)).sqrt();
        let (across_reach, thin_reach) = (
            self.reach(&self.across, radius),
            self.reach(&self.thin, radius),
        );
        // A reach far shorter than the spacing (rounding around a single line) is one row.
        let rows =
            |(lo, hi): (f64, f64), spacing: f64| ((hi - lo) / spacing - 1e-3).ceil().max(0.0) + 1.0;
        // Widen the spacing until there are at most MAX_LINES lines (counted in floating point:
        // a crafted mesh's extent over a tiny spacing would overflow an integer).
        while spacing <= 0.0
            || rows(across_reach, spacing) * rows(thin_reach, spacing) > MAX_LINES as f64
        {
            spacing = if spacing > 0.0 {
                spacing * 1.25
            } else {
                radius
            };
        }
        let offsets = |(lo, hi): (f64, f64)| {
            let n = rows((lo, hi), spacing) as usize;
            (0..n).map(move |k| {
                if n == 1 {
                    0.5 * (lo + hi)
                } else {
                    lo + (hi - lo) * k as f64 / (n - 1) as f64
                }
            })
        };
        let (mut capsules, mut lines) = (Vec::new(), Vec::new());
        for u in offsets(across_reach) {
            for v in offsets(thin_reach) {
                let origin = self.centre + self.across * u + self.thin * v;
                lines.push(origin);
                match self.fullest(&origin, radius) {
                    Some((r, s0, s1)) if r >= THINNEST_SHARE * radius => {
                        capsules.push((origin + self.long * s0, origin + self.long * s1, r))
                    }
                    _ => {}
                }
            }
        }
        (capsules, lines)
    }

    /// A tapered part's ends and a rounded part's rim lie past the rows: fills them with thinner
    /// capsules on the same `lines`, which reach further along them, each chosen for how much it
    /// brings the `samples` nearer, while that is worth a capsule.
    fn fill(
        &self,
        lines: &[Point3],
        samples: &[Point3],
        radius: f64,
        tolerance: f64,
        capsules: &mut Vec<CapsuleSpec>,
    ) {
        let mut gaps: Vec<f64> = samples.iter().map(|p| nearest_gap(p, capsules)).collect();
        let candidates: Vec<CapsuleSpec> = lines
            .iter()
            .flat_map(|origin| {
                let top = (self.thickest(origin) * (1.0 - 1e-7)).min(radius);
                FILL_LEVELS.iter().filter_map(move |level| {
                    let r = top * level;
                    let (s0, s1) = clip_line(&self.planes, origin, &self.long, r)?;
                    Some((origin + self.long * s0, origin + self.long * s1, r))
                })
            })
            .filter(|c| c.2 > 0.0)
            .collect();
        for _ in 0..MAX_FILL_CAPSULES {
            let gain = |c: &CapsuleSpec| -> f64 {
                samples
                    .iter()
                    .zip(&gaps)
                    .map(|(p, g)| (g - gap(p, c).max(0.0)).max(0.0))
                    .sum()
            };
            let Some((best, gained)) = candidates
                .iter()
                .map(|c| (c, gain(c)))
                .max_by(|a, b| a.1.total_cmp(&b.1))
            else {
                break;
            };
            if gained < FILL_GAIN * tolerance * samples.len() as f64 {
                break;
            }
            for (p, g) in samples.iter().zip(gaps.iter_mut()) {
                *g = g.min(gap(p, best).max(0.0));
            }
            capsules.push(*best);
        }
    }
}

/// The centroid and principal axes of the solid hull, longest spread first: from its volume,
/// not its vertices, so that a mesh's repeated or crowded vertices do not tilt them.
fn solid_axes(hull: &ConvexHull<3>, points: &[Point3]) -> (Point3, [Vec3; 3]) {
    let o = Point3::from(hull.interior_point());
    let (mut volume, mut first, mut second) = (0.0, Vec3::zeros(), nalgebra::Matrix3::zeros());
    for f in hull.facets() {
        let [a, b, c] = f.vertices.map(|i| points[i as usize]);
        // The tetrahedron from the interior point to the facet.
        let v = ((a - o).cross(&(b - o)).dot(&(c - o)) / 6.0).abs();
        let corners = [o.coords, a.coords, b.coords, c.coords];
        let sum: Vec3 = corners.iter().sum();
        volume += v;
        first += sum * (v / 4.0);
        // ∫ x xᵀ over a tetrahedron: V/20 · (Σ vᵢvᵢᵀ + (Σ vᵢ)(Σ vᵢ)ᵀ).
        let outer: nalgebra::Matrix3<f64> = corners.iter().map(|p| p * p.transpose()).sum();
        second += (outer + sum * sum.transpose()) * (v / 20.0);
    }
    let centre = first / volume;
    let covariance = second - centre * centre.transpose() * volume;
    let eigen = nalgebra::SymmetricEigen::new(covariance);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    // Each axis signed so that its largest component is positive: near-equal meshes give
    // capsules running the same way.
    let axis = |k: usize| {
        let v = Vec3::from(eigen.eigenvectors.column(order[k])).normalize();
        if v[v.iamax()] < 0.0 {
            -v
        } else {
            v
        }
    };
    let (long, across) = (axis(0), axis(1));
    // A right-handed frame whatever signs the solver gave.
    (
        Point3::from(centre),
        [long, across, long.cross(&across).normalize()],
    )
}

/// Where along the line `origin + s·direction` (s within `range`) the clearance is largest, and
/// that clearance: golden-section search, exact for the concave, piecewise linear clearance of a
/// convex polytope, to a billionth of the range.
fn thickest_on_line(
    clearance: &impl Fn(&Point3) -> f64,
    origin: &Point3,
    direction: &Vec3,
    (mut lo, mut hi): (f64, f64),
) -> (f64, f64) {
    let at = |s: f64| clearance(&(origin + direction * s));
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
    let (mut f1, mut f2) = (at(x1), at(x2));
    let bracket = 1e-9 * (hi - lo);
    for _ in 0..60 {
        if hi - lo <= bracket {
            break;
        }
        if f1 < f2 {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + ratio * (hi - lo);
            f2 = at(x2);
        } else {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - ratio * (hi - lo);
            f1 = at(x1);
        }
    }
    let s = 0.5 * (lo + hi);
    (s, at(s))
}

/// The stretch `[s0, s1]` of the line `origin + s·direction` whose points are at least `radius`
/// inside every plane, if any.
fn clip_line(
    planes: &[(Vec3, f64)],
    origin: &Point3,
    direction: &Vec3,
    radius: f64,
) -> Option<(f64, f64)> {
    let (mut s0, mut s1) = (f64::NEG_INFINITY, f64::INFINITY);
    for (n, d) in planes {
        // n·(origin + s·direction) <= d − radius.
        let room = d - radius - n.dot(&origin.coords);
        let rate = n.dot(direction);
        if rate.abs() < 1e-12 {
            if room < -1e-12 {
                return None;
            }
        } else if rate > 0.0 {
            s1 = s1.min(room / rate);
        } else {
            s0 = s0.max(room / rate);
        }
    }
    (s0 <= s1 && s0.is_finite() && s1.is_finite()).then_some((s0, s1))
}

/// Removes capsules that lie inside another (both ends within the other's radius less theirs,
/// to a nanometre).
fn drop_contained(capsules: &mut Vec<(Point3, Point3, f64)>) {
    let mut k = 0;
    while k < capsules.len() {
        let (a, b, r) = capsules[k];
        let inside_another = capsules.iter().enumerate().any(|(m, (c, d, s))| {
            m != k
                && *s >= r
                && distance_to_segment(&a, c, d) <= s - r + 1e-9
                && distance_to_segment(&b, c, d) <= s - r + 1e-9
        });
        if inside_another {
            capsules.swap_remove(k);
        } else {
            k += 1;
        }
    }
}

/// Distance from `p` to the segment `a`–`b`.
fn distance_to_segment(p: &Point3, a: &Point3, b: &Point3) -> f64 {
    crate::geometry::distance_squared_segment_segment(p, p, a, b).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rotation;

    /// The corners of a box of half extents `half`, turned by `turn` and moved to `at`.
    fn box_corners(half: Vec3, turn: Rotation, at: Vec3) -> Vec<Point3> {
        let mut out = Vec::new();
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                for sz in [-1.0, 1.0] {
                    let local = Vec3::new(sx * half.x, sy * half.y, sz * half.z);
                    out.push(Point3::from(turn * local + at));
                }
            }
        }
        out
    }

    /// A prism of `sides` sides and circumradius `radius`, `length` long along the unit `axis`.
    fn prism(sides: usize, radius: f64, length: f64, turn: Rotation) -> Vec<Point3> {
        let mut out = Vec::new();
        for k in 0..sides {
            let a = k as f64 * std::f64::consts::TAU / sides as f64;
            for z in [-length / 2.0, length / 2.0] {
                out.push(Point3::from(
                    turn * Vec3::new(radius * a.cos(), radius * a.sin(), z),
                ));
            }
        }
        out
    }

    /// Every capsule lies inside the box of half extents `half` (in its own frame).
    fn inside_box(capsules: &[(Point3, Point3, f64)], half: Vec3, turn: Rotation, at: Vec3) {
        for (a, b, r) in capsules {
            for end in [a, b] {
                let local = turn.inverse() * (end.coords - at);
                for k in 0..3 {
                    assert!(
                        local[k].abs() + r <= half[k] + 1e-9,
                        "{local:?} r {r} in {half:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_plate_becomes_rows_that_cover_its_faces_within_the_tolerance_and_stay_inside() {
        let (half, turn, at) = (
            Vec3::new(0.03, 0.002, 0.015),
            Rotation::from_euler_angles(0.3, -0.7, 1.1),
            Vec3::new(0.01, -0.02, 0.005),
        );
        let made = convex_capsules(&box_corners(half, turn, at), 0.001).unwrap();
        inside_box(&made.capsules, half, turn, at);
        for (_, _, r) in &made.capsules {
            assert!(
                (r - 0.002).abs() < 1e-6,
                "radius {r}: half the plate's thickness"
            );
        }
        assert!(
            made.capsules.len() >= 4,
            "{} rows across 3 cm",
            made.capsules.len()
        );
        // The triangles' centres on the large faces lie between rows: within the tolerance.
        assert!(made.face_gap <= 0.001 + 1e-6, "face gap {}", made.face_gap);
        // Corners are rounded by at most the radius.
        assert!(
            made.corner_gap <= 0.002 * 2f64.sqrt(),
            "corner gap {}",
            made.corner_gap
        );
    }

    #[test]
    fn a_round_rod_becomes_one_capsule_along_its_axis_with_its_inscribed_radius() {
        let turn = Rotation::from_euler_angles(0.9, 0.4, -0.2);
        let made = convex_capsules(&prism(24, 0.01, 0.05, turn), 0.001).unwrap();
        let inscribed = 0.01 * (std::f64::consts::PI / 24.0).cos();
        let (a, b, r) = made
            .capsules
            .iter()
            .copied()
            .max_by(|x, y| x.2.total_cmp(&y.2))
            .unwrap();
        assert!(
            (r - inscribed).abs() < 1e-6,
            "radius {r}, inscribed {inscribed}"
        );
        let axis = turn * Vec3::z();
        assert!(((b - a).normalize().dot(&axis)).abs() > 1.0 - 1e-9);
        // Its ends stop a radius short of the caps.
        assert!(
            ((b - a).norm() - (0.05 - 2.0 * inscribed)).abs() < 1e-6,
            "{:?}",
            made.capsules
        );
        assert_eq!(made.capsules.len(), 1, "{:?}", made.capsules);
        // The flat ends are rounded: a point of an end face's rim is (√2 − 1)·r from the cap.
        assert!(
            made.face_gap <= (2f64.sqrt() - 1.0) * inscribed + 1e-6,
            "face gap {}",
            made.face_gap
        );
    }

    #[test]
    fn every_capsule_of_a_random_convex_shape_lies_inside_its_hull() {
        let mut rng = crate::random::SplitMix64::new(7);
        for case in 0..30 {
            let stretch = Vec3::new(
                rng.uniform(0.005, 0.04),
                rng.uniform(0.005, 0.04),
                rng.uniform(0.005, 0.04),
            );
            let points: Vec<Point3> = (0..40)
                .map(|_| {
                    let d = Vec3::new(
                        rng.uniform(-1.0, 1.0),
                        rng.uniform(-1.0, 1.0),
                        rng.uniform(-1.0, 1.0),
                    );
                    Point3::from(d.normalize().component_mul(&stretch))
                })
                .collect();
            let made = convex_capsules(&points, 0.001).unwrap();
            assert!(!made.capsules.is_empty(), "case {case}: no capsule");
            // Independent of the hull code: the hull's faces are the planes through three of
            // the points with every other point on one side; a capsule end must lie at least
            // its radius inside each.
            let mut faces = Vec::new();
            for i in 0..points.len() {
                for j in i + 1..points.len() {
                    for k in j + 1..points.len() {
                        let n = (points[j] - points[i]).cross(&(points[k] - points[i]));
                        if n.norm() < 1e-12 {
                            continue;
                        }
                        let n = n.normalize();
                        let side =
                            |s: f64| points.iter().all(|p| s * n.dot(&(p - points[i])) <= 1e-12);
                        if side(1.0) {
                            faces.push((n, points[i]));
                        } else if side(-1.0) {
                            faces.push((-n, points[i]));
                        }
                    }
                }
            }
            assert!(faces.len() >= 4, "case {case}");
            for (a, b, r) in &made.capsules {
                for end in [a, b] {
                    for (outward, on) in &faces {
                        let depth = -outward.dot(&(end - on));
                        assert!(depth >= r - 1e-9, "case {case}: end {depth} deep, r {r}");
                    }
                }
            }
        }
    }

    #[test]
    fn flat_too_few_or_not_finite_points_are_refused() {
        let flat: Vec<Point3> = (0..6)
            .map(|k| Point3::new(k as f64 * 0.01, (k * k) as f64 * 0.001, 0.0))
            .collect();
        assert!(matches!(
            convex_capsules(&flat, 0.001),
            Err(HullError::Flat { .. })
        ));
        assert!(matches!(
            convex_capsules(&flat[..3], 0.001),
            Err(HullError::TooFewPoints { .. })
        ));
        let mut bad = box_corners(Vec3::repeat(0.01), Rotation::identity(), Vec3::zeros());
        bad[3].y = f64::NAN;
        assert!(matches!(
            convex_capsules(&bad, 0.001),
            Err(HullError::NotFinite)
        ));
    }
}
