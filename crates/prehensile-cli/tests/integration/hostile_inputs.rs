//! Inputs that once made a command panic, hang or read outside their folder: each ends with
//! exit code 2 and a message, within a few seconds. Named after what broke.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Exit code, stdout and stderr of a run, killed (and failed) after 60 s.
fn run(args: &[&str], stdout: Stdio) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .args(args)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let began = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
            assert!(!err.contains("panicked"), "{args:?} panicked:\n{err}");
            return (status.code(), err);
        }
        if began.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("{args:?} hung");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn refused(args: &[&str], says: &str) {
    let (code, err) = run(args, Stdio::null());
    assert_eq!(code, Some(2), "{args:?}: {err}");
    assert!(err.contains(says), "{args:?}: expected '{says}' in:\n{err}");
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn a_full_or_closed_stdout_ends_with_a_message_not_a_panic() {
    let full = std::fs::File::create("/dev/full").unwrap();
    let (code, err) = run(&["hands"], Stdio::from(full));
    assert_eq!(code, Some(2));
    assert!(err.contains("cannot write to standard output"), "{err}");
    // `prehensile hands | head -1`: the reader goes away.
    let mut child = Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .args([
            "hands",
            "--file",
            "../../assets/hands/shadow_hand/reach.xml",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

#[test]
fn a_fifo_or_a_device_is_not_read() {
    let fifo = scratch("pipe.stl");
    let _ = std::fs::remove_file(&fifo);
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    refused(&["check", s(&fifo)], "not a regular file");
    refused(&["grasp", "--object", s(&fifo)], "not a regular file");
    let dev = scratch("zero.obj");
    let _ = std::fs::remove_file(&dev);
    std::os::unix::fs::symlink("/dev/zero", &dev).unwrap();
    refused(&["check", s(&dev)], "not a regular file");
}

#[test]
fn gltf_buffers_outside_the_files_folder_are_refused() {
    let dir = scratch("gltf/inner");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.parent().unwrap().join("secret.bin"), [0u8; 64]).unwrap();
    for uri in [
        "../secret.bin",
        "/etc/passwd",
        "%2E%2E/secret.bin",
        "file:///etc/passwd",
    ] {
        let gltf = dir.join("scan.gltf");
        std::fs::write(
            &gltf,
            format!(
                r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"uri":"{uri}","byteLength":36}}]}}"#
            ),
        )
        .unwrap();
        refused(&["check", s(&gltf)], "own folder");
    }
}

#[test]
fn mjcf_includes_stay_in_the_folder_and_comments_are_not_followed() {
    let dir = scratch("mjcf");
    std::fs::create_dir_all(&dir).unwrap();
    let hand = dir.join("hand.xml");
    std::fs::write(
        &hand,
        r#"<mujoco><include file="../../../etc/passwd"/></mujoco>"#,
    )
    .unwrap();
    refused(&["hands", "--file", s(&hand)], "own folder");
    // An include inside a comment is a comment: the reader does not try to open it (and then
    // fails for this file's own reason, not the include's).
    std::fs::write(
        &hand,
        r#"<mujoco><!-- <include file="/etc/passwd"/> --><worldbody/></mujoco>"#,
    )
    .unwrap();
    let (code, err) = run(&["hands", "--file", s(&hand)], Stdio::null());
    assert_eq!(code, Some(2));
    assert!(!err.contains("passwd"), "{err}");
    // A fan-out of includes (each file including the next one ten times) is bounded.
    for level in 0..6 {
        let next = if level == 5 {
            "<worldbody/>".to_string()
        } else {
            format!(r#"<include file="l{}.xml"/>"#, level + 1).repeat(10)
        };
        std::fs::write(
            dir.join(format!("l{level}.xml")),
            format!("<mujoco>{next}</mujoco>"),
        )
        .unwrap();
    }
    refused(
        &["hands", "--file", s(&dir.join("l0.xml"))],
        "included files",
    );
}

#[test]
fn absurd_numbers_are_refused_with_the_reason() {
    refused(&["grasp", "--scale", "1e300"], "--scale");
    refused(&["grasp", "--scale", "1e-300"], "--scale");
    refused(&["grasp", "--budget-ms", "1e300"], "at most");
    refused(&["grasp", "--shoulder=1e200,0,0"], "shoulder");
    refused(
        &["simulate", "--scenario", "drop", "--dt", "1e-9"],
        "dt = 0.000000001 is outside its range [0.00001, 0.01]",
    );
    refused(&["grasp", "--weights", "0,0,0,0"], "all are zero");
    refused(&["grasp", "--weights", "1,1"], "four (G, F, T, W) or five");
    refused(&["grasp", "--friction", "nan"], "friction = NaN is outside");
    refused(&["grasp", "--hook=nan,0,0"], "hook");
    refused(&["grasp", "--up", "w"], "unknown up axis 'w'");
    refused(&["batch", "--seeds", "0"], "the batch has no seeds");
    refused(&["batch", "--seeds", "2000000"], "seeds: give 1 to 1000000");
    refused(&["grasp", "--hand", "hand.stl"], "hand");
}

#[test]
fn negative_coordinates_need_no_equals_sign() {
    let (code, err) = run(
        &[
            "grasp",
            "--movement",
            "power",
            "--shoulder",
            "-0.35,-0.2,0.35",
            "--budget-ms",
            "50",
        ],
        Stdio::null(),
    );
    assert!(matches!(code, Some(0 | 1)), "{err}");
}

/// A GLB file of `json` and the binary chunk `bin`.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    prehensile_formats::glb_container(json.as_bytes(), bin)
}

