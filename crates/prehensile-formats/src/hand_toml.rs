//! Hands described in TOML (see `docs/HAND_FORMAT.md`), and the built-in hands.

use std::path::Path;

use prehensile_core::{HandDescription, HandModel};

use crate::FormatError;

/// Names of the built-in hands.
pub const BUILTIN_HANDS: [&str; 4] = ["human", "human-left", "robot3", "cartoon4"];

/// The built-in hand with this name, or `None`.
pub fn builtin_hand(name: &str) -> Option<HandModel> {
    let text = match name {
        "human-left" => {
            let right: HandDescription =
                toml::from_str(include_str!("../../../assets/hands/human.toml"))
                    .expect("the built-in human hand parses");
            return Some(
                HandModel::from_description(&right.mirrored("human-left"))
                    .expect("the mirrored human hand is valid (tested)"),
            );
        }
        "human" => include_str!("../../../assets/hands/human.toml"),
        "robot3" => include_str!("../../../assets/hands/robot3.toml"),
        "cartoon4" => include_str!("../../../assets/hands/cartoon4.toml"),
        _ => return None,
    };
    Some(parse_hand_toml(text, name).expect("built-in hands are valid (tested)"))
}

/// Parses and validates a hand description. `source_name` names the text in errors.
pub fn parse_hand_toml(text: &str, source_name: &str) -> Result<HandModel, FormatError> {
    let desc: HandDescription = toml::from_str(text).map_err(|e| match e.span() {
        Some(span) => FormatError::at(
            source_name,
            format!("line {}", line_of(text, span.start)),
            e.message(),
        ),
        None => FormatError::new(source_name, e.message()),
    })?;
    let mut hand =
        HandModel::from_description(&desc).map_err(|e| FormatError::caused_by(source_name, e))?;
    prehensile_core::movement_derivation::add_derived_movements(&mut hand);
    Ok(hand)
}

/// Reads a hand file: `.toml` (our format), `.urdf`, `.xml` / `.mjcf` (MuJoCo) or `.glb` /
/// `.gltf` (a skinned mesh).
pub fn load_hand(path: &Path) -> Result<HandModel, FormatError> {
    let name = path.display().to_string();
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("urdf") => return crate::load_hand_urdf(path),
        Some("xml") | Some("mjcf") => return crate::load_hand_mjcf(path),
        Some("glb") | Some("gltf") => return crate::load_hand_gltf(path),
        Some("toml") => {}
        other => {
            return Err(FormatError::new(
                &name,
                format!(
                    "unknown hand file extension '{}'; use .toml, .urdf, .xml (MJCF) or .glb (skinned glTF)",
                    other.map_or("(none)".to_string(), |e| format!(".{e}"))
                ),
            ))
        }
    }
    let text = crate::read_input_text(path, crate::MAX_TEXT_BYTES)?;
    parse_hand_toml(&text, &name)
}

/// A hand from one file's bytes (`.toml`, `.urdf`, MJCF `.xml` without includes, or a skinned
/// `.glb`), by `name`'s extension: for hands that do not come from a path (a browser's dropped
/// file). Files that need other files (MJCF includes, sidecars) need [`load_hand`] or
/// [`crate::parse_hand_mjcf_files`].
pub fn parse_hand(bytes: &[u8], name: &str) -> Result<HandModel, FormatError> {
    if name.to_ascii_lowercase().ends_with(".glb") {
        return crate::parse_hand_gltf_skinned(bytes, name, None).map(|(hand, _)| hand);
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|e| FormatError::new(name, format!("a hand file must be text: {e}")))?;
    let ext = Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("toml") => parse_hand_toml(text, name),
        Some("urdf") => crate::parse_hand_urdf(text, name),
        Some("xml") | Some("mjcf") => crate::parse_hand_mjcf(text, name),
        other => Err(FormatError::new(
            name,
            format!(
                "unknown hand file extension '{}'; give .toml, .urdf, .xml (MJCF) or .glb (a skinned hand) here",
                other.map_or("(none)".to_string(), |e| format!(".{e}"))
            ),
        )),
    }
}

fn line_of(text: &str, byte: usize) -> usize {
    text[..byte.min(text.len())].matches('\n').count() + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_hands_load() {
        for name in BUILTIN_HANDS {
            let hand = builtin_hand(name).unwrap();
            assert!(hand.fingers().len() >= 2, "{name}");
            assert!(hand.movement("close").is_some(), "{name}");
        }
        assert!(builtin_hand("octopus").is_none());
    }

    #[test]
    fn a_hand_with_a_thumb_gets_the_movements_its_file_does_not_write() {
        let cartoon = builtin_hand("cartoon4").unwrap();
        for name in ["power", "precision"] {
            assert!(cartoon.movement(name).is_some(), "cartoon4 lacks {name}");
        }
        // No thumb, nothing derived.
        assert!(builtin_hand("robot3").unwrap().movement("power").is_none());
        // A movement the file writes is kept as written.
        let human = builtin_hand("human").unwrap();
        let derived = prehensile_core::movement_derivation::derive_power(&human).unwrap();
        assert_ne!(
            human.movement("power").unwrap().end_angles(),
            derived.end_angles()
        );
    }

    #[test]
    fn syntax_errors_give_the_line() {
        let err = parse_hand_toml("name = \"x\"\n[[bones]]\nname = 3\n", "bad.toml").unwrap_err();
        assert_eq!(err.location.as_deref(), Some("line 3"), "{err}");
    }
}
