//! Reads a `.glb` back and checks the glTF 2.0 rules this crate relies on.

use super::{CHUNK_BIN, CHUNK_JSON, GLB_MAGIC};
use crate::error::{GlbErrorKind, Result, glb_error};
use serde_json::Value;

/// What a valid `.glb` holds, for tests and reports.
#[derive(Debug, Clone, PartialEq)]
pub struct GlbSummary {
    /// Length of the JSON chunk (bytes, padding included).
    pub json_length: u64,
    /// Length of the BIN chunk (bytes), 0 when absent.
    pub bin_length: u64,
    /// `byteLength` of the buffer, 0 when absent.
    pub buffer_length: u64,
    /// Node names, in node order (`None` for unnamed nodes).
    pub node_names: Vec<Option<String>>,
    /// Parent of each node, in node order.
    pub node_parents: Vec<Option<usize>>,
    /// Number of meshes.
    pub meshes: usize,
    /// Number of materials.
    pub materials: usize,
    /// Number of accessors.
    pub accessors: usize,
    /// Number of buffer views.
    pub buffer_views: usize,
    /// Triangles over every mesh primitive.
    pub triangles: u64,
    /// Vertices over every mesh primitive.
    pub vertices: u64,
    /// Primitives that carry a `COLOR_0` attribute.
    pub coloured_primitives: usize,
    /// The animations.
    pub animations: Vec<AnimationSummary>,
}

/// One animation of a [`GlbSummary`].
#[derive(Debug, Clone, PartialEq)]
pub struct AnimationSummary {
    /// Its name.
    pub name: Option<String>,
    /// Last keyframe time over all samplers (s).
    pub duration: f64,
    /// Its channels, in file order.
    pub channels: Vec<ChannelSummary>,
}

/// One animation channel of an [`AnimationSummary`].
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelSummary {
    /// Target node.
    pub node: usize,
    /// Target path (`translation`, `rotation`, `scale` or `weights`).
    pub path: String,
    /// Number of keyframes (input count = output count for `LINEAR`).
    pub samples: u64,
}

fn truncated(what: &'static str, needed: u64, available: u64) -> crate::Error {
    glb_error(GlbErrorKind::Truncated {
        what,
        needed,
        available,
    })
}

fn property(element: &'static str, index: usize, property: &'static str) -> crate::Error {
    glb_error(GlbErrorKind::Property {
        element,
        index,
        property,
    })
}

fn rule(element: &'static str, index: usize, rule: &'static str) -> crate::Error {
    glb_error(GlbErrorKind::Rule {
        element,
        index,
        rule,
    })
}

