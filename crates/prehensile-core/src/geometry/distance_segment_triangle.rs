//! Squared distance between a segment and a triangle.
//!
//! If the segment pierces the triangle the distance is zero; otherwise the minimum is reached
//! either at a segment endpoint against the triangle or between the segment and a triangle edge.

use super::{closest_point_on_triangle, closest_segment_segment};
use crate::math::{Point3, Vec3};

/// Squared distance between segment `p–q` and triangle `(a, b, c)`.
pub fn distance_squared_segment_triangle(
    p: &Point3,
    q: &Point3,
    a: &Point3,
    b: &Point3,
    c: &Point3,
) -> f64 {
    closest_segment_triangle(p, q, a, b, c).0
}

/// Squared distance between segment `p–q` and triangle `(a, b, c)`, with the fraction `s` along
/// the segment where it is reached (where the segment pierces the triangle, at distance 0).
pub fn closest_segment_triangle(
    p: &Point3,
    q: &Point3,
    a: &Point3,
    b: &Point3,
    c: &Point3,
) -> (f64, f64) {
    if let Some(s) = segment_pierces_triangle(p, q, a, b, c) {
        return (0.0, s);
    }
    let dp = (closest_point_on_triangle(p, a, b, c).0 - p).norm_squared();
    let dq = (closest_point_on_triangle(q, a, b, c).0 - q).norm_squared();
    [
        (dp, 0.0),
        (dq, 1.0),
        edge(p, q, a, b),
        edge(p, q, b, c),
        edge(p, q, c, a),
    ]
    .into_iter()
    .fold(
        (f64::INFINITY, 0.0),
        |best, x| if x.0 < best.0 { x } else { best },
    )
}

/// Squared distance from segment `p–q` to the edge `u–v`, and the fraction along `p–q`.
fn edge(p: &Point3, q: &Point3, u: &Point3, v: &Point3) -> (f64, f64) {
    let (d, s, _) = closest_segment_segment(p, q, u, v);
    (d, s)
}

/// True when segment `p–q` comes within `radius` of triangle `(a, b, c)`. `normal` is the
/// triangle's unit normal, oriented as `(b − a) × (c − a)`, or zero for a sliver or a collapsed
/// triangle (no plane to trust: the full distance decides).
///
/// With a normal the test needs no nearest point on the triangle. It rejects when both ends lie
/// more than `radius` on one side of the plane, or beyond the plane through an edge along the
/// normal. It accepts where the segment pierces the triangle, or where an end within `radius`
/// of the plane lies over the triangle. Otherwise the nearest points are on an edge (an end not
/// over the triangle is nearest to its boundary), so the three segment–edge distances decide,
/// the first one near enough ending it. The radius is not negative.
#[inline]
pub fn segment_within_triangle(
    p: &Point3,
    q: &Point3,
    [a, b, c]: &[Point3; 3],
    normal: &Vec3,
    radius: f64,
) -> bool {
    if *normal == Vec3::zeros() {
        return distance_squared_segment_triangle(p, q, a, b, c) <= radius * radius;
    }
    let sp = normal.dot(&(p - a));
    let sq = normal.dot(&(q - a));
    if (sp > radius && sq > radius) || (sp < -radius && sq < -radius) {
        return false;
    }
    // For each edge u→v, (x − u)·(n × (v − u)) is |v − u| times x's signed distance from the
    // plane through the edge along n, positive on the triangle's side.
    let r2 = radius * radius;
    let mut inward = [[0.0; 3]; 2];
    for (k, (u, v)) in [(a, b), (b, c), (c, a)].into_iter().enumerate() {
        let across = normal.cross(&(v - u));
        let (hp, hq) = ((p - u).dot(&across), (q - u).dot(&across));
        // Both ends more than `radius` beyond this edge's plane: a separating plane.
        if hp < 0.0 && hq < 0.0 && hp.max(hq).powi(2) > r2 * across.norm_squared() {
            return false;
        }
        inward[0][k] = hp;
        inward[1][k] = hq;
    }
    let over = |h: &[f64; 3]| h.iter().all(|&x| x >= 0.0);
    if (sp <= 0.0) != (sq <= 0.0) {
        let t = sp / (sp - sq);
        let at: [f64; 3] =
            std::array::from_fn(|k| inward[0][k] + t * (inward[1][k] - inward[0][k]));
        if over(&at) {
            return true;
        }
    }
    if (sp.abs() <= radius && over(&inward[0])) || (sq.abs() <= radius && over(&inward[1])) {
        return true;
    }
    // At the nearest points x (segment) and y (an edge), x − y lies in the triangle's normal
    // cone at y, so x is not strictly inside that edge's plane (at a corner, not inside one of
    // its two edges' planes): an edge with both ends of the segment strictly inside its plane is
    // never the nearest, and its distance is not needed.
    [(a, b), (b, c), (c, a)]
        .into_iter()
        .enumerate()
        .any(|(k, (u, v))| {
            inward[0][k].min(inward[1][k]) <= 0.0 && closest_segment_segment(p, q, u, v).0 <= r2
        })
}

