//! One entry point per reader for fuzzing: the cargo-fuzz targets in `fuzz/` call these, and
//! `tests/integration/fuzz_corpus.rs` replays the committed corpus through the same functions on stable Rust,
//! so CI checks every saved input even where no nightly toolchain is installed. Each returns
//! whether the input was accepted; what matters is that none panics, aborts or hangs.

use std::path::PathBuf;

/// The readers that can be fuzzed, by target name.
pub const TARGETS: [&str; 9] = [
    "mesh_obj",
    "mesh_stl",
    "mesh_ply",
    "mesh_gltf",
    "hand_toml",
    "hand_urdf",
    "hand_mjcf",
    "hand_gltf",
    "bvh",
];

/// Runs reader `target` on `data`. Readers of files (glTF, through their buffers) get `data`
/// written to a scratch file first. Returns `None` for an unknown target.
pub fn run(target: &str, data: &[u8]) -> Option<bool> {
    let text = || String::from_utf8_lossy(data).into_owned();
    Some(match target {
        "mesh_obj" => crate::parse_obj(&text(), "fuzz.obj").is_ok(),
        "mesh_stl" => crate::parse_stl(data, "fuzz.stl").is_ok(),
        "mesh_ply" => crate::parse_ply(data, "fuzz.ply").is_ok(),
        "mesh_gltf" => crate::read_mesh(&scratch("fuzz.glb", data), 1.0).is_ok(),
        "hand_toml" => crate::parse_hand_toml(&text(), "fuzz.toml").is_ok(),
        "hand_urdf" => crate::parse_hand_urdf(&text(), "fuzz.urdf").is_ok(),
        "hand_mjcf" => crate::parse_hand_mjcf(&text(), "fuzz.xml").is_ok(),
        "hand_gltf" => crate::load_hand_gltf(&scratch("fuzz.glb", data)).is_ok(),
        "bvh" => crate::parse_bvh(&text(), "fuzz.bvh").is_ok(),
        _ => return None,
    })
}

/// `data` written to `name` in a folder of this process's own.
fn scratch(name: &str, data: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("prehensile-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("the temporary folder is writable");
    let path = dir.join(name);
    std::fs::write(&path, data).expect("the temporary folder is writable");
    path
}
