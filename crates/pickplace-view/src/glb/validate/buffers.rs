//! The binary data: the buffer, its buffer views and the accessors that read them.

use super::fields::{floats, list, optional_u64, property, reference, required_u64, rule};
use crate::error::{GlbErrorKind, Result, glb_error};
use serde_json::Value;

/// A checked accessor: where its elements are and what they are.
#[derive(Debug, Clone)]
pub(super) struct Accessor {
    pub(super) component_type: u64,
    pub(super) components: usize,
    pub(super) type_name: String,
    pub(super) count: u64,
    /// Absolute offset of the first element in the BIN chunk.
    pub(super) start: usize,
    pub(super) stride: usize,
    pub(super) min: Option<Vec<f64>>,
    pub(super) max: Option<Vec<f64>>,
}

impl Accessor {
    pub(super) fn component(&self, bin: &[u8], element: u64, k: usize) -> f64 {
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

/// The buffers: none (then no BIN chunk), or the one GLB-stored buffer (no `uri`) whose
/// `byteLength` is the BIN chunk's content up to 3 padding bytes. Returns that length (0
/// without a buffer).
pub(super) fn check_buffer(root: &Value, bin: &[u8]) -> Result<u64> {
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
pub(super) struct View {
    pub(super) offset: u64,
    pub(super) length: u64,
    pub(super) stride: Option<u64>,
}

/// Every buffer view: refers to the (only) buffer, is not empty, lies inside the buffer of
/// `buffer_length` bytes, has a stride that is a multiple of 4 in [4, 252] and a vertex or
/// index target.
pub(super) fn check_buffer_views(root: &Value, buffer_length: u64) -> Result<Vec<View>> {
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
pub(super) fn check_accessors(root: &Value, views: &[View], bin: &[u8]) -> Result<Vec<Accessor>> {
    list(root, "accessors")?
        .iter()
        .enumerate()
        .map(|(i, a)| check_accessor(i, a, views, bin))
        .collect()
}

/// Accessor `i`: in a buffer view, of a known component type and type, not empty, aligned to
/// its component size, with a stride that holds an element, inside its view, and with `min` and
/// `max` (together or neither) equal to the data ([`check_min_max`]).
pub(super) fn check_accessor(i: usize, a: &Value, views: &[View], bin: &[u8]) -> Result<Accessor> {
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
