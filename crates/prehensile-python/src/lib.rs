//! The `prehensile` Python package: hands, objects, the grasp search, the anytime planner, the
//! simulation and batch datasets, over the same library the CLI uses (same defaults, same
//! messages). Searches and simulations release the GIL.
//!
//! Results cross into Python as numpy arrays (poses, angles, contacts) and, for nested records,
//! through their JSON (the same schema as `prehensile grasp --out`), decoded by Python's `json`.

use std::sync::Arc;
use std::time::Duration;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2};
use prehensile_core::math::{Point3, Vec3};
use prehensile_core::mesh::TriangleMesh;
use prehensile_core::object::MeshCheck;
use prehensile_core::search::{
    default_shoulder, find_grasp, GraspRequest, GraspResult, PlannerStatus, QualityWeights,
    SearchParams, SharedPlanner, ValidityRule, ONE_SIDED_PATIENCE,
};
use prehensile_core::stability::ContactModel;
use prehensile_core::{HandModel, ObjectModel};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::create_exception!(
    prehensile,
    PrehensileError,
    PyException,
    "A bad input or a failed run; the message says what, where and how to fix it."
);

fn error(e: impl std::fmt::Display) -> PyErr {
    PrehensileError::new_err(e.to_string())
}

/// Python value of a serializable record, through its JSON.
fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(error)?;
    py.import("json")?.call_method1("loads", (text,))
}

fn points<'py>(py: Python<'py>, rows: impl Iterator<Item = [f64; 3]>) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.flatten().collect();
    let n = flat.len() / 3;
    Array2::from_shape_vec((n, 3), flat)
        .expect("three numbers per row")
        .into_pyarray(py)
}

fn up_axis(up: &str) -> PyResult<Vec3> {
    match up {
        "x" => Ok(Vec3::x()),
        "y" => Ok(Vec3::y()),
        "z" => Ok(Vec3::z()),
        other => Err(error(format!("up='{other}': use 'x', 'y' or 'z'"))),
    }
}

fn validity_rule(rule: &str) -> PyResult<ValidityRule> {
    rule.parse()
        .map_err(|e: String| error(format!("validity={e}")))
}

fn units_factor(units: &str) -> PyResult<f64> {
    match units {
        "m" => Ok(1.0),
        "cm" => Ok(0.01),
        "mm" => Ok(0.001),
        other => Err(error(format!("units='{other}': use 'm', 'cm' or 'mm'"))),
    }
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
            .map_err(error)?;
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
        let factor = units_factor(units)? * scale;
        let (model, _notes) = py
            .detach(|| prehensile_formats::sources::object_from_spec(spec, factor, weld))
            .map_err(error)?;
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
        let mesh = mesh_from_arrays(vertices, faces, units_factor(units)? * scale)?;
        let model = py
            .detach(|| ObjectModel::new(name, mesh, None))
            .map_err(|e| error(format!("{name}: {e}")))?;
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
        self.model.repairs().to_vec()
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
        return Err(error(format!(
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
                    error(format!(
                        "face {i} names vertex {}, but there are {} vertices (0-based)",
                        r[k],
                        positions.len()
                    ))
                })?;
        }
        triangles.push(t);
    }
    TriangleMesh::weld(&positions, &triangles).map_err(error)
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
        let mut value = serde_json::to_value(&self.result).map_err(error)?;
        if let (Some(h), Some(map)) = (&self.hold, value.as_object_mut()) {
            map.insert("hold".into(), h.clone());
        }
        serde_json::to_string_pretty(&value).map_err(error)
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
    let spec: String = hand
        .extract()
        .map_err(|_| error("hand: give a prehensile.Hand, a built-in name or a file path"))?;
    Ok(Hand::new(py, &spec)?.model)
}

/// An object given as an `Object` or as a name/path.
fn object_of(py: Python<'_>, object: &Bound<'_, PyAny>) -> PyResult<Arc<ObjectModel>> {
    if let Ok(o) = object.cast::<Object>() {
        return Ok(o.get().model.clone());
    }
    let spec: String = object
        .extract()
        .map_err(|_| error("object: give a prehensile.Object, a built-in name or a file path"))?;
    Ok(Object::new(py, &spec, "m", 1.0, None)?.model)
}

/// Everything the search takes, checked as the CLI checks it.
fn search_params(
    seed: u64,
    up: &str,
    weights: Option<Vec<f64>>,
    friction: f64,
    validity: &str,
    one_sided_patience: u32,
) -> PyResult<SearchParams> {
    let weights = match weights.as_deref() {
        None => None,
        Some([g, f, t, w]) => Some(QualityWeights {
            gdist: *g,
            fdist: *f,
            tdist: *t,
            wdist: *w,
            stability: prehensile_core::search::quality::STABILITY_WEIGHT,
        }),
        Some([g, f, t, w, s]) => Some(QualityWeights {
            gdist: *g,
            fdist: *f,
            tdist: *t,
            wdist: *w,
            stability: *s,
        }),
        Some(other) => {
            return Err(error(format!(
                "weights: give 4 or 5 numbers (G, F, T, W[, S]), got {}",
                other.len()
            )))
        }
    };
    if weights
        .iter()
        .flat_map(|w| [w.gdist, w.fdist, w.tdist, w.wdist, w.stability])
        .any(|w| !(w.is_finite() && w >= 0.0))
    {
        return Err(error("weights must be finite and not negative"));
    }
    Ok(SearchParams {
        seed,
        up: up_axis(up)?,
        weights,
        validity: validity_rule(validity)?,
        one_sided_patience,
        contact_model: ContactModel {
            friction,
            ..ContactModel::default()
        },
        ..SearchParams::default()
    })
}