fn read_u32(bytes: &[u8], at: usize, what: &'static str) -> Result<u32> {
    bytes
        .get(at..at + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .ok_or_else(|| truncated(what, at as u64 + 4, bytes.len() as u64))
}

fn list<'a>(root: &'a Value, key: &'static str) -> Result<&'a [Value]> {
    match root.get(key) {
        None => Ok(&[]),
        Some(Value::Array(a)) => Ok(a),
        Some(_) => Err(property("root", 0, key)),
    }
}

fn required_u64(v: &Value, element: &'static str, index: usize, key: &'static str) -> Result<u64> {
    v.get(key)
        .and_then(Value::as_u64)
        .ok_or_else(|| property(element, index, key))
}

fn optional_u64(
    v: &Value,
    element: &'static str,
    index: usize,
    key: &'static str,
) -> Result<Option<u64>> {
    match v.get(key) {
        None => Ok(None),
        Some(x) => x
            .as_u64()
            .map(Some)
            .ok_or_else(|| property(element, index, key)),
    }
}

fn reference(
    v: &Value,
    element: &'static str,
    index: usize,
    key: &'static str,
    count: usize,
) -> Result<Option<usize>> {
    match optional_u64(v, element, index, key)? {
        None => Ok(None),
        Some(value) if value < count as u64 => Ok(Some(value as usize)),
        Some(value) => Err(glb_error(GlbErrorKind::Reference {
            element,
            index,
            property: key,
            value,
            count,
        })),
    }
}

fn floats(
    v: &Value,
    element: &'static str,
    index: usize,
    key: &'static str,
) -> Result<Option<Vec<f64>>> {
    match v.get(key) {
        None => Ok(None),
        Some(Value::Array(a)) => a
            .iter()
            .map(|x| x.as_f64().ok_or_else(|| property(element, index, key)))
            .collect::<Result<_>>()
            .map(Some),
        Some(_) => Err(property(element, index, key)),
    }
}

/// A checked accessor: where its elements are and what they are.
#[derive(Debug, Clone)]
struct Accessor {
    component_type: u64,
    components: usize,
    type_name: String,
    count: u64,
    /// Absolute offset of the first element in the BIN chunk.
    start: usize,
    stride: usize,
    min: Option<Vec<f64>>,
    max: Option<Vec<f64>>,
}

impl Accessor {
    fn component(&self, bin: &[u8], element: u64, k: usize) -> f64 {
        let size = component_size(self.component_type).unwrap_or(4);
        let at = self.start + element as usize * self.stride + k * size;
        let b = &bin[at..at + size];
        match self.component_type {
            5120 => f64::from(b[0] as i8),
            5121 => f64::from(b[0]),
            5122 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            5123 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            5125 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            _ => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        }
    }
}

fn component_size(component_type: u64) -> Option<usize> {
    match component_type {
        5120 | 5121 => Some(1),
        5122 | 5123 => Some(2),
        5125 | 5126 => Some(4),
        _ => None,
    }
}

fn component_count(type_name: &str) -> Option<usize> {
    match type_name {
        "SCALAR" => Some(1),
        "VEC2" => Some(2),
        "VEC3" => Some(3),
        "VEC4" | "MAT2" => Some(4),
        "MAT3" => Some(9),
        "MAT4" => Some(16),
        _ => None,
    }
}

/// Parses a `.glb` and checks it.
///
/// Checked: the header (magic, version 2, length equal to the file's); the JSON chunk (type,
/// 4-byte padding, valid JSON, `asset.version` "2.0") and the BIN chunk (type, padding, the
/// buffer's `byteLength` equal to its content up to 3 padding bytes); every buffer view inside
/// the buffer; every accessor's type, component type, alignment and byte range inside its
/// buffer view, its `min`/`max` (required for `POSITION` and animation inputs) equal to the
/// data; every mesh primitive's attributes of one count and its indices in range; node
/// references, single parents and the absence of cycles; scenes listing root nodes; animation
/// samplers with strictly increasing non-negative times and output counts equal to input
/// counts (`LINEAR`, `STEP`) and output types matching their channel's path.
///
/// Each check is a function of its own, run in the file's order: `check_header`,
/// `split_chunks`, `parse_document`, `check_buffer`, `check_buffer_views`, `check_accessors`,
/// `check_meshes`, `check_nodes`, `check_scenes`, `check_animations`.
///
/// # Errors
/// [`crate::Error::InvalidGlb`] with the first rule found broken.
pub fn validate_glb(bytes: &[u8]) -> Result<GlbSummary> {
    check_header(bytes)?;
    let (json_bytes, bin) = split_chunks(bytes)?;
    let root = parse_document(json_bytes)?;
    let buffer_length = check_buffer(&root, bin)?;
    let views = check_buffer_views(&root, buffer_length)?;
    let accessors = check_accessors(&root, &views, bin)?;
    let materials = list(&root, "materials")?.len();
    let meshes = check_meshes(&root, &accessors, materials, bin)?;
    let nodes = check_nodes(&root, meshes.count)?;
    check_scenes(&root, &nodes.parents)?;
    let animations = check_animations(&root, &accessors, nodes.parents.len(), bin)?;
    Ok(GlbSummary {
        json_length: json_bytes.len() as u64,
        bin_length: bin.len() as u64,
        buffer_length,
        node_names: nodes.names,
        node_parents: nodes.parents,
        meshes: meshes.count,
        materials,
        accessors: accessors.len(),
        buffer_views: views.len(),
        triangles: meshes.triangles,
        vertices: meshes.vertices,
        coloured_primitives: meshes.coloured_primitives,
        animations,
    })
}

/// The 12-byte header: magic `glTF`, version 2, and a total length equal to the file's.
fn check_header(bytes: &[u8]) -> Result<()> {
    if bytes.len() < 12 {
        return Err(truncated("header", 12, bytes.len() as u64));
    }
    if read_u32(bytes, 0, "header")? != GLB_MAGIC {
        return Err(glb_error(GlbErrorKind::BadMagic));
    }
    let version = read_u32(bytes, 4, "header")?;
    if version != 2 {
        return Err(glb_error(GlbErrorKind::Version { version }));
    }
    let length = u64::from(read_u32(bytes, 8, "header")?);
    if length != bytes.len() as u64 {
        return Err(glb_error(GlbErrorKind::LengthMismatch {
            header: length,
            actual: bytes.len() as u64,
        }));
    }
    Ok(())
}

/// The chunks after the header: a JSON chunk, then at most one BIN chunk, each of a length
/// that is a multiple of 4. Returns the JSON chunk's data and the BIN chunk's (empty when
/// absent).
fn split_chunks(bytes: &[u8]) -> Result<(&[u8], &[u8])> {
    let mut chunks: Vec<&[u8]> = Vec::new();
    let mut at = 12usize;
    while at < bytes.len() {
        let chunk_length = read_u32(bytes, at, "chunk header")? as usize;
        let chunk_type = read_u32(bytes, at + 4, "chunk header")?;
        let end = at + 8 + chunk_length;
        let data = bytes
            .get(at + 8..end)
            .ok_or_else(|| truncated("chunk", end as u64, bytes.len() as u64))?;
        let index = chunks.len();
        let chunk_rule = |reason| {
            glb_error(GlbErrorKind::Chunk {
                index,
                chunk_type,
                length: chunk_length as u64,
                reason,
            })
        };
        if !chunk_length.is_multiple_of(4) {
            return Err(chunk_rule("length is not a multiple of 4"));
        }
        match (index, chunk_type) {
            (0, CHUNK_JSON) | (1, CHUNK_BIN) => {}
            (0, _) => return Err(chunk_rule("the first chunk must be JSON")),
            (1, _) => return Err(chunk_rule("the second chunk must be BIN")),
            _ => return Err(chunk_rule("this writer never emits more than two chunks")),
        }
        chunks.push(data);
        at = end;
    }
    let json = chunks
        .first()
        .copied()
        .ok_or_else(|| truncated("JSON chunk", 20, bytes.len() as u64))?;
    Ok((json, chunks.get(1).copied().unwrap_or(&[])))
}

/// The JSON chunk parsed, with `asset.version` "2.0".
fn parse_document(json_bytes: &[u8]) -> Result<Value> {
    let root: Value = serde_json::from_slice(json_bytes).map_err(|e| {
        glb_error(GlbErrorKind::Json {
            detail: e.to_string(),
        })
    })?;
    if root
        .get("asset")
        .and_then(|a| a.get("version"))
        .and_then(Value::as_str)
        != Some("2.0")
    {
        return Err(property("asset", 0, "version"));
    }
    Ok(root)
}

/// The buffers: none (then no BIN chunk), or the one GLB-stored buffer (no `uri`) whose
/// `byteLength` is the BIN chunk's content up to 3 padding bytes. Returns that length (0
/// without a buffer).
fn check_buffer(root: &Value, bin: &[u8]) -> Result<u64> {
    match list(root, "buffers")? {
        [] => {
            if !bin.is_empty() {
                return Err(rule(
                    "buffer",
                    0,
                    "a BIN chunk is present but no buffer describes it",
                ));
            }
            Ok(0)
        }
        [buffer] => {
            if buffer.get("uri").is_some() {
                return Err(rule("buffer", 0, "the GLB buffer must not have a uri"));
            }
            let n = required_u64(buffer, "buffer", 0, "byteLength")?;
            if n > bin.len() as u64 || bin.len() as u64 - n > 3 {
                return Err(rule(
                    "buffer",
                    0,
                    "byteLength must equal the BIN chunk's content (up to 3 padding bytes)",
                ));
            }
            Ok(n)
        }
        _ => Err(rule("buffer", 1, "only the GLB-stored buffer is supported")),
    }
}

/// A checked buffer view: where it is in the buffer.
#[derive(Debug, Clone, Copy, PartialEq)]
struct View {
    offset: u64,
    length: u64,
    stride: Option<u64>,
}

/// Every buffer view: refers to the (only) buffer, is not empty, lies inside the buffer of
/// `buffer_length` bytes, has a stride that is a multiple of 4 in [4, 252] and a vertex or
/// index target.
fn check_buffer_views(root: &Value, buffer_length: u64) -> Result<Vec<View>> {
    let buffers = list(root, "buffers")?.len();
    let mut views = Vec::new();
    for (i, v) in list(root, "bufferViews")?.iter().enumerate() {
        reference(v, "bufferView", i, "buffer", buffers)?
            .ok_or_else(|| property("bufferView", i, "buffer"))?;
        let offset = optional_u64(v, "bufferView", i, "byteOffset")?.unwrap_or(0);
        let length = required_u64(v, "bufferView", i, "byteLength")?;
        if length == 0 {
            return Err(rule("bufferView", i, "byteLength must be at least 1"));
        }
        if offset.saturating_add(length) > buffer_length {
            return Err(glb_error(GlbErrorKind::Range {
                element: "bufferView",
                index: i,
                start: offset,
                end: offset.saturating_add(length),
                container: buffer_length,
            }));
        }
        let stride = optional_u64(v, "bufferView", i, "byteStride")?;
        if let Some(s) = stride
            && !((4..=252).contains(&s) && s % 4 == 0)
        {
            return Err(rule(
                "bufferView",
                i,
                "byteStride must be a multiple of 4 in [4, 252]",
            ));
        }
        if let Some(t) = optional_u64(v, "bufferView", i, "target")?
            && t != 34962
            && t != 34963
        {
            return Err(rule(
                "bufferView",
                i,
                "target must be ARRAY_BUFFER or ELEMENT_ARRAY_BUFFER",
            ));
        }
        views.push(View {
            offset,
            length,
            stride,
        });
    }
    Ok(views)
}

/// Every accessor, checked by [`check_accessor`].
fn check_accessors(root: &Value, views: &[View], bin: &[u8]) -> Result<Vec<Accessor>> {
    list(root, "accessors")?
        .iter()
        .enumerate()
        .map(|(i, a)| check_accessor(i, a, views, bin))
        .collect()
}

/// Accessor `i`: in a buffer view, of a known component type and type, not empty, aligned to
/// its component size, with a stride that holds an element, inside its view, and with `min` and
/// `max` (together or neither) equal to the data ([`check_min_max`]).
fn check_accessor(i: usize, a: &Value, views: &[View], bin: &[u8]) -> Result<Accessor> {
    let view = reference(a, "accessor", i, "bufferView", views.len())?.ok_or_else(|| {
        rule(
            "accessor",
            i,
            "accessors without a bufferView are not supported",
        )
    })?;
    let component_type = required_u64(a, "accessor", i, "componentType")?;
    let size =
        component_size(component_type).ok_or_else(|| property("accessor", i, "componentType"))?;
    let type_name = a
        .get("type")
        .and_then(Value::as_str)
        .ok_or_else(|| property("accessor", i, "type"))?;
    let components = component_count(type_name).ok_or_else(|| property("accessor", i, "type"))?;
    let count = required_u64(a, "accessor", i, "count")?;
    if count == 0 {
        return Err(rule("accessor", i, "count must be at least 1"));
    }
    let offset = optional_u64(a, "accessor", i, "byteOffset")?.unwrap_or(0);
    let view = views[view];
    if offset % size as u64 != 0 || !(view.offset + offset).is_multiple_of(size as u64) {
        return Err(rule(
            "accessor",
            i,
            "byteOffset must be a multiple of the component size",
        ));
    }
    let element = (size * components) as u64;
    let stride = view.stride.unwrap_or(element);
    if stride < element {
        return Err(rule(
            "accessor",
            i,
            "the buffer view's byteStride is smaller than an element",
        ));
    }
    let end = offset
        .saturating_add(stride.saturating_mul(count - 1))
        .saturating_add(element);
    if end > view.length {
        return Err(glb_error(GlbErrorKind::Range {
            element: "accessor",
            index: i,
            start: offset,
            end,
            container: view.length,
        }));
    }
    let accessor = Accessor {
        component_type,
        components,
        type_name: type_name.to_owned(),
        count,
        start: (view.offset + offset) as usize,
        stride: stride as usize,
        min: floats(a, "accessor", i, "min")?,
        max: floats(a, "accessor", i, "max")?,
    };
    check_min_max(i, &accessor, bin)?;
    Ok(accessor)
}

/// Accessor `i`'s `min` and `max`: both or neither, one value per component, equal (in f32)
/// to the smallest and largest value of each component in the data.
fn check_min_max(i: usize, accessor: &Accessor, bin: &[u8]) -> Result<()> {
    let (lo, hi) = match (&accessor.min, &accessor.max) {
        (Some(lo), Some(hi)) => (lo, hi),
        (None, None) => return Ok(()),
        _ => return Err(rule("accessor", i, "min and max come together")),
    };
    let components = accessor.components;
    if lo.len() != components || hi.len() != components {
        return Err(rule(
            "accessor",
            i,
            "min and max need one value per component",
        ));
    }
    for k in 0..components {
        let (mut dlo, mut dhi) = (f64::INFINITY, f64::NEG_INFINITY);
        for e in 0..accessor.count {
            let v = accessor.component(bin, e, k);
            dlo = dlo.min(v);
            dhi = dhi.max(v);
        }
        // Compared in f32 (the data's precision): JSON parsers may miss the exact f64 by an
        // ulp, which the f32 rounding absorbs.
        if dlo as f32 != lo[k] as f32 || dhi as f32 != hi[k] as f32 {
            return Err(rule("accessor", i, "min/max do not match the data"));
        }
    }
    Ok(())
}

/// Totals over every mesh primitive.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct MeshTotals {
    /// Number of meshes.
    count: usize,
    triangles: u64,
    vertices: u64,
    coloured_primitives: usize,
}

