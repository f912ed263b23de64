//! Resolving `--hand` and `--object` into models (see `prehensile_formats::sources`), with the
//! CLI's option names in the messages and repair notes printed.

use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::sources::{hand_from_spec, object_from_spec};

use crate::CliError;

/// A built-in hand by name, or a hand file.
pub fn hand(spec: &str) -> Result<HandModel, CliError> {
    hand_from_spec(spec).map_err(CliError::from)
}

/// A built-in object by name (scaled), or a mesh file, optionally repaired by welding vertices
/// within `weld` metres; what was repaired is printed.
pub fn object(spec: &str, scale: f64, weld: Option<f64>) -> Result<ObjectModel, CliError> {
    let (object, notes) = object_from_spec(spec, scale, weld)?;
    for note in notes {
        eprintln!("note: {spec}: {note}");
    }
    Ok(object)
}
