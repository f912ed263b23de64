//! One entry point per reader for fuzzing: the cargo-fuzz targets in `fuzz/` call these, and
//! `crates/prehensile-formats/tests/integration/fuzz_corpus.rs` replays the committed corpus through the same functions on stable Rust,
//! so CI checks every saved input even where no nightly toolchain is installed. Each returns
//! whether the input was accepted; what matters is that none panics, aborts or hangs.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

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
        "mesh_obj" => prehensile_formats::parse_obj(&text(), "fuzz.obj").is_ok(),
        "mesh_stl" => prehensile_formats::parse_stl(data, "fuzz.stl").is_ok(),
        "mesh_ply" => prehensile_formats::parse_ply(data, "fuzz.ply").is_ok(),
        "mesh_gltf" => in_scratch_file("fuzz.glb", data, |path| {
            prehensile_formats::read_mesh(path, 1.0).is_ok()
        }),
        "hand_toml" => prehensile_formats::parse_hand_toml(&text(), "fuzz.toml").is_ok(),
        "hand_urdf" => prehensile_formats::parse_hand_urdf(&text(), "fuzz.urdf").is_ok(),
        "hand_mjcf" => prehensile_formats::parse_hand_mjcf(&text(), "fuzz.xml").is_ok(),
        "hand_gltf" => in_scratch_file("fuzz.glb", data, |path| {
            prehensile_formats::load_hand_gltf(path).is_ok()
        }),
        "bvh" => prehensile_formats::parse_bvh(&text(), "fuzz.bvh").is_ok(),
        _ => return None,
    })
}

/// `read` of `data` written to `name` in a folder of this call's own (so that the file's
/// references find nothing else), removed afterwards.
fn in_scratch_file(name: &str, data: &[u8], read: impl FnOnce(&Path) -> bool) -> bool {
    static CALLS: AtomicU64 = AtomicU64::new(0);
    let call = CALLS.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("prehensile-fuzz-{}-{call}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("the temporary folder is writable");
    let path = dir.join(name);
    std::fs::write(&path, data).expect("the temporary folder is writable");
    let accepted = read(&path);
    let _ = std::fs::remove_dir_all(&dir);
    accepted
}
