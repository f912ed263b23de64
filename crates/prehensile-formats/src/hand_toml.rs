//! Hands described in TOML (see `docs/HAND_FORMAT.md`).

use std::path::Path;

use prehensile_core::{HandDescription, HandModel};

use crate::FormatError;

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
    prehensile_core::hand::movement_derivation::add_derived_movements(&mut hand);
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
    use crate::builtin::builtin_hand;
    use crate::BUILTIN_HANDS;

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
        let derived = prehensile_core::hand::movement_derivation::derive_power(&human).unwrap();
        assert_ne!(
            human.movement("power").unwrap().end_angles(),
            derived.end_angles()
        );
    }

    #[test]
    fn a_movement_passes_through_its_via_pose() {
        let human = include_str!("../../../assets/hands/human.toml");
        // The power movement's own via pose, its fraction and thumb metacarpal
        // angles replaced.
        let (fraction_line, thumb_line) = (
            "via_fraction = 0.5\n",
            "[movements.via]\nthumb_metacarpal = [50.0, -15.0]",
        );
        assert!(human.contains(fraction_line) && human.contains(thumb_line));
        let with_via = |fraction: &str, thumb: &str| {
            human
                .replacen(fraction_line, &format!("via_fraction = {fraction}\n"), 1)
                .replacen(
                    thumb_line,
                    &format!("[movements.via]\nthumb_metacarpal = {thumb}"),
                    1,
                )
        };
        let hand = parse_hand_toml(&with_via("0.25", "[60.0, -20.0]"), "via.toml").unwrap();
        let power = hand.movement("power").unwrap();
        let via = power.via().expect("the file's via pose");
        assert_eq!(via.fraction(), 0.25);
        // At the via fraction the named bone is at its via angles, the others a quarter of the
        // way from start to end; past it, on the way from via to end.
        let angles_at = |f: f64| {
            let mut q = vec![0.0; hand.dof_count()];
            for (b, bone) in hand.bones().iter().enumerate() {
                let n = bone.joint.dofs();
                bone.joint.angles(
                    &power.rotation_at(b, f),
                    &mut q[bone.first_dof..bone.first_dof + n],
                );
            }
            q
        };
        let dof = |bone: &str| hand.bones()[hand.bone_index(bone).unwrap()].first_dof;
        let (thumb, index) = (dof("thumb_metacarpal"), dof("index_proximal"));
        let at = angles_at(0.25);
        assert!((at[thumb].to_degrees() - 60.0).abs() < 1e-9);
        assert!((at[thumb + 1].to_degrees() + 20.0).abs() < 1e-9);
        assert!(
            (at[index].to_degrees() - 20.0).abs() < 1e-9,
            "{}",
            at[index]
        );
        // (A hinge's angle goes linearly; the thumb's two-axis joint goes by slerp.)
        let later = angles_at(0.625);
        assert!((later[index].to_degrees() - 50.0).abs() < 1e-9);
        assert!((angles_at(1.0)[thumb].to_degrees() - 45.0).abs() < 1e-9);
        for (a, b) in at.iter().zip(via.angles()) {
            assert!((a - b).abs() < 1e-9);
        }
        // Bad fractions and angles are named.
        for bad in ["0.0", "1.0", "nan", "-3"] {
            let e = parse_hand_toml(&with_via(bad, "[60.0, -20.0]"), "via.toml").unwrap_err();
            assert!(e.to_string().contains("via_fraction"), "{e}");
        }
        let e = parse_hand_toml(&with_via("0.5", "[500.0, 0.0]"), "via.toml").unwrap_err();
        assert!(e.to_string().contains("its via pose"), "{e}");
        let e = parse_hand_toml(&with_via("0.5", "[5.0]"), "via.toml").unwrap_err();
        assert!(e.to_string().contains("gives 1 angle(s)"), "{e}");
    }

    #[test]
    fn syntax_errors_give_the_line() {
        let err = parse_hand_toml("name = \"x\"\n[[bones]]\nname = 3\n", "bad.toml").unwrap_err();
        assert_eq!(err.location.as_deref(), Some("line 3"), "{err}");
    }
}
