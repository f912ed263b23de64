//! What a batch runs: the inputs, and the attempts they make.

use std::fmt;
use std::path::Path;

use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::ValidityRule;

use crate::BatchError;

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
    pub fn parse(s: &str) -> Result<Self, BatchError> {
        if s == "default" {
            return Ok(Self::Default);
        }
        let numbers: Vec<f64> = s
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| BatchError::Plan(format!("shoulder '{s}': use default or X,Y,Z")))?;
        match numbers.as_slice() {
            [x, y, z] if numbers.iter().all(|v| v.is_finite() && v.abs() <= 1e6) => {
                Ok(Self::At([*x, *y, *z]))
            }
            _ => Err(BatchError::Plan(format!(
                "shoulder '{s}': use default or three finite numbers X,Y,Z (metres, at most 1e6)"
            ))),
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
    /// The world's up axis: `x`, `y` or `z`.
    pub up: char,
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
    prehensile_core::search::ONE_SIDED_PATIENCE
}

impl Default for BatchOptions {
    fn default() -> Self {
        Self {
            scale: 1.0,
            weld: None,
            up: 'z',
            validity: ValidityRule::default(),
            friction: 0.5,
            one_sided_patience: one_sided_patience(),
        }
    }
}

impl BatchOptions {
    /// The up axis as a vector.
    pub fn up_vector(&self) -> Result<Vec3, BatchError> {
        match self.up {
            'x' => Ok(Vec3::x()),
            'y' => Ok(Vec3::y()),
            'z' => Ok(Vec3::z()),
            other => Err(BatchError::Plan(format!(
                "up axis '{other}': use x, y or z"
            ))),
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
    pub fn check(&self) -> Result<(), BatchError> {
        let lists = [
            ("hands", self.hands.len()),
            ("objects", self.objects.len()),
            ("movements", self.movements.len()),
            ("shoulders", self.shoulders.len()),
            ("seeds", self.seeds.len()),
        ];
        for (what, n) in lists {
            if n == 0 {
                return Err(BatchError::Plan(format!("the batch has no {what}")));
            }
        }
        let repeated = |names: &[String]| {
            names
                .iter()
                .enumerate()
                .find(|(i, n)| names[..*i].contains(n))
                .map(|(_, n)| n.clone())
        };
        for (what, names) in [
            ("hand", &self.hands),
            ("object", &self.objects),
            ("movement", &self.movements),
        ] {
            if let Some(n) = repeated(names) {
                return Err(BatchError::Plan(format!("{what} '{n}' is listed twice")));
            }
        }
        let shoulders: Vec<String> = self.shoulders.iter().map(|s| s.to_string()).collect();
        let seeds: Vec<String> = self.seeds.iter().map(|s| s.to_string()).collect();
        if let Some(n) = repeated(&shoulders).or_else(|| repeated(&seeds)) {
            return Err(BatchError::Plan(format!("'{n}' is listed twice")));
        }
        if !(self.options.scale.is_finite() && self.options.scale > 0.0) {
            return Err(BatchError::Plan(format!(
                "scale {} must be a positive number",
                self.options.scale
            )));
        }
        if !(self.options.friction.is_finite()
            && self.options.friction > 0.0
            && self.options.friction <= 10.0)
        {
            return Err(BatchError::Plan(format!(
                "friction {} must be in (0, 10]",
                self.options.friction
            )));
        }
        self.options.up_vector()?;
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

    /// The shoulder of `attempt` in the object's frame, given the object's hook and the hand's
    /// default for it.
    pub fn shoulder_point(&self, attempt: &Attempt, default: Point3) -> Point3 {
        match self.shoulders[attempt.shoulder] {
            Shoulder::Default => default,
            Shoulder::At(p) => Point3::from(p),
        }
    }
}

/// Expands object arguments: a folder becomes its mesh files (sorted, not recursive), a pattern
/// with `*`, `?` or `[` its matches (sorted), anything else stays as given (a built-in name or a
/// file). Fails on a folder or pattern that matches nothing.
pub fn expand_objects(specs: &[String]) -> Result<Vec<String>, BatchError> {
    let mut out = Vec::new();
    for spec in specs {
        let path = Path::new(spec);
        if path.is_dir() {
            let entries = std::fs::read_dir(path).map_err(|e| BatchError::Io {
                path: spec.clone(),
                reason: e.to_string(),
            })?;
            let mut found: Vec<String> = entries
                .filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_file() && is_mesh(p))
                .map(|p| p.display().to_string())
                .collect();
            if found.is_empty() {
                return Err(BatchError::Plan(format!(
                    "{spec}: the folder has no mesh files ({})",
                    MESH_EXTENSIONS.join(", ")
                )));
            }
            found.sort();
            out.extend(found);
        } else if spec.contains(['*', '?', '[']) {
            let matches = glob::glob(spec)
                .map_err(|e| BatchError::Plan(format!("{spec}: not a valid pattern: {e}")))?;
            let mut found: Vec<String> = matches
                .filter_map(|m| m.ok())
                .filter(|p| p.is_file())
                .map(|p| p.display().to_string())
                .collect();
            if found.is_empty() {
                return Err(BatchError::Plan(format!("{spec}: matches no file")));
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
