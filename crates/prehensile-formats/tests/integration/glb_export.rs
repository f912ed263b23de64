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

#[test]
fn a_simulation_scene_carries_every_hand_and_the_object_track() {
    let hand = builtin_hand("human").unwrap();
    let mesh = builtin_object("sphere").unwrap();
    let movement = hand.movement("power").unwrap();
    let fractions = vec![0.6; hand.bones().len()];
    let first = approach_and_close(
        &hand,
        movement,
        &Transform::identity(),
        0.01,
        &fractions,
        0.1,
        5,
    );
    let second: Vec<_> = first
        .iter()
        .map(|f| {
            let mut f = f.clone();
            f.root = Transform::translation(0.0, 0.3, 0.0) * f.root;
            f
        })
        .collect();
    let track: Vec<Transform> = first.iter().map(|f| f.root).collect();
    let bytes = prehensile_formats::simulation_glb(
        Some((&mesh, &track)),
        &[(&hand, &first), (&hand, &second)],
    );
    let gltf = gltf::Gltf::from_slice(&bytes).expect("a valid glTF");
    let names: Vec<&str> = gltf.nodes().filter_map(|n| n.name()).collect();
    assert!(names.contains(&"hand 1: index_distal") && names.contains(&"hand 2: index_distal"));
    assert_eq!(gltf.nodes().count(), 1 + 2 * hand.bones().len());
    let scene = gltf.scenes().next().unwrap();
    assert_eq!(scene.nodes().count(), 3, "the object and each hand's root");
    let animation = gltf.animations().next().expect("an animation");
    // Per hand: every bone's rotation and the root's translation; the object: both.
    assert_eq!(
        animation.channels().count(),
        2 * (hand.bones().len() + 1) + 2
    );
    let mut translated: Vec<usize> = animation
        .channels()
        .filter(|c| c.target().property() == gltf::animation::Property::Translation)
        .map(|c| c.target().node().index())
        .collect();
    translated.sort();
    assert_eq!(translated, [0, 1, 1 + hand.bones().len()]);
}