/// The object with its hook moved, or as it is.
fn hooked(object: Arc<ObjectModel>, hook: Option<[f64; 3]>) -> PyResult<Arc<ObjectModel>> {
    match hook {
        None => Ok(object),
        Some(h) => Ok(Arc::new(
            (*object)
                .clone()
                .with_hooks(vec![Point3::from(h)])
                .map_err(error)?,
        )),
    }
}

/// Searches a grasp of `object` by `hand` (each a model, a built-in name or a file), exactly as
/// `prehensile grasp` does; with `hold=True` also runs the hold test (in the simulation's default engine).
/// `one_sided_patience` is `--one-sided-patience`: steps to go on looking past a grasp whose
/// contacts all push from one side. `budget_ms` is `--budget-ms`: the whole search's time, every
/// movement of `auto` within it.
#[pyfunction]
#[pyo3(signature = (hand, object, movement = "auto", *, shoulder = None, hook = None, up = "z",
    seed = 1, weights = None, friction = 0.5, validity = "holds", budget_ms = None, hold = false,
    one_sided_patience = ONE_SIDED_PATIENCE))]
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
) -> PyResult<GraspResultPy> {
    let hand = hand_of(py, hand)?;
    let object = hooked(object_of(py, object)?, hook)?;
    let params = search_params(seed, up, weights, friction, validity, one_sided_patience)?;
    let budget = match budget_ms {
        None => None,
        Some(ms) if ms.is_finite() && ms > 0.0 && ms <= 86_400_000.0 => {
            Some(Duration::from_secs_f64(ms / 1e3))
        }
        Some(ms) => {
            return Err(error(format!(
                "budget_ms={ms}: a positive number of milliseconds, at most a day"
            )))
        }
    };
    let request = GraspRequest {
        movement: movement.to_string(),
        shoulder: shoulder
            .map(Point3::from)
            .unwrap_or_else(|| default_shoulder(&hand, &object.hooks()[0], &params.up)),
        params,
        budget,
    };
    let (result, hold) = py
        .detach(|| -> Result<_, String> {
            let result =
                find_grasp(&hand, &object, &request, &mut ()).map_err(|e| e.to_string())?;
            let hold = if hold {
                let report = prehensile_sim::scenarios::hold_test_of_result(
                    &hand,
                    &object,
                    &result,
                    prehensile_sim::Engine::default(),
                )
                .map_err(|e| e.to_string())?;
                Some(serde_json::to_value(report).map_err(|e| e.to_string())?)
            } else {
                None
            };
            Ok((result, hold))
        })
        .map_err(error)?;
    Ok(GraspResultPy { result, hold })
}

