//! The `prehensile` Python package: hands, objects, the grasp search, the anytime planner, the
//! simulation and batch datasets, over the same library the CLI uses (same defaults, same
//! messages). Searches and simulations release the GIL.
//!
//! Results cross into Python as numpy arrays (poses, angles, contacts) and, for nested records,
//! through their JSON (the same schema as `prehensile grasp --out`), decoded by Python's `json`.
#![deny(missing_docs)]

use std::sync::Arc;
use std::time::Duration;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2};
use prehensile_batch::FLUSH_ROWS;
use prehensile_core::math::Point3;
use prehensile_core::mesh::TriangleMesh;
use prehensile_core::object::MeshCheck;
use prehensile_core::parameter::in_range;
use prehensile_core::search::{
    defaults, find_grasp, GraspOptions, GraspResult, PlannerStatus, SharedPlanner,
};
use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::builtin::DEFAULT_HAND;
use prehensile_formats::Units;
use prehensile_sim::scenarios::{self, defaults as sim_defaults, Options, Scenario};
use prehensile_sim::{Engine, Settings};
use pyo3::prelude::*;
use pyo3::types::PyDict;

mod errors;

use errors::raise;

/// Python value of a serializable record, through its JSON.
fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).expect("records always serialize");
    py.import("json")?.call_method1("loads", (text,))
}

fn points<'py>(py: Python<'py>, rows: impl Iterator<Item = [f64; 3]>) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.flatten().collect();
    let n = flat.len() / 3;
    Array2::from_shape_vec((n, 3), flat)
        .expect("three numbers per row")
        .into_pyarray(py)
}

/// Metres per unit of `units` times `scale` (the library checks both).
fn length_factor(units: &str, scale: f64) -> PyResult<f64> {
    Ok(units.parse::<Units>().map_err(raise)?.metres() * scale)
}

/// A hand: a built-in name (`human`, `human-left`, `robot3`, `cartoon4`) or a hand file
/// (.toml, .urdf, MJCF .xml, skinned .glb/.gltf).
#[pyclass(frozen, module = "prehensile")]
struct Hand {
    model: Arc<HandModel>,
}

#[pymethods]
impl Hand {
    #[new]
    fn new(py: Python<'_>, spec: &str) -> PyResult<Self> {
        let model = py
            .detach(|| prehensile_formats::sources::hand_from_spec(spec))
            .map_err(raise)?;
        Ok(Self {
            model: Arc::new(model),
        })
    }

    /// The hand's name.
    #[getter]
    fn name(&self) -> &str {
        self.model.name()
    }

    /// Where the hand came from and what the import did.
    #[getter]
    fn description(&self) -> &str {
        self.model.description()
    }

    /// Joint degrees of freedom, by the file's names.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.model.dof_names().to_vec()
    }

    /// Joint limits, radians, shape (n, 2).
    #[getter]
    fn joint_limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let flat: Vec<f64> = self.model.dof_limits().into_iter().flatten().collect();
        Array2::from_shape_vec((flat.len() / 2, 2), flat)
            .expect("two limits per joint")
            .into_pyarray(py)
    }

    /// Bone names, parents first.
    #[getter]
    fn bone_names(&self) -> Vec<String> {
        self.model.bones().iter().map(|b| b.name.clone()).collect()
    }

    /// Finger names.
    #[getter]
    fn fingers(&self) -> Vec<String> {
        self.model
            .fingers()
            .iter()
            .map(|f| f.name.clone())
            .collect()
    }

    /// Movement names (plus `auto` for the search).
    #[getter]
    fn movements(&self) -> Vec<String> {
        self.model
            .movements()
            .iter()
            .map(|m| m.name().to_string())
            .collect()
    }

    /// Whether this is a left hand.
    #[getter]
    fn is_left(&self) -> bool {
        self.model.is_left()
    }

    fn __repr__(&self) -> String {
        format!(
            "Hand('{}': {} bones, {} joints, fingers {}, movements {})",
            self.model.name(),
            self.model.bones().len(),
            self.model.dof_count(),
            self.fingers().join(", "),
            self.movements().join(", ")
        )
    }
}

