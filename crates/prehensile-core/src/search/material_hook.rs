//! A hook in the object's material for a search whose hook lies outside it (a ring's or a
//! torus's centre of mass, in the hole). Hung from such a hook, a hand closes through the hole
//! or around the whole object; when neither gives a grasp that pushes from every side, the
//! planner searches again from the middle of the material a person would take: the rim nearest
//! the shoulder, else the top, else the material nearest the hook.
//!
//! Written by hand: the material along a ray is found by sphere tracing (Hart 1996) on the
//! exact signed distance the object already has; a ray-cast crate would need a second copy of
//! the mesh in its own structure for the few dozen queries this makes once per search.

use crate::collision::TriangleBvh;
use crate::math::{Point3, Vec3};

/// Closer than this to the surface counts as on it, metres.
const ON_SURFACE: f64 = 1e-5;

/// The least advance of a trace, metres: a trace near a surface it runs along still ends.
const LEAST_STEP: f64 = 1e-4;

/// Most distance queries one trace makes.
const MOST_QUERIES: usize = 400;

/// The middle of the material nearest `hook` along, in turn, the horizontal direction toward
/// the shoulder (`toward_shoulder`), `up`, and the direction of the surface point nearest the
/// hook: where the first of them meets the material within `reach` of the hook, the midpoint of
/// its first run through it. `None` when `hook` is not outside the material or no direction
/// meets it.
pub fn material_hook(
    exact: &TriangleBvh,
    hook: &Point3,
    toward_shoulder: &Vec3,
    up: &Vec3,
    reach: f64,
) -> Option<Point3> {
    let outside = exact.signed_distance(hook);
    if !(outside > ON_SURFACE && reach.is_finite()) {
        return None;
    }
    let nearest = exact
        .closest_point_within(hook, f64::INFINITY)
        .map(|s| s.point - hook);
    [Some(*toward_shoulder), Some(*up), nearest]
        .into_iter()
        .flatten()
        .filter_map(|d| d.try_normalize(1e-12))
        .find_map(|d| middle_of_first_run(exact, hook, &d, reach))
}

/// The midpoint of the first run of material along the ray from `from` (outside) in unit
/// direction `d`, if the ray enters the material within `reach`.
fn middle_of_first_run(exact: &TriangleBvh, from: &Point3, d: &Vec3, reach: f64) -> Option<Point3> {
    // Outside: advance by the distance to the surface, which no surface is nearer than.
    let mut t = 0.0;
    let mut queries = 0;
    let entry = loop {
        let s = exact.signed_distance(&(from + d * t));
        queries += 1;
        if s < ON_SURFACE {
            break t;
        }
        t += s.max(LEAST_STEP);
        if t > reach || queries >= MOST_QUERIES {
            return None;
        }
    };
    // Inside: the same, by the distance to the surface from within, until outside again.
    t += LEAST_STEP;
    let exit = loop {
        let s = exact.signed_distance(&(from + d * t));
        queries += 1;
        if s >= 0.0 || queries >= MOST_QUERIES {
            break t;
        }
        t += (-s).max(LEAST_STEP);
    };
    Some(from + d * (0.5 * (entry + exit)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::torus;

    #[test]
    fn a_torus_is_hooked_in_its_tube_on_the_shoulders_side() {
        let exact = TriangleBvh::new(&torus(0.045, 0.014, 64, 32));
        let toward = Vec3::new(-0.8, -0.6, 0.0);
        let hook = material_hook(&exact, &Point3::origin(), &toward, &Vec3::z(), 0.2).unwrap();
        // The tube's centre line is 4.5 cm from the axis; the hook is on it, toward the shoulder.
        assert!((hook.coords.norm() - 0.045).abs() < 1e-3, "{hook:?}");
        assert!((hook.coords.normalize() - toward.normalize()).norm() < 1e-3);
        assert!(exact.signed_distance(&hook) < -0.013);
    }

    #[test]
    fn an_upright_ring_seen_through_its_hole_is_hooked_at_the_top() {
        // The ring's axis along x, the shoulder's direction: the first ray goes through the hole.
        let mut mesh = torus(0.045, 0.014, 64, 32);
        for v in &mut mesh.vertices {
            *v = Point3::new(v.z, v.y, -v.x);
        }
        let exact = TriangleBvh::new(&mesh);
        let hook = material_hook(&exact, &Point3::origin(), &-Vec3::x(), &Vec3::z(), 0.2).unwrap();
        assert!(
            (hook - Point3::new(0.0, 0.0, 0.045)).norm() < 1e-3,
            "{hook:?}"
        );
    }

    #[test]
    fn a_hook_in_the_material_or_out_of_reach_gets_none() {
        let exact = TriangleBvh::new(&torus(0.045, 0.014, 64, 32));
        let in_tube = Point3::new(0.045, 0.0, 0.0);
        assert_eq!(
            material_hook(&exact, &in_tube, &Vec3::x(), &Vec3::z(), 0.2),
            None
        );
        // Reach shorter than the way to the tube: only the nearest-surface direction is left,
        // and it too is out of reach.
        assert_eq!(
            material_hook(&exact, &Point3::origin(), &Vec3::x(), &Vec3::z(), 0.01),
            None
        );
    }
}