/// Every mesh: at least one primitive, each checked by [`check_primitive`].
fn check_meshes(
    root: &Value,
    accessors: &[Accessor],
    materials: usize,
    bin: &[u8],
) -> Result<MeshTotals> {
    let meshes = list(root, "meshes")?;
    let mut totals = MeshTotals {
        count: meshes.len(),
        ..MeshTotals::default()
    };
    for (m, mesh) in meshes.iter().enumerate() {
        let primitives = mesh
            .get("primitives")
            .and_then(Value::as_array)
            .filter(|p| !p.is_empty())
            .ok_or_else(|| property("mesh", m, "primitives"))?;
        for p in primitives {
            check_primitive(m, p, accessors, materials, bin, &mut totals)?;
        }
    }
    Ok(totals)
}

/// One primitive of mesh `m`: attributes referring to accessors of one count, a float VEC3
/// `POSITION` with min and max, unit `NORMAL`s, a material in range, unsigned integer indices
/// below the vertex count and, for triangle lists, a multiple of 3 corners. Adds its
/// triangles, vertices and colour to `totals`.
fn check_primitive(
    m: usize,
    p: &Value,
    accessors: &[Accessor],
    materials: usize,
    bin: &[u8],
    totals: &mut MeshTotals,
) -> Result<()> {
    let attributes = p
        .get("attributes")
        .and_then(Value::as_object)
        .ok_or_else(|| property("mesh", m, "attributes"))?;
    let mut vertex_count = None;
    for (name, value) in attributes {
        let index = value
            .as_u64()
            .filter(|&x| x < accessors.len() as u64)
            .ok_or_else(|| rule("mesh", m, "an attribute refers to a missing accessor"))?
            as usize;
        let a = &accessors[index];
        if *vertex_count.get_or_insert(a.count) != a.count {
            return Err(rule(
                "mesh",
                m,
                "attributes of a primitive must have the same count",
            ));
        }
        if name == "POSITION"
            && (a.type_name != "VEC3" || a.component_type != 5126 || a.min.is_none())
        {
            return Err(rule(
                "mesh",
                m,
                "POSITION must be a float VEC3 accessor with min and max",
            ));
        }
        if name == "NORMAL" {
            for e in 0..a.count {
                let n: f64 = (0..3)
                    .map(|k| a.component(bin, e, k).powi(2))
                    .sum::<f64>()
                    .sqrt();
                if (n - 1.0).abs() > 1e-3 {
                    return Err(rule("mesh", m, "NORMAL values must be unit vectors"));
                }
            }
        }
        if name == "COLOR_0" {
            totals.coloured_primitives += 1;
        }
    }
    let vertex_count = attributes
        .get("POSITION")
        .and(vertex_count)
        .ok_or_else(|| property("mesh", m, "POSITION"))?;
    reference(p, "mesh", m, "material", materials)?;
    let mode = optional_u64(p, "mesh", m, "mode")?.unwrap_or(4);
    let corner_count = match reference(p, "mesh", m, "indices", accessors.len())? {
        Some(k) => {
            let a = &accessors[k];
            if a.type_name != "SCALAR" || !matches!(a.component_type, 5121 | 5123 | 5125) {
                return Err(rule("mesh", m, "indices must be unsigned integer scalars"));
            }
            if (0..a.count).any(|e| a.component(bin, e, 0) as u64 >= vertex_count) {
                return Err(rule("mesh", m, "an index is not below the vertex count"));
            }
            a.count
        }
        None => vertex_count,
    };
    if mode == 4 {
        if corner_count % 3 != 0 {
            return Err(rule(
                "mesh",
                m,
                "a triangle list needs a multiple of 3 corners",
            ));
        }
        totals.triangles += corner_count / 3;
    }
    totals.vertices += vertex_count;
    Ok(())
}