/// An object: a closed mesh set up for the search (distance grid, hooks, mass properties).
#[pyclass(frozen, module = "prehensile")]
struct Object {
    model: Arc<ObjectModel>,
}

#[pymethods]
impl Object {
    /// A built-in object (`sphere`, `box`, `cylinder`, `torus`, `mug`) or a mesh file (.obj,
    /// .stl, .ply, .gltf, .glb) in `units` times `scale`, optionally welded within `weld` metres.
    #[new]
    #[pyo3(signature = (spec, *, units = "m", scale = 1.0, weld = None))]
    fn new(
        py: Python<'_>,
        spec: &str,
        units: &str,
        scale: f64,
        weld: Option<f64>,
    ) -> PyResult<Self> {
        let factor = length_factor(units, scale)?;
        let (model, _notes) = py
            .detach(|| prehensile_formats::sources::object_from_spec(spec, factor, weld))
            .map_err(raise)?;
        Ok(Self {
            model: Arc::new(model),
        })
    }

    /// An object from arrays: `vertices` (n, 3) floats in `units` times `scale`, `faces` (m, 3)
    /// vertex indices, counter-clockwise seen from outside.
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, *, name = "object", units = "m", scale = 1.0))]
    fn from_arrays(
        py: Python<'_>,
        vertices: PyReadonlyArray2<'_, f64>,
        faces: PyReadonlyArray2<'_, i64>,
        name: &str,
        units: &str,
        scale: f64,
    ) -> PyResult<Self> {
        let mesh = mesh_from_arrays(vertices, faces, length_factor(units, scale)?)?;
        let model = py
            .detach(|| ObjectModel::new(name, mesh, None))
            .map_err(raise)?;
        Ok(Self {
            model: Arc::new(model),
        })
    }

    /// The object's name.
    #[getter]
    fn name(&self) -> &str {
        self.model.name()
    }

    /// Vertices, metres, shape (n, 3) (after the repairs in `repairs`).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(
            py,
            self.model.mesh().vertices.iter().map(|p| [p.x, p.y, p.z]),
        )
    }

    /// Triangles as vertex indices, shape (m, 3).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<u32>> {
        let flat: Vec<u32> = self
            .model
            .mesh()
            .triangles
            .iter()
            .flatten()
            .copied()
            .collect();
        Array2::from_shape_vec((flat.len() / 3, 3), flat)
            .expect("three indices per triangle")
            .into_pyarray(py)
    }

    /// Hooks (where the search centres grasps), metres, shape (k, 3).
    #[getter]
    fn hooks<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, self.model.hooks().iter().map(|p| [p.x, p.y, p.z]))
    }

    /// Volume, cubic metres.
    #[getter]
    fn volume(&self) -> f64 {
        self.model.volume()
    }

    /// Centre of mass, metres.
    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let c = self.model.center_of_mass();
        PyArray1::from_slice(py, &[c.x, c.y, c.z])
    }

    /// Repairs made when setting the object up.
    #[getter]
    fn repairs(&self) -> Vec<String> {
        self.model.repairs().iter().map(|r| r.to_string()).collect()
    }

    fn __repr__(&self) -> String {
        let (lo, hi) = self.model.mesh().bounds();
        let size = hi - lo;
        format!(
            "Object('{}': {} triangles, {:.3} x {:.3} x {:.3} m)",
            self.model.name(),
            self.model.mesh().triangles.len(),
            size.x,
            size.y,
            size.z
        )
    }
}

fn mesh_from_arrays(
    vertices: PyReadonlyArray2<'_, f64>,
    faces: PyReadonlyArray2<'_, i64>,
    factor: f64,
) -> PyResult<TriangleMesh> {
    let v = vertices.as_array();
    let f = faces.as_array();
    if v.ncols() != 3 || f.ncols() != 3 {
        return Err(errors::MeshError::new_err(format!(
            "vertices must be (n, 3) and faces (m, 3); got {:?} and {:?}",
            v.shape(),
            f.shape()
        )));
    }
    let positions: Vec<Point3> = v
        .rows()
        .into_iter()
        .map(|r| Point3::new(r[0], r[1], r[2]) * factor)
        .collect();
    let mut triangles = Vec::with_capacity(f.nrows());
    for (i, r) in f.rows().into_iter().enumerate() {
        let mut t = [0usize; 3];
        for k in 0..3 {
            t[k] = usize::try_from(r[k])
                .ok()
                .filter(|&x| x < positions.len())
                .ok_or_else(|| {
                    errors::MeshError::new_err(format!(
                        "face {i} names vertex {}, but there are {} vertices (0-based)",
                        r[k],
                        positions.len()
                    ))
                })?;
        }
        triangles.push(t);
    }
    TriangleMesh::weld(&positions, &triangles).map_err(raise)
}

