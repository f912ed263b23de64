//! Collision meshes of imported hands: URDF `<mesh>` and MJCF mesh geoms become capsules inside
//! their convex hull, read only from the hand file's folder; what cannot be read is named.

use std::path::{Path, PathBuf};

use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::{GraspPlanner, GraspResult, SearchParams};
use prehensile_core::shapes::builtin_object;
use prehensile_core::{HandModel, ObjectModel, Workspace};
use prehensile_formats::{
    load_hand, parse_hand_mjcf_files, parse_hand_urdf, parse_hand_urdf_files,
};

fn assets(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/hands")
        .join(path)
}

/// A fresh folder of this test's own.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "prehensile-collision-meshes-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// An octagonal prism, `radius` to its corners, from z = 0 to `length`, in the file's units.
fn prism(radius: f64, length: f64) -> Vec<Point3> {
    (0..8)
        .flat_map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 8.0;
            [0.0, length].map(|z| Point3::new(radius * a.cos(), radius * a.sin(), z))
        })
        .collect()
}

/// A binary STL whose triangles fan over `points` (only the vertices matter to a hull).
fn binary_stl(points: &[Point3]) -> Vec<u8> {
    let triangles: Vec<[usize; 3]> = (1..points.len() - 1).map(|k| [0, k, k + 1]).collect();
    let mut out = vec![0u8; 80];
    out.extend((triangles.len() as u32).to_le_bytes());
    for t in &triangles {
        out.extend([0f32; 3].iter().flat_map(|v| v.to_le_bytes()));
        for &i in t {
            for c in points[i].iter() {
                out.extend((*c as f32).to_le_bytes());
            }
        }
        out.extend([0u8; 2]);
    }
    out
}

/// The oracle URDF hand with a collision `<mesh filename=…>` on the index's proximal link.
fn urdf_with_mesh(filename: &str) -> String {
    let urdf = std::fs::read_to_string(assets("urdf/hand_tree_public.urdf")).unwrap();
    let link = r#"<link name="index_proximal">"#;
    urdf.replacen(
        link,
        &format!(
            r#"{link}<collision name="proximal_shell"><origin xyz="0 0 0.002" rpy="0 0 0"/><geometry><mesh filename="{filename}" scale="0.001 0.001 0.001"/></geometry></collision>"#
        ),
        1,
    )
}

/// Every capsule of `bone` lies inside the prism of `radius` (to the corners) from z = `z0` to
/// `z0 + length` along the bone's z, in metres; returns the thickest radius.
fn inside_prism(hand: &HandModel, bone: &str, radius: f64, z0: f64, length: f64) -> f64 {
    let b = hand.bone_index(bone).unwrap();
    let capsules = hand.bone_capsules(b);
    assert!(!capsules.is_empty());
    let inscribed = radius * (std::f64::consts::PI / 8.0).cos();
    for c in capsules {
        for end in [c.a, c.b] {
            let local = end; // capsule ends are in the bone's (the link's) frame
                             // Inside each of the eight side faces and both ends by the radius.
            for k in 0..8 {
                let a = (k as f64 + 0.5) * std::f64::consts::TAU / 8.0;
                let depth = inscribed - local.coords.dot(&Vec3::new(a.cos(), a.sin(), 0.0));
                assert!(depth >= c.radius - 1e-9, "{bone}: {local:?} r {}", c.radius);
            }
            assert!(local.z - c.radius >= z0 - 1e-9 && local.z + c.radius <= z0 + length + 1e-9);
        }
    }
    capsules.iter().map(|c| c.radius).fold(0.0, f64::max)
}

