//! Bad hand files: every error names what and where, and nothing panics.

use prehensile_formats::{builtin_hand, parse_hand_toml};

/// A valid two-finger claw; tests break one thing at a time.
const CLAW: &str = r#"
name = "claw"
[[bones]]
name = "palm"
origin = [0.0, 0.0, 0.0]
radius = 0.02
[[bones]]
name = "a_base"
parent = "palm"
origin = [-0.02, 0.0, 0.06]
radius = 0.01
joint = { kind = "hinge", flexion = [0.0, 90.0] }
[[bones]]
name = "a_tip"
parent = "a_base"
origin = [-0.02, 0.0, 0.10]
tip = [-0.02, 0.0, 0.14]
radius = 0.009
joint = { kind = "hinge", flexion = [0.0, 90.0] }
[[bones]]
name = "b_base"
parent = "palm"
origin = [0.02, 0.0, 0.06]
radius = 0.01
joint = { kind = "two-axis", flexion = [0.0, 90.0], abduction = [-10.0, 10.0] }
[[bones]]
name = "b_tip"
parent = "b_base"
origin = [0.02, 0.0, 0.10]
tip = [0.02, 0.0, 0.14]
radius = 0.009
joint = { kind = "hinge", flexion = [0.0, 90.0] }
"#;

fn error_of(text: &str) -> String {
    parse_hand_toml(text, "claw.toml").unwrap_err().to_string()
}

#[test]
fn the_claw_is_valid() {
    let hand = parse_hand_toml(CLAW, "claw.toml").unwrap();
    assert_eq!(hand.fingers().len(), 2);
    assert_eq!(hand.capsules().len(), 2 + 4);
    assert_eq!(hand.dof_count(), 5);
}

#[test]
fn cycle_is_named() {
    let text = CLAW.replace(
        "name = \"a_base\"\nparent = \"palm\"",
        "name = \"a_base\"\nparent = \"a_tip\"",
    );
    let e = error_of(&text);
    assert!(
        e.contains("cycle") && (e.contains("a_base") || e.contains("a_tip")),
        "{e}"
    );
}

#[test]
fn missing_parent_is_named() {
    let e = error_of(&CLAW.replace("parent = \"a_base\"", "parent = \"a_bse\""));
    assert!(e.contains("a_tip") && e.contains("a_bse"), "{e}");
}

#[test]
fn zero_length_bone_is_named() {
    let e = error_of(&CLAW.replace("tip = [-0.02, 0.0, 0.14]", "tip = [-0.02, 0.0, 0.10]"));
    assert!(e.contains("a_tip") && e.contains("length"), "{e}");
}

#[test]
fn bad_numbers_are_named() {
    let e = error_of(&CLAW.replace("radius = 0.009\njoint = { kind = \"hinge\", flexion = [0.0, 90.0] }\n[[bones]]\nname = \"b_base\"", "radius = -0.009\njoint = { kind = \"hinge\", flexion = [0.0, 90.0] }\n[[bones]]\nname = \"b_base\""));
    assert!(e.contains("a_tip") && e.contains("radius"), "{e}");
    let e = error_of(&CLAW.replace("origin = [0.02, 0.0, 0.06]", "origin = [nan, 0.0, 0.06]"));
    assert!(e.contains("b_base") && e.contains("finite"), "{e}");
    let e = error_of(&CLAW.replace("abduction = [-10.0, 10.0]", "abduction = [10.0, -10.0]"));
    assert!(e.contains("b_base") && e.contains("not ordered"), "{e}");
}

#[test]
fn structure_errors_are_named() {
    // Two roots.
    let e = error_of(&CLAW.replace("name = \"b_base\"\nparent = \"palm\"", "name = \"b_base\""));
    assert!(e.contains("exactly one root"), "{e}");
    // A finger that branches.
    let e = error_of(&CLAW.replace(
        "name = \"b_base\"\nparent = \"palm\"",
        "name = \"b_base\"\nparent = \"a_base\"",
    ));
    assert!(e.contains("a_base") && e.contains("children"), "{e}");
    // One finger only.
    let one = CLAW.split("[[bones]]\nname = \"b_base\"").next().unwrap();
    let e = error_of(one);
    assert!(e.contains("at least") || e.contains("finger"), "{e}");
    // Missing tip.
    let e = error_of(&CLAW.replace("tip = [0.02, 0.0, 0.14]\n", ""));
    assert!(e.contains("b_tip") && e.contains("tip"), "{e}");
    // Duplicate names.
    let e = error_of(&CLAW.replace("name = \"b_tip\"", "name = \"a_tip\""));
    assert!(e.contains("a_tip") && e.contains("twice"), "{e}");
}