/// A grasp found by the search (or the best attempt, with why it is not valid).
#[pyclass(frozen, module = "prehensile")]
struct GraspResultPy {
    result: GraspResult,
    hold: Option<serde_json::Value>,
}

#[pymethods]
impl GraspResultPy {
    /// Whether this is a valid grasp under the search's validity rule.
    #[getter]
    fn valid(&self) -> bool {
        self.result.valid
    }

    /// Why not, when not.
    #[getter]
    fn invalid_reason(&self) -> Option<String> {
        self.result.invalid_reason.clone()
    }

    /// The movement of this result.
    #[getter]
    fn movement(&self) -> &str {
        &self.result.movement
    }

    /// The search's quality (None when minus infinity).
    #[getter]
    fn quality(&self) -> Option<f64> {
        self.result.quality
    }

    /// Fingers touching the object.
    #[getter]
    fn fingers_touching(&self) -> Vec<String> {
        self.result.fingers_touching.clone()
    }

    /// Joint degrees of freedom, by the hand file's names.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.result.joints.iter().map(|j| j.name.clone()).collect()
    }

    /// Joint angles, radians, in `joint_names` order.
    #[getter]
    fn joint_angles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let a: Vec<f64> = self.result.joints.iter().map(|j| j.angle).collect();
        a.into_pyarray(py)
    }

    /// Bone positions in the object's frame, metres, shape (bones, 3).
    #[getter]
    fn bone_positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, self.result.bones.iter().map(|b| b.pose.position))
    }

    /// Bone rotations as unit quaternions x, y, z, w, shape (bones, 4).
    #[getter]
    fn bone_rotations_xyzw<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let flat: Vec<f64> = self
            .result
            .bones
            .iter()
            .flat_map(|b| b.pose.rotation_xyzw)
            .collect();
        Array2::from_shape_vec((flat.len() / 4, 4), flat)
            .expect("four numbers per quaternion")
            .into_pyarray(py)
    }

    /// The hand's capsules: first ends, metres, shape (capsules, 3).
    #[getter]
    fn capsule_starts<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, self.result.capsules.iter().map(|c| c.a))
    }

    /// The hand's capsules: second ends, metres, shape (capsules, 3).
    #[getter]
    fn capsule_ends<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, self.result.capsules.iter().map(|c| c.b))
    }

    /// The hand's capsules: radii, metres.
    #[getter]
    fn capsule_radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let r: Vec<f64> = self.result.capsules.iter().map(|c| c.radius).collect();
        r.into_pyarray(py)
    }

    /// Contact points on the object's surface, metres, shape (contacts, 3).
    #[getter]
    fn contact_points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, self.result.contacts.iter().map(|c| c.point))
    }

    /// Contact normals into the object, shape (contacts, 3).
    #[getter]
    fn contact_normals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points(py, self.result.contacts.iter().map(|c| c.normal))
    }

    /// Half-angle, degrees, of the narrowest cone holding every contact normal: 90 when the
    /// contacts push from every side, less when they all push the object one way.
    #[getter]
    fn normal_cone_degrees(&self) -> f64 {
        self.result.normal_cone_degrees
    }

    /// Force closure, Ferrari–Canny epsilon and load ratios, as a dict.
    #[getter]
    fn stability<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.result.stability)
    }

    /// Every quality term, as a dict.
    #[getter]
    fn terms<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.result.terms)
    }

    /// Search statistics, as a dict.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.result.stats)
    }

    /// The hold test's report (`grasp(..., hold=True)`), else None.
    #[getter]
    fn hold<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.hold.as_ref().map(|h| to_python(py, h)).transpose()
    }

    /// The whole result as JSON (`prehensile.grasp/3`, docs/RESULT_SCHEMA.md).
    fn to_json(&self) -> PyResult<String> {
        let mut value = serde_json::to_value(&self.result).expect("results always serialize");
        if let (Some(h), Some(map)) = (&self.hold, value.as_object_mut()) {
            map.insert("hold".into(), h.clone());
        }
        Ok(serde_json::to_string_pretty(&value).expect("results always serialize"))
    }

    /// The whole result as a dict (the JSON's structure).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (self.to_json()?,))
    }

    fn __repr__(&self) -> String {
        format!(
            "GraspResult({} on {}, {}, {}, fingers touching: {})",
            self.result.hand,
            self.result.object,
            self.result.movement,
            if self.result.valid {
                "valid".to_string()
            } else {
                format!(
                    "not valid: {}",
                    self.result.invalid_reason.as_deref().unwrap_or("?")
                )
            },
            self.result.fingers_touching.join(", ")
        )
    }
}