#[test]
fn a_urdf_collision_mesh_becomes_capsules_inside_its_hull() {
    let dir = scratch("urdf");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(
        dir.join("meshes/proximal.stl"),
        binary_stl(&prism(9.0, 40.0)),
    )
    .unwrap();
    let file = dir.join("hand.urdf");
    std::fs::write(
        &file,
        urdf_with_mesh("package://demo_hand/meshes/proximal.stl"),
    )
    .unwrap();
    let hand = load_hand(&file).unwrap();
    let thickest = inside_prism(&hand, "index_proximal", 0.009, 0.002, 0.040);
    // The octagon's inscribed radius, not the radius guessed from the link's mass (5.3 mm).
    assert!((thickest - 0.009 * (std::f64::consts::PI / 8.0).cos()).abs() < 1e-6);
    let description = hand.description();
    assert!(
        description.contains("meshes as capsules: proximal_shell (1 capsules"),
        "{description}"
    );
    // Dropped on a web page: the mesh found by its file name among the files given.
    let files = vec![
        ("hand.urdf".to_string(), std::fs::read(&file).unwrap()),
        (
            "proximal.stl".to_string(),
            std::fs::read(dir.join("meshes/proximal.stl")).unwrap(),
        ),
    ];
    let from_memory = parse_hand_urdf_files("hand.urdf", &files).unwrap();
    assert_eq!(from_memory.capsules(), hand.capsules());
    // The same text without its folder: the mesh is named as skipped, and the link gets the
    // capsule guessed from its mass, as before.
    let text_only = parse_hand_urdf(
        &urdf_with_mesh("package://demo_hand/meshes/proximal.stl"),
        "hand.urdf",
    )
    .unwrap();
    let d = text_only.description();
    assert!(
        d.contains("collision meshes skipped") && d.contains("without its folder"),
        "{d}"
    );
}

#[test]
fn collision_meshes_outside_the_folder_or_unreadable_are_skipped_and_named() {
    let dir = scratch("hostile");
    let outside = dir
        .parent()
        .unwrap()
        .join(format!("prehensile-outside-{}.stl", std::process::id()));
    std::fs::write(&outside, binary_stl(&prism(9.0, 40.0))).unwrap();
    std::fs::write(dir.join("shell.dae"), "<COLLADA/>").unwrap();
    std::fs::write(
        dir.join("flat.stl"),
        binary_stl(&[
            Point3::origin(),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
        ]),
    )
    .unwrap();
    // 10,001 distinct vertices on a sphere (30,000 as the STL repeats them per triangle).
    let crowd: Vec<Point3> = (0..10_001)
        .map(|k| {
            let (z, a) = (1.0 - 2.0 * (k as f64 + 0.5) / 10_001.0, k as f64 * 2.399963);
            let r = (1.0 - z * z).sqrt();
            Point3::new(r * a.cos(), r * a.sin(), z) * 10.0
        })
        .collect();
    std::fs::write(dir.join("crowd.stl"), binary_stl(&crowd)).unwrap();
    std::fs::write(dir.join("fine.stl"), binary_stl(&crowd[..3000])).unwrap();
    let outside_name = outside.file_name().unwrap().to_string_lossy().to_string();
    let cases: Vec<(String, &str)> = vec![
        (format!("../{outside_name}"), "leaves the folder"),
        ("/etc/passwd".into(), "absolute path"),
        ("file:///etc/passwd".into(), "absolute path or URI"),
        ("missing.stl".into(), "cannot read"),
        ("shell.dae".into(), "unknown mesh extension '.dae'"),
        ("flat.stl".into(), "hull cannot be built"),
        ("crowd.stl".into(), "10001 vertices, more than the 10000"),
    ];
    #[cfg(unix)]
    let cases = {
        let mut cases = cases;
        let fifo = dir.join("pipe.stl");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            cases.push(("pipe.stl".into(), "not a regular file"));
        }
        cases
    };
    for (filename, why) in cases {
        let file = dir.join("hand.urdf");
        std::fs::write(&file, urdf_with_mesh(&filename)).unwrap();
        let hand = load_hand(&file).unwrap();
        let d = hand.description();
        assert!(
            d.contains("collision meshes skipped") && d.contains(why),
            "{filename}: {d}"
        );
        // The link keeps the capsule guessed from its mass (5.3 mm).
        let b = hand.bone_index("index_proximal").unwrap();
        assert_eq!(hand.bone_capsules(b).len(), 1, "{filename}");
    }
    std::fs::remove_file(outside).unwrap();
    // 3,000 distinct vertices are read although the STL holds them 9,000 times.
    std::fs::write(dir.join("hand.urdf"), urdf_with_mesh("fine.stl")).unwrap();
    let hand = load_hand(&dir.join("hand.urdf")).unwrap();
    assert!(
        hand.description()
            .contains("meshes as capsules: proximal_shell"),
        "{}",
        hand.description()
    );
}