/// A triangle's three positions (36 bytes) then three u32 indices (12 bytes).
fn triangle_bin() -> Vec<u8> {
    let mut bin = Vec::new();
    for v in [[0f32, 0.0, 0.0], [0.05, 0.0, 0.0], [0.0, 0.05, 0.0]] {
        for c in v {
            bin.extend(c.to_le_bytes());
        }
    }
    for i in [0u32, 1, 2] {
        bin.extend(i.to_le_bytes());
    }
    bin
}

fn triangle_gltf(index_type: u32, position_stride: &str, nodes: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":{nodes},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
        "buffers":[{{"byteLength":48}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36{position_stride}}},{{"buffer":0,"byteOffset":36,"byteLength":12}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[0.05,0.05,0]}},
                     {{"bufferView":1,"componentType":{index_type},"count":3,"type":"SCALAR"}}]}}"#
    )
}

#[test]
fn crafted_gltf_accessors_are_refused_before_the_reader_sees_them() {
    let file = scratch("crafted.glb");
    // The control: well-formed, read (and then refused as an open mesh, exit 2 too).
    std::fs::write(
        &file,
        glb(&triangle_gltf(5125, "", r#"[{"mesh":0}]"#), &triangle_bin()),
    )
    .unwrap();
    refused(&["check", s(&file), "--json"], "");
    // An index accessor of FLOAT (5126) used to panic inside the gltf crate.
    std::fs::write(
        &file,
        glb(&triangle_gltf(5126, "", r#"[{"mesh":0}]"#), &triangle_bin()),
    )
    .unwrap();
    refused(
        &["check", s(&file)],
        "accessor 1 (indices) is Scalar of F32",
    );
    // A POSITION stride of 4 bytes, shorter than one 12-byte element, too.
    std::fs::write(
        &file,
        glb(
            &triangle_gltf(5125, r#","byteStride":4"#, r#"[{"mesh":0}]"#),
            &triangle_bin(),
        ),
    )
    .unwrap();
    refused(&["check", s(&file)], "stride of 4 bytes");
    // A node that lists itself 1000 times used to allocate gigabytes.
    let children = vec!["0"; 1000].join(",");
    std::fs::write(
        &file,
        glb(
            &triangle_gltf(
                5125,
                "",
                &format!(r#"[{{"mesh":0,"children":[{children}]}}]"#),
            ),
            &triangle_bin(),
        ),
    )
    .unwrap();
    refused(&["check", s(&file)], "must be trees");
    // A primitive naming an accessor in a file with none panicked inside the gltf crate's own
    // validation (found by the gltf_structured fuzzer).
    let json = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
    std::fs::write(&file, glb(json, &[])).unwrap();
    refused(
        &["check", s(&file)],
        "refers to accessor 0, but the file has 0",
    );
    refused(&["grasp", "--hand", s(&file)], "refers to accessor 0");
}

#[test]
fn millions_of_copies_of_one_face_are_counted_once() {
    // A 12 MB OBJ whose one face lists "1 2 3" two million times: fanned out, six million
    // triangles, a third collapsed and the rest copies of one face. Every inside test visited
    // each copy (over a minute); the copies are now dropped as duplicates, the tetrahedron kept.
    let path = scratch("stacked.obj");
    let mut obj = String::from("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2");
    obj.push_str(&" 1 3 2".repeat(2_000_000));
    obj.push_str("\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    std::fs::write(&path, obj).unwrap();
    let (code, err) = run(&["check", s(&path)], Stdio::null());
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("duplicate triangle(s)"), "{err}");
    assert!(err.contains("accepts this mesh"), "{err}");
}

/// OBJ lines of `count` vertices evenly round a circle of 5 cm radius at height `z`.
fn ring_of_vertices(count: usize, z: f64) -> String {
    (0..count)
        .map(|i| {
            let angle = std::f64::consts::TAU * i as f64 / count as f64;
            format!("v {} {} {z}\n", 0.05 * angle.cos(), 0.05 * angle.sin())
        })
        .collect()
}

#[test]
fn a_book_of_pages_sharing_one_edge_is_refused_before_its_winding_numbers() {
    // 100,000 triangles all on the edge from (0, 0, 0) to (0, 0, 0.05), fanned around it like
    // the pages of a book: every winding-number query summed every page, and `check` took two
    // minutes. Probing a few points now finds them too costly, in well under a second.
    let path = scratch("book.obj");
    let pages = 100_000;
    let mut obj = String::from("v 0 0 0\nv 0 0 0.05\n");
    obj.push_str(&ring_of_vertices(pages, 0.02));
    for i in 0..pages {
        obj.push_str(&format!("f 1 2 {}\n", i + 3));
    }
    std::fs::write(&path, &obj).unwrap();
    refused(&["check", s(&path)], "would take too long");
    refused(
        &["grasp", "--object", s(&path)],
        "needs more than 8192 triangle terms",
    );
    // One flat face of 100,000 corners, fanned from its first: refused as flat, before any
    // winding number is asked.
    let path = scratch("polygon.obj");
    let mut obj = ring_of_vertices(pages, 0.0);
    obj.push('f');
    for i in 0..pages {
        obj.push_str(&format!(" {}", i + 1));
    }
    obj.push('\n');
    std::fs::write(&path, &obj).unwrap();
    refused(&["check", s(&path)], "encloses no volume");
}

#[test]
fn a_hand_of_a_thousand_fingers_is_searched_in_seconds() {
    // A URDF palm with 999 one-link fingers in a ring (the most bones a hand may have): every
    // pose's contacts ran into hundreds, and the narrowest cone of their normals, O(n⁴) by
    // trying every candidate direction, kept one search going for minutes. The incremental
    // algorithm ends it in seconds, with whatever grasp there is.
    let path = scratch("thousand_fingers.urdf");
    let fingers = 999;
    let mut urdf = String::from(
        r#"<robot name="many"><link name="palm"><collision><geometry><box size="0.08 0.02 0.08"/></geometry></collision></link>"#,
    );
    for i in 0..fingers {
        let angle = std::f64::consts::TAU * i as f64 / fingers as f64;
        urdf.push_str(&format!(
            r#"<link name="f{i}"><collision><origin xyz="0 0 0.02"/><geometry><cylinder radius="0.004" length="0.04"/></geometry></collision></link><joint name="j{i}" type="revolute"><parent link="palm"/><child link="f{i}"/><origin xyz="{:.4} 0.01 {:.4}"/><axis xyz="1 0 0"/><limit lower="0" upper="1.5" effort="1" velocity="1"/></joint>"#,
            0.04 * angle.cos(),
            0.04 * angle.sin()
        ));
    }
    urdf.push_str("</robot>");
    std::fs::write(&path, urdf).unwrap();
    let (code, err) = run(&["grasp", "--hand", s(&path)], Stdio::null());
    assert!(matches!(code, Some(0 | 1)), "{err}");
    assert!(err.contains("many on sphere"), "{err}");
}

#[test]
fn no_command_writes_over_its_input() {
    let mesh = scratch("part.obj");
    let original = std::fs::read("../../crates/prehensile-core/tests/data/box.obj").unwrap();
    std::fs::write(&mesh, &original).unwrap();
    refused(
        &["grasp", "--object", s(&mesh), "--out", s(&mesh)],
        "is an input of this command",
    );
    // The same file by another path, and as the picture.
    let other = format!("{}/./part.obj", mesh.parent().unwrap().display());
    refused(
        &["grasp", "--object", s(&mesh), "--svg", &other],
        "is an input of this command",
    );
    let hand = "../../assets/hands/robot3.toml";
    refused(
        &[
            "simulate",
            "--scenario",
            "drop",
            "--hand",
            hand,
            "--out",
            hand,
        ],
        "is an input of this command",
    );
    refused(
        &[
            "grasp",
            "--out",
            s(&scratch("twice.json")),
            "--svg",
            s(&scratch("twice.json")),
        ],
        "two different outputs",
    );
    assert_eq!(
        std::fs::read(&mesh).unwrap(),
        original,
        "the input was changed"
    );
}
