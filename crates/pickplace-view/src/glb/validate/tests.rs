//! Unit tests of the checks, one concern at a time.

use super::animations::{check_animations, check_channel, check_sampler};
use super::buffers::{Accessor, View, check_accessor, check_buffer, check_buffer_views};
use super::container::{check_header, parse_document, split_chunks};
use super::meshes::{MeshTotals, check_meshes, check_primitive};
use super::nodes::{check_acyclic, check_nodes, check_scenes};
use super::validate_glb;
use crate::error::{GlbErrorKind, Result};
use crate::glb::{CHUNK_BIN, CHUNK_JSON, GLB_MAGIC};
use serde_json::json;

/// The text of an error, for comparing with the messages users see.
fn message<T: std::fmt::Debug>(r: Result<T>) -> String {
    r.expect_err("an error").to_string()
}

/// Little-endian f32 bytes of `values`.
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A GLB container of `json` (padded with spaces) and `bin` (padded with zeros).
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut out = Vec::new();
    out.extend(GLB_MAGIC.to_le_bytes());
    out.extend(2u32.to_le_bytes());
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(CHUNK_JSON.to_le_bytes());
    out.extend(&json);
    if !bin.is_empty() {
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(CHUNK_BIN.to_le_bytes());
        out.extend(&bin);
    }
    out
}

/// A float accessor over `count` elements of `type_name` at the start of view 0.
fn float_accessor(type_name: &str, components: usize, count: u64) -> Accessor {
    Accessor {
        component_type: 5126,
        components,
        type_name: type_name.to_owned(),
        count,
        start: 0,
        stride: 4 * components,
        min: None,
        max: None,
    }
}

