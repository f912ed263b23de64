//! The scipy oracle's contact sets (`tests/data/stability_oracle.json`, written by
//! `tools/oracle/stability_oracle.py`), read for the stability test and the stability bench.

use prehensile_core::math::{Point3, Vec3};
use prehensile_core::stability::{Contact, ContactModel};
use serde_json::Value;

/// One contact set with its contact model and the oracle's answers.
pub struct OracleCase {
    /// What the set is.
    pub name: String,
    /// The contacts.
    pub contacts: Vec<Contact>,
    /// Friction, cone edges and torsion patch.
    pub model: ContactModel,
    /// The object's centre of mass.
    pub center: Point3,
    /// The torque scale L.
    pub scale: f64,
    /// The whole case as the oracle wrote it (`force_closure`, `epsilon`, `load_ratio`).
    pub answer: Value,
}

fn vector(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("a 3-vector");
    [0, 1, 2].map(|k| a[k].as_f64().expect("a number"))
}

/// Every case of the oracle file.
pub fn oracle_cases() -> Vec<OracleCase> {
    let data: Value =
        serde_json::from_str(include_str!("../data/stability_oracle.json")).expect("oracle JSON");
    data["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|case| OracleCase {
            name: case["name"].as_str().expect("name").to_string(),
            contacts: case["contacts"]
                .as_array()
                .expect("contacts")
                .iter()
                .map(|c| Contact {
                    bone: 0,
                    capsule: 0,
                    point: Point3::from(vector(&c["point"])),
                    normal: Vec3::from(vector(&c["normal"])),
                    gap: 0.0,
                    radius: c["radius"].as_f64().expect("radius"),
                })
                .collect(),
            model: ContactModel {
                friction: case["friction"].as_f64().expect("friction"),
                cone_edges: case["cone_edges"].as_u64().expect("cone edges") as usize,
                torsion_patch: case["torsion_patch"].as_f64().expect("torsion patch"),
            },
            center: Point3::from(vector(&case["center"])),
            scale: case["scale"].as_f64().expect("scale"),
            answer: case.clone(),
        })
        .collect()
}