/// A hand given as a `Hand` or as a name/path.
fn hand_of(py: Python<'_>, hand: &Bound<'_, PyAny>) -> PyResult<Arc<HandModel>> {
    if let Ok(h) = hand.cast::<Hand>() {
        return Ok(h.get().model.clone());
    }
    let spec: String = hand.extract().map_err(|_| {
        errors::ParameterError::new_err(
            "hand: give a prehensile.Hand, a built-in name or a file path",
        )
    })?;
    Ok(Hand::new(py, &spec)?.model)
}

/// An object given as an `Object` or as a name/path.
fn object_of(py: Python<'_>, object: &Bound<'_, PyAny>) -> PyResult<Arc<ObjectModel>> {
    if let Ok(o) = object.cast::<Object>() {
        return Ok(o.get().model.clone());
    }
    let spec: String = object.extract().map_err(|_| {
        errors::ParameterError::new_err(
            "object: give a prehensile.Object, a built-in name or a file path",
        )
    })?;
    Ok(Object::new(py, &spec, "m", 1.0, None)?.model)
}

/// The object hung from the options' hook, or as it is.
fn hooked(object: Arc<ObjectModel>, options: &GraspOptions) -> PyResult<Arc<ObjectModel>> {
    match options.hook_point().map_err(raise)? {
        None => Ok(object),
        Some(h) => Ok(Arc::new(
            (*object).clone().with_hooks(vec![h]).map_err(raise)?,
        )),
    }
}

/// Searches a grasp of `object` by `hand` (each a model, a built-in name or a file), exactly as
/// `prehensile grasp` does (the same defaults: `prehensile.defaults()["grasp"]`); with
/// `hold=True` also runs the hold test (in the simulation's default engine).
/// `one_sided_patience` is `--one-sided-patience`: steps to go on looking past a grasp whose
/// contacts all push from one side. `budget_ms` is `--budget-ms`: the whole search's time, every
/// movement of `auto` within it.
#[pyfunction]
#[pyo3(signature = (hand, object, movement = defaults::MOVEMENT, *, shoulder = None, hook = None,
    up = defaults::UP.name(), seed = defaults::SEED, weights = None, friction = defaults::FRICTION,
    validity = defaults::VALIDITY.name(), budget_ms = None, hold = false,
    one_sided_patience = defaults::ONE_SIDED_PATIENCE, threads = None))]
#[allow(clippy::too_many_arguments)]
fn grasp(
    py: Python<'_>,
    hand: &Bound<'_, PyAny>,
    object: &Bound<'_, PyAny>,
    movement: &str,
    shoulder: Option<[f64; 3]>,
    hook: Option<[f64; 3]>,
    up: &str,
    seed: u64,
    weights: Option<Vec<f64>>,
    friction: f64,
    validity: &str,
    budget_ms: Option<f64>,
    hold: bool,
    one_sided_patience: u32,
    threads: Option<usize>,
) -> PyResult<GraspResultPy> {
    let options = GraspOptions {
        movement: movement.to_string(),
        hook,
        shoulder,
        up: up.parse().map_err(raise)?,
        seed,
        threads,
        weights,
        friction,
        validity: validity.parse().map_err(raise)?,
        one_sided_patience,
        budget_ms,
    };
    let hand = hand_of(py, hand)?;
    let object = hooked(object_of(py, object)?, &options)?;
    let request = options.request(&hand, &object).map_err(raise)?;
    let result = py
        .detach(|| find_grasp(&hand, &object, &request, &mut ()))
        .map_err(raise)?;
    let hold = if hold {
        let report = py
            .detach(|| {
                prehensile_sim::scenarios::hold_test_of_result(
                    &hand,
                    &object,
                    &result,
                    prehensile_sim::Engine::default(),
                )
            })
            .map_err(raise)?;
        Some(serde_json::to_value(report).expect("reports always serialize"))
    } else {
        None
    };
    Ok(GraspResultPy { result, hold })
}

