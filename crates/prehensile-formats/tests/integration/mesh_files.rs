//! Mesh files: the fixture meshes, and malformed files that must give clear errors.

use prehensile_core::MeshDefect;
use std::path::PathBuf;

use prehensile_formats::{load_object, read_mesh};

fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/objects")
        .join(name)
}

fn temp(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn closed_fixtures_are_closed_and_open_ones_are_named() {
    for (name, scale) in [
        ("robosuite_lemon.stl", 1.0),
        ("robosuite_bread.stl", 1.0),
        ("robosuite_cereal.stl", 1.0),
        ("robosuite_can.obj", 1.0),
        ("pybullet_bunny.obj", 0.06),
        ("pybullet_duck.obj", 0.06),
        ("pybullet_soccerball.obj", 0.08),
        ("pybullet_torus.obj", 0.06),
    ] {
        let report = read_mesh(&asset(name), scale).unwrap().report();
        let closed =
            report.boundary_edges + report.non_manifold_edges + report.inconsistent_edges == 0;
        assert!(
            closed && report.volume > 0.0,
            "{name}: {:?}",
            report.defects
        );
        // Slivers (the cereal box has one) are the only defect, and objects repair them.
        assert!(
            report
                .defects
                .iter()
                .all(|d| matches!(d, MeshDefect::Degenerate { .. })),
            "{name}: {:?}",
            report.defects
        );
        assert!(load_object(&asset(name), scale).is_ok(), "{name}");
    }
    let holes = read_mesh(&asset("robosuite_can_with_holes.stl"), 1.0)
        .unwrap()
        .report();
    // The fixture table says 72: trimesh rounds positions to 1e-8 m before welding. We weld exact
    // positions only, so vertices about 1e-7 m apart stay apart and 92 edges are open.
    assert_eq!(holes.boundary_edges, 92);
    assert!(
        matches!(holes.defects[0], MeshDefect::Holes { edges: 92, .. })
            && holes.defects[0]
                .to_string()
                .starts_with("92 boundary edges"),
        "{}",
        holes.defects[0]
    );
    let bottle = read_mesh(&asset("robosuite_bottle.stl"), 1.0)
        .unwrap()
        .report();
    assert_eq!(bottle.non_manifold_edges, 6);
    let mug = read_mesh(&asset("pybullet_mug.obj"), 1.0).unwrap().report();
    assert_eq!(mug.boundary_edges, 24);
    // Open meshes become objects with their inside from winding numbers: the can with holes
    // has the closed can's volume, and the open mug a plausible one.
    let can = load_object(&asset("robosuite_can.obj"), 1.0).unwrap();
    let holed = load_object(&asset("robosuite_can_with_holes.stl"), 1.0).unwrap();
    assert!(holed.collider().exact().uses_winding_numbers());
    assert!(!can.collider().exact().uses_winding_numbers());
    let relative = (holed.volume() - can.volume()).abs() / can.volume();
    assert!(relative < 0.01, "{} vs {}", holed.volume(), can.volume());
    let mug = load_object(&asset("pybullet_mug.obj"), 1.0).unwrap();
    assert!(mug.collider().exact().uses_winding_numbers());
    assert!(mug.volume() > 0.0);
}

#[test]
fn absurd_sizes_suggest_a_scale() {
    // 800 m across: millimetres read as metres, and the hint says so (it used to say
    // --scale 0.001 whichever way the size was off).
    let e = load_object(&asset("robosuite_can.obj"), 10_000.0).unwrap_err();
    assert!(e.to_string().contains("--units mm"), "{e}");
    assert!(
        matches!(
            e.cause.as_deref(),
            Some(prehensile_formats::FormatCause::Object(
                prehensile_core::ObjectError::AbsurdSize { .. }
            ))
        ),
        "{:?}",
        e.cause
    );
    let e = load_object(&asset("robosuite_can.obj"), 1e-5).unwrap_err();
    assert!(e.to_string().contains("--scale 1e5"), "{e}");
    assert!(read_mesh(&asset("robosuite_can.obj"), f64::NAN).is_err());
    assert!(read_mesh(&asset("robosuite_can.obj"), -1.0).is_err());
}

#[test]
fn truncated_stl_file_is_an_error() {
    let bytes = std::fs::read(asset("robosuite_lemon.stl")).unwrap();
    let path = temp("cut.stl", &bytes[..bytes.len() / 2]);
    let e = read_mesh(&path, 1.0).unwrap_err();
    assert!(
        e.to_string().contains("cut.stl") && e.reason.contains("truncated"),
        "{e}"
    );
}

#[test]
fn obj_with_out_of_range_index_or_nan_is_an_error() {
    let path = temp("bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    let e = read_mesh(&path, 1.0).unwrap_err();
    assert_eq!(e.location.as_deref(), Some("line 4"), "{e}");
    let path = temp("nan.obj", b"v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
    let e = read_mesh(&path, 1.0).unwrap_err();
    assert!(
        e.reason.contains("non-finite") && e.reason.contains("vertex 1"),
        "{e}"
    );
}

#[test]
fn zero_area_triangles_are_reported() {
    // A tetrahedron plus a zero-area triangle along one of its edges (leaves edges unmatched too).
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.5 0 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 5 2\n";
    let report = read_mesh(&temp("flat.obj", text.as_bytes()), 1.0)
        .unwrap()
        .report();
    assert_eq!(report.degenerate_triangles, 1);
    assert!(
        report
            .defects
            .iter()
            .any(|d| matches!(d, MeshDefect::Degenerate { .. })),
        "{:?}",
        report.defects
    );
}

#[test]
fn unknown_extension_and_missing_file_are_errors() {
    let e = read_mesh(&temp("x.dae", b"{}"), 1.0).unwrap_err();
    assert!(e.reason.contains(".obj, .stl, .ply, .gltf or .glb"), "{e}");
    let e = read_mesh(&temp("x.gltf", b"{}"), 1.0).unwrap_err();
    assert!(e.reason.contains("not a readable glTF"), "{e}");
    let e = read_mesh(&asset("no_such_file.stl"), 1.0).unwrap_err();
    assert!(e.reason.contains("cannot read"), "{e}");
}

#[test]
fn a_glb_scene_is_read_with_its_node_transforms() {
    // Our own export: the object mesh is the first node (identity transform), then the hand.
    let hand = prehensile_formats::builtin_hand("robot3").unwrap();
    let mesh = prehensile_core::shapes::builtin_object("torus").unwrap();
    let glb = prehensile_formats::grasp_glb(&mesh, &hand, &[], None);
    let path = temp("scene.glb", &glb);
    let read = read_mesh(&path, 1.0).unwrap();
    // The object plus one capsule mesh per bone with capsules, all merged.
    assert!(read.triangles.len() > mesh.triangles.len());
    let report = read.report();
    assert!(report.size[0] > 0.118, "{:?}", report.size);
}
