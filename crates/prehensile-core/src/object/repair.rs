//! What [`super::ObjectModel::new`] repaired, and why a mesh takes its inside from winding
//! numbers: typed, each with the message `check` prints.

use std::fmt;

use crate::mesh::MeshDefect;

/// Why a mesh is not one clean closed surface.
#[derive(Debug, Clone, PartialEq)]
pub enum Unclean {
    /// It has these defects.
    Defects(Vec<MeshDefect>),
    /// It is closed but covers some space twice: parts overlap or a face passes through
    /// another.
    Overlaps,
}

impl fmt::Display for Unclean {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Defects(defects) => {
                for (i, d) in defects.iter().enumerate() {
                    write!(f, "{}{}", if i > 0 { ", " } else { "" }, d.summary())?;
                }
                Ok(())
            }
            Self::Overlaps => {
                f.write_str("it overlaps itself: parts overlap or a face passes through another")
            }
        }
    }
}

/// One repair of a mesh on its way to a graspable object. Written to JSON as its message.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Repair {
    /// Triangles with a vertex repeated, dropped.
    Collapsed(usize),
    /// Pairs of coincident triangles wound opposite ways, dropped.
    CancellingPairs(usize),
    /// Copies of a triangle (same corners, same winding), dropped.
    Duplicates(usize),
    /// Triangles facing against their neighbours, turned.
    Turned(usize),
    /// Zero-area triangles of a closed mesh, removed by splitting their neighbours.
    SliversSplit(usize),
    /// A closed mesh inside out, turned the other way.
    InsideOut,
    /// Vertices no triangle uses, dropped.
    UnusedVertices(usize),
    /// Zero-area triangles of an unclean mesh, dropped.
    ZeroAreaDropped(usize),
    /// The mesh takes its inside from winding numbers.
    WindingInside {
        /// Why.
        why: Unclean,
        /// The volume of that inside, m³.
        volume: f64,
        /// Whether the search keeps its distance grid (closed parts that overlap) or uses the
        /// exact path only (a mesh with holes).
        keeps_grid: bool,
    },
    /// Separate parts with the centre of mass between them: the hook is the largest part's
    /// centre.
    HookOnLargestPart {
        /// How many parts.
        parts: usize,
    },
}

impl fmt::Display for Repair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Collapsed(n) => write!(f, "dropped {n} collapsed triangle(s) (a vertex repeated); the shape is unchanged"),
            Self::CancellingPairs(n) => write!(f, "dropped {n} pair(s) of coincident triangles wound opposite ways (they cancel); the shape is unchanged"),
            Self::Duplicates(n) => write!(f, "dropped {n} duplicate triangle(s) (the same corners, wound the same way, as one kept); the surface is unchanged, counted once"),
            Self::Turned(n) => write!(f, "turned {n} triangle(s) that faced the other way from their neighbours; the shape is unchanged"),
            Self::SliversSplit(n) => write!(f, "removed {n} zero-area triangle(s) by splitting their neighbours; the shape is unchanged"),
            Self::InsideOut => f.write_str("the closed mesh was inside out (negative volume); every triangle was turned the other way"),
            Self::UnusedVertices(n) => write!(f, "dropped {n} vertex(es) that no triangle uses; the shape is unchanged"),
            Self::ZeroAreaDropped(n) => write!(f, "dropped {n} zero-area triangle(s); they bound nothing"),
            Self::WindingInside { why, volume, keeps_grid } => write!(
                f,
                "the mesh is not one clean closed surface ({why}): its inside is where the generalized winding number exceeds ½ in magnitude, volume {volume:.4e} m³ from that inside; {}",
                if *keeps_grid {
                    "the search's collision tests read the distance grid, signed by that inside"
                } else {
                    "collision uses the exact path only"
                }
            ),
            Self::HookOnLargestPart { parts } => write!(f, "the mesh has {parts} separate parts and its centre of mass lies between them; the hook is the largest part's centre"),
        }
    }
}

impl serde::Serialize for Repair {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}