/// Checks a mesh file as `prehensile check --json` does: topology, volume, size, parts, the
/// repairs the search would make and whether it accepts the mesh.
#[pyfunction]
#[pyo3(signature = (path, *, units = "m", scale = 1.0))]
fn check<'py>(py: Python<'py>, path: &str, units: &str, scale: f64) -> PyResult<Bound<'py, PyAny>> {
    let factor = length_factor(units, scale)?;
    let check = py
        .detach(|| {
            prehensile_formats::read_mesh(std::path::Path::new(path), factor)
                .map(|mesh| MeshCheck::new(path, mesh))
        })
        .map_err(raise)?;
    to_python(py, &check)
}

/// The anytime planner of one movement (thesis §5.1, §6.5.6): call `step()` or
/// `run_for(ms)` from your loop and read `best()` whenever you like; `set_shoulder` moves the
/// character (the search restarts when the hand would have to turn too far).
#[pyclass(unsendable, module = "prehensile")]
struct Planner {
    planner: SharedPlanner,
}

fn status_name(s: PlannerStatus) -> &'static str {
    match s {
        PlannerStatus::Searching => "searching",
        PlannerStatus::Converged => "converged",
        PlannerStatus::StepLimit => "step_limit",
    }
}

#[pymethods]
impl Planner {
    #[new]
    #[pyo3(signature = (hand, object, movement = "power", *, shoulder = None, hook = None,
        up = defaults::UP.name(), seed = defaults::SEED, weights = None,
        friction = defaults::FRICTION, validity = defaults::VALIDITY.name(),
        one_sided_patience = defaults::ONE_SIDED_PATIENCE, threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        hand: &Bound<'_, PyAny>,
        object: &Bound<'_, PyAny>,
        movement: &str,
        shoulder: Option<[f64; 3]>,
        hook: Option<[f64; 3]>,
        up: &str,
        seed: u64,
        weights: Option<Vec<f64>>,
        friction: f64,
        validity: &str,
        one_sided_patience: u32,
        threads: Option<usize>,
    ) -> PyResult<Self> {
        let options = GraspOptions {
            movement: movement.to_string(),
            hook,
            shoulder,
            up: up.parse().map_err(raise)?,
            seed,
            threads: Some(threads.unwrap_or(1)),
            weights,
            friction,
            validity: validity.parse().map_err(raise)?,
            one_sided_patience,
            budget_ms: None,
        };
        let hand = hand_of(py, hand)?;
        let object = hooked(object_of(py, object)?, &options)?;
        let request = options.request(&hand, &object).map_err(raise)?;
        let planner = SharedPlanner::new(hand, object, movement, request.shoulder, request.params)
            .map_err(raise)?;
        Ok(Self { planner })
    }

    /// One optimization step; returns the status (`searching`, `converged`, `step_limit`).
    fn step(&mut self, py: Python<'_>) -> &'static str {
        status_name(self.planner.with_mut(|p| py.detach(|| p.step())))
    }

    /// Steps for `ms` milliseconds of wall time; returns the status.
    fn run_for(&mut self, py: Python<'_>, ms: f64) -> PyResult<&'static str> {
        let ms = in_range("ms", ms, 0.0, defaults::MAX_BUDGET_MS, "milliseconds").map_err(raise)?;
        let budget = Duration::from_secs_f64(ms / 1e3);
        Ok(status_name(
            self.planner.with_mut(|p| py.detach(|| p.run_for(budget))),
        ))
    }

    /// Steps until the stop rule holds; returns the status.
    fn run_to_end(&mut self, py: Python<'_>) -> &'static str {
        status_name(self.planner.with_mut(|p| py.detach(|| p.run_to_end())))
    }

    /// Moves the shoulder; returns whether the search restarted.
    fn set_shoulder(&mut self, shoulder: [f64; 3]) -> PyResult<bool> {
        self.planner
            .with_mut(|p| p.set_shoulder(Point3::from(shoulder)))
            .map_err(raise)
    }

    /// The planner's status.
    #[getter]
    fn status(&self) -> &'static str {
        status_name(self.planner.with(|p| p.status()))
    }

    /// The best valid grasp so far, else None.
    fn best(&self) -> Option<GraspResultPy> {
        self.planner
            .with(|p| p.best().is_some())
            .then(|| GraspResultPy {
                result: self.planner.result(),
                hold: None,
            })
    }

    /// The best valid grasp so far, or the current pose marked not valid.
    fn result(&self) -> GraspResultPy {
        GraspResultPy {
            result: self.planner.result(),
            hold: None,
        }
    }

    /// Search statistics, as a dict.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let stats = self.planner.with(|p| p.stats());
        to_python(py, &stats)
    }
}