/// Where the segment crosses the triangle's plane inside the triangle (boundary included), as a
/// fraction along it; `None` if it does not.
fn segment_pierces_triangle(
    p: &Point3,
    q: &Point3,
    a: &Point3,
    b: &Point3,
    c: &Point3,
) -> Option<f64> {
    let n: Vec3 = (b - a).cross(&(c - a));
    let sp = n.dot(&(p - a));
    let sq = n.dot(&(q - a));
    if (sp > 0.0 && sq > 0.0) || (sp < 0.0 && sq < 0.0) || sp == sq {
        // Same side, or parallel to the plane (handled by the edge and endpoint distances).
        return None;
    }
    let t = sp / (sp - sq);
    let x = p + (q - p) * t;
    let inside_edge = |u: &Point3, v: &Point3| n.dot(&(v - u).cross(&(x - u))) >= 0.0;
    (inside_edge(a, b) && inside_edge(b, c) && inside_edge(c, a)).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_reject_agrees_with_the_distance() {
        let p = |x, y, z| Point3::new(x, y, z);
        let tri = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
        let n = Vec3::z();
        for (a, b, r) in [
            (p(0.2, 0.2, 0.5), p(0.3, 0.2, 0.6), 0.49),
            (p(0.2, 0.2, 0.5), p(0.3, 0.2, 0.6), 0.51),
            (p(2.0, 2.0, 0.0), p(3.0, 2.0, 0.0), 1.0),
            (p(0.2, 0.2, -0.5), p(0.2, 0.2, 0.5), 0.01),
        ] {
            let expected =
                distance_squared_segment_triangle(&a, &b, &tri[0], &tri[1], &tri[2]) <= r * r;
            assert_eq!(segment_within_triangle(&a, &b, &tri, &n, r), expected);
        }
    }

    /// The shortcut test (no nearest point on the triangle) against the full distance, with
    /// radii just below and above it; in a quarter of the cases segment and triangle lie in one
    /// plane.
    #[test]
    fn the_within_test_agrees_with_the_distance() {
        let mut rng = crate::random::SplitMix64::new(11);
        let mut point = |flat: bool| {
            Point3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                if flat { 0.0 } else { rng.uniform(-1.0, 1.0) },
            )
        };
        for case in 0..20_000 {
            let flat = case % 4 == 0;
            let (p, q, a, b, c) = (
                point(flat),
                point(flat),
                point(flat),
                point(flat),
                point(flat),
            );
            let normal = (b - a).cross(&(c - a)).normalize();
            let d = distance_squared_segment_triangle(&p, &q, &a, &b, &c).sqrt();
            // Radii within rounding of the distance (1e-12) are ties either answer may take.
            let radii = [d * 0.999 - 1e-9, d * 1.001 + 1e-9, 0.5 * d, d + 0.1];
            for r in radii
                .into_iter()
                .filter(|&r| r >= 0.0 && (r - d).abs() > 1e-12)
            {
                assert_eq!(
                    segment_within_triangle(&p, &q, &[a, b, c], &normal, r),
                    d <= r,
                    "case {case}: distance {d}, radius {r}"
                );
            }
        }
    }

    /// The edges skipped (both ends inside their planes) on the cases where rounding decides:
    /// segments in an edge's plane or within 1e-15…1e-9 of it, through corners, along edges,
    /// at heights around the radius.
    #[test]
    fn the_within_test_agrees_along_edges_and_corners() {
        let mut rng = crate::random::SplitMix64::new(5);
        let mut point = || {
            Point3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
        };
        let mut cases = 0;
        for _ in 0..3000 {
            let (a, b, c) = (point(), point(), point());
            let normal = (b - a).cross(&(c - a)).normalize();
            for (u, v) in [(a, b), (b, c), (c, a)] {
                let outward = (v - u).cross(&normal).normalize();
                for (along, offset, height, length) in [
                    (0.5, 0.0, 0.1, 0.2),
                    (0.0, 1e-15, 0.1, 0.05),
                    (1.0, -1e-15, 0.05, 0.3),
                    (0.3, 1e-9, -0.1, 0.1),
                    (0.7, -1e-9, 0.0, 0.2),
                    (-0.2, 0.0, 0.02, 0.1),
                    (1.2, 1e-12, 0.2, 0.6),
                ] {
                    let at = u + (v - u) * along + outward * offset;
                    let edge = (v - u).normalize();
                    for direction in [edge, outward, normal, (edge + normal).normalize()] {
                        let p = at + normal * height - direction * (0.5 * length);
                        let q = at + normal * height + direction * (0.5 * length);
                        let d = distance_squared_segment_triangle(&p, &q, &a, &b, &c).sqrt();
                        for r in [d * 0.999 - 1e-9, d * 1.001 + 1e-9, d + 1e-6]
                            .into_iter()
                            .filter(|&r| r >= 0.0 && (r - d).abs() > 1e-12)
                        {
                            cases += 1;
                            assert_eq!(
                                segment_within_triangle(&p, &q, &[a, b, c], &normal, r),
                                d <= r,
                                "distance {d}, radius {r}, segment {p} {q}, triangle {a} {b} {c}"
                            );
                        }
                    }
                }
            }
        }
        assert!(cases > 200_000, "{cases} cases");
    }

    #[test]
    fn piercing_above_and_beside() {
        let p = |x, y, z| Point3::new(x, y, z);
        let (a, b, c) = (p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0));
        let d =
            distance_squared_segment_triangle(&p(0.2, 0.2, -1.0), &p(0.2, 0.2, 1.0), &a, &b, &c);
        assert_eq!(d, 0.0);
        let d = distance_squared_segment_triangle(&p(0.2, 0.2, 0.5), &p(0.2, 0.2, 1.0), &a, &b, &c);
        assert!((d - 0.25).abs() < 1e-12);
        // Parallel segment beside the hypotenuse.
        let d = distance_squared_segment_triangle(&p(1.0, 1.0, 0.0), &p(2.0, 0.0, 0.0), &a, &b, &c);
        assert!((d - 0.5).abs() < 1e-12);
        // Segment passing over an edge without piercing: distance to the edge.
        let d =
            distance_squared_segment_triangle(&p(0.5, -1.0, 0.1), &p(0.5, 1.0, 0.1), &a, &b, &c);
        assert!(d <= 0.01 + 1e-12);
    }

    #[test]
    fn the_fraction_returned_is_where_the_segment_is_that_near() {
        let mut rng = crate::random::SplitMix64::new(3);
        let mut point = || {
            Point3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
        };
        for _ in 0..2000 {
            let (p, q, a, b, c) = (point(), point(), point(), point(), point());
            let (d, s) = closest_segment_triangle(&p, &q, &a, &b, &c);
            assert!((0.0..=1.0).contains(&s));
            let at = p + (q - p) * s;
            let there = (closest_point_on_triangle(&at, &a, &b, &c).0 - at).norm_squared();
            assert!((there - d).abs() < 1e-12, "{there} against {d}");
            // No point of the segment is nearer (sampled).
            for k in 0..=50 {
                let x = p + (q - p) * (k as f64 / 50.0);
                let e = (closest_point_on_triangle(&x, &a, &b, &c).0 - x).norm_squared();
                assert!(e >= d - 1e-12);
            }
        }
    }
}