/// The node hierarchy: names and parents, in node order.
#[derive(Debug, Clone, PartialEq)]
struct Nodes {
    names: Vec<Option<String>>,
    parents: Vec<Option<usize>>,
}

/// Every node: a mesh in range, a 3-vector translation, a unit quaternion rotation, children
/// in range with one parent each; then no cycle ([`check_acyclic`]).
fn check_nodes(root: &Value, mesh_count: usize) -> Result<Nodes> {
    let nodes = list(root, "nodes")?;
    let mut parents: Vec<Option<usize>> = vec![None; nodes.len()];
    let mut names = Vec::with_capacity(nodes.len());
    for (i, node) in nodes.iter().enumerate() {
        reference(node, "node", i, "mesh", mesh_count)?;
        if let Some(t) = floats(node, "node", i, "translation")?
            && t.len() != 3
        {
            return Err(property("node", i, "translation"));
        }
        if let Some(q) = floats(node, "node", i, "rotation")? {
            let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if q.len() != 4 || (norm - 1.0).abs() > 1e-6 {
                return Err(rule("node", i, "rotation must be a unit quaternion"));
            }
        }
        if let Some(children) = node.get("children") {
            let children = children
                .as_array()
                .ok_or_else(|| property("node", i, "children"))?;
            for c in children {
                let c = c.as_u64().ok_or_else(|| property("node", i, "children"))?;
                if c >= nodes.len() as u64 {
                    return Err(glb_error(GlbErrorKind::Reference {
                        element: "node",
                        index: i,
                        property: "children",
                        value: c,
                        count: nodes.len(),
                    }));
                }
                if parents[c as usize].replace(i).is_some() {
                    return Err(rule("node", c as usize, "a node has more than one parent"));
                }
            }
        }
        names.push(node.get("name").and_then(Value::as_str).map(str::to_owned));
    }
    check_acyclic(&parents)?;
    Ok(Nodes { names, parents })
}

