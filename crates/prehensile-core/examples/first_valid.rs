//! How soon a search finds its first valid pose, the measurement behind `AUTO_PATIENCE`: every
//! movement but `close` of the human, Shadow and cartoon4 hands, searched to its stop rule on
//! the five built-in objects and the meshes of `assets/objects`, seeds 1–3. Prints one line per
//! search, then the quantiles of the first valid step and, for several patiences, how many
//! `auto` winners the patience rule changes and how many steps it saves. Run from the repository
//! root: `cargo run --release -p prehensile-core --example first_valid`.
use std::collections::BTreeMap;
use std::path::Path;

use prehensile_core::math::Vec3;
use prehensile_core::search::{
    default_shoulder, GraspPlanner, GraspResult, PlannerStatus, SearchParams,
};
use prehensile_core::{shapes, HandModel, ObjectModel, Workspace};

/// One movement's search.
struct Search {
    movement: String,
    steps: u32,
    /// The step after which the search first had a valid pose.
    first_valid: Option<u32>,
    valid: bool,
    epsilon: f64,
}

/// A request: (hand, object, seed).
type Request = (String, String, u64);

fn main() {
    let hands = hands();
    let objects = objects();
    let requests = search_all(&hands, &objects);
    print_first_valid_quantiles(&requests);
    print_patience_outcomes(&requests);
}

/// The human, Shadow and cartoon4 hands.
fn hands() -> Vec<(&'static str, HandModel)> {
    vec![
        ("human", prehensile_formats::builtin_hand("human").unwrap()),
        (
            "shadow",
            prehensile_formats::load_hand_mjcf(Path::new("assets/hands/shadow_hand/reach.xml"))
                .unwrap(),
        ),
        (
            "cartoon4",
            prehensile_formats::builtin_hand("cartoon4").unwrap(),
        ),
    ]
}

/// The built-in objects and the meshes of `assets/objects`.
fn objects() -> Vec<(String, ObjectModel)> {
    let mut objects: Vec<(String, ObjectModel)> = ["sphere", "box", "cylinder", "torus", "mug"]
        .iter()
        .map(|n| {
            let mesh = shapes::builtin_object(n).unwrap();
            (n.to_string(), ObjectModel::new(n, mesh, None).unwrap())
        })
        .collect();
    let mut files: Vec<_> = std::fs::read_dir("assets/objects")
        .expect("run from the repository root")
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj" || e == "stl"))
        .collect();
    files.sort();
    for path in files {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        objects.push((name, prehensile_formats::load_object(&path, 1.0).unwrap()));
    }
    objects
}

/// Every request's searches, one per movement but `close`, each to its stop rule.
fn search_all(
    hands: &[(&str, HandModel)],
    objects: &[(String, ObjectModel)],
) -> BTreeMap<Request, Vec<Search>> {
    let mut requests: BTreeMap<Request, Vec<Search>> = BTreeMap::new();
    for (hand_name, hand) in hands {
        for (object_name, object) in objects {
            let shoulder = default_shoulder(hand, &object.center_of_mass(), &Vec3::z());
            for seed in 1..=3 {
                for movement in hand.movements().iter().filter(|m| m.name() != "close") {
                    let params = SearchParams {
                        seed,
                        ..Default::default()
                    };
                    let Ok(mut planner) =
                        GraspPlanner::new(hand, object, movement, shoulder, params)
                    else {
                        continue; // e.g. an object too large for the hand
                    };
                    let mut first_valid = None;
                    loop {
                        let status = planner.step();
                        if first_valid.is_none() && planner.best().is_some() {
                            first_valid = Some(planner.stats().steps);
                        }
                        if status != PlannerStatus::Searching {
                            break;
                        }
                    }
                    let result = GraspResult::from_planner(&planner, &mut Workspace::new(hand));
                    let search = Search {
                        movement: movement.name().to_string(),
                        steps: planner.stats().steps,
                        first_valid,
                        valid: result.valid,
                        epsilon: result.stability.epsilon,
                    };
                    println!(
                        "{hand_name} {object_name} seed {seed} {}: {} steps, first valid {:?}, valid {}, ε {:.5}",
                        search.movement, search.steps, search.first_valid, search.valid, search.epsilon
                    );
                    requests
                        .entry((hand_name.to_string(), object_name.clone(), seed))
                        .or_default()
                        .push(search);
                }
            }
        }
    }
    requests
}

/// The quantiles of the step each valid search first had a valid pose at.
fn print_first_valid_quantiles(requests: &BTreeMap<Request, Vec<Search>>) {
    let mut firsts: Vec<u32> = requests
        .values()
        .flatten()
        .filter(|s| s.valid)
        .filter_map(|s| s.first_valid)
        .collect();
    firsts.sort_unstable();
    let quantile = |q: f64| firsts[(q * (firsts.len() - 1) as f64) as usize];
    println!(
        "{} searches, {} valid; first valid step: median {}, 90% {}, 95% {}, 99% {}, most {}",
        requests.values().map(Vec::len).sum::<usize>(),
        firsts.len(),
        quantile(0.5),
        quantile(0.9),
        quantile(0.95),
        quantile(0.99),
        quantile(1.0)
    );
}

/// For several patiences, how many `auto` winners the patience rule changes and how many steps
/// it saves.
fn print_patience_outcomes(requests: &BTreeMap<Request, Vec<Search>>) {
    let winner = |searches: &[(bool, f64)]| {
        (0..searches.len())
            .max_by(|&a, &b| searches[a].partial_cmp(&searches[b]).unwrap())
            .unwrap()
    };
    for patience in [25, 50, 100, 200] {
        let (mut changed, mut saved, mut total) = (Vec::new(), 0, 0);
        for (request, searches) in requests.iter().filter(|(_, s)| s.len() > 1) {
            total += searches.iter().map(|s| s.steps).sum::<u32>();
            let full: Vec<(bool, f64)> = searches.iter().map(|s| (s.valid, s.epsilon)).collect();
            // A search still without a valid pose at round max(patience, the step another
            // search ended valid at) stops there, invalid.
            let cut: Vec<(bool, f64)> = searches
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    let others_end = searches
                        .iter()
                        .enumerate()
                        .filter(|&(j, o)| j != k && o.valid)
                        .map(|(_, o)| o.steps)
                        .min();
                    match others_end.map(|end| end.max(patience)) {
                        Some(round)
                            if s.steps > round && s.first_valid.is_none_or(|f| f > round) =>
                        {
                            saved += s.steps - round;
                            (false, s.epsilon)
                        }
                        _ => (s.valid, s.epsilon),
                    }
                })
                .collect();
            if winner(&full) != winner(&cut) {
                changed.push(request.clone());
            }
        }
        println!(
            "patience {patience}: {} winners of {} changed {changed:?}, {saved} of {total} steps saved",
            changed.len(),
            requests.values().filter(|s| s.len() > 1).count()
        );
    }
}