#[test]
fn unknown_keys_and_bad_movements_are_named() {
    let e = parse_hand_toml(
        &CLAW.replace("radius = 0.02", "radius = 0.02\nradus = 1"),
        "claw.toml",
    )
    .unwrap_err();
    assert!(e.location.is_some(), "{e}");
    assert!(e.reason.contains("radus"), "{e}");
    let moving =
        format!("{CLAW}\n[[movements]]\nname = \"pinch\"\n[movements.end]\na_base = [120.0]\n");
    let e = error_of(&moving);
    assert!(
        e.contains("pinch") && e.contains("a_base") && e.contains("limits"),
        "{e}"
    );
    let moving =
        format!("{CLAW}\n[[movements]]\nname = \"pinch\"\n[movements.end]\nb_base = [12.0]\n");
    let e = error_of(&moving);
    assert!(e.contains("b_base") && e.contains("angle"), "{e}");
    let coupled =
        format!("{CLAW}\n[[couplings]]\nfollower = \"a_tip\"\nleader = \"nobody\"\nratio = 0.5\n");
    assert!(error_of(&coupled).contains("nobody"));
}

#[test]
fn the_human_hand_is_the_thesis_skeleton() {
    let h = builtin_hand("human").unwrap();
    assert_eq!(h.bones().len(), 20);
    assert_eq!(h.capsules().len(), 24, "§6.6: nb = 24");
    let names: Vec<&str> = h.fingers().iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["thumb", "index", "middle", "ring", "little"]);
    assert_eq!(h.fingers()[0].bones.len(), 3);
    assert!(h.fingers()[1..].iter().all(|f| f.bones.len() == 4));
    // Parents first.
    for (i, b) in h.bones().iter().enumerate() {
        assert!(b.parent.is_none_or(|p| p < i));
    }
    // Distal = 2/3 middle in every movement's end pose.
    let power = h.movement("power").unwrap();
    let (mid, dist) = (
        h.bone_index("index_middle").unwrap(),
        h.bone_index("index_distal").unwrap(),
    );
    let a = power.end_angles();
    let (m, d) = (a[h.bones()[mid].first_dof], a[h.bones()[dist].first_dof]);
    assert!((d - 0.6667 * m).abs() < 1e-12 && m > 1.0);
    // The fingers start straight in both movements (Fig. 5.6); the precision grasp's thumb starts
    // curled across the palm, opposite the index (assets/hands/human.toml).
    let precision = h.movement("precision").unwrap();
    let thumb_dofs = {
        let last = &h.bones()[*h.fingers()[0].bones.last().unwrap()];
        h.bones()[h.fingers()[0].bones[0]].first_dof..last.first_dof + last.joint.dofs()
    };
    for (k, (p, q)) in power
        .start_angles()
        .iter()
        .zip(precision.start_angles())
        .enumerate()
    {
        assert_eq!(p == q, !thumb_dofs.contains(&k), "degree of freedom {k}");
    }
    assert_eq!(precision.contact_fingers(), &[0, 1]);
}

fn with_couplings(pairs: &[(&str, &str)]) -> String {
    let mut text = CLAW.to_string();
    for (follower, leader) in pairs {
        text += &format!(
            "\n[[couplings]]\nfollower = \"{follower}\"\nleader = \"{leader}\"\nratio = 0.5\n"
        );
    }
    text
}

#[test]
fn coupling_cycles_and_self_couplings_are_refused_not_violated() {
    assert!(parse_hand_toml(&with_couplings(&[("a_tip", "a_base")]), "c.toml").is_ok());
    let e = error_of(&with_couplings(&[("a_tip", "a_tip")]));
    assert!(e.contains("coupled to itself"), "{e}");
    let e = error_of(&with_couplings(&[("a_tip", "a_base"), ("a_base", "a_tip")]));
    assert!(e.contains("cycle"), "{e}");
    let e = error_of(&with_couplings(&[("a_tip", "a_base"), ("a_tip", "b_tip")]));
    assert!(e.contains("two leaders"), "{e}");
}

#[test]
fn absurd_sizes_are_refused_not_searched_forever() {
    let e = error_of(&CLAW.replace("radius = 0.02", "radius = 1e300"));
    assert!(e.contains("at most 2 m"), "{e}");
    let e = error_of(&CLAW.replace(
        "origin = [-0.02, 0.0, 0.10]",
        "origin = [-0.02, 0.0, 1e308]",
    ));
    assert!(e.contains("units"), "{e}");
}