/// Runs one of the paper's scenarios (`drop`, `grasp`, `grip-sweep`, `handshake`, `open-close`,
/// `shake`) as `prehensile simulate` does (the same defaults: `prehensile.defaults()["simulate"]`;
/// `engine` `reduced`, the default, or `rapier`); returns its report as a dict.
#[pyfunction]
#[pyo3(signature = (scenario = sim_defaults::SCENARIO.name(), *, hand = None, objects = None,
    alpha = sim_defaults::ALPHA, dt = Settings::default().dt,
    friction = Settings::default().friction, density = Settings::default().object_density,
    seconds = None, candidates = sim_defaults::CANDIDATES, engine = Engine::default().name()))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    scenario: &str,
    hand: Option<&Bound<'py, PyAny>>,
    objects: Option<Vec<Bound<'py, PyAny>>>,
    alpha: f64,
    dt: f64,
    friction: f64,
    density: f64,
    seconds: Option<f64>,
    candidates: usize,
    engine: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let scenario: Scenario = scenario.parse().map_err(raise)?;
    let hand = match hand {
        Some(h) => hand_of(py, h)?,
        None => Hand::new(py, sim_defaults::HAND)?.model,
    };
    let objects: Vec<ObjectModel> = match objects {
        Some(list) => list
            .iter()
            .map(|o| object_of(py, o).map(|m| (*m).clone()))
            .collect::<PyResult<_>>()?,
        None => sim_defaults::OBJECTS
            .iter()
            .map(|name| Object::new(py, name, "m", 1.0, None).map(|o| (*o.model).clone()))
            .collect::<PyResult<_>>()?,
    };
    let options = Options {
        hand: (*hand).clone(),
        objects,
        alpha,
        settings: Settings {
            friction,
            object_density: density,
            engine: engine.parse().map_err(raise)?,
            ..Settings::for_step(dt)
        },
        seconds,
        candidates,
    };
    let report = py
        .detach(|| scenarios::run(scenario, &options, &mut |_, _| {}).map(|(r, _)| r))
        .map_err(raise)?;
    to_python(py, &report)
}

/// Runs a batch into a Parquet dataset folder, as `prehensile batch` does (resumable; failures
/// are rows; the same defaults: `prehensile.defaults()["batch"]`). Returns a summary dict.
#[pyfunction]
#[pyo3(signature = (out, *, hands = vec![DEFAULT_HAND.to_string()], objects = None,
    movements = vec![defaults::MOVEMENT.to_string()], shoulders = vec!["default".to_string()],
    seeds = 1, units = "m", scale = 1.0, up = defaults::UP.name(), friction = defaults::FRICTION,
    validity = defaults::VALIDITY.name(), flush_rows = FLUSH_ROWS,
    one_sided_patience = defaults::ONE_SIDED_PATIENCE))]
