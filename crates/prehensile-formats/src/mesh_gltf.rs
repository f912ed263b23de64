//! Meshes from glTF 2.0 (`.gltf` with its buffers, or `.glb`): every triangle primitive of every
//! mesh in the default scene, merged, with node transforms applied. Read with the `gltf` crate.

use std::path::Path;

use prehensile_core::math::Point3;

use crate::FormatError;

/// Every triangle of the default scene of a glTF file's bytes. Buffers in other files are read
/// beside `file` (confined to its folder); without a file (bytes from a browser, say) only a
/// `.glb`'s own binary chunk can be used.
pub fn parse_gltf_triangles(
    bytes: &[u8],
    name: &str,
    file: Option<&Path>,
) -> Result<(Vec<Point3>, Vec<[usize; 3]>), FormatError> {
    let gltf = crate::gltf_accessors::parse_gltf(bytes).map_err(|e| FormatError::new(name, e))?;
    let doc = &gltf.document;
    let buffers = read_buffers(&gltf, name, file)?;
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| FormatError::new(name, "the file has no scene"))?;
    let mut mesh = (Vec::new(), Vec::new());
    let nodes = crate::gltf_accessors::scene_nodes(&scene, doc.nodes().len())
        .map_err(|e| FormatError::new(name, e))?;
    let mut worlds = vec![nalgebra::Matrix4::<f64>::identity(); doc.nodes().len()];
    for (node, parent) in nodes {
        let local = nalgebra::Matrix4::from_fn(|r, c| node.transform().matrix()[c][r] as f64);
        let world = parent.map_or(nalgebra::Matrix4::identity(), |p| worlds[p]) * local;
        worlds[node.index()] = world;
        if let Some(m) = node.mesh() {
            for (pi, primitive) in m.primitives().enumerate() {
                let at = format!("mesh '{}' primitive {pi}", m.name().unwrap_or("?"));
                add_primitive(&primitive, &world, &buffers, &mut mesh)
                    .map_err(|e| FormatError::at(name, at, e))?;
            }
        }
    }
    if mesh.1.is_empty() {
        return Err(FormatError::new(name, "the scene has no triangles"));
    }
    Ok(mesh)
}

/// The file's buffers: the GLB's binary chunk, or files beside a .gltf. (Embedded base64 data
/// URIs are not supported: they would need the crate's image-decoding import feature.)
fn read_buffers(
    gltf: &gltf::Gltf,
    name: &str,
    file: Option<&Path>,
) -> Result<Vec<Vec<u8>>, FormatError> {
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for buffer in gltf.document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                FormatError::new(
                    name,
                    "buffer refers to a binary chunk the file does not have",
                )
            })?,
            gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => match file {
                Some(path) => {
                    let beside = crate::confined(path, uri)?;
                    crate::read_input(&beside, crate::MAX_MESH_BYTES)?
                }
                None => {
                    return Err(FormatError::new(
                        name,
                        format!(
                            "its buffer is another file ('{uri}'); give a .glb, which holds its own"
                        ),
                    ))
                }
            },
            gltf::buffer::Source::Uri(_) => {
                return Err(FormatError::new(
                    name,
                    "embedded (data: URI) buffers are not supported; export as .glb",
                ))
            }
        };
        if data.len() < buffer.length() {
            return Err(FormatError::new(
                name,
                format!(
                    "buffer {} is shorter than its declared length",
                    buffer.index()
                ),
            ));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// Adds a triangle primitive's vertices (placed by `world`) and triangles to `mesh`; the error
/// says what is wrong with the primitive.
fn add_primitive(
    primitive: &gltf::Primitive,
    world: &nalgebra::Matrix4<f64>,
    buffers: &[Vec<u8>],
    (vertices, triangles): &mut (Vec<Point3>, Vec<[usize; 3]>),
) -> Result<(), String> {
    if primitive.mode() != gltf::mesh::Mode::Triangles {
        return Err(format!(
            "uses {:?}; only triangles describe a closed object",
            primitive.mode()
        ));
    }
    let slices: Vec<&[u8]> = buffers.iter().map(|b| &b[..]).collect();
    crate::gltf_accessors::check_primitive(primitive, false, &slices)?;
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
    let positions = reader
        .read_positions()
        .ok_or_else(|| "has no POSITION attribute".to_string())?;
    let first = vertices.len();
    for p in positions {
        let v = world * nalgebra::Vector4::new(p[0] as f64, p[1] as f64, p[2] as f64, 1.0);
        vertices.push(Point3::new(v.x, v.y, v.z));
    }
    let count = vertices.len() - first;
    let indices: Vec<usize> = match reader.read_indices() {
        Some(i) => i.into_u32().map(|i| i as usize).collect(),
        None => (0..count).collect(),
    };
    if !indices.len().is_multiple_of(3) {
        return Err(format!(
            "{} indices is not a whole number of triangles",
            indices.len()
        ));
    }
    for t in indices.chunks(3) {
        if t.iter().any(|&i| i >= count) {
            return Err(format!("an index refers past its {count} vertices"));
        }
        triangles.push([first + t[0], first + t[1], first + t[2]]);
    }
    Ok(())
}