/// No node is its own ancestor: following parents from any node ends at a root.
fn check_acyclic(parents: &[Option<usize>]) -> Result<()> {
    for start in 0..parents.len() {
        let (mut at, mut steps) = (start, 0);
        while let Some(p) = parents[at] {
            at = p;
            steps += 1;
            if steps > parents.len() {
                return Err(rule("node", start, "the node hierarchy has a cycle"));
            }
        }
    }
    Ok(())
}

/// Every scene lists existing root nodes.
fn check_scenes(root: &Value, parents: &[Option<usize>]) -> Result<()> {
    for (s, scene) in list(root, "scenes")?.iter().enumerate() {
        for n in floats(scene, "scene", s, "nodes")?.unwrap_or_default() {
            let n = n as usize;
            if n >= parents.len() || parents[n].is_some() {
                return Err(rule("scene", s, "scene nodes must be existing root nodes"));
            }
        }
    }
    Ok(())
}

/// What a checked sampler tells its channels.
#[derive(Debug, Clone, PartialEq)]
struct Sampler {
    /// Keyframes (input count).
    samples: u64,
    /// Output accessor type (`VEC3`, …).
    output_type: String,
    /// Output component type.
    output_component_type: u64,
    /// Last keyframe time (s).
    end: f64,
}

/// Every animation: its samplers ([`check_sampler`]) and channels ([`check_channel`]).
fn check_animations(
    root: &Value,
    accessors: &[Accessor],
    node_count: usize,
    bin: &[u8],
) -> Result<Vec<AnimationSummary>> {
    let mut animations = Vec::new();
    for (a, animation) in list(root, "animations")?.iter().enumerate() {
        let samplers = animation
            .get("samplers")
            .and_then(Value::as_array)
            .ok_or_else(|| property("animation", a, "samplers"))?
            .iter()
            .enumerate()
            .map(|(s, sampler)| check_sampler(a, s, sampler, accessors, bin))
            .collect::<Result<Vec<_>>>()?;
        let duration = samplers.iter().fold(0.0_f64, |d, s| d.max(s.end));
        let channels_json = animation
            .get("channels")
            .and_then(Value::as_array)
            .ok_or_else(|| property("animation", a, "channels"))?;
        let mut channels: Vec<ChannelSummary> = Vec::with_capacity(channels_json.len());
        for (c, channel) in channels_json.iter().enumerate() {
            let summary = check_channel(c, channel, &samplers, node_count)?;
            if channels
                .iter()
                .any(|other| other.node == summary.node && other.path == summary.path)
            {
                return Err(rule(
                    "animation channel",
                    c,
                    "two channels target the same node and path",
                ));
            }
            channels.push(summary);
        }
        let name = animation
            .get("name")
            .and_then(Value::as_str)
            .map(str::to_owned);
        animations.push(AnimationSummary {
            name,
            duration,
            channels,
        });
    }
    Ok(animations)
}

