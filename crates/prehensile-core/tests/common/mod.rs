//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod stability_cases;

use prehensile_core::math::{Point3, Transform};
use prehensile_core::search::translate_to_free::{hand_root, translate_to_free, TranslateMode};
use prehensile_core::shapes::builtin_object;
use prehensile_core::{HandModel, ObjectModel, TriangleMesh, Workspace};

/// Path of a file in the repository.
pub fn repo_path(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// An OBJ from the repository, scaled and welded.
pub fn obj_mesh(rel: &str, scale: f64) -> TriangleMesh {
    let text = std::fs::read_to_string(repo_path(rel)).unwrap();
    let (v, t) = prehensile_formats::parse_obj(&text, rel).unwrap();
    let v: Vec<Point3> = v.iter().map(|p| p * scale).collect();
    TriangleMesh::weld(&v, &t).unwrap()
}

/// A built-in object.
pub fn object(name: &str) -> ObjectModel {
    ObjectModel::new(name, builtin_object(name).unwrap(), None).unwrap()
}

/// A built-in hand.
pub fn hand(name: &str) -> HandModel {
    prehensile_formats::builtin_hand(name).unwrap()
}

/// Root placement with the grasp center on the object's centre of mass, palm toward it (hand y
/// along world y), backed off until the start pose is free.
pub fn free_root(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &str,
    ws: &mut Workspace,
) -> Transform {
    let m = hand.movement(movement).unwrap();
    let hook = Transform::translation(
        object.center_of_mass().x,
        object.center_of_mass().y,
        object.center_of_mass().z,
    );
    let offset = translate_to_free(
        hand,
        object,
        m,
        &hook,
        TranslateMode::Steps { step: 0.001 },
        0.3,
        f64::INFINITY,
        ws,
    )
    .unwrap();
    hand_root(&hook, m, offset)
}
