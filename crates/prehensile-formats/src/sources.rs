//! Hands and objects named the way users name them: a built-in name, or a file.

use std::path::Path;

use prehensile_core::{HandModel, ObjectModel};

use crate::builtin::{builtin_hand, builtin_object, BUILTIN_HANDS, BUILTIN_OBJECTS};
use crate::{load_hand, load_object_repaired, FormatError, LoadNote};

/// A built-in hand by name, or a hand file.
pub fn hand_from_spec(spec: &str) -> Result<HandModel, FormatError> {
    if let Some(h) = builtin_hand(spec) {
        return Ok(h);
    }
    let path = Path::new(spec);
    if path.exists() {
        return load_hand(path);
    }
    Err(FormatError::new(
        spec,
        format!(
            "neither a built-in hand ({}) nor an existing hand file{}",
            BUILTIN_HANDS.join(", "),
            did_you_mean(spec, &BUILTIN_HANDS)
        ),
    ))
}

/// "; did you mean 'x'?" for the built-in name closest to `spec` when it is a likely typo.
fn did_you_mean(spec: &str, names: &[&str]) -> String {
    names
        .iter()
        .map(|n| (edit_distance(&spec.to_lowercase(), n), n))
        .min()
        .filter(|(d, n)| *d <= 2.max(n.len() / 3))
        .map_or(String::new(), |(_, n)| format!("; did you mean '{n}'?"))
}

/// Levenshtein distance (written here: a dozen lines against a dependency for one message).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (row[j + 1] + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != cb));
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// A built-in object by name (scaled), or a mesh file, optionally repaired by welding vertices
/// within `weld` metres; with notes on what was repaired.
pub fn object_from_spec(
    spec: &str,
    scale: f64,
    weld: Option<f64>,
) -> Result<(ObjectModel, Vec<LoadNote>), FormatError> {
    if let Some(w) = weld {
        if !(w.is_finite() && w > 0.0) {
            return Err(FormatError::new(
                spec,
                format!("weld tolerance {w} must be a positive number of metres"),
            ));
        }
    }
    if !(scale.is_finite() && scale > 0.0) {
        return Err(FormatError::new(
            spec,
            format!("scale {scale} must be a positive number"),
        ));
    }
    if let Some(mesh) = builtin_object(spec) {
        return ObjectModel::new(spec, mesh.scaled(scale), None)
            .map(|o| (o, Vec::new()))
            .map_err(|e| FormatError::caused_by(spec, e));
    }
    let path = Path::new(spec);
    if path.exists() {
        return load_object_repaired(path, scale, weld);
    }
    Err(FormatError::new(
        spec,
        format!(
            "neither a built-in object ({}) nor an existing mesh file{}",
            BUILTIN_OBJECTS.join(", "),
            did_you_mean(spec, &BUILTIN_OBJECTS)
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typos_get_a_suggestion_and_strangers_do_not() {
        assert_eq!(
            did_you_mean("humna", &BUILTIN_HANDS),
            "; did you mean 'human'?"
        );
        assert_eq!(
            did_you_mean("Sphere", &BUILTIN_OBJECTS),
            "; did you mean 'sphere'?"
        );
        assert_eq!(
            did_you_mean("cylnder", &BUILTIN_OBJECTS),
            "; did you mean 'cylinder'?"
        );
        assert_eq!(did_you_mean("teapot.obj", &BUILTIN_OBJECTS), "");
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
