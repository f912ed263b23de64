//! GLB export read back by an independent reader (the `gltf` crate, which validates on load).

use prehensile_core::animation::approach_and_close;
use prehensile_core::math::{Point3, Transform};
use prehensile_core::shapes::builtin_object;
use prehensile_formats::{builtin_hand, grasp_glb};

#[test]
fn a_grasp_scene_reads_back_with_its_bones_meshes_and_animation() {
    let hand = builtin_hand("human").unwrap();
    let mesh = builtin_object("sphere").unwrap();
    let movement = hand.movement("power").unwrap();
    let hook = Transform::translation(0.0, 0.0, 0.0);
    let fractions = vec![0.6; hand.bones().len()];
    let frames = approach_and_close(&hand, movement, &hook, 0.01, &fractions, 0.1, 12);
    assert_eq!(frames.len(), 25);
    let bytes = grasp_glb(&mesh, &hand, &frames, None);
    let gltf = gltf::Gltf::from_slice(&bytes).expect("a valid glTF");
    let names: Vec<&str> = gltf.nodes().filter_map(|n| n.name()).collect();
    assert!(names.contains(&"object") && names.contains(&"index_distal"));
    assert_eq!(gltf.nodes().count(), 1 + hand.bones().len());
    // Every bone has a capsule mesh here; plus the object.
    assert_eq!(gltf.meshes().count(), 1 + hand.bones().len());
    let animation = gltf.animations().next().expect("an animation");
    assert_eq!(animation.channels().count(), hand.bones().len() + 1);
    // The object's vertices come through unchanged (as f32).
    let object = gltf.meshes().next().unwrap();
    let accessor = object
        .primitives()
        .next()
        .unwrap()
        .get(&gltf::Semantic::Positions)
        .unwrap();
    assert_eq!(accessor.count(), mesh.vertices.len());
    // The hand's root starts 10 cm further back than its final offset, along the hook's -y.
    let first = &frames[0].root;
    let last = &frames[24].root;
    assert!(((first.translation.vector - last.translation.vector).norm() - 0.1).abs() < 1e-12);
    assert!((first * Point3::origin()).y < (last * Point3::origin()).y);
}