#[test]
fn an_mjcf_axis_too_large_to_normalize_is_refused() {
    let xml = |axis: &str| {
        format!(
            r#"<mujoco model="m"><worldbody><body name="palm">
            <geom type="sphere" size="0.02"/>
            <body name="a" pos="-0.02 0 0.06"><joint name="ja" axis="{axis}" range="0 1.5"/>
              <geom type="capsule" fromto="0 0 0 0 0 0.04" size="0.008"/></body>
            <body name="b" pos="0.02 0 0.06"><joint name="jb" axis="1 0 0" range="0 1.5"/>
              <geom type="capsule" fromto="0 0 0 0 0 0.04" size="0.008"/></body>
            </body></worldbody></mujoco>"#
        )
    };
    assert!(prehensile_formats::parse_hand_mjcf(&xml("1 0 0"), "m.xml").is_ok());
    let e = prehensile_formats::parse_hand_mjcf(&xml("1e308 1e308 0"), "m.xml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("joint axis"), "{e}");
}

#[test]
fn two_mjcf_bodies_with_one_name_are_refused_instead_of_looping() {
    // The fuzzer found that a body named like its parent sent the finger-naming walk,
    // which follows the chain by name, round forever.
    let xml = |inner: &str| {
        format!(
            r#"<mujoco model="m"><worldbody><body name="palm">
            <geom type="sphere" size="0.02"/>
            <body name="a" pos="-0.02 0 0.06"><joint name="ja" axis="1 0 0" range="0 1.5"/>
              <geom type="capsule" fromto="0 0 0 0 0 0.04" size="0.008"/>
              <body name="{inner}" pos="0 0 0.04"><joint name="ja2" axis="1 0 0" range="0 1.5"/>
                <geom type="capsule" fromto="0 0 0 0 0 0.03" size="0.008"/></body></body>
            <body name="b" pos="0.02 0 0.06"><joint name="jb" axis="1 0 0" range="0 1.5"/>
              <geom type="capsule" fromto="0 0 0 0 0 0.04" size="0.008"/></body>
            </body></worldbody></mujoco>"#
        )
    };
    assert!(prehensile_formats::parse_hand_mjcf(&xml("a2"), "m.xml").is_ok());
    let e = prehensile_formats::parse_hand_mjcf(&xml("a"), "m.xml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("two bodies are named 'a'"), "{e}");
}

#[test]
fn two_urdf_links_with_one_name_are_refused_instead_of_panicking() {
    // Found while splitting the URDF reader into one method per element: a link defined twice
    // and moved by a joint left the bone list one bone short, and the importer panicked.
    let urdf = |second: &str| {
        format!(
            r#"<robot name="r"><link name="palm"/><link name="a"/><link name="{second}"/>
            <joint name="j" type="fixed"><parent link="palm"/><child link="a"/></joint>
            <joint name="k" type="fixed"><parent link="palm"/><child link="b"/></joint></robot>"#
        )
    };
    // With distinct names the file reads on to the hand's own checks (no fingertip here).
    let distinct = prehensile_formats::parse_hand_urdf(&urdf("b"), "r.urdf").unwrap_err();
    assert!(!distinct.to_string().contains("named"), "{distinct}");
    let e = prehensile_formats::parse_hand_urdf(&urdf("a"), "r.urdf")
        .unwrap_err()
        .to_string();
    assert!(e.contains("two links are named 'a'"), "{e}");
}

#[test]
fn hands_and_meshes_read_from_bytes_as_from_files() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets");
    let toml = std::fs::read(dir.join("hands/robot3.toml")).unwrap();
    let from_bytes = prehensile_formats::parse_hand(&toml, "robot3.toml").unwrap();
    let from_file = prehensile_formats::load_hand(&dir.join("hands/robot3.toml")).unwrap();
    assert_eq!(from_bytes.dof_names(), from_file.dof_names());
    let e = prehensile_formats::parse_hand(&toml, "robot3.txt").unwrap_err();
    assert!(e.to_string().contains("unknown hand file extension"), "{e}");
    let stl_path = dir.join("objects/robosuite_lemon.stl");
    let stl = std::fs::read(&stl_path).unwrap();
    assert_eq!(
        prehensile_formats::parse_mesh(&stl, "lemon.stl", 1.0).unwrap(),
        prehensile_formats::read_mesh(&stl_path, 1.0).unwrap()
    );
    // A .gltf whose buffer is another file cannot be read from its bytes alone.
    let gltf = br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"mesh.bin","byteLength":12}]}"#;
    let e = prehensile_formats::parse_mesh(gltf, "scene.gltf", 1.0).unwrap_err();
    assert!(e.to_string().contains("give a .glb"), "{e}");
}

#[test]
fn the_hand_error_is_carried_typed_not_only_as_text() {
    use prehensile_core::HandError;
    use prehensile_formats::FormatCause;
    let e = parse_hand_toml(
        &CLAW.replace("parent = \"a_base\"", "parent = \"a_bse\""),
        "claw.toml",
    )
    .unwrap_err();
    assert!(
        matches!(
            e.cause.as_deref(),
            Some(FormatCause::Hand(HandError::MissingParent { .. }))
        ),
        "{:?}",
        e.cause
    );
    // And as the standard error source, for `anyhow`-style reporting chains.
    let source = std::error::Error::source(&e).expect("a source");
    assert_eq!(source.to_string(), e.reason);
    // A TOML syntax error has no library cause.
    assert!(parse_hand_toml("name = ", "x.toml")
        .unwrap_err()
        .cause
        .is_none());
}