/// Sampler `s` of animation `a`: float scalar input times with min and max, non-negative and
/// strictly increasing; a known interpolation; as many outputs as it needs.
fn check_sampler(
    a: usize,
    s: usize,
    sampler: &Value,
    accessors: &[Accessor],
    bin: &[u8],
) -> Result<Sampler> {
    let input = reference(sampler, "animation sampler", s, "input", accessors.len())?
        .ok_or_else(|| property("animation sampler", s, "input"))?;
    let output = reference(sampler, "animation sampler", s, "output", accessors.len())?
        .ok_or_else(|| property("animation sampler", s, "output"))?;
    let (input, output) = (&accessors[input], &accessors[output]);
    if input.type_name != "SCALAR" || input.component_type != 5126 || input.min.is_none() {
        return Err(rule(
            "animation sampler",
            s,
            "input must be float scalars with min and max",
        ));
    }
    let mut previous = -1.0;
    for e in 0..input.count {
        let t = input.component(bin, e, 0);
        if !(t >= 0.0 && t > previous) {
            return Err(rule(
                "animation sampler",
                s,
                "input times must be non-negative and strictly increasing",
            ));
        }
        previous = t;
    }
    let interpolation = sampler
        .get("interpolation")
        .and_then(Value::as_str)
        .unwrap_or("LINEAR");
    let expected = match interpolation {
        "LINEAR" | "STEP" => input.count,
        "CUBICSPLINE" => 3 * input.count,
        _ => return Err(property("animation sampler", s, "interpolation")),
    };
    if output.count != expected {
        return Err(glb_error(GlbErrorKind::SamplerCounts {
            animation: a,
            sampler: s,
            input: input.count,
            output: output.count,
        }));
    }
    Ok(Sampler {
        samples: input.count,
        output_type: output.type_name.clone(),
        output_component_type: output.component_type,
        end: previous,
    })
}