/// The Shadow hand's files, with `asset` added to its `<asset>` and `geom` in the index's
/// distal body, written to `dir`.
fn shadow_with(dir: &Path, asset: &str, geom: &str) -> Vec<(String, Vec<u8>)> {
    let mut files = Vec::new();
    for name in ["reach.xml", "shared.xml", "shared_asset.xml", "robot.xml"] {
        let mut text = std::fs::read_to_string(assets("shadow_hand").join(name)).unwrap();
        if name == "shared_asset.xml" {
            text = text.replacen("<mujoco>", &format!("<mujoco>{asset}"), 1);
        }
        if name == "robot.xml" {
            let distal = r#"<body name="robot0:ffdistal" pos="0 0 0.025">"#;
            assert!(text.contains(distal));
            text = text.replacen(distal, &format!("{distal}{geom}"), 1);
        }
        std::fs::write(dir.join(name), &text).unwrap();
        files.push((name.to_string(), text.into_bytes()));
    }
    files
}

#[test]
fn an_mjcf_mesh_geom_from_a_file_or_inline_vertices_becomes_capsules() {
    let dir = scratch("mjcf");
    std::fs::create_dir_all(dir.join("stls")).unwrap();
    let pad = binary_stl(&prism(6.0, 20.0));
    std::fs::write(dir.join("stls/pad.stl"), &pad).unwrap();
    // The inline mesh: the same prism's vertices in metres.
    let inline: Vec<String> = prism(0.006, 0.020)
        .iter()
        .map(|p| format!("{} {} {}", p.x, p.y, p.z))
        .collect();
    let asset = format!(
        r#"<mesh name="pad" file="pad.stl" scale="0.001 0.001 0.001"/><mesh name="pad_inline" vertex="{}"/>"#,
        inline.join(" ")
    );
    let geom = r#"<geom class="robot0:DC_Hand" name="robot0:C_pad" type="mesh" mesh="pad" pos="0 0 0.004"/><geom class="robot0:DC_Hand" name="robot0:C_pad_inline" type="mesh" mesh="pad_inline" pos="0 0 0.004"/><geom class="robot0:DC_Hand" name="robot0:C_floor" type="plane" size="1 1 1"/>"#;
    let files = shadow_with(&dir, &asset, geom);
    let plain = load_hand(&assets("shadow_hand/reach.xml")).unwrap();
    let hand = load_hand(&dir.join("reach.xml")).unwrap();
    let b = hand.bone_index("robot0:ffdistal").unwrap();
    // One capsule per mesh geom (the geoms come first in the body), then the file's capsule.
    assert_eq!(
        hand.bone_capsules(b).len(),
        plain.bone_capsules(b).len() + 2,
        "{:?}",
        hand.bone_capsules(b)
    );
    let meshes = &hand.bone_capsules(b)[..2];
    // The inline vertices are the STL's prism (which holds them as 32-bit floats).
    for (x, y) in [(meshes[0].a, meshes[1].a), (meshes[0].b, meshes[1].b)] {
        assert!((x - y).norm() < 1e-8, "{meshes:?}");
    }
    assert!((meshes[0].radius - meshes[1].radius).abs() < 1e-8);
    let (a, c) = (meshes[0].a, meshes[0].b);
    let inscribed = 0.006 * (std::f64::consts::PI / 8.0).cos();
    assert!((meshes[0].radius - inscribed).abs() < 1e-6);
    let (lo, hi) = (a.z.min(c.z), a.z.max(c.z));
    assert!((lo - (0.004 + inscribed)).abs() < 1e-6 && (hi - (0.024 - inscribed)).abs() < 1e-6);
    let d = hand.description();
    assert!(
        d.contains("meshes as capsules: robot0:C_pad (1 capsules")
            && d.contains("robot0:C_pad_inline (1 capsules")
            && d.contains("robot0:C_floor (a plane)"),
        "{d}"
    );
    // Dropped on a web page: the mesh file given by name with the model's files.
    let mut with_mesh = files.clone();
    with_mesh.push(("pad.stl".into(), pad));
    let from_memory = parse_hand_mjcf_files("reach.xml", &with_mesh).unwrap();
    assert_eq!(from_memory.capsules(), hand.capsules());
    let without = parse_hand_mjcf_files("reach.xml", &files).unwrap();
    let d = without.description();
    assert!(d.contains("'pad.stl' was not given"), "{d}");
    // A geom naming a mesh the asset does not have is named too.
    let dir = scratch("mjcf-missing");
    shadow_with(
        &dir,
        "",
        r#"<geom class="robot0:DC_Hand" name="robot0:C_ghost" type="mesh" mesh="ghost"/>"#,
    );
    let d = load_hand(&dir.join("reach.xml")).unwrap();
    let d = d.description();
    assert!(
        d.contains("robot0:C_ghost (mesh 'ghost' is not in the <asset>)"),
        "{d}"
    );
}

