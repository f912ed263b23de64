//! Force closure, ε and load ratios against scipy's Qhull (`tools/oracle/stability_oracle.py`,
//! answers committed in `tests/data/stability_oracle.json`).

use crate::common;

use common::stability_cases::oracle_cases;
use prehensile_core::stability::{force_closure_margin, GraspWrenchSpace};

#[test]
fn stability_matches_scipy_qhull() {
    let cases = oracle_cases();
    assert!(cases.len() >= 80);
    let mut gws = GraspWrenchSpace::new();
    let (mut closed, mut open) = (0, 0);
    for c in &cases {
        let (name, case) = (&c.name, &c.answer);
        let s = gws.evaluate(&c.contacts, &c.model, &c.center, c.scale);
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
        // ε alone, from the part of the hull that decides it, is the same number.
        let alone = GraspWrenchSpace::new().epsilon(&c.contacts, &c.model, &c.center, c.scale);
        assert!(
            (alone - s.epsilon).abs() < 1e-9,
            "{name}: epsilon alone {alone} against {}",
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
