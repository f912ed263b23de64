//! One Python exception per kind of error, each a subclass of `PrehensileError`, carrying the
//! library's own message: a program can catch `prehensile.ParameterError` for a bad argument
//! apart from `prehensile.FileFormatError` for a file it cannot read.

use prehensile_batch::{BatchError as Batch, PlanError};
use prehensile_core::parameter::ParameterError as Parameter;
use prehensile_core::search::SearchError as Search;
use prehensile_core::{MeshError as Mesh, ObjectError as Object};
use prehensile_formats::{FormatCause, FormatError};
use prehensile_sim::SimError;
use pyo3::exceptions::PyException;
use pyo3::PyErr;

pyo3::create_exception!(
    prehensile,
    PrehensileError,
    PyException,
    "Every error Prehensile raises; the message says what, where and how to fix it."
);
pyo3::create_exception!(
    prehensile,
    ParameterError,
    PrehensileError,
    "An argument's value or name is not one the library takes (a range, a unit, a movement)."
);
pyo3::create_exception!(
    prehensile,
    FileFormatError,
    PrehensileError,
    "A file could not be read or understood (its name and the place in it are in the message)."
);
pyo3::create_exception!(
    prehensile,
    HandError,
    PrehensileError,
    "A hand is not a valid hand (bones, joints, couplings, movements)."
);
pyo3::create_exception!(
    prehensile,
    MeshError,
    PrehensileError,
    "A mesh cannot become a graspable object (no triangles, no inside, an absurd size)."
);
pyo3::create_exception!(
    prehensile,
    SearchError,
    PrehensileError,
    "A grasp search cannot start (no hook, a shoulder on the hook, an object too big)."
);
pyo3::create_exception!(
    prehensile,
    SimulationError,
    PrehensileError,
    "A simulation cannot run, or stopped (it diverged, a bone has no mass, no grasp found)."
);
pyo3::create_exception!(
    prehensile,
    BatchError,
    PrehensileError,
    "A batch cannot run (its plan, or its dataset folder)."
);

/// An error of the library as the Python exception of its kind.
pub trait Raise {
    /// The exception.
    fn raise(self) -> PyErr;
}

/// [`Raise::raise`] as a function, for `map_err`.
pub fn raise(e: impl Raise) -> PyErr {
    e.raise()
}

impl Raise for Parameter {
    fn raise(self) -> PyErr {
        ParameterError::new_err(self.to_string())
    }
}

impl Raise for Mesh {
    fn raise(self) -> PyErr {
        MeshError::new_err(self.to_string())
    }
}

impl Raise for Object {
    fn raise(self) -> PyErr {
        MeshError::new_err(self.to_string())
    }
}

impl Raise for FormatError {
    fn raise(self) -> PyErr {
        let message = self.to_string();
        match self.cause.as_deref() {
            Some(FormatCause::Hand(_)) => HandError::new_err(message),
            Some(FormatCause::Mesh(_) | FormatCause::Object(_)) => MeshError::new_err(message),
            _ => FileFormatError::new_err(message),
        }
    }
}

impl Raise for Search {
    fn raise(self) -> PyErr {
        match self {
            Search::BadParameter(p) => p.raise(),
            Search::UnknownMovement { .. } => ParameterError::new_err(self.to_string()),
            other => SearchError::new_err(other.to_string()),
        }
    }
}

impl Raise for SimError {
    fn raise(self) -> PyErr {
        match self {
            SimError::OutOfRange { .. } | SimError::UnknownName { .. } => {
                ParameterError::new_err(self.to_string())
            }
            SimError::Search(e) => e.raise(),
            other => SimulationError::new_err(other.to_string()),
        }
    }
}

impl Raise for PlanError {
    fn raise(self) -> PyErr {
        match self {
            PlanError::Parameter(p) => p.raise(),
            other => BatchError::new_err(other.to_string()),
        }
    }
}

impl Raise for Batch {
    fn raise(self) -> PyErr {
        match self {
            Batch::Plan(p) => p.raise(),
            other => BatchError::new_err(other.to_string()),
        }
    }
}

/// Registers the exceptions in the module.
pub fn register(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
    use pyo3::prelude::*;
    let py = m.py();
    m.add("PrehensileError", py.get_type::<PrehensileError>())?;
    m.add("ParameterError", py.get_type::<ParameterError>())?;
    m.add("FileFormatError", py.get_type::<FileFormatError>())?;
    m.add("HandError", py.get_type::<HandError>())?;
    m.add("MeshError", py.get_type::<MeshError>())?;
    m.add("SearchError", py.get_type::<SearchError>())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    m.add("BatchError", py.get_type::<BatchError>())?;
    Ok(())
}
