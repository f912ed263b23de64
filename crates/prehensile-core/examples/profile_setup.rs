//! Sets up a torus of the given number of quads around (default 1024 × 512, about a million
//! triangles) several times, for profiling object setup (`ObjectModel::new`) under perf or
//! callgrind: `profile_setup [U V [ROUNDS]]`.
use prehensile_core::{shapes, ObjectModel};
fn main() {
    let arg = |k: usize, default: usize| {
        std::env::args()
            .nth(k)
            .map_or(default, |a| a.parse().expect("a whole number"))
    };
    let mesh = shapes::torus(0.045, 0.014, arg(1, 1024), arg(2, 512));
    for _ in 0..arg(3, 2) {
        let start = std::time::Instant::now();
        let object = ObjectModel::new("torus", mesh.clone(), None).unwrap();
        eprintln!(
            "{} triangles set up in {:.2} ms",
            object.mesh().triangles.len(),
            start.elapsed().as_secs_f64() * 1e3
        );
    }
}
