//! Plans: shoulders, checks and object expansion.

use prehensile_batch::{expand_objects, BatchOptions, BatchPlan, PlanError, Shoulder};

fn plan() -> BatchPlan {
    BatchPlan {
        hands: vec!["human".into()],
        objects: vec!["sphere".into(), "box".into()],
        movements: vec!["auto".into()],
        shoulders: vec![Shoulder::Default, Shoulder::At([0.3, -0.2, 0.4])],
        seeds: vec![1, 2, 3],
        options: BatchOptions::default(),
    }
}

#[test]
fn shoulders_parse_and_print_back() {
    assert_eq!(Shoulder::parse("default").unwrap(), Shoulder::Default);
    let s = Shoulder::parse("0.3,-0.2,0.4").unwrap();
    assert_eq!(s, Shoulder::At([0.3, -0.2, 0.4]));
    assert_eq!(Shoulder::parse(&s.to_string()).unwrap(), s);
    for bad in ["", "1,2", "1,2,3,4", "nan,0,0", "1e300,0,0", "x,y,z"] {
        assert!(
            matches!(Shoulder::parse(bad), Err(PlanError::Shoulder(_))),
            "{bad}"
        );
    }
}

#[test]
fn a_plan_counts_its_attempts_and_refuses_empty_or_repeated_lists() {
    let p = plan();
    p.check().unwrap();
    assert_eq!(p.attempt_count(), 2 * 2 * 3);
    assert_eq!(p.attempts_of(1).len(), 2 * 3);
    assert!(p.attempts_of(1).iter().all(|a| a.object == 1));
    let mut empty = plan();
    empty.seeds.clear();
    assert!(empty.check().unwrap_err().to_string().contains("no seeds"));
    let mut twice = plan();
    twice.objects.push("sphere".into());
    assert!(twice.check().unwrap_err().to_string().contains("'sphere'"));
    let mut friction = plan();
    friction.options.friction = f64::NAN;
    assert!(friction.check().is_err());
    let mut seeds = plan();
    seeds.seeds = vec![7, 7];
    assert!(matches!(
        seeds.check(),
        Err(PlanError::Repeated { what: "seed", .. })
    ));
}

#[test]
fn a_manifest_keeps_the_up_axis_as_a_letter() {
    let json = serde_json::to_value(BatchOptions::default()).unwrap();
    assert_eq!(json["up"], "z");
}

#[test]
fn folders_and_patterns_expand_to_sorted_mesh_files() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-plan-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    for f in ["b.stl", "a.OBJ", "notes.txt", "sub/c.ply"] {
        std::fs::write(dir.join(f), "").unwrap();
    }
    let d = dir.display().to_string();
    let found = expand_objects(&[d.clone(), "sphere".into()]).unwrap();
    assert_eq!(
        found,
        [format!("{d}/a.OBJ"), format!("{d}/b.stl"), "sphere".into()]
    );
    let matched = expand_objects(&[format!("{d}/*.stl")]).unwrap();
    assert_eq!(matched, [format!("{d}/b.stl")]);
    assert!(expand_objects(&[format!("{d}/*.glb")]).is_err());
    assert!(expand_objects(&[format!("{d}/sub/none")]).unwrap().len() == 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_plan_written_before_one_sided_patience_reads_with_its_default() {
    // A manifest from before the option existed resumes with its default.
    let mut json = serde_json::to_value(BatchOptions::default()).unwrap();
    json.as_object_mut().unwrap().remove("one_sided_patience");
    let read: BatchOptions = serde_json::from_value(json).unwrap();
    assert_eq!(
        read.one_sided_patience,
        prehensile_core::search::ONE_SIDED_PATIENCE
    );
    assert_eq!(read, BatchOptions::default());
}