/// Checks a mesh file as `prehensile check --json` does: topology, volume, size, parts, the
/// repairs the search would make and whether it accepts the mesh.
#[pyfunction]
#[pyo3(signature = (path, *, units = "m", scale = 1.0))]
fn check<'py>(py: Python<'py>, path: &str, units: &str, scale: f64) -> PyResult<Bound<'py, PyAny>> {
    let factor = units_factor(units)? * scale;
    let check = py
        .detach(|| {
            prehensile_formats::read_mesh(std::path::Path::new(path), factor)
                .map(|mesh| MeshCheck::new(path, mesh))
        })
        .map_err(error)?;
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
        up = "z", seed = 1, weights = None, friction = 0.5, validity = "holds",
        one_sided_patience = ONE_SIDED_PATIENCE))]
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
    ) -> PyResult<Self> {
        let hand = hand_of(py, hand)?;
        let object = hooked(object_of(py, object)?, hook)?;
        let params = search_params(seed, up, weights, friction, validity, one_sided_patience)?;
        let shoulder = shoulder
            .map(Point3::from)
            .unwrap_or_else(|| default_shoulder(&hand, &object.hooks()[0], &params.up));
        let planner = SharedPlanner::new(hand, object, movement, shoulder, params)
            .map_err(|e| error(format!("{e}; grasp() tries every movement with 'auto'")))?;
        Ok(Self { planner })
    }

    /// One optimization step; returns the status (`searching`, `converged`, `step_limit`).
    fn step(&mut self, py: Python<'_>) -> &'static str {
        status_name(self.planner.with_mut(|p| py.detach(|| p.step())))
    }

    /// Steps for `ms` milliseconds of wall time; returns the status.
    fn run_for(&mut self, py: Python<'_>, ms: f64) -> PyResult<&'static str> {
        if !(ms.is_finite() && (0.0..=86_400_000.0).contains(&ms)) {
            return Err(error(format!(
                "ms={ms}: a number of milliseconds, 0 to a day"
            )));
        }
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
            .map_err(error)
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
/// `shake`) as `prehensile simulate` does (same defaults: the human hand; sphere, box and
/// cylinder; `candidates` grasps per object checked; `engine` `reduced`, the default, or `rapier`); returns its
/// report as a dict.
#[pyfunction]
#[pyo3(signature = (scenario = "grasp", *, hand = None, objects = None, alpha = 0.5, dt = 0.001,
    friction = 1.0, density = 20.0, seconds = None, candidates = 3, engine = "reduced"))]
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
    use prehensile_sim::scenarios::{self, Options, Scenario};
    let engine = prehensile_sim::Engine::from_name(engine).ok_or_else(|| {
        error(format!(
            "unknown engine '{engine}'; choose one of {}",
            prehensile_sim::Engine::NAMES.join(", ")
        ))
    })?;
    if !(1..=20).contains(&candidates) {
        return Err(error(format!(
            "candidates={candidates}: give 1 to 20 grasps per object"
        )));
    }
    use prehensile_sim::Settings;
    let scenario = Scenario::from_name(scenario).ok_or_else(|| {
        error(format!(
            "unknown scenario '{scenario}'; choose one of {}",
            Scenario::NAMES.join(", ")
        ))
    })?;
    let hand = match hand {
        Some(h) => hand_of(py, h)?,
        None => Hand::new(py, "human")?.model,
    };
    let objects: Vec<ObjectModel> = match objects {
        Some(list) => list
            .iter()
            .map(|o| object_of(py, o).map(|m| (*m).clone()))
            .collect::<PyResult<_>>()?,
        None => ["sphere", "box", "cylinder"]
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
            solver_iterations: Settings::iterations_for(dt),
            inner_iterations: Settings::inner_iterations_for(dt),
            engine,
            ..Settings::for_step(dt)
        },
        seconds,
        candidates,
    };
    let report = py
        .detach(|| scenarios::run(scenario, &options, &mut |_, _| {}).map(|(r, _)| r))
        .map_err(error)?;
    to_python(py, &report)
}

/// Runs a batch into a Parquet dataset folder, as `prehensile batch` does (resumable; failures
/// are rows). Returns a summary dict.
#[pyfunction]
#[pyo3(signature = (out, *, hands = vec!["human".to_string()], objects = None,
    movements = vec!["auto".to_string()], shoulders = vec!["default".to_string()], seeds = 1,
    units = "m", scale = 1.0, up = "z", friction = 0.5, validity = "holds", flush_rows = 256,
    one_sided_patience = ONE_SIDED_PATIENCE))]
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
    if seeds == 0 || seeds > 1_000_000 {
        return Err(error(format!(
            "seeds={seeds}: how many seeds, 1 to 1000000"
        )));
    }
    let up = match up {
        "x" | "y" | "z" => up.chars().next().expect("one letter"),
        other => return Err(error(format!("up='{other}': use 'x', 'y' or 'z'"))),
    };
    let objects = objects.unwrap_or_else(|| {
        prehensile_core::shapes::BUILTIN_OBJECTS
            .iter()
            .map(|s| s.to_string())
            .collect()
    });
    let plan = BatchPlan {
        hands,
        objects: expand_objects(&objects).map_err(error)?,
        movements,
        shoulders: shoulders
            .iter()
            .map(|s| Shoulder::parse(s))
            .collect::<Result<_, _>>()
            .map_err(error)?,
        seeds: (1..=seeds).collect(),
        options: BatchOptions {
            scale: units_factor(units)? * scale,
            weld: None,
            up,
            validity: validity_rule(validity)?,
            friction,
            one_sided_patience,
        },
    };
    let summary = py
        .detach(|| run_batch(&plan, &out, flush_rows, &()))
        .map_err(error)?;
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
    prehensile_batch::expand_objects(&objects).map_err(error)
}

/// The built-in hand and object names.
#[pyfunction]
fn builtins<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("hands", prehensile_formats::BUILTIN_HANDS.to_vec())?;
    d.set_item("objects", prehensile_core::shapes::BUILTIN_OBJECTS.to_vec())?;
    Ok(d)
}

#[pymodule]
fn _prehensile(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("PrehensileError", m.py().get_type::<PrehensileError>())?;
    m.add_class::<Hand>()?;
    m.add_class::<Object>()?;
    m.add_class::<GraspResultPy>()?;
    m.add_class::<Planner>()?;
    m.add_function(wrap_pyfunction!(grasp, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(batch, m)?)?;
    m.add_function(wrap_pyfunction!(builtins, m)?)?;
    m.add_function(wrap_pyfunction!(expand_objects, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
