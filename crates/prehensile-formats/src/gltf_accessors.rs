//! Checks every glTF accessor before the `gltf` crate's reader touches it: the reader trusts the
//! file and panics on a FLOAT index accessor, a stride shorter than an element, or a float
//! JOINTS_0. An accessor that passes has a supported type, no sparse part, and every element
//! inside its buffer view and buffer.

use gltf::accessor::{DataType, Dimensions};
use gltf::json::validation::Checked;
use gltf::mesh::Semantic;

/// Parses glTF or GLB bytes with our own checks of every index and enum the readers use, instead
/// of the `gltf` crate's validation: that validation indexes accessors before checking that they
/// exist, and panicked on a primitive naming an accessor in a file with none (found by fuzzing).
pub fn parse_gltf(bytes: &[u8]) -> Result<gltf::Gltf, String> {
    // The gltf crate subtracts the 12-byte header from the declared length unchecked, which
    // overflows (a panic in debug builds) when a GLB declares less than its own header.
    if let [b'g', b'l', b'T', b'F', _, _, _, _, l0, l1, l2, l3, ..] = bytes {
        let declared = u32::from_le_bytes([*l0, *l1, *l2, *l3]);
        if declared < 12 {
            return Err(format!(
                "not a readable glTF file: the GLB header declares a length of {declared} bytes, \
                 less than the header itself"
            ));
        }
    }
    let gltf = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| format!("not a readable glTF file: {e}"))?;
    check_indices(gltf.document.as_json())?;
    Ok(gltf)
}

/// Every index the readers follow points at an existing object, and every enum they read is
/// known.
fn check_indices(root: &gltf::json::Root) -> Result<(), String> {
    let within = |what: &str, index: usize, len: usize, of: &str| {
        if index < len {
            Ok(())
        } else {
            Err(format!(
                "{what} refers to {of} {index}, but the file has {len}"
            ))
        }
    };
    let (accessors, views, nodes) = (
        root.accessors.len(),
        root.buffer_views.len(),
        root.nodes.len(),
    );
    for (i, a) in root.accessors.iter().enumerate() {
        let what = format!("accessor {i}");
        if let Some(v) = a.buffer_view {
            within(&what, v.value(), views, "buffer view")?;
        }
        if !matches!(a.component_type, Checked::Valid(_)) || !matches!(a.type_, Checked::Valid(_)) {
            return Err(format!("{what} has an unknown componentType or type"));
        }
        if let Some(sparse) = &a.sparse {
            within(
                &what,
                sparse.indices.buffer_view.value(),
                views,
                "buffer view",
            )?;
            within(
                &what,
                sparse.values.buffer_view.value(),
                views,
                "buffer view",
            )?;
        }
    }
    for (i, v) in root.buffer_views.iter().enumerate() {
        within(
            &format!("buffer view {i}"),
            v.buffer.value(),
            root.buffers.len(),
            "buffer",
        )?;
    }
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let what = format!("mesh {m} primitive {p}");
            for a in primitive.attributes.values() {
                within(&what, a.value(), accessors, "accessor")?;
            }
            if let Some(a) = primitive.indices {
                within(&what, a.value(), accessors, "accessor")?;
            }
            if !matches!(primitive.mode, Checked::Valid(_)) {
                return Err(format!("{what} has an unknown mode"));
            }
        }
    }
    for (i, node) in root.nodes.iter().enumerate() {
        let what = format!("node {i}");
        for c in node.children.iter().flatten() {
            within(&what, c.value(), nodes, "node")?;
        }
        if let Some(m) = node.mesh {
            within(&what, m.value(), root.meshes.len(), "mesh")?;
        }
        if let Some(s) = node.skin {
            within(&what, s.value(), root.skins.len(), "skin")?;
        }
    }
    for (i, scene) in root.scenes.iter().enumerate() {
        for n in &scene.nodes {
            within(&format!("scene {i}"), n.value(), nodes, "node")?;
        }
    }
    if let Some(s) = root.scene {
        within("the default scene", s.value(), root.scenes.len(), "scene")?;
    }
    for (i, skin) in root.skins.iter().enumerate() {
        let what = format!("skin {i}");
        for j in &skin.joints {
            within(&what, j.value(), nodes, "node")?;
        }
        if let Some(a) = skin.inverse_bind_matrices {
            within(&what, a.value(), accessors, "accessor")?;
        }
        if let Some(n) = skin.skeleton {
            within(&what, n.value(), nodes, "node")?;
        }
    }
    Ok(())
}

