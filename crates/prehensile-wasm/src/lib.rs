//! The grasp search in the browser: a [`Session`] holds a hand, an object and the anytime
//! planner of one movement (thesis §5.1, §6.5.6). The viewer's search worker calls `run_for(ms)`
//! in slices of the user's budget, reads the best pose so far as JSON (the CLI's result schema,
//! `prehensile.grasp/3`) for the page to draw, and moves the shoulder when the user drags the
//! object or the shoulder: the planner restarts when the hand would have to turn too far.
//!
//! The same library and the same seed give the same result as the native build (tested against
//! the CLI from Node in CI).
#![deny(missing_docs)]

use std::sync::Arc;
use std::time::Duration;

use prehensile_core::math::Point3;
use prehensile_core::search::{default_movement, GraspOptions, PlannerStatus, SharedPlanner};
use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::SkinnedMesh;
use wasm_bindgen::prelude::*;

fn js(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// The skinned WebXR hands the page offers beside the library's built-in hands (the files are
/// in `assets/hands/webxr_generic_hand`, compiled in: a page has no folder to read them from).
const WEBXR_HANDS: [(&str, &[u8]); 2] = [
    (
        "webxr-right",
        include_bytes!("../../../assets/hands/webxr_generic_hand/right.glb"),
    ),
    (
        "webxr-left",
        include_bytes!("../../../assets/hands/webxr_generic_hand/left.glb"),
    ),
];

/// The built-in hand names, comma-separated: the library's, then the skinned WebXR hands.
#[wasm_bindgen]
pub fn builtin_hands() -> String {
    let webxr = WEBXR_HANDS.iter().map(|(name, _)| *name);
    prehensile_formats::BUILTIN_HANDS
        .into_iter()
        .chain(webxr)
        .collect::<Vec<_>>()
        .join(",")
}

/// The built-in object names, comma-separated.
#[wasm_bindgen]
pub fn builtin_objects() -> String {
    prehensile_core::shapes::BUILTIN_OBJECTS.join(",")
}

/// A hand, an object and a running search.
#[wasm_bindgen]
pub struct Session {
    planner: SharedPlanner,
    movement: String,
    seed: u64,
    /// A skinned hand's mesh (glTF hands), drawn posed by the result's bones.
    skin: Option<SkinnedMesh>,
}

fn object_named(name: &str) -> Result<ObjectModel, JsError> {
    let mesh = prehensile_core::shapes::builtin_object(name).ok_or_else(|| {
        js(format!(
            "'{name}' is not a built-in object ({})",
            builtin_objects()
        ))
    })?;
    ObjectModel::new(name, mesh, None).map_err(js)
}

/// A built-in hand by name, with its skinned mesh if it has one.
fn hand_named(name: &str) -> Result<(HandModel, Option<SkinnedMesh>), JsError> {
    if let Some((_, bytes)) = WEBXR_HANDS.iter().find(|(n, _)| *n == name) {
        let (hand, skin) =
            prehensile_formats::parse_hand_gltf_skinned(bytes, &format!("{name}.glb"), None)
                .map_err(js)?;
        return Ok((hand, Some(skin)));
    }
    let hand = prehensile_formats::builtin_hand(name).ok_or_else(|| {
        js(format!(
            "'{name}' is not a built-in hand ({})",
            builtin_hands()
        ))
    })?;
    Ok((hand, None))
}

#[wasm_bindgen]
impl Session {
    /// A session of a built-in hand on a built-in object, searching `movement` (empty: the
    /// hand's power grasp, else its first movement) with `seed` from the hand's default
    /// shoulder.
    #[wasm_bindgen(constructor)]
    pub fn new(hand: &str, object: &str, movement: &str, seed: u64) -> Result<Session, JsError> {
        let (hand, skin) = hand_named(hand)?;
        Self::start(
            Arc::new(hand),
            skin,
            Arc::new(object_named(object)?),
            movement,
            seed,
        )
    }

    /// A session from what the user chose or dropped: a built-in hand by name, or a hand file's
    /// bytes (`hand_bytes` non-empty; `.toml`, `.urdf`, MJCF `.xml`, skinned `.glb` named by
    /// `hand`); likewise
    /// the object (`.obj`, `.stl`, `.ply`, `.glb`). An MJCF hand's `<include>` files and an
    /// MJCF or URDF hand's collision mesh files, dropped with it, come as `include_names` (one
    /// per line) and their bytes one after another in `include_bytes`, `include_lengths` long
    /// each. Errors carry the CLI's messages.
    #[allow(clippy::too_many_arguments)] // one call from JavaScript, every argument a plain value
    pub fn open(
        hand: &str,
        hand_bytes: &[u8],
        include_names: &str,
        include_bytes: &[u8],
        include_lengths: &[u32],
        object: &str,
        object_bytes: &[u8],
        movement: &str,
        seed: u64,
    ) -> Result<Session, JsError> {
        let (hand, skin) = if hand_bytes.is_empty() {
            hand_named(hand)?
        } else if hand.to_ascii_lowercase().ends_with(".glb") {
            let (hand, skin) =
                prehensile_formats::parse_hand_gltf_skinned(hand_bytes, hand, None).map_err(js)?;
            (hand, Some(skin))
        } else if include_lengths.is_empty() {
            (
                prehensile_formats::parse_hand(hand_bytes, hand).map_err(js)?,
                None,
            )
        } else {
            let names: Vec<&str> = include_names.lines().collect();
            if names.len() != include_lengths.len()
                || include_lengths.iter().map(|&n| n as u64).sum::<u64>()
                    != include_bytes.len() as u64
            {
                return Err(js(
                    "the include files' names, lengths and bytes do not agree",
                ));
            }
            let mut files = vec![(hand.to_string(), hand_bytes.to_vec())];
            let mut at = 0;
            for (name, &len) in names.iter().zip(include_lengths) {
                files.push((
                    name.to_string(),
                    include_bytes[at..at + len as usize].to_vec(),
                ));
                at += len as usize;
            }
            let parsed = if hand.to_ascii_lowercase().ends_with(".urdf") {
                prehensile_formats::parse_hand_urdf_files(hand, &files)
            } else {
                prehensile_formats::parse_hand_mjcf_files(hand, &files)
            };
            (parsed.map_err(js)?, None)
        };
        let object = if object_bytes.is_empty() {
            object_named(object)?
        } else {
            let mesh = prehensile_formats::parse_mesh(object_bytes, object, 1.0).map_err(js)?;
            ObjectModel::new(object, mesh, None).map_err(|e| js(format!("{object}: {e}")))?
        };
        Self::start(Arc::new(hand), skin, Arc::new(object), movement, seed)
    }

    /// The movements of the session's hand, comma-separated.
    pub fn hand_movements(&self) -> String {
        self.planner
            .hand()
            .movements()
            .iter()
            .map(|m| m.name())
            .collect::<Vec<_>>()
            .join(",")
    }

    fn start(
        hand: Arc<HandModel>,
        skin: Option<SkinnedMesh>,
        object: Arc<ObjectModel>,
        movement: &str,
        seed: u64,
    ) -> Result<Session, JsError> {
        let movement = match movement {
            "" => default_movement(&hand).map_err(js)?.name().to_string(),
            m => m.to_string(),
        };
        let movement = movement.as_str();
        // The library's defaults, on the calling thread (the page's worker).
        let options = GraspOptions {
            movement: movement.to_string(),
            seed,
            threads: Some(1),
            ..GraspOptions::default()
        };
        let request = options.request(&hand, &object).map_err(js)?;
        let planner = SharedPlanner::new(hand, object, movement, request.shoulder, request.params)
            .map_err(js)?;
        Ok(Session {
            planner,
            movement: movement.to_string(),
            seed,
            skin,
        })
    }

    /// Searches for `ms` milliseconds (at least one step, which after a restart includes the
    /// initial approximation and may take longer); returns the status: `searching`,
    /// `converged` or `step_limit`.
    pub fn run_for(&mut self, ms: f64) -> String {
        let budget = Duration::from_secs_f64((ms.clamp(0.0, 60_000.0)) / 1e3);
        let status = self.planner.with_mut(|p| {
            if p.status() == PlannerStatus::Searching {
                p.run_for(budget)
            } else {
                p.status()
            }
        });
        match status {
            PlannerStatus::Searching => "searching",
            PlannerStatus::Converged => "converged",
            PlannerStatus::StepLimit => "step_limit",
        }
        .into()
    }

    /// Runs the search to its stop rule (for tests and non-interactive use).
    pub fn run_to_end(&mut self) {
        self.planner.with_mut(|p| p.run_to_end());
    }

    /// How far the search is, as "steps/evaluations": cheap, for deciding whether to ask for
    /// [`Session::result_json`] (which poses the hand and computes its contacts) this frame.
    pub fn progress(&self) -> String {
        self.planner.with(|p| {
            let stats = p.stats();
            format!("{}/{}", stats.steps, stats.evaluations)
        })
    }

    /// The best valid grasp so far, or the current pose marked not valid, as the CLI's JSON.
    pub fn result_json(&self) -> Result<String, JsError> {
        serde_json::to_string(&self.planner.result()).map_err(js)
    }

    /// Moves the shoulder (object frame, metres); returns whether the search restarted.
    pub fn set_shoulder(&mut self, x: f64, y: f64, z: f64) -> Result<bool, JsError> {
        self.planner
            .with_mut(|p| p.set_shoulder(Point3::new(x, y, z)))
            .map_err(js)
    }

    /// The shoulder, object frame: x, y, z.
    pub fn shoulder(&self) -> Vec<f64> {
        self.planner
            .with(|p| p.context().shoulder.coords.as_slice().to_vec())
    }

    /// The object's vertices, flat x, y, z.
    pub fn object_positions(&self) -> Vec<f32> {
        self.planner
            .object()
            .mesh()
            .vertices
            .iter()
            .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32])
            .collect()
    }

    /// The object's triangles, flat.
    pub fn object_indices(&self) -> Vec<u32> {
        self.planner
            .object()
            .mesh()
            .triangles
            .iter()
            .flatten()
            .copied()
            .collect()
    }

    /// A skinned hand's vertices in the hand frame at rest, flat x, y, z (empty: the hand has
    /// no skin and is drawn as capsules). Pose it with [`Session::rest_inverses`] and the
    /// result's bone poses (linear blend skinning, as a glTF skin).
    pub fn skin_positions(&self) -> Vec<f32> {
        self.skin
            .iter()
            .flat_map(|s| &s.positions)
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect()
    }

    /// The skin's triangles, flat.
    pub fn skin_indices(&self) -> Vec<u32> {
        self.skin
            .iter()
            .flat_map(|s| &s.triangles)
            .flatten()
            .copied()
            .collect()
    }

    /// Up to four bone indices per skin vertex (the hand's bone order), flat.
    pub fn skin_joints(&self) -> Vec<u16> {
        self.skin
            .iter()
            .flat_map(|s| &s.joints)
            .flatten()
            .copied()
            .collect()
    }

    /// Their weights, flat.
    pub fn skin_weights(&self) -> Vec<f32> {
        self.skin
            .iter()
            .flat_map(|s| &s.weights)
            .flatten()
            .copied()
            .collect()
    }

    /// Per bone, the inverse of its rest frame in the hand frame, 16 numbers column-major (the
    /// skin's inverse bind matrices).
    pub fn rest_inverses(&self) -> Vec<f32> {
        prehensile_formats::inverse_bind_matrices(self.planner.hand())
    }

    /// The hand's name (a result's `hand`).
    pub fn hand_name(&self) -> String {
        self.planner.hand().name().to_string()
    }

    /// The movement searched.
    pub fn movement(&self) -> String {
        self.movement.clone()
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }
}
