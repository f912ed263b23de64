//! Squared distance between two segments (Ericson §5.1.9), robust to zero-length segments.

use crate::math::{Point3, Vec3};

/// Squared distance between segments `p1–q1` and `p2–q2`.
pub fn distance_squared_segment_segment(p1: &Point3, q1: &Point3, p2: &Point3, q2: &Point3) -> f64 {
    closest_segment_segment(p1, q1, p2, q2).0
}

/// Squared distance between segments `p1–q1` and `p2–q2`, with the fraction `s` along the first
/// and `t` along the second where it is reached.
pub fn closest_segment_segment(
    p1: &Point3,
    q1: &Point3,
    p2: &Point3,
    q2: &Point3,
) -> (f64, f64, f64) {
    let d1: Vec3 = q1 - p1;
    let d2: Vec3 = q2 - p2;
    let r: Vec3 = p1 - p2;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&r);
    const EPS: f64 = 1e-30;
    let (s, t);
    if a <= EPS && e <= EPS {
        return (r.norm_squared(), 0.0, 0.0);
    }
    if a <= EPS {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= EPS {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > EPS * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    let c1 = p1 + d1 * s;
    let c2 = p2 + d2 * t;
    ((c1 - c2).norm_squared(), s, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_parallel_and_degenerate() {
        let p = |x, y, z| Point3::new(x, y, z);
        let d = distance_squared_segment_segment(
            &p(-1.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(0.0, -1.0, 2.0),
            &p(0.0, 1.0, 2.0),
        );
        assert!((d - 4.0).abs() < 1e-12);
        let d = distance_squared_segment_segment(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(0.5, 3.0, 0.0),
            &p(4.0, 3.0, 0.0),
        );
        assert!((d - 9.0).abs() < 1e-12);
        let d = distance_squared_segment_segment(
            &p(0.0, 0.0, 0.0),
            &p(0.0, 0.0, 0.0),
            &p(3.0, 4.0, 0.0),
            &p(3.0, 4.0, 0.0),
        );
        assert!((d - 25.0).abs() < 1e-12);
    }
}
