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

/// True when segment `p–q` comes within `radius` of triangle `(a, b, c)` whose unit normal is
/// `normal`, zero for a sliver or a collapsed triangle (no plane to trust). Rejects first,
/// cheaply, when both ends lie more than `radius` on one side of the triangle's plane.
#[inline]
pub fn segment_within_triangle(
    p: &Point3,
    q: &Point3,
    [a, b, c]: &[Point3; 3],
    normal: &Vec3,
    radius: f64,
) -> bool {
    let sp = normal.dot(&(p - a));
    let sq = normal.dot(&(q - a));
    if (sp > radius && sq > radius) || (sp < -radius && sq < -radius) {
        return false;
    }
    distance_squared_segment_triangle(p, q, a, b, c) <= radius * radius
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
        let mut rng = crate::search::random::SplitMix64::new(3);
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
