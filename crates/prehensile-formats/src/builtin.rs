//! The built-in hands and objects, by name: what `--hand NAME` and `--object NAME` take, and
//! the defaults of every front end. The hands are the TOML files under `assets/hands/` (the
//! left human hand is the right one mirrored); the objects are
//! [`prehensile_core::shapes`] at their default sizes.

use prehensile_core::{HandDescription, HandModel};

use crate::hand_toml::parse_hand_toml;

pub use prehensile_core::shapes::{builtin_object, BUILTIN_OBJECTS};

/// The hand every front end uses when none is named.
pub const DEFAULT_HAND: &str = "human";
/// The object `prehensile grasp` uses when none is named.
pub const DEFAULT_OBJECT: &str = "sphere";

/// Names of the built-in hands, in the order `prehensile demo` uses them.
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
