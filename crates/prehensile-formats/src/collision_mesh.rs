//! Collision meshes of imported hands (MJCF mesh geoms, URDF `<mesh>`): read from the hand's own
//! folder (or from files given in memory), scaled per axis, and turned into capsules inside their
//! convex hull ([`prehensile_core::hand::convex_capsules`]), as MuJoCo collides a mesh geom as
//! its hull. A mesh that cannot be read is not an error: the hand loads without it, and the
//! reason is named in the hand's description.

use std::path::Path;

use prehensile_core::hand::convex_capsules::convex_capsules;
use prehensile_core::math::{Point3, Transform, Vec3};

/// Largest collision mesh file read, bytes.
const MAX_COLLISION_MESH_BYTES: u64 = 64 << 20;

/// Most vertices of one collision mesh (a hand's are hundreds to a few thousand; convex
/// decompositions keep each part under 256). Its capsules take about 0.5 s at this size.
const MAX_COLLISION_MESH_VERTICES: usize = 10_000;

/// Most vertices of all of one hand's collision meshes together, so that a file of many large
/// meshes cannot keep the reader busy for minutes.
pub const MAX_HAND_MESH_VERTICES: usize = 100_000;

/// Faces of a mesh's hull are covered by its capsules within this distance, metres.
pub const MESH_FACE_TOLERANCE: f64 = 0.001;

/// Where an imported hand's collision meshes are read from.
#[derive(Clone, Copy)]
pub enum MeshFiles<'a> {
    /// Nowhere: a hand parsed from text alone; its mesh geoms are skipped and named.
    None,
    /// The file system, in the hand file's folder and below.
    Disk(&'a Path),
    /// Files held in memory (dropped on a web page), found by file name.
    Named(&'a [(String, Vec<u8>)]),
}

/// One collision mesh as read: its capsules in the bone's frame, and a note for the hand's
/// description saying what it became or why it was skipped.
pub struct MeshCapsules {
    /// The capsules, `(a, b, radius)`, in the frame the geom's placement maps into.
    pub capsules: Vec<(Point3, Point3, f64)>,
    /// `name (what it became)` or `name (why it was skipped)`.
    pub note: String,
}

impl MeshFiles<'_> {
    /// The capsules of the mesh file `reference` (relative to the hand file, `/`-separated),
    /// every vertex multiplied by `scale` per axis and placed by `placement`; or why not, as the
    /// `Err` note. `budget` is the hand's vertices still to be read ([`MAX_HAND_MESH_VERTICES`]).
    pub fn capsules(
        &self,
        name: &str,
        reference: &str,
        scale: Vec3,
        placement: &Transform,
        budget: &mut usize,
    ) -> Result<MeshCapsules, String> {
        let skip = |why: String| Err(format!("{name} ({why})"));
        let vertices = match self.vertices(reference) {
            Ok(v) => v,
            Err(why) => return skip(why),
        };
        vertex_capsules(name, &vertices, scale, placement, budget)
    }

    /// The vertices of `reference`, or why they cannot be read.
    fn vertices(&self, reference: &str) -> Result<Vec<Point3>, String> {
        let file_name = reference.rsplit(['/', '\\']).next().unwrap_or(reference);
        let (bytes, path) = match self {
            MeshFiles::None => {
                return Err("not read: the hand was given as text, without its folder".into())
            }
            MeshFiles::Disk(hand_file) => {
                let path = crate::confined(hand_file, reference).map_err(|e| e.to_string())?;
                let bytes = crate::read_input(&path, MAX_COLLISION_MESH_BYTES)
                    .map_err(|e| e.to_string())?;
                (bytes, Some(path))
            }
            MeshFiles::Named(files) => (
                files
                    .iter()
                    .find(|(n, _)| n == file_name)
                    .map(|(_, b)| b.clone())
                    .ok_or_else(|| format!("'{file_name}' was not given with the hand file"))?,
                None,
            ),
        };
        let (vertices, _) = crate::meshes::parse_triangles(&bytes, file_name, path.as_deref())
            .map_err(|e| e.to_string())?;
        Ok(vertices)
    }
}

/// The capsules of a mesh given by its `vertices` (scaled per axis by `scale`, then placed by
/// `placement`), or why not, as the `Err` note; `budget` as for [`MeshFiles::capsules`].
pub fn vertex_capsules(
    name: &str,
    vertices: &[Point3],
    scale: Vec3,
    placement: &Transform,
    budget: &mut usize,
) -> Result<MeshCapsules, String> {
    // STL repeats a vertex in every triangle that has it: count each position once.
    let mut vertices = vertices.to_vec();
    vertices.sort_unstable_by(|p, q| {
        (p.x.to_bits(), p.y.to_bits(), p.z.to_bits()).cmp(&(
            q.x.to_bits(),
            q.y.to_bits(),
            q.z.to_bits(),
        ))
    });
    vertices.dedup();
    if vertices.len() > *budget {
        return Err(format!(
            "{name} (the hand's collision meshes have more than {MAX_HAND_MESH_VERTICES} \
             vertices in all; simplify them)"
        ));
    }
    *budget -= vertices.len();
    if vertices.len() > MAX_COLLISION_MESH_VERTICES {
        return Err(format!(
            "{name} ({} vertices, more than the {MAX_COLLISION_MESH_VERTICES} read for one \
             collision mesh; simplify it or give its convex parts)",
            vertices.len()
        ));
    }
    if !(scale.iter().all(|s| s.is_finite() && *s != 0.0)) {
        return Err(format!(
            "{name} (scale {scale:?} must be finite and not zero)"
        ));
    }
    let placed: Vec<Point3> = vertices
        .iter()
        .map(|p| placement * Point3::from(p.coords.component_mul(&scale)))
        .collect();
    let made = convex_capsules(&placed, MESH_FACE_TOLERANCE)
        .map_err(|e| format!("{name} (its hull cannot be built: {e})"))?;
    if made.capsules.is_empty() {
        return Err(format!("{name} (too thin for a capsule inside it)"));
    }
    Ok(MeshCapsules {
        note: format!(
            "{name} ({} capsules inside its hull, faces within {:.1} mm, corners within {:.1} mm)",
            made.capsules.len(),
            made.face_gap * 1e3,
            made.corner_gap * 1e3
        ),
        capsules: made.capsules,
    })
}
