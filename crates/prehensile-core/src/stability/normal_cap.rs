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
//! as 90°. Above 32 normals (a crafted hand of hundreds of fingers: 500 of them
//! took 53 s a search, nearly all of it here) the same cap is found by the randomized
//! incremental algorithm of the smallest enclosing circle (Welzl 1991), in expected O(n).

use crate::math::Vec3;

/// Normals that fit an open hemisphere by a cosine smaller than this (a cap within 6·10⁻⁸° of
/// 90°) count as not fitting it. A box held on two opposite faces and a third at right angles
/// has its normals exactly on a hemisphere's edge, and rounding must not decide on which side
/// of it a grasp falls: it did, when the search began to rank such grasps, and
/// the WebAssembly build and the native one, whose results differ in the last bits, took
/// different paths on the cartoon hand's box.
const HEMISPHERE_SLACK: f64 = 1e-9;

/// The half-angle, radians, of the narrowest cone about some direction that contains every unit
/// vector in `normals`; π/2 when they do not all fit in an open hemisphere (none, or normals
/// that push from opposite sides), which is what a grasp that squeezes needs.
pub fn narrowest_normal_cap(normals: impl Iterator<Item = Vec3> + Clone) -> f64 {
    if normals.clone().nth(DIRECT_NORMALS).is_some() {
        incremental_cap(normals.collect())
    } else {
        candidates_cap(normals)
    }
}

/// [`narrowest_normal_cap`] by trying every candidate direction (module docs): O(n³), with no
/// allocation.
fn candidates_cap(normals: impl Iterator<Item = Vec3> + Clone) -> f64 {
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

/// Most normals whose cap is found by trying every candidate direction; more take the
/// incremental algorithm. Every grasp of a real hand measured has fewer (17 at most).
const DIRECT_NORMALS: usize = 32;
/// How far outside a cap a normal may lie and still count as in it, in cosine.
const IN_CAP: f64 = 1e-12;

/// A spherical cap: its axis and the cosine of its half-angle.
type Cap = (Vec3, f64);

/// [`narrowest_normal_cap`] by the smallest-enclosing-circle algorithm in its iterative form
/// (each normal outside the cap so far is on the new cap's edge), over the normals in a
/// shuffled order, which makes it expected O(n) whatever order they came in (a ring of
/// fingertips in order is its worst case). Within an open hemisphere spherical caps behave as
/// circles do in the plane; when the normals are in none, the cap it ends with is not narrower
/// than a hemisphere or leaves some normal out, and the answer is 90°. Allocates the shuffled
/// copy.
fn incremental_cap(mut normals: Vec<Vec3>) -> f64 {
    // Fisher–Yates with a fixed linear congruential sequence: the same answer every run.
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    for i in (1..normals.len()).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        normals.swap(i, (state >> 33) as usize % (i + 1));
    }
    let holds = |(axis, cosine): &Cap, n: &Vec3| axis.dot(n) >= cosine - IN_CAP;
    let Some(&first) = normals.first() else {
        return std::f64::consts::FRAC_PI_2;
    };
    let mut cap = (first, 1.0);
    for i in 1..normals.len() {
        if holds(&cap, &normals[i]) {
            continue;
        }
        cap = (normals[i], 1.0);
        for j in 0..i {
            if holds(&cap, &normals[j]) {
                continue;
            }
            cap = cap_through_two(&normals[i], &normals[j]);
            for k in 0..j {
                if !holds(&cap, &normals[k]) {
                    cap = cap_through_three(&normals[i], &normals[j], &normals[k]);
                }
            }
        }
    }
    if cap.1 > HEMISPHERE_SLACK && normals.iter().all(|n| holds(&cap, n)) {
        cap.1.min(1.0).acos()
    } else {
        std::f64::consts::FRAC_PI_2
    }
}

/// The narrowest cap with `a` and `b` on its edge: about their bisector (a whole sphere's
/// worth, cosine −1, for opposite normals).
fn cap_through_two(a: &Vec3, b: &Vec3) -> Cap {
    match (a + b).try_normalize(1e-12) {
        Some(axis) => (axis, axis.dot(a)),
        None => (*a, -1.0),
    }
}

/// The cap narrower than a hemisphere with `a`, `b` and `c` on its edge; for three normals on
/// one great circle (or two the same), the widest cap through two of them.
fn cap_through_three(a: &Vec3, b: &Vec3, c: &Vec3) -> Cap {
    match (b - a).cross(&(c - a)).try_normalize(1e-12) {
        Some(axis) => {
            let axis = if axis.dot(a) < 0.0 { -axis } else { axis };
            (axis, axis.dot(a))
        }
        None => [(a, b), (a, c), (b, c)]
            .map(|(p, q)| cap_through_two(p, q))
            .into_iter()
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("three pairs"),
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
    fn many_normals_get_the_cap_that_trying_every_direction_finds() {
        // Above 32 normals the incremental algorithm answers; on sets small enough for both
        // (33–60 normals, inside cones and not), it agrees with the candidates' answer.
        let mut seed = 11u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut one_sided = 0;
        for round in 0..60 {
            let axis = Vec3::new(next(), next(), next()).normalize();
            // Tighter cones, wider ones and sets with no common hemisphere.
            let spread = [0.3, 1.0, 3.0][round % 3];
            let n = 33 + round % 28;
            let normals: Vec<Vec3> = (0..n)
                .map(|_| (axis + Vec3::new(next(), next(), next()) * spread).normalize())
                .collect();
            let incremental = incremental_cap(normals.clone());
            let direct = candidates_cap(normals.iter().copied());
            assert!(
                (incremental - direct).abs() < 1e-9,
                "{n} normals: {incremental} against {direct}"
            );
            if incremental < std::f64::consts::FRAC_PI_2 {
                one_sided += 1;
            }
        }
        assert!((20..60).contains(&one_sided), "{one_sided}");
        // A ring of 3,000 fingertips' normals tilted 40° from z: the cap is that ring.
        let ring: Vec<Vec3> = (0..3000)
            .map(|k| {
                let phi = std::f64::consts::TAU * k as f64 / 3000.0;
                let t = 40f64.to_radians();
                Vec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
            })
            .collect();
        assert!((degrees(&ring) - 40.0).abs() < 1e-9);
        // And the same ring with one normal pointing down: not one-sided.
        let mut pushed = ring;
        pushed.push(-Vec3::z());
        assert_eq!(degrees(&pushed), 90.0);
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
