//! Resolving `--hand` and `--object` into models: built-in names or files.

use std::path::Path;

use prehensile_core::shapes::{builtin_object, BUILTIN_OBJECTS};
use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::{builtin_hand, load_hand, load_object_repaired, BUILTIN_HANDS};

use crate::CliError;

/// A built-in hand by name, or a hand file.
pub fn hand(spec: &str) -> Result<HandModel, CliError> {
    if let Some(h) = builtin_hand(spec) {
        return Ok(h);
    }
    let path = Path::new(spec);
    if path.exists() {
        return load_hand(path).map_err(CliError::from_display);
    }
    Err(CliError(format!(
        "'{spec}' is neither a built-in hand ({}) nor an existing hand file",
        BUILTIN_HANDS.join(", ")
    )))
}

/// A built-in object by name (scaled), or a mesh file, optionally repaired by welding vertices
/// within `weld` metres; what was repaired is printed.
pub fn object(spec: &str, scale: f64, weld: Option<f64>) -> Result<ObjectModel, CliError> {
    if let Some(w) = weld {
        if !(w.is_finite() && w > 0.0) {
            return Err(CliError(format!(
                "--weld {w} must be a positive number of metres"
            )));
        }
    }
    if !(scale.is_finite() && scale > 0.0) {
        return Err(CliError(format!(
            "--scale {scale} must be a positive number"
        )));
    }
    if let Some(mesh) = builtin_object(spec) {
        return ObjectModel::new(spec, mesh.scaled(scale), None).map_err(CliError::from_display);
    }
    let path = Path::new(spec);
    if path.exists() {
        let (object, notes) =
            load_object_repaired(path, scale, weld).map_err(CliError::from_display)?;
        for note in notes {
            eprintln!("note: {}: {note}", path.display());
        }
        return Ok(object);
    }
    Err(CliError(format!(
        "'{spec}' is neither a built-in object ({}) nor an existing mesh file",
        BUILTIN_OBJECTS.join(", ")
    )))
}
