//! The fast path's error bound is zero: on random capsules near concave and genus-1 objects, and
//! near two closed parts that overlap (signed by winding numbers), it gives the exact path's
//! answer every time.

use crate::common;

use prehensile_core::geometry::{closest_point_on_triangle, distance_squared_segment_triangle};
use prehensile_core::math::Point3;
use prehensile_core::{Capsule, CollisionCounters};
use proptest::prelude::*;

thread_local! {
    /// The objects the tests query, built once per name and test thread.
    static OBJECTS: std::collections::HashMap<&'static str, prehensile_core::ObjectModel> =
        ["mug", "torus", "box", "sphere"]
            .into_iter()
            .map(|n| (n, common::object(n)))
            .chain([("box through ring", box_through_ring())])
            .collect();
}

/// The built-in box with the built-in torus around its middle, sunk 5 mm into it: two closed
/// parts that overlap, so its inside comes from winding numbers, whole numbers off the surface,
/// and the search's distance grid still applies.
fn box_through_ring() -> prehensile_core::ObjectModel {
    let cuboid = prehensile_core::shapes::builtin_object("box").unwrap();
    let ring = prehensile_core::shapes::torus(0.035, 0.01, 32, 16);
    let offset = cuboid.vertices.len();
    let mut mesh = cuboid;
    mesh.vertices.extend(ring.vertices);
    mesh.triangles
        .extend(ring.triangles.iter().map(|t| t.map(|v| v + offset as u32)));
    let object = prehensile_core::ObjectModel::new("box through ring", mesh, None).unwrap();
    let exact = object.collider().exact();
    assert!(exact.uses_winding_numbers() && exact.signs_change_only_at_the_surface());
    // The grid serves the yes/no tests only: no contact grid, no clearance bounds (buried
    // triangles make its inside distances too short for contact normals).
    let collider = object.collider();
    assert!(collider.grid().is_some() && collider.contact_grid().is_none());
    let centre = object.center_of_mass();
    let bound = collider.segment_clearance_upper_bound(&centre, &centre, f64::INFINITY);
    assert_eq!(bound, f64::INFINITY);
    object
}