#[test]
fn header_magic_version_and_length() {
    let good = glb(r#"{"asset":{"version":"2.0"}}"#, &[]);
    assert!(check_header(&good).is_ok());
    assert!(message(check_header(&good[..8])).contains("header"));
    let mut bad = good.clone();
    bad[0] = b'x';
    assert_eq!(
        message(check_header(&bad)),
        message(validate_glb(&bad)),
        "validate_glb reports the header's error"
    );
    let mut v1 = good.clone();
    v1[4] = 1;
    assert!(matches!(
        check_header(&v1),
        Err(crate::Error::InvalidGlb {
            kind: GlbErrorKind::Version { version: 1 }
        })
    ));
    let mut longer = good.clone();
    longer.extend([0; 4]);
    assert!(matches!(
        check_header(&longer),
        Err(crate::Error::InvalidGlb {
            kind: GlbErrorKind::LengthMismatch { .. }
        })
    ));
}

#[test]
fn chunks_json_then_bin() {
    let file = glb("{}", &[1, 2, 3, 4]);
    let (json, bin) = split_chunks(&file).expect("two chunks");
    assert_eq!(json, b"{}  ");
    assert_eq!(bin, [1, 2, 3, 4]);
    let json_only = glb("{}", &[]);
    assert_eq!(
        split_chunks(&json_only).expect("one chunk").1,
        [] as [u8; 0]
    );
    // The BIN chunk first.
    let mut swapped = json_only.clone();
    swapped[16..20].copy_from_slice(&CHUNK_BIN.to_le_bytes());
    assert!(message(split_chunks(&swapped)).contains("the first chunk must be JSON"));
    // No chunk at all.
    assert!(message(split_chunks(&json_only[..12])).contains("JSON chunk"));
    // A chunk length that is not a multiple of 4.
    let mut odd = json_only.clone();
    odd[12] = 3;
    assert!(message(split_chunks(&odd)).contains("multiple of 4"));
}

#[test]
fn document_needs_asset_version_2() {
    assert!(parse_document(br#"{"asset":{"version":"2.0"}}"#).is_ok());
    assert!(message(parse_document(br#"{"asset":{"version":"1.0"}}"#)).contains("version"));
    assert!(matches!(
        parse_document(b"{"),
        Err(crate::Error::InvalidGlb {
            kind: GlbErrorKind::Json { .. }
        })
    ));
}

#[test]
fn buffer_length_against_the_bin_chunk() {
    assert_eq!(check_buffer(&json!({}), &[]).expect("no buffer"), 0);
    assert!(message(check_buffer(&json!({}), &[0; 4])).contains("no buffer describes it"));
    let one = |n: u64| json!({"buffers": [{"byteLength": n}]});
    assert_eq!(check_buffer(&one(6), &[0; 8]).expect("padding"), 6);
    assert!(message(check_buffer(&one(4), &[0; 8])).contains("byteLength must equal"));
    assert!(message(check_buffer(&one(9), &[0; 8])).contains("byteLength must equal"));
    let uri = json!({"buffers": [{"byteLength": 8, "uri": "x.bin"}]});
    assert!(message(check_buffer(&uri, &[0; 8])).contains("must not have a uri"));
    let two = json!({"buffers": [{"byteLength": 8}, {"byteLength": 8}]});
    assert!(message(check_buffer(&two, &[0; 8])).contains("only the GLB-stored buffer"));
}

#[test]
fn buffer_views_inside_the_buffer() {
    let root =
        |view: serde_json::Value| json!({"buffers": [{"byteLength": 16}], "bufferViews": [view]});
    let views = check_buffer_views(
        &root(json!({"buffer": 0, "byteOffset": 4, "byteLength": 12, "byteStride": 12})),
        16,
    )
    .expect("valid");
    assert_eq!(
        views,
        [View {
            offset: 4,
            length: 12,
            stride: Some(12)
        }]
    );
    let outside = root(json!({"buffer": 0, "byteOffset": 8, "byteLength": 12}));
    assert!(matches!(
        check_buffer_views(&outside, 16),
        Err(crate::Error::InvalidGlb {
            kind: GlbErrorKind::Range { end: 20, .. }
        })
    ));
    let stride = root(json!({"buffer": 0, "byteLength": 16, "byteStride": 6}));
    assert!(message(check_buffer_views(&stride, 16)).contains("byteStride"));
    let empty = root(json!({"buffer": 0, "byteLength": 0}));
    assert!(message(check_buffer_views(&empty, 16)).contains("at least 1"));
    let target = root(json!({"buffer": 0, "byteLength": 4, "target": 1}));
    assert!(message(check_buffer_views(&target, 16)).contains("ARRAY_BUFFER"));
    let no_buffer = root(json!({"byteLength": 4}));
    assert!(message(check_buffer_views(&no_buffer, 16)).contains("buffer"));
}

#[test]
fn accessors_range_alignment_and_min_max() {
    let bin = f32_bytes(&[0.0, 1.0, 2.0, -1.0, 0.5, 3.0]);
    let views = [View {
        offset: 0,
        length: 24,
        stride: None,
    }];
    let accessor = |extra: serde_json::Value| {
        let mut a = json!({"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 2});
        if let (Some(a), Some(extra)) = (a.as_object_mut(), extra.as_object()) {
            a.extend(extra.clone());
        }
        a
    };
    let a = check_accessor(
        0,
        &accessor(json!({"min": [-1.0, 0.5, 2.0], "max": [0.0, 1.0, 3.0]})),
        &views,
        &bin,
    )
    .expect("valid");
    assert_eq!((a.components, a.count, a.stride), (3, 2, 12));
    assert!(
        message(check_accessor(
            0,
            &accessor(json!({"min": [-1.0, 0.5, 2.0], "max": [0.0, 1.0, 9.0]})),
            &views,
            &bin
        ))
        .contains("min/max do not match")
    );
    assert!(
        message(check_accessor(
            0,
            &accessor(json!({"min": [0.0, 0.0, 0.0]})),
            &views,
            &bin
        ))
        .contains("min and max come together")
    );
    assert!(
        message(check_accessor(
            0,
            &accessor(json!({"min": [0.0], "max": [1.0]})),
            &views,
            &bin
        ))
        .contains("one value per component")
    );
    assert!(
        message(check_accessor(
            0,
            &accessor(json!({"count": 3})),
            &views,
            &bin
        ))
        .contains("accessor")
    );
    assert!(
        message(check_accessor(
            0,
            &accessor(json!({"byteOffset": 2})),
            &views,
            &bin
        ))
        .contains("multiple of the component size")
    );
    assert!(
        message(check_accessor(
            0,
            &accessor(json!({"count": 0})),
            &views,
            &bin
        ))
        .contains("at least 1")
    );
    assert!(
        message(check_accessor(
            0,
            &accessor(json!({"type": "VEC5"})),
            &views,
            &bin
        ))
        .contains("type")
    );
    let no_view = json!({"componentType": 5126, "type": "SCALAR", "count": 1});
    assert!(message(check_accessor(0, &no_view, &views, &bin)).contains("without a bufferView"));
}

#[test]
fn primitives_positions_normals_and_indices() {
    // Accessor 0: three unit-length VEC3 (positions and normals alike); 1: three u8 indices.
    let bin: Vec<u8> = f32_bytes(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0])
        .into_iter()
        .chain([0u8, 1, 2])
        .collect();
    let mut position = float_accessor("VEC3", 3, 3);
    position.min = Some(vec![0.0; 3]);
    position.max = Some(vec![1.0; 3]);
    let indices = Accessor {
        component_type: 5121,
        components: 1,
        type_name: "SCALAR".into(),
        count: 3,
        start: 36,
        stride: 1,
        min: None,
        max: None,
    };
    let accessors = [position, indices];
    let mut totals = MeshTotals::default();
    let p = json!({"attributes": {"POSITION": 0, "NORMAL": 0, "COLOR_0": 0}, "indices": 1, "material": 0});
    check_primitive(0, &p, &accessors, 1, &bin, &mut totals).expect("valid");
    assert_eq!(
        (
            totals.triangles,
            totals.vertices,
            totals.coloured_primitives
        ),
        (1, 3, 1)
    );
    let no_position = json!({"attributes": {"NORMAL": 0}});
    assert!(
        message(check_primitive(
            0,
            &no_position,
            &accessors,
            1,
            &bin,
            &mut totals
        ))
        .contains("POSITION")
    );
    let wrong_indices = json!({"attributes": {"POSITION": 0}, "indices": 0});
    assert!(
        message(check_primitive(
            0,
            &wrong_indices,
            &accessors,
            1,
            &bin,
            &mut totals
        ))
        .contains("unsigned integer scalars")
    );
    let missing = json!({"attributes": {"POSITION": 5}});
    assert!(
        message(check_primitive(
            0,
            &missing,
            &accessors,
            1,
            &bin,
            &mut totals
        ))
        .contains("missing accessor")
    );
    let material = json!({"attributes": {"POSITION": 0}, "material": 1});
    assert!(
        message(check_primitive(
            0,
            &material,
            &accessors,
            1,
            &bin,
            &mut totals
        ))
        .contains("material")
    );
    let meshes = json!({"meshes": [{"primitives": []}]});
    assert!(message(check_meshes(&meshes, &accessors, 1, &bin)).contains("primitives"));
}

#[test]
fn node_hierarchy_parents_cycles_and_scenes() {
    let root = json!({"nodes": [
        {"name": "base", "children": [1], "translation": [0.0, 0.0, 1.0]},
        {"rotation": [0.0, 0.0, 0.0, 1.0]}
    ], "scenes": [{"nodes": [0]}]});
    let nodes = check_nodes(&root, 0).expect("valid");
    assert_eq!(nodes.names, [Some("base".to_owned()), None]);
    assert_eq!(nodes.parents, [None, Some(0)]);
    assert!(check_scenes(&root, &nodes.parents).is_ok());
    let child_scene = json!({"scenes": [{"nodes": [1]}]});
    assert!(message(check_scenes(&child_scene, &nodes.parents)).contains("existing root nodes"));
    assert!(message(check_acyclic(&[Some(1), Some(0)])).contains("cycle"));
    let two_parents = json!({"nodes": [{"children": [2]}, {"children": [2]}, {}]});
    assert!(message(check_nodes(&two_parents, 0)).contains("more than one parent"));
    let rotation = json!({"nodes": [{"rotation": [0.0, 0.0, 0.0, 2.0]}]});
    assert!(message(check_nodes(&rotation, 0)).contains("unit quaternion"));
    let mesh = json!({"nodes": [{"mesh": 0}]});
    assert!(message(check_nodes(&mesh, 0)).contains("mesh"));
}

#[test]
fn samplers_and_channels() {
    // Accessor 0: times 0, 0.5, 1 (with min and max); 1: three VEC3; 2: times 0, 0, 1.
    let bin: Vec<u8> = [
        f32_bytes(&[0.0, 0.5, 1.0]),
        f32_bytes(&[0.0; 9]),
        f32_bytes(&[0.0, 0.0, 1.0]),
    ]
    .concat();
    let mut times = float_accessor("SCALAR", 1, 3);
    times.min = Some(vec![0.0]);
    times.max = Some(vec![1.0]);
    let mut values = float_accessor("VEC3", 3, 3);
    values.start = 12;
    let mut repeated = times.clone();
    repeated.start = 48;
    let accessors = [times, values, repeated];
    let sampler =
        check_sampler(0, 0, &json!({"input": 0, "output": 1}), &accessors, &bin).expect("valid");
    assert_eq!((sampler.samples, sampler.end), (3, 1.0));
    assert!(
        message(check_sampler(
            0,
            0,
            &json!({"input": 2, "output": 1}),
            &accessors,
            &bin
        ))
        .contains("strictly increasing")
    );
    assert!(matches!(
        check_sampler(
            0,
            0,
            &json!({"input": 0, "output": 1, "interpolation": "CUBICSPLINE"}),
            &accessors,
            &bin
        ),
        Err(crate::Error::InvalidGlb {
            kind: GlbErrorKind::SamplerCounts { .. }
        })
    ));
    assert!(
        message(check_sampler(
            0,
            0,
            &json!({"input": 1, "output": 1}),
            &accessors,
            &bin
        ))
        .contains("float scalars")
    );
    let samplers = [sampler];
    let channel = |path: &str| json!({"sampler": 0, "target": {"node": 0, "path": path}});
    let summary = check_channel(0, &channel("translation"), &samplers, 1).expect("valid");
    assert_eq!(
        (summary.node, summary.path.as_str(), summary.samples),
        (0, "translation", 3)
    );
    assert!(
        message(check_channel(0, &channel("rotation"), &samplers, 1))
            .contains("does not match the target path")
    );
    assert!(message(check_channel(0, &channel("colour"), &samplers, 1)).contains("path"));
    assert!(message(check_channel(0, &channel("translation"), &samplers, 0)).contains("node"));
    let root = json!({"animations": [{"name": "a", "samplers": [{"input": 0, "output": 1}],
        "channels": [channel("translation"), channel("translation")]}]});
    assert!(message(check_animations(&root, &accessors, 1, &bin)).contains("same node and path"));
}
