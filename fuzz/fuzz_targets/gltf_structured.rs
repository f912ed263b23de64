//! Structure-aware glTF fuzzing: arbitrary accessors (type, component type, count, offset),
//! buffer views (offset, length, stride), node graphs (children lists with repeats and cycles) and
//! skins, assembled into a GLB and given to both glTF readers (mesh and skinned hand).
#![no_main]

use arbitrary::Arbitrary;
use serde_json::json;

#[derive(Arbitrary, Debug)]
struct View {
    offset: u16,
    length: u16,
    stride: Option<u8>,
}

#[derive(Arbitrary, Debug)]
struct Accessor {
    view: u8,
    component: u8,
    kind: u8,
    count: u16,
    offset: u16,
    sparse: bool,
}

#[derive(Arbitrary, Debug)]
struct Node {
    mesh: bool,
    children: Vec<u8>,
}

#[derive(Arbitrary, Debug)]
struct Input {
    views: Vec<View>,
    accessors: Vec<Accessor>,
    nodes: Vec<Node>,
    roots: Vec<u8>,
    attributes: [Option<u8>; 4],
    indices: Option<u8>,
    skin: Option<(Vec<u8>, Option<u8>)>,
    bin: Vec<u8>,
}

const COMPONENTS: [u32; 6] = [5120, 5121, 5122, 5123, 5125, 5126];
const KINDS: [&str; 5] = ["SCALAR", "VEC2", "VEC3", "VEC4", "MAT4"];

fn glb(input: &Input) -> Vec<u8> {
    let n = |i: u8, len: usize| i as usize % len.max(1);
    let mut attributes = serde_json::Map::new();
    for (name, a) in ["POSITION", "JOINTS_0", "WEIGHTS_0", "NORMAL"]
        .iter()
        .zip(input.attributes)
    {
        if let Some(a) = a {
            attributes.insert(name.to_string(), json!(n(a, input.accessors.len())));
        }
    }
    let mut primitive = json!({ "attributes": attributes });
    if let Some(i) = input.indices {
        primitive["indices"] = json!(n(i, input.accessors.len()));
    }
    let mut doc = json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": input.roots.iter().map(|&r| n(r, input.nodes.len())).collect::<Vec<_>>() }],
        "nodes": input.nodes.iter().map(|node| {
            let mut v = json!({ "children": node.children.iter().map(|&c| n(c, input.nodes.len())).collect::<Vec<_>>() });
            if node.mesh { v["mesh"] = json!(0); }
            v
        }).collect::<Vec<_>>(),
        "meshes": [{ "primitives": [primitive] }],
        "buffers": [{ "byteLength": input.bin.len() }],
        "bufferViews": input.views.iter().map(|v| {
            let mut view = json!({ "buffer": 0, "byteOffset": v.offset, "byteLength": v.length });
            if let Some(s) = v.stride { view["byteStride"] = json!(s); }
            view
        }).collect::<Vec<_>>(),
        "accessors": input.accessors.iter().map(|a| {
            let mut acc = json!({
                "bufferView": n(a.view, input.views.len()),
                "componentType": COMPONENTS[a.component as usize % COMPONENTS.len()],
                "type": KINDS[a.kind as usize % KINDS.len()],
                "count": a.count,
                "byteOffset": a.offset,
            });
            if a.sparse {
                acc["sparse"] = json!({ "count": 1, "indices": { "bufferView": 0, "componentType": 5125 }, "values": { "bufferView": 0 } });
            }
            acc
        }).collect::<Vec<_>>(),
    });
    if let Some((joints, inverse)) = &input.skin {
        let mut skin = json!({ "joints": joints.iter().map(|&j| n(j, input.nodes.len())).collect::<Vec<_>>() });
        if let Some(i) = inverse {
            skin["inverseBindMatrices"] = json!(n(*i, input.accessors.len()));
        }
        doc["skins"] = json!([skin]);
    }
    prehensile_formats::glb_container(
        &serde_json::to_vec(&doc).expect("a JSON value serializes"),
        &input.bin,
    )
}

libfuzzer_sys::fuzz_target!(|input: Input| {
    let bytes = glb(&input);
    let _ = prehensile_testkit::fuzz_entry::run("mesh_gltf", &bytes);
    let _ = prehensile_testkit::fuzz_entry::run("hand_gltf", &bytes);
});