/// Channel `c`: a sampler and a target node in range, and a target path whose type the
/// sampler's output matches (float VEC3 for translation and scale, VEC4 for rotation, SCALAR
/// for weights).
fn check_channel(
    c: usize,
    channel: &Value,
    samplers: &[Sampler],
    node_count: usize,
) -> Result<ChannelSummary> {
    let s = reference(channel, "animation channel", c, "sampler", samplers.len())?
        .ok_or_else(|| property("animation channel", c, "sampler"))?;
    let target = channel
        .get("target")
        .ok_or_else(|| property("animation channel", c, "target"))?;
    let node = reference(target, "animation channel", c, "node", node_count)?
        .ok_or_else(|| property("animation channel", c, "node"))?;
    let path = target
        .get("path")
        .and_then(Value::as_str)
        .ok_or_else(|| property("animation channel", c, "path"))?;
    let sampler = &samplers[s];
    let output_type = sampler.output_type.as_str();
    let ok = match path {
        "translation" | "scale" => output_type == "VEC3" && sampler.output_component_type == 5126,
        "rotation" => output_type == "VEC4",
        "weights" => output_type == "SCALAR",
        _ => return Err(property("animation channel", c, "path")),
    };
    if !ok {
        return Err(rule(
            "animation channel",
            c,
            "the output type does not match the target path",
        ));
    }
    Ok(ChannelSummary {
        node,
        path: path.to_owned(),
        samples: sampler.samples,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
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
        let root = |view: serde_json::Value| json!({"buffers": [{"byteLength": 16}], "bufferViews": [view]});
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
        assert!(
            message(check_accessor(0, &no_view, &views, &bin)).contains("without a bufferView")
        );
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
        assert!(
            message(check_scenes(&child_scene, &nodes.parents)).contains("existing root nodes")
        );
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
        let sampler = check_sampler(0, 0, &json!({"input": 0, "output": 1}), &accessors, &bin)
            .expect("valid");
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
        assert!(
            message(check_animations(&root, &accessors, 1, &bin)).contains("same node and path")
        );
    }
}