/// A segment of `length` through `centre` (lifted 5 cm, over the objects) along `direction`
/// (x when it has none).
fn segment(centre: [f64; 3], direction: [f64; 3], length: f64) -> (Point3, Point3) {
    let d = nalgebra::Vector3::from(direction);
    let d = if d.norm() > 1e-9 {
        d.normalize()
    } else {
        nalgebra::Vector3::x()
    };
    let c = Point3::from(centre) + nalgebra::Vector3::new(0.0, 0.0, 0.05);
    (c - d * length / 2.0, c + d * length / 2.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn fast_path_agrees_with_exact(
        object in prop::sample::select(vec!["mug", "torus", "box", "sphere", "box through ring"]),
        centre in prop::array::uniform3(-0.08f64..0.08),
        direction in prop::array::uniform3(-1.0f64..1.0),
        length in 0.0f64..0.06,
        radius in 0.0005f64..0.02,
    ) {
        let (a, b) = segment(centre, direction, length);
        let capsule = Capsule { a, b, radius };
        OBJECTS.with(|objects| {
            let o = &objects[object];
            let exact = o.collider().exact().capsule_touches(&capsule.a, &capsule.b, radius);
            let fast = o.capsule_touches(&capsule, &mut CollisionCounters::default());
            prop_assert_eq!(fast, exact, "{} {:?}", object, capsule);
            Ok(())
        })?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The BVH's bounded nearest-point query (what fills the grid's nodes) finds the distance a
    /// loop over every triangle finds, and nothing when that is beyond the bound.
    #[test]
    fn nearest_surface_point_is_the_nearest_of_every_triangle(
        object in prop::sample::select(vec!["mug", "torus", "box", "sphere"]),
        point in prop::array::uniform3(-0.1f64..0.1),
        bound in prop::sample::select(vec![0.005, 0.02, f64::INFINITY]),
    ) {
        let p = Point3::from(point) + nalgebra::Vector3::new(0.0, 0.0, 0.05);
        OBJECTS.with(|objects| {
            let o = &objects[object];
            let mesh = o.mesh();
            let nearest = (0..mesh.triangles.len())
                .map(|t| {
                    let [a, b, c] = mesh.corners(t);
                    (closest_point_on_triangle(&p, &a, &b, &c).0 - p).norm()
                })
                .fold(f64::INFINITY, f64::min);
            match o.collider().exact().closest_point_within(&p, bound) {
                Some(found) => {
                    prop_assert!(nearest <= bound);
                    prop_assert!((found.signed_distance.abs() - nearest).abs() < 1e-12,
                        "{} {:?}: BVH {} against {}", object, p, found.signed_distance, nearest);
                }
                None => prop_assert!(nearest > bound, "{} {:?}: missed {}", object, p, nearest),
            }
            Ok(())
        })?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The BVH's segment query (what finds a capsule's contacts) finds the distance a loop over
    /// every triangle with the segment–triangle kernel finds, at a point of the segment that is
    /// that far from the surface, and nothing when that is beyond the bound.
    #[test]
    fn the_point_of_a_segment_nearest_the_surface_is_the_nearest_of_every_triangle(
        object in prop::sample::select(vec!["mug", "torus", "box", "sphere"]),
        centre in prop::array::uniform3(-0.1f64..0.1),
        direction in prop::array::uniform3(-1.0f64..1.0),
        length in 0.0f64..0.05,
        bound in prop::sample::select(vec![0.005, 0.02, f64::INFINITY]),
    ) {
        let (a, b) = segment(centre, direction, length);
        OBJECTS.with(|objects| {
            let o = &objects[object];
            let mesh = o.mesh();
            let nearest = (0..mesh.triangles.len())
                .map(|t| {
                    let [p, q, r] = mesh.corners(t);
                    distance_squared_segment_triangle(&a, &b, &p, &q, &r)
                })
                .fold(f64::INFINITY, f64::min)
                .sqrt();
            let exact = o.collider().exact();
            match exact.closest_point_to_segment_within(&a, &b, bound) {
                Some((s, found)) => {
                    prop_assert!(nearest <= bound);
                    prop_assert!((0.0..=1.0).contains(&s));
                    prop_assert!((found.signed_distance.abs() - nearest).abs() < 1e-12,
                        "{} {:?}–{:?}: BVH {} against {}", object, a, b, found.signed_distance, nearest);
                    // The surface point is the one nearest that point of the segment.
                    let at = a + (b - a) * s;
                    let from_point = exact.closest_point_within(&at, f64::INFINITY).unwrap();
                    prop_assert!((from_point.signed_distance - found.signed_distance).abs() < 1e-12);
                }
                None => prop_assert!(nearest > bound, "{} {:?}–{:?}: missed {}", object, a, b, nearest),
            }
            Ok(())
        })?;
    }
}

/// The distance grid fills itself on first use: setting an object up computes no node, a whole
/// grasp search reads only part of the grid, and threads sharing one object agree with a
/// thread that has it alone.
#[test]
fn the_grid_fills_lazily_and_threads_sharing_it_agree() {
    use prehensile_core::search::{GraspPlanner, GraspResult, SearchParams};
    use prehensile_core::Workspace;
    let object = common::object("mug");
    let grid = object.collider().grid().expect("a clean mesh has the grid");
    assert_eq!(grid.filled_nodes(), 0);
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let search = |object: &prehensile_core::ObjectModel, seed: u64| {
        let mut planner = GraspPlanner::new(
            &hand,
            object,
            hand.movement("power").unwrap(),
            Point3::new(-0.35, -0.2, 0.35),
            SearchParams {
                seed,
                ..SearchParams::default()
            },
        )
        .unwrap();
        planner.run_to_end();
        serde_json::to_value(GraspResult::from_planner(
            &planner,
            &mut Workspace::new(&hand),
        ))
        .map(|mut v| {
            v["stats"]["seconds"] = 0.0.into();
            v
        })
        .unwrap()
    };
    let alone: Vec<_> = (1..=4)
        .map(|seed| search(&common::object("mug"), seed))
        .collect();
    let shared: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (1..=4)
            .map(|seed| {
                let object = &object;
                let search = &search;
                s.spawn(move || search(object, seed))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(alone, shared);
    let filled = grid.filled_nodes();
    assert!(
        filled > 0 && filled < grid.node_count() / 2,
        "four searches filled {filled} of {} nodes",
        grid.node_count()
    );
}
