//! The narrowest cone of directions that holds every contact normal: how one-sided a grasp's
//! pushes are. When every normal lies within less than 90° of one direction, a hand that squeezes
//! pushes the object that way and only friction keeps it in; MuJoCo's replay of the Shadow hand's
//! grasps drops most such grasps (docs/QUALITY.md).
//!
//! The cone's half-angle is `acos(max over unit u of min_i u·n_i)`: the smallest spherical cap
//! holding the unit normals. As with the smallest circle around points in the plane, a cap
//! narrower than a hemisphere is fixed by one, two or three of its points, so it is found by
//! trying every such cap (the normalised sum of a pair; the direction equally far from a triple)
//! and keeping the one whose farthest normal is nearest. That is O(n³) candidate directions for n
//! contacts (about 20 µs for the 17 contacts of the largest grasps measured, 0.5 ms for 40), and
//! needs no solver; caps of a hemisphere or wider all count as "not one-sided" and are reported
//! as 90°.

use crate::math::Vec3;

/// Normals that fit an open hemisphere by a cosine smaller than this (a cap within 6·10⁻⁸° of
/// 90°) count as not fitting it. A box held on two opposite faces and a third at right angles
/// has its normals exactly on a hemisphere's edge, and rounding must not decide on which side
/// of it a grasp falls: it did, when the search began to rank such grasps (session 27), and
/// the WebAssembly build and the native one, whose results differ in the last bits, took
/// different paths on the cartoon hand's box.
const HEMISPHERE_SLACK: f64 = 1e-9;

/// The half-angle, radians, of the narrowest cone about some direction that contains every unit
/// vector in `normals`; π/2 when they do not all fit in an open hemisphere (none, or normals
/// that push from opposite sides), which is what a grasp that squeezes needs.
pub fn narrowest_normal_cap(normals: impl Iterator<Item = Vec3> + Clone) -> f64 {
    let mut best = 0.0_f64; // the largest smallest cosine found: > 0 means one-sided
                            // A direction's smallest cosine over the normals, given up as soon as it cannot beat the best
                            // so far (the answer is the same as scanning every normal; half the time).
    let mut consider = |u: Vec3| {
        let length = u.norm();
        if length <= 1e-12 {
            return;
        }
        let u = u / length;
        let mut smallest = f64::INFINITY;
        for n in normals.clone() {
            smallest = smallest.min(u.dot(&n));
            if smallest <= best {
                return;
            }
        }
        best = smallest;
    };
    for (i, a) in normals.clone().enumerate() {
        consider(a);
        for (j, b) in normals.clone().enumerate().skip(i + 1) {
            consider(a + b);
            for c in normals.clone().skip(j + 1) {
                // Equally far from a, b and c: perpendicular to b − a and c − a; both sides.
                let u = (b - a).cross(&(c - a));
                consider(u);
                consider(-u);
            }
        }
    }
    if best <= HEMISPHERE_SLACK {
        std::f64::consts::FRAC_PI_2
    } else {
        best.min(1.0).acos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn degrees(normals: &[Vec3]) -> f64 {
        narrowest_normal_cap(normals.iter().map(|n| n.normalize())).to_degrees()
    }

    #[test]
    fn opposite_pushes_are_not_one_sided() {
        let x = Vec3::x();
        assert_eq!(degrees(&[x, -x]), 90.0);
        // A palm opposing four fingers, and a box held on four side faces.
        let fingers =
            [(0.3, 0.3), (0.3, -0.3), (-0.3, 0.3), (-0.3, -0.3)].map(|(y, z)| Vec3::new(1.0, y, z));
        assert_eq!(degrees(&[fingers, [-Vec3::x(); 4]].concat()), 90.0);
        assert_eq!(degrees(&[x, -x, Vec3::y(), -Vec3::y()]), 90.0);
        assert_eq!(degrees(&[]), 90.0);
        // On a hemisphere's edge, give or take rounding: not one-sided.
        for tilt in [-1e-13, 0.0, 1e-13] {
            let z = Vec3::z() * tilt;
            assert_eq!(degrees(&[x + z, -x + z, Vec3::y() + z]), 90.0);
        }
        // Clearly off it: one-sided.
        assert!(degrees(&[x + Vec3::z() * 1e-6, -x + Vec3::z() * 1e-6]) < 90.0);
    }

    #[test]
    fn the_cap_of_one_sided_normals_is_their_widest_spread() {
        let x = Vec3::x();
        assert!((degrees(&[x]) - 0.0).abs() < 1e-6);
        // Two normals 120° apart: a cap of 60° about their bisector.
        let b = Vec3::new(-0.5, 3f64.sqrt() / 2.0, 0.0);
        assert!((degrees(&[x, b]) - 60.0).abs() < 1e-9);
        // Three normals 30° from z, evenly round it (a fingertip tripod on a dome), plus one
        // inside: the cap is their circumcircle, 30°, whatever the inner one.
        let tripod: Vec<Vec3> = (0..3)
            .map(|k| {
                let phi = 2.0 * std::f64::consts::PI * k as f64 / 3.0;
                let t = 30f64.to_radians();
                Vec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
            })
            .chain([Vec3::new(0.1, 0.0, 1.0)])
            .collect();
        assert!((degrees(&tripod) - 30.0).abs() < 1e-9);
    }

    #[test]
    fn agrees_with_a_dense_search_over_directions() {
        // Random normals inside a cone about a random axis; compare with the best of 200k
        // directions (which can only be slightly worse).
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..20 {
            let axis = Vec3::new(next(), next(), next()).normalize();
            let normals: Vec<Vec3> = (0..8)
                .map(|_| (axis * 1.5 + Vec3::new(next(), next(), next())).normalize())
                .collect();
            let exact = degrees(&normals);
            let mut sampled = 90.0_f64;
            for _ in 0..200_000 {
                let u = Vec3::new(next(), next(), next());
                if u.norm() < 1e-3 {
                    continue;
                }
                let u = u.normalize();
                let worst = normals.iter().map(|n| u.dot(n)).fold(1.0, f64::min);
                sampled = sampled.min(worst.clamp(0.0, 1.0).acos().to_degrees());
            }
            assert!(exact <= sampled + 1e-9, "exact {exact} > sampled {sampled}");
            assert!(sampled - exact < 0.5, "exact {exact}, sampled {sampled}");
        }
    }
}