#[allow(clippy::too_many_arguments)]
fn batch<'py>(
    py: Python<'py>,
    out: std::path::PathBuf,
    hands: Vec<String>,
    objects: Option<Vec<String>>,
    movements: Vec<String>,
    shoulders: Vec<String>,
    seeds: u64,
    units: &str,
    scale: f64,
    up: &str,
    friction: f64,
    validity: &str,
    flush_rows: usize,
    one_sided_patience: u32,
) -> PyResult<Bound<'py, PyDict>> {
    use prehensile_batch::{expand_objects, run_batch, BatchOptions, BatchPlan, Shoulder};
    let objects = objects.unwrap_or_else(|| {
        prehensile_formats::BUILTIN_OBJECTS
            .map(String::from)
            .to_vec()
    });
    let plan = BatchPlan {
        hands,
        objects: expand_objects(&objects).map_err(raise)?,
        movements,
        shoulders: shoulders
            .iter()
            .map(|s| Shoulder::parse(s))
            .collect::<Result<_, _>>()
            .map_err(raise)?,
        seeds: (1..=seeds.min(prehensile_batch::MAX_SEEDS + 1)).collect(),
        options: BatchOptions {
            scale: length_factor(units, scale)?,
            weld: None,
            up: up.parse().map_err(raise)?,
            validity: validity.parse().map_err(raise)?,
            friction,
            one_sided_patience,
        },
    };
    let summary = py
        .detach(|| run_batch(&plan, &out, flush_rows, &()))
        .map_err(raise)?;
    let d = PyDict::new(py);
    d.set_item("total", summary.total)?;
    d.set_item("already_done", summary.already_done)?;
    d.set_item("ran", summary.ran)?;
    d.set_item("valid", summary.valid)?;
    d.set_item("invalid", summary.invalid)?;
    d.set_item("errors", summary.errors)?;
    d.set_item("parts_written", summary.parts_written)?;
    Ok(d)
}

/// Object arguments as the batch expands them: a folder becomes its mesh files, a pattern its
/// matches (both sorted), anything else stays as given.
#[pyfunction]
fn expand_objects(objects: Vec<String>) -> PyResult<Vec<String>> {
    prehensile_batch::expand_objects(&objects).map_err(raise)
}

/// The built-in hand and object names.
#[pyfunction]
fn builtins<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("hands", prehensile_formats::BUILTIN_HANDS.to_vec())?;
    d.set_item("objects", prehensile_formats::BUILTIN_OBJECTS.to_vec())?;
    Ok(d)
}

/// The library's defaults of every function's arguments, by function: what the signatures and
/// the type stubs must say (tested).
#[pyfunction]
#[pyo3(name = "defaults")]
fn library_defaults<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
    let grasp = GraspOptions::default();
    let settings = Settings::default();
    let batch = prehensile_batch::BatchOptions::default();
    let value = serde_json::json!({
        "grasp": {
            "movement": grasp.movement,
            "up": grasp.up,
            "seed": grasp.seed,
            "friction": grasp.friction,
            "validity": grasp.validity.name(),
            "one_sided_patience": grasp.one_sided_patience,
        },
        "simulate": {
            "scenario": sim_defaults::SCENARIO.name(),
            "objects": sim_defaults::OBJECTS,
            "alpha": sim_defaults::ALPHA,
            "dt": settings.dt,
            "friction": settings.friction,
            "density": settings.object_density,
            "candidates": sim_defaults::CANDIDATES,
            "engine": Engine::default().name(),
        },
        "batch": {
            "hands": [DEFAULT_HAND],
            "movements": [defaults::MOVEMENT],
            "up": batch.up,
            "friction": batch.friction,
            "validity": batch.validity.name(),
            "flush_rows": FLUSH_ROWS,
            "one_sided_patience": batch.one_sided_patience,
        },
    });
    to_python(py, &value)
}

#[pymodule]
fn _prehensile(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<Hand>()?;
    m.add_class::<Object>()?;
    m.add_class::<GraspResultPy>()?;
    m.add_class::<Planner>()?;
    m.add_function(wrap_pyfunction!(grasp, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(batch, m)?)?;
    m.add_function(wrap_pyfunction!(builtins, m)?)?;
    m.add_function(wrap_pyfunction!(library_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(expand_objects, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