/// The Shadow hand with its phalanges' own meshes (`stls/F1–F3`, `TH1–TH3`, the shapes its
/// visual geoms draw) as their colliders instead of the file's capsules, written to `dir`.
fn shadow_with_phalanx_meshes(dir: &Path) {
    std::fs::create_dir_all(dir.join("stls")).unwrap();
    for mesh in ["F1", "F2", "F3", "TH1_z", "TH2_z", "TH3_z"] {
        let file = format!("stls/{mesh}.stl");
        std::fs::copy(assets("shadow_hand").join(&file), dir.join(&file)).unwrap();
    }
    for name in ["reach.xml", "shared.xml", "shared_asset.xml"] {
        std::fs::copy(assets("shadow_hand").join(name), dir.join(name)).unwrap();
    }
    let mut robot = std::fs::read_to_string(assets("shadow_hand/robot.xml")).unwrap();
    let phalanges = ["proximal", "middle", "distal"];
    for finger in ["ff", "mf", "rf", "lf", "th"] {
        for phalanx in phalanges {
            let bone = format!("{finger}{phalanx}");
            // The capsule goes; the visual mesh collides.
            let capsule = format!(r#"<geom class="robot0:DC_Hand" name="robot0:C_{bone}""#);
            let start = robot.find(&capsule).unwrap();
            let end = start + robot[start..].find("</geom>").unwrap() + "</geom>".len();
            robot.replace_range(start..end, "");
            robot = robot.replacen(
                &format!(r#"class="robot0:D_Vizual" name="robot0:V_{bone}""#),
                &format!(r#"class="robot0:DC_Hand" type="mesh" name="robot0:V_{bone}""#),
                1,
            );
        }
    }
    std::fs::write(dir.join("robot.xml"), robot).unwrap();
}

#[test]
fn the_shadow_hand_colliding_with_its_own_phalanx_meshes_is_near_its_capsules_and_grasps() {
    let dir = scratch("shadow-meshes");
    shadow_with_phalanx_meshes(&dir);
    let capsules = load_hand(&assets("shadow_hand/reach.xml")).unwrap();
    let meshes = load_hand(&dir.join("reach.xml")).unwrap();
    let d = meshes.description();
    assert!(
        d.contains("robot0:V_ffdistal (") && !d.contains("skipped"),
        "{d}"
    );
    for finger in ["ff", "mf", "rf", "lf", "th"] {
        for phalanx in ["proximal", "middle", "distal"] {
            let bone = format!("robot0:{finger}{phalanx}");
            let (c, m) = (
                capsules.bone_capsules(capsules.bone_index(&bone).unwrap()),
                meshes.bone_capsules(meshes.bone_index(&bone).unwrap()),
            );
            let (file, thickest) = (
                c[0],
                m.iter()
                    .copied()
                    .max_by(|x, y| x.radius.total_cmp(&y.radius))
                    .unwrap(),
            );
            // The meshes are the phalanges the file's capsules stand for, which are a little
            // fatter (the thumb's proximal capsule, 13 mm, is wider than its mesh): thinner than
            // the capsule but more than half as thick, and running the same way within 25°.
            assert!(
                thickest.radius <= file.radius + 1e-3 && thickest.radius > 0.5 * file.radius,
                "{bone}: mesh {} mm, capsule {} mm",
                thickest.radius * 1e3,
                file.radius * 1e3
            );
            let (u, v) = ((file.b - file.a).normalize(), thickest.b - thickest.a);
            if v.norm() > 0.005 {
                let angle = u.dot(&v.normalize()).abs().acos().to_degrees();
                assert!(angle < 25.0, "{bone}: {angle}°");
            }
        }
    }
    // Every mesh's hull lies within 5 mm of its capsules (the description's measure).
    let corners: Vec<f64> = d
        .split("corners within ")
        .skip(1)
        .map(|rest| rest.split(' ').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(corners.len(), 15, "{d}");
    assert!(corners.iter().all(|&mm| mm <= 5.0), "{corners:?}");
    // And it grasps the cylinder with them.
    let object = ObjectModel::new("cylinder", builtin_object("cylinder").unwrap(), None).unwrap();
    let mut planner = GraspPlanner::new(
        &meshes,
        &object,
        meshes.movement("power").unwrap(),
        Point3::new(-0.35, -0.2, 0.35),
        SearchParams::default(),
    )
    .unwrap();
    planner.run_to_end();
    let result = GraspResult::from_planner(&planner, &mut Workspace::new(&meshes));
    assert!(result.valid, "{:?}", result.invalid_reason);
}

#[test]
fn a_fingertip_whose_only_collider_is_an_unreadable_mesh_says_why() {
    // Absurd, flat and too few vertices: the hand is refused, naming what was skipped.
    let hand = |vertex: &str| {
        format!(
            r#"<mujoco><asset><mesh name="pad" vertex="{vertex}"/></asset><worldbody><body name="palm"><geom type="box" size="0.03 0.01 0.04"/>
<body name="thumb" pos="-0.03 0 0.04"><joint name="t" axis="1 0 0" range="0 1.5"/><geom type="mesh" mesh="pad" name="thumb_pad"/></body>
<body name="index" pos="0.03 0 0.04"><joint name="i" axis="1 0 0" range="0 1.5"/><geom type="capsule" fromto="0 0 0 0 0 0.03" size="0.006"/></body>
</body></worldbody></mujoco>"#
        )
    };
    for (vertex, why) in [
        (
            "1e300 0 0 -1e300 0 0 0 1e300 0 0 0 1e300 0 0 -1e300",
            "hull cannot be built",
        ),
        (
            "0 0 0 0.01 0 0 0 0.01 0 0.01 0.01 0",
            "hull cannot be built",
        ),
        ("0 0 0 1 0 0", "hull cannot be built"),
    ] {
        let e = prehensile_formats::parse_hand_mjcf(&hand(vertex), "h.xml").unwrap_err();
        assert!(
            e.reason.contains("no tip site or collision geom")
                && e.reason.contains("thumb_pad (")
                && e.reason.contains(why),
            "{vertex}: {e}"
        );
    }
}
