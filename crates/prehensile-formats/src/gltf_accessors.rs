//! Checks every glTF accessor before the `gltf` crate's reader touches it: the reader trusts the
//! file and panics on a FLOAT index accessor, a stride shorter than an element, or a float
//! JOINTS_0. An accessor that passes has a supported type, no sparse part, and every element
//! inside its buffer view and buffer.

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Semantic;

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