/// Why `accessor` cannot be read as one of `allowed` from `buffers` (one byte vector per buffer,
/// in the document's order), or `Ok`.
pub fn check_accessor(
    accessor: &gltf::Accessor,
    what: &str,
    allowed: &[(Dimensions, DataType)],
    buffers: &[&[u8]],
) -> Result<(), String> {
    let index = accessor.index();
    let (dims, kind) = (accessor.dimensions(), accessor.data_type());
    if !allowed.contains(&(dims, kind)) {
        return Err(format!(
            "accessor {index} ({what}) is {dims:?} of {kind:?}; expected one of {allowed:?}"
        ));
    }
    if accessor.sparse().is_some() {
        return Err(format!(
            "accessor {index} ({what}) is sparse, which is not supported; export without sparse accessors"
        ));
    }
    let Some(view) = accessor.view() else {
        return Err(format!("accessor {index} ({what}) has no buffer view"));
    };
    let element = dims.multiplicity() * kind.size();
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(format!(
            "accessor {index} ({what}): buffer view {} has a stride of {stride} bytes, shorter than one {element}-byte element",
            view.index()
        ));
    }
    let count = accessor.count();
    let end = if count == 0 {
        Some(accessor.offset())
    } else {
        (count - 1)
            .checked_mul(stride)
            .and_then(|b| b.checked_add(accessor.offset()))
            .and_then(|b| b.checked_add(element))
    };
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!(
            "accessor {index} ({what}): {count} elements from byte {} run past the end of buffer view {} ({} bytes)",
            accessor.offset(),
            view.index(),
            view.length()
        ));
    }
    let buffer = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|e| e > buffer)
    {
        return Err(format!(
            "accessor {index} ({what}): buffer view {} runs past the end of buffer {} ({buffer} bytes)",
            view.index(),
            view.buffer().index()
        ));
    }
    Ok(())
}

/// Checks the accessors a triangle primitive is read through: POSITION (3 floats), the indices
/// (unsigned integers) and, with `skinned`, JOINTS_0 (4 unsigned integers) and WEIGHTS_0 (4
/// floats or normalized unsigned integers).
pub fn check_primitive(
    primitive: &gltf::Primitive,
    skinned: bool,
    buffers: &[&[u8]],
) -> Result<(), String> {
    use DataType::{F32, U16, U32, U8};
    use Dimensions::{Scalar, Vec3, Vec4};
    if let Some(a) = primitive.get(&Semantic::Positions) {
        check_accessor(&a, "POSITION", &[(Vec3, F32)], buffers)?;
    }
    if let Some(a) = primitive.indices() {
        check_accessor(
            &a,
            "indices",
            &[(Scalar, U8), (Scalar, U16), (Scalar, U32)],
            buffers,
        )?;
    }
    if skinned {
        if let Some(a) = primitive.get(&Semantic::Joints(0)) {
            check_accessor(&a, "JOINTS_0", &[(Vec4, U8), (Vec4, U16)], buffers)?;
        }
        if let Some(a) = primitive.get(&Semantic::Weights(0)) {
            check_accessor(
                &a,
                "WEIGHTS_0",
                &[(Vec4, F32), (Vec4, U8), (Vec4, U16)],
                buffers,
            )?;
        }
    }
    Ok(())
}

/// The nodes of `scene` with their parent, each once, refusing a hierarchy that is not a forest
/// (a node listed twice, by itself or by two parents, or a cycle), as glTF requires.
pub fn scene_nodes<'a>(
    scene: &gltf::Scene<'a>,
    node_count: usize,
) -> Result<Vec<(gltf::Node<'a>, Option<usize>)>, String> {
    let mut seen = vec![false; node_count];
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node<'a>, Option<usize>)> =
        scene.nodes().map(|n| (n, None)).collect();
    while let Some((node, parent)) = stack.pop() {
        let i = node.index();
        if seen.get(i).copied().unwrap_or(true) {
            return Err(format!(
                "node {i} is reached twice (listed by two parents, twice by one, or in a cycle); glTF node hierarchies must be trees"
            ));
        }
        seen[i] = true;
        stack.extend(node.children().map(|c| (c, Some(i))));
        out.push((node, parent));
    }
    Ok(out)
}
