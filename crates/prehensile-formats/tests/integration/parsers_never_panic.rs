//! Mutated mesh files never panic a parser: they parse or give an error.

use proptest::prelude::*;

const OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
const PLY: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

fn stl() -> Vec<u8> {
    std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/objects/robosuite_bread.stl"
    ))
    .unwrap()
}

fn asset(rel: &str) -> Vec<u8> {
    std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets")
            .join(rel),
    )
    .unwrap()
}

/// robot.xml with shared.xml's defaults in front of it, as reach.xml includes them.
fn shadow_with_defaults() -> Vec<u8> {
    let shared = String::from_utf8(asset("hands/shadow_hand/shared.xml")).unwrap();
    let defaults =
        &shared[shared.find("<default>").unwrap()..shared.rfind("</default>").unwrap() + 10];
    let robot = String::from_utf8(asset("hands/shadow_hand/robot.xml")).unwrap();
    robot
        .replacen(
            "<mujoco>",
            &format!("<mujoco><compiler angle=\"radian\"/>{defaults}"),
            1,
        )
        .into_bytes()
}

fn mutate(mut bytes: Vec<u8>, edits: &[(usize, u8)], cut: usize) -> Vec<u8> {
    for &(at, value) in edits {
        if !bytes.is_empty() {
            let i = at % bytes.len();
            bytes[i] = value;
        }
    }
    let keep = bytes.len() - cut % (bytes.len() + 1);
    bytes.truncate(keep);
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn obj_ply_stl_survive_mutation(edits in proptest::collection::vec((any::<usize>(), any::<u8>()), 0..8), cut in any::<usize>()) {
        let obj = mutate(OBJ.as_bytes().to_vec(), &edits, cut % 4);
        let _ = prehensile_formats::parse_obj(&String::from_utf8_lossy(&obj), "m.obj");
        let ply = mutate(PLY.as_bytes().to_vec(), &edits, cut % 8);
        let _ = prehensile_formats::parse_ply(&ply, "m.ply");
        let stl = mutate(stl(), &edits, cut % 64);
        let _ = prehensile_formats::parse_stl(&stl, "m.stl");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(150))]

    /// Mutations inside numbers, names and structure of the URDF and MJCF fixtures.
    #[test]
    fn urdf_and_mjcf_survive_mutation(edits in proptest::collection::vec((any::<usize>(), prop::sample::select(b"0-9. <>/\"aezn".to_vec())), 1..6), cut in any::<usize>()) {
        let urdf = mutate(asset("hands/urdf/hand_tree_public.urdf"), &edits, cut % 16);
        let _ = prehensile_formats::parse_hand_urdf(&String::from_utf8_lossy(&urdf), "m.urdf");
        let mjcf = mutate(shadow_with_defaults(), &edits, cut % 16);
        let _ = prehensile_formats::parse_hand_mjcf(&String::from_utf8_lossy(&mjcf), "m.xml");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]

    /// Byte mutations of the WebXR hand's GLB, read as a mesh and as a skinned hand.
    #[test]
    fn glb_survives_mutation(edits in proptest::collection::vec((any::<usize>(), any::<u8>()), 1..6), cut in any::<usize>()) {
        let bytes = mutate(asset("hands/webxr_generic_hand/right.glb"), &edits, cut % 64);
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("prehensile-glb-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.glb");
        std::fs::write(&path, &bytes).unwrap();
        let _ = prehensile_formats::read_mesh(&path, 1.0);
        let _ = prehensile_formats::load_hand_gltf(&path);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Mutated hand files in our TOML format give errors, never panics.
    #[test]
    fn hand_toml_survives_mutation(edits in proptest::collection::vec((any::<usize>(), prop::sample::select(b"0123456789.-[]=\" \nabz".to_vec())), 1..6)) {
        let bytes = mutate(asset("hands/human.toml"), &edits, 0);
        let _ = prehensile_formats::parse_hand_toml(&String::from_utf8_lossy(&bytes), "m.toml");
    }
}
