//! The fast path's error bound is zero: on random capsules near concave and genus-1 objects it
//! gives the exact path's answer every time.

mod common;

use prehensile_core::math::Point3;
use prehensile_core::{Capsule, CollisionCounters};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn fast_path_agrees_with_exact(
        object in prop::sample::select(vec!["mug", "torus", "box", "sphere"]),
        centre in prop::array::uniform3(-0.08f64..0.08),
        direction in prop::array::uniform3(-1.0f64..1.0),
        length in 0.0f64..0.06,
        radius in 0.0005f64..0.02,
    ) {
        // Objects are built once per name and cached by the test harness's thread.
        thread_local! {
            static OBJECTS: std::collections::HashMap<&'static str, prehensile_core::ObjectModel> =
                ["mug", "torus", "box", "sphere"].into_iter().map(|n| (n, common::object(n))).collect();
        }
        let d = nalgebra::Vector3::from(direction);
        let d = if d.norm() > 1e-9 { d.normalize() } else { nalgebra::Vector3::x() };
        let c = Point3::from(centre) + nalgebra::Vector3::new(0.0, 0.0, 0.05);
        let capsule = Capsule { a: c - d * length / 2.0, b: c + d * length / 2.0, radius };
        OBJECTS.with(|objects| {
            let o = &objects[object];
            let exact = o.collider().exact().capsule_touches(&capsule.a, &capsule.b, radius);
            let fast = o.capsule_touches(&capsule, &mut CollisionCounters::default());
            prop_assert_eq!(fast, exact, "{} {:?}", object, capsule);
            Ok(())
        })?;
    }
}
