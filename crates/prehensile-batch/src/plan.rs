//! What a batch runs: the inputs, and the attempts they make.

use std::fmt;
use std::path::Path;

use prehensile_core::search::ValidityRule;

use prehensile_core::parameter::UpAxis;
use prehensile_core::search::{defaults, GraspOptions};

use crate::error::{PlanError, MAX_SEEDS};

/// Mesh file extensions a folder of objects is searched for.
const MESH_EXTENSIONS: [&str; 5] = ["obj", "stl", "ply", "glb", "gltf"];

/// Where the character's shoulder is for an attempt.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum Shoulder {
    /// The hand's default shoulder for the object's hook (`default_shoulder`).
    Default,
    /// A fixed point in the object's frame, metres.
    At([f64; 3]),
}

impl Shoulder {
    /// Parses `default` or `X,Y,Z`.
    pub fn parse(s: &str) -> Result<Self, PlanError> {
        if s == "default" {
            return Ok(Self::Default);
        }
        let numbers: Vec<f64> = s
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| PlanError::Shoulder(s.to_string()))?;
        match numbers.as_slice() {
            [x, y, z] if numbers.iter().all(|v| v.is_finite() && v.abs() <= 1e6) => {
                Ok(Self::At([*x, *y, *z]))
            }
            _ => Err(PlanError::Shoulder(s.to_string())),
        }
    }
}

impl fmt::Display for Shoulder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Default => write!(f, "default"),
            Self::At([x, y, z]) => write!(f, "{x},{y},{z}"),
        }
    }
}

/// Options every attempt shares.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BatchOptions {
    /// Scale applied to mesh files (0.001 for millimetres).
    pub scale: f64,
    /// Repair: merge vertices of mesh files closer than this many metres.
    pub weld: Option<f64>,
    /// The world's up axis.
    pub up: UpAxis,
    /// Which grasps are valid.
    pub validity: ValidityRule,
    /// Coulomb friction of the contacts.
    pub friction: f64,
    /// Steps to go on looking past a one-sided power grasp
    /// ([`SearchParams::one_sided_patience`](prehensile_core::search::SearchParams)).
    #[serde(default = "one_sided_patience")]
    pub one_sided_patience: u32,
}

fn one_sided_patience() -> u32 {
    defaults::ONE_SIDED_PATIENCE
}

impl Default for BatchOptions {
    fn default() -> Self {
        Self {
            scale: 1.0,
            weld: None,
            up: defaults::UP,
            validity: defaults::VALIDITY,
            friction: defaults::FRICTION,
            one_sided_patience: one_sided_patience(),
        }
    }
}

impl BatchOptions {
    /// The request of one attempt: every option of the batch, the attempt's own movement,
    /// shoulder (`None`: the hand's default) and seed, one thread (the batch runs attempts side
    /// by side instead).
    pub fn grasp_options(
        &self,
        movement: &str,
        shoulder: Option<[f64; 3]>,
        seed: u64,
    ) -> GraspOptions {
        GraspOptions {
            movement: movement.to_string(),
            shoulder,
            up: self.up,
            seed,
            threads: Some(1),
            friction: self.friction,
            validity: self.validity,
            one_sided_patience: self.one_sided_patience,
            ..GraspOptions::default()
        }
    }
}

/// The inputs of a batch: every combination is one attempt.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BatchPlan {
    /// Hands: built-in names or hand files.
    pub hands: Vec<String>,
    /// Objects: built-in names or mesh files.
    pub objects: Vec<String>,
    /// Movements, or `auto`.
    pub movements: Vec<String>,
    /// Shoulders.
    pub shoulders: Vec<Shoulder>,
    /// Seeds of the random search angles.
    pub seeds: Vec<u64>,
    /// Shared options.
    pub options: BatchOptions,
}

/// One search of the plan, by index into its lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Attempt {
    /// Index into `hands`.
    pub hand: usize,
    /// Index into `objects`.
    pub object: usize,
    /// Index into `movements`.
    pub movement: usize,
    /// Index into `shoulders`.
    pub shoulder: usize,
    /// The seed itself.
    pub seed: u64,
}

