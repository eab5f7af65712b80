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
/// # Errors
/// [`crate::Error::InvalidGlb`] with the first rule found broken.
pub fn validate_glb(bytes: &[u8]) -> Result<GlbSummary> {
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
    let mut chunks: Vec<(u32, &[u8])> = Vec::new();
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
        chunks.push((chunk_type, data));
        at = end;
    }
    let json_bytes = chunks
        .first()
        .map(|c| c.1)
        .ok_or_else(|| truncated("JSON chunk", 20, bytes.len() as u64))?;
    let bin: &[u8] = chunks.get(1).map_or(&[], |c| c.1);
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

    // Buffer.
    let buffers = list(&root, "buffers")?;
    let buffer_length = match buffers {
        [] => {
            if !bin.is_empty() {
                return Err(rule(
                    "buffer",
                    0,
                    "a BIN chunk is present but no buffer describes it",
                ));
            }
            0
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
            n
        }
        _ => return Err(rule("buffer", 1, "only the GLB-stored buffer is supported")),
    };

    // Buffer views: (offset, length, stride).
    let mut views = Vec::new();
    for (i, v) in list(&root, "bufferViews")?.iter().enumerate() {
        reference(v, "bufferView", i, "buffer", buffers.len())?
            .ok_or_else(|| property("bufferView", i, "buffer"))?;
        let offset = optional_u64(v, "bufferView", i, "byteOffset")?.unwrap_or(0);
        let len = required_u64(v, "bufferView", i, "byteLength")?;
        if len == 0 {
            return Err(rule("bufferView", i, "byteLength must be at least 1"));
        }
        if offset.saturating_add(len) > buffer_length {
            return Err(glb_error(GlbErrorKind::Range {
                element: "bufferView",
                index: i,
                start: offset,
                end: offset.saturating_add(len),
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
        views.push((offset, len, stride));
    }

    // Accessors.
    let mut accessors = Vec::new();
    for (i, a) in list(&root, "accessors")?.iter().enumerate() {
        let view = reference(a, "accessor", i, "bufferView", views.len())?.ok_or_else(|| {
            rule(
                "accessor",
                i,
                "accessors without a bufferView are not supported",
            )
        })?;
        let component_type = required_u64(a, "accessor", i, "componentType")?;
        let size = component_size(component_type)
            .ok_or_else(|| property("accessor", i, "componentType"))?;
        let type_name = a
            .get("type")
            .and_then(Value::as_str)
            .ok_or_else(|| property("accessor", i, "type"))?;
        let components =
            component_count(type_name).ok_or_else(|| property("accessor", i, "type"))?;
        let count = required_u64(a, "accessor", i, "count")?;
        if count == 0 {
            return Err(rule("accessor", i, "count must be at least 1"));
        }
        let offset = optional_u64(a, "accessor", i, "byteOffset")?.unwrap_or(0);
        let (view_offset, view_length, view_stride) = views[view];
        if offset % size as u64 != 0 || (view_offset + offset) % size as u64 != 0 {
            return Err(rule(
                "accessor",
                i,
                "byteOffset must be a multiple of the component size",
            ));
        }
        let element = (size * components) as u64;
        let stride = view_stride.unwrap_or(element);
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
        if end > view_length {
            return Err(glb_error(GlbErrorKind::Range {
                element: "accessor",
                index: i,
                start: offset,
                end,
                container: view_length,
            }));
        }
        let min = floats(a, "accessor", i, "min")?;
        let max = floats(a, "accessor", i, "max")?;
        let accessor = Accessor {
            component_type,
            components,
            type_name: type_name.to_owned(),
            count,
            start: (view_offset + offset) as usize,
            stride: stride as usize,
            min,
            max,
        };
        if let (Some(lo), Some(hi)) = (&accessor.min, &accessor.max) {
            if lo.len() != components || hi.len() != components {
                return Err(rule(
                    "accessor",
                    i,
                    "min and max need one value per component",
                ));
            }
            for k in 0..components {
                let (mut dlo, mut dhi) = (f64::INFINITY, f64::NEG_INFINITY);
                for e in 0..count {
                    let v = accessor.component(bin, e, k);
                    dlo = dlo.min(v);
                    dhi = dhi.max(v);
                }
                // Compared in f32 (the data's precision): JSON parsers may miss the exact f64 by
                // an ulp, which the f32 rounding absorbs.
                if dlo as f32 != lo[k] as f32 || dhi as f32 != hi[k] as f32 {
                    return Err(rule("accessor", i, "min/max do not match the data"));
                }
            }
        } else if accessor.min.is_some() || accessor.max.is_some() {
            return Err(rule("accessor", i, "min and max come together"));
        }
        accessors.push(accessor);
    }

    // Materials and meshes.
    let materials = list(&root, "materials")?.len();
    let meshes = list(&root, "meshes")?;
    let (mut triangles, mut vertices, mut coloured_primitives) = (0u64, 0u64, 0usize);
    for (m, mesh) in meshes.iter().enumerate() {
        let primitives = mesh
            .get("primitives")
            .and_then(Value::as_array)
            .filter(|p| !p.is_empty())
            .ok_or_else(|| property("mesh", m, "primitives"))?;
        for p in primitives {
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
                    coloured_primitives += 1;
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
                triangles += corner_count / 3;
            }
            vertices += vertex_count;
        }
    }

    // Nodes.
    let nodes = list(&root, "nodes")?;
    let mut parents: Vec<Option<usize>> = vec![None; nodes.len()];
    let mut node_names = Vec::with_capacity(nodes.len());
    for (i, node) in nodes.iter().enumerate() {
        reference(node, "node", i, "mesh", meshes.len())?;
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
        node_names.push(node.get("name").and_then(Value::as_str).map(str::to_owned));
    }
    for start in 0..nodes.len() {
        let (mut at, mut steps) = (start, 0);
        while let Some(p) = parents[at] {
            at = p;
            steps += 1;
            if steps > nodes.len() {
                return Err(rule("node", start, "the node hierarchy has a cycle"));
            }
        }
    }
    for (s, scene) in list(&root, "scenes")?.iter().enumerate() {
        for n in floats(scene, "scene", s, "nodes")?.unwrap_or_default() {
            let n = n as usize;
            if n >= nodes.len() || parents[n].is_some() {
                return Err(rule("scene", s, "scene nodes must be existing root nodes"));
            }
        }
    }

    // Animations.
    let mut animations = Vec::new();
    for (a, animation) in list(&root, "animations")?.iter().enumerate() {
        let samplers = animation
            .get("samplers")
            .and_then(Value::as_array)
            .ok_or_else(|| property("animation", a, "samplers"))?;
        let mut duration: f64 = 0.0;
        let mut sampler_info = Vec::with_capacity(samplers.len());
        for (s, sampler) in samplers.iter().enumerate() {
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
            duration = duration.max(previous);
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
            sampler_info.push((
                input.count,
                output.type_name.clone(),
                output.components,
                output.component_type,
            ));
        }
        let channels_json = animation
            .get("channels")
            .and_then(Value::as_array)
            .ok_or_else(|| property("animation", a, "channels"))?;
        let mut channels: Vec<ChannelSummary> = Vec::with_capacity(channels_json.len());
        for (c, channel) in channels_json.iter().enumerate() {
            let s = reference(channel, "animation channel", c, "sampler", samplers.len())?
                .ok_or_else(|| property("animation channel", c, "sampler"))?;
            let target = channel
                .get("target")
                .ok_or_else(|| property("animation channel", c, "target"))?;
            let node = reference(target, "animation channel", c, "node", nodes.len())?
                .ok_or_else(|| property("animation channel", c, "node"))?;
            let path = target
                .get("path")
                .and_then(Value::as_str)
                .ok_or_else(|| property("animation channel", c, "path"))?;
            let (samples, ref output_type, _, component_type) = sampler_info[s];
            let ok = match path {
                "translation" | "scale" => output_type == "VEC3" && component_type == 5126,
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
            if channels
                .iter()
                .any(|other| other.node == node && other.path == path)
            {
                return Err(rule(
                    "animation channel",
                    c,
                    "two channels target the same node and path",
                ));
            }
            channels.push(ChannelSummary {
                node,
                path: path.to_owned(),
                samples,
            });
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

    Ok(GlbSummary {
        json_length: json_bytes.len() as u64,
        bin_length: bin.len() as u64,
        buffer_length,
        node_names,
        node_parents: parents,
        meshes: meshes.len(),
        materials,
        accessors: accessors.len(),
        buffer_views: views.len(),
        triangles,
        vertices,
        coloured_primitives,
        animations,
    })
}
