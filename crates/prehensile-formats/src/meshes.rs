//! Mesh files by extension, and objects loaded from them.

use std::path::Path;

use prehensile_core::math::Point3;
use prehensile_core::object::Repair;
use prehensile_core::{ObjectModel, TriangleMesh};

use crate::{parse_obj, parse_ply, parse_stl, FormatError};

/// Reads an OBJ, STL, PLY or glTF/GLB file into a welded mesh, every coordinate multiplied by `scale`.
pub fn read_mesh(path: &Path, scale: f64) -> Result<TriangleMesh, FormatError> {
    let bytes = crate::read_input(path, crate::MAX_MESH_BYTES)?;
    parse_mesh_in(&bytes, &path.display().to_string(), scale, Some(path))
}

/// A mesh from a file's bytes (OBJ, STL, PLY or GLB, by `name`'s extension), coordinates times
/// `scale`: for meshes that do not come from a path (a browser's dropped file, a network
/// message). A `.gltf` whose buffers are other files needs [`read_mesh`].
pub fn parse_mesh(bytes: &[u8], name: &str, scale: f64) -> Result<TriangleMesh, FormatError> {
    parse_mesh_in(bytes, name, scale, None)
}

fn parse_mesh_in(
    bytes: &[u8],
    name: &str,
    scale: f64,
    file: Option<&Path>,
) -> Result<TriangleMesh, FormatError> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(FormatError::new(
            name,
            format!("scale {scale} must be a positive number"),
        ));
    }
    let (vertices, triangles) = parse_triangles(bytes, name, file)?;
    let scaled: Vec<Point3> = vertices.iter().map(|p| p * scale).collect();
    TriangleMesh::weld(&scaled, &triangles).map_err(|e| FormatError::caused_by(name, e))
}

/// The vertices and triangles of a mesh file's bytes (OBJ, STL, PLY or glTF/GLB, by `name`'s
/// extension), as the file has them: not welded or checked. `file` is where a `.gltf` finds its
/// buffers.
pub(crate) fn parse_triangles(
    bytes: &[u8],
    name: &str,
    file: Option<&Path>,
) -> Result<(Vec<Point3>, Vec<[usize; 3]>), FormatError> {
    let ext = Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "obj" => {
            let text = std::str::from_utf8(bytes)
                .map_err(|e| FormatError::new(name, format!("an OBJ file must be text: {e}")))?;
            parse_obj(text, name)
        }
        "stl" => parse_stl(bytes, name),
        "ply" => parse_ply(bytes, name),
        "gltf" | "glb" => crate::mesh_gltf::parse_gltf_triangles(bytes, name, file),
        _ => Err(FormatError::new(
            name,
            format!("unknown mesh extension '.{ext}'; use .obj, .stl, .ply, .gltf or .glb"),
        )),
    }
}

/// Reads a mesh file and makes a graspable object of it, hooked at its centre of mass.
pub fn load_object(path: &Path, scale: f64) -> Result<ObjectModel, FormatError> {
    load_object_repaired(path, scale, None).map(|(o, _)| o)
}

/// What loading an object did to its mesh: the weld asked for, and the library's repairs.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum LoadNote {
    /// Vertices closer than the weld tolerance were merged.
    Welded {
        /// Vertices merged.
        merged: usize,
        /// The tolerance, metres.
        tolerance: f64,
        /// Boundary edges before and after.
        boundary_edges: [usize; 2],
        /// Non-manifold edges before and after.
        non_manifold_edges: [usize; 2],
    },
    /// A repair the object made ([`ObjectModel::repairs`]).
    Repaired(Repair),
}

impl std::fmt::Display for LoadNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Welded {
                merged,
                tolerance,
                boundary_edges: [b0, b1],
                non_manifold_edges: [n0, n1],
            } => write!(
                f,
                "merged {merged} vertices closer than {tolerance:.1e} m: boundary edges {b0} -> {b1}, non-manifold edges {n0} -> {n1}"
            ),
            Self::Repaired(r) => r.fmt(f),
        }
    }
}

/// As [`load_object`], but with `weld_tolerance` first merges vertices closer than that many
/// metres (an explicit repair for scans with hairline seams); returns what was done.
pub fn load_object_repaired(
    path: &Path,
    scale: f64,
    weld_tolerance: Option<f64>,
) -> Result<(ObjectModel, Vec<LoadNote>), FormatError> {
    let mut mesh = read_mesh(path, scale)?;
    let mut notes = Vec::new();
    if let Some(tolerance) = weld_tolerance {
        let before = mesh.report();
        let (welded, merged) = mesh.weld_within(tolerance);
        let after = welded.report();
        notes.push(LoadNote::Welded {
            merged,
            tolerance,
            boundary_edges: [before.boundary_edges, after.boundary_edges],
            non_manifold_edges: [before.non_manifold_edges, after.non_manifold_edges],
        });
        mesh = welded;
    }
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "object".into());
    let object = ObjectModel::new(&name, mesh, None)
        .map_err(|e| FormatError::caused_by(&path.display().to_string(), e))?;
    notes.extend(object.repairs().iter().cloned().map(LoadNote::Repaired));
    Ok((object, notes))
}

/// Writes a mesh as OBJ text.
pub fn write_obj(mesh: &TriangleMesh) -> String {
    let mut s = String::with_capacity(mesh.vertices.len() * 40 + mesh.triangles.len() * 20);
    for v in &mesh.vertices {
        s.push_str(&format!("v {:.9} {:.9} {:.9}\n", v.x, v.y, v.z));
    }
    for t in &mesh.triangles {
        s.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    s
}