impl BatchPlan {
    /// Checks the plan: every list non-empty, no name twice, options in range.
    pub fn check(&self) -> Result<(), PlanError> {
        let lists = [
            ("hands", self.hands.len()),
            ("objects", self.objects.len()),
            ("movements", self.movements.len()),
            ("shoulders", self.shoulders.len()),
            ("seeds", self.seeds.len()),
        ];
        if let Some((what, _)) = lists.iter().find(|(_, n)| *n == 0) {
            return Err(PlanError::Empty(what));
        }
        if self.seeds.len() as u64 > MAX_SEEDS {
            return Err(PlanError::Seeds(self.seeds.len() as u64));
        }
        let shoulders: Vec<String> = self.shoulders.iter().map(|s| s.to_string()).collect();
        let seeds: Vec<String> = self.seeds.iter().map(|s| s.to_string()).collect();
        for (what, names) in [
            ("hand", &self.hands),
            ("object", &self.objects),
            ("movement", &self.movements),
            ("shoulder", &shoulders),
            ("seed", &seeds),
        ] {
            if let Some(name) = repeated(names) {
                return Err(PlanError::Repeated { what, name });
            }
        }
        prehensile_core::parameter::in_range("scale", self.options.scale, 1e-9, 1e9, "")?;
        self.options.grasp_options("auto", None, 1).params()?;
        Ok(())
    }

    /// Every attempt of one object, in a fixed order.
    pub fn attempts_of(&self, object: usize) -> Vec<Attempt> {
        let mut out = Vec::new();
        for hand in 0..self.hands.len() {
            for movement in 0..self.movements.len() {
                for shoulder in 0..self.shoulders.len() {
                    for &seed in &self.seeds {
                        out.push(Attempt {
                            hand,
                            object,
                            movement,
                            shoulder,
                            seed,
                        });
                    }
                }
            }
        }
        out
    }

    /// How many attempts the plan makes.
    pub fn attempt_count(&self) -> usize {
        self.hands.len()
            * self.objects.len()
            * self.movements.len()
            * self.shoulders.len()
            * self.seeds.len()
    }
}

/// The first name of `names` that comes again later, if any.
fn repeated(names: &[String]) -> Option<String> {
    names
        .iter()
        .enumerate()
        .find(|(i, n)| names[..*i].contains(n))
        .map(|(_, n)| n.clone())
}

/// Expands object arguments: a folder becomes its mesh files (sorted, not recursive), a pattern
/// with `*`, `?` or `[` its matches (sorted), anything else stays as given (a built-in name or a
/// file). Fails on a folder or pattern that matches nothing.
pub fn expand_objects(specs: &[String]) -> Result<Vec<String>, PlanError> {
    let mut out = Vec::new();
    for spec in specs {
        let path = Path::new(spec);
        if path.is_dir() {
            let entries = std::fs::read_dir(path).map_err(|e| PlanError::UnreadableFolder {
                folder: spec.clone(),
                kind: e.kind(),
            })?;
            let mut found: Vec<String> = entries
                .filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_file() && is_mesh(p))
                .map(|p| p.display().to_string())
                .collect();
            if found.is_empty() {
                return Err(PlanError::EmptyFolder {
                    folder: spec.clone(),
                    extensions: &MESH_EXTENSIONS,
                });
            }
            found.sort();
            out.extend(found);
        } else if spec.contains(['*', '?', '[']) {
            let matches = glob::glob(spec).map_err(|e| PlanError::Pattern {
                pattern: spec.clone(),
                position: e.pos,
                problem: e.msg,
            })?;
            let mut found: Vec<String> = matches
                .filter_map(|m| m.ok())
                .filter(|p| p.is_file())
                .map(|p| p.display().to_string())
                .collect();
            if found.is_empty() {
                return Err(PlanError::NoMatch(spec.clone()));
            }
            found.sort();
            out.extend(found);
        } else {
            out.push(spec.clone());
        }
    }
    Ok(out)
}

fn is_mesh(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| MESH_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}
