//! Force closure, ε and load ratios against scipy's Qhull (`tools/oracle/stability_oracle.py`,
//! answers committed in `tests/data/stability_oracle.json`).

use prehensile_core::math::{Point3, Vec3};
use prehensile_core::stability::{force_closure_margin, Contact, ContactModel, GraspWrenchSpace};
use serde_json::Value;

fn vector(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [0, 1, 2].map(|k| a[k].as_f64().unwrap())
}

#[test]
fn stability_matches_scipy_qhull() {
    let data: Value =
        serde_json::from_str(include_str!("data/stability_oracle.json")).expect("oracle JSON");
    let cases = data["cases"].as_array().unwrap();
    assert!(cases.len() >= 80);
    let mut gws = GraspWrenchSpace::new();
    let (mut closed, mut open) = (0, 0);
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let contacts: Vec<Contact> = case["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| Contact {
                bone: 0,
                capsule: 0,
                point: Point3::from(vector(&c["point"])),
                normal: Vec3::from(vector(&c["normal"])),
                gap: 0.0,
                radius: c["radius"].as_f64().unwrap(),
            })
            .collect();
        let model = ContactModel {
            friction: case["friction"].as_f64().unwrap(),
            cone_edges: case["cone_edges"].as_u64().unwrap() as usize,
            torsion_patch: case["torsion_patch"].as_f64().unwrap(),
        };
        let center = Point3::from(vector(&case["center"]));
        let s = gws.evaluate(&contacts, &model, &center, case["scale"].as_f64().unwrap());
        let expected = case["force_closure"].as_bool().unwrap();
        assert_eq!(s.force_closure, expected, "{name}: force closure");
        // The search's linear program agrees with the hull.
        let margin = force_closure_margin(gws.wrenches());
        assert_eq!(margin > 0.0, expected, "{name}: margin {margin}");
        let epsilon = case["epsilon"].as_f64().unwrap();
        assert!(
            (s.epsilon - epsilon).abs() < 1e-6,
            "{name}: epsilon {} against {epsilon}",
            s.epsilon
        );
        for (k, load) in case["load_ratio"].as_array().unwrap().iter().enumerate() {
            let load = load.as_f64().unwrap();
            assert!(
                (s.load_ratio[k] - load).abs() < 1e-6,
                "{name}: load ratio {k}: {} against {load}",
                s.load_ratio[k]
            );
        }
        if expected {
            closed += 1;
        } else {
            open += 1;
        }
    }
    // Both answers are exercised.
    assert!(closed >= 20 && open >= 5, "{closed} closed, {open} open");
}
