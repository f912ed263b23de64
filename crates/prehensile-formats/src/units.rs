//! The length unit of a mesh file: what `--units` and `units=` take.

use std::fmt;
use std::str::FromStr;

use prehensile_core::parameter::ParameterError;

/// Length unit of a mesh file.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Millimetres.
    Mm,
    /// Centimetres.
    Cm,
    /// Metres (the default: every length in Prehensile is in metres).
    #[default]
    M,
}

impl Units {
    /// Every unit's name, as [`FromStr`] takes it.
    pub const NAMES: [&'static str; 3] = ["mm", "cm", "m"];

    /// Metres per unit.
    pub fn metres(self) -> f64 {
        match self {
            Self::Mm => 0.001,
            Self::Cm => 0.01,
            Self::M => 1.0,
        }
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(Self::NAMES[*self as usize])
    }
}

impl FromStr for Units {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, ParameterError> {
        match s {
            "mm" => Ok(Self::Mm),
            "cm" => Ok(Self::Cm),
            "m" => Ok(Self::M),
            _ => Err(ParameterError::UnknownName {
                what: "unit",
                name: s.to_string(),
                known: &Self::NAMES,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_parse_print_and_scale() {
        for name in Units::NAMES {
            assert_eq!(name.parse::<Units>().unwrap().to_string(), name);
        }
        assert_eq!("cm".parse::<Units>().unwrap().metres(), 0.01);
        assert!("inch".parse::<Units>().is_err());
    }
}
