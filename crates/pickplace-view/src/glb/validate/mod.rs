//! Reads a `.glb` back and checks the glTF 2.0 rules this crate relies on.
//!
//! Each concern has its own module, in the order [`validate_glb`] runs them: `container` (the
//! header, the chunks and the JSON document), `buffers` (the buffer, buffer views and
//! accessors), `meshes`, `nodes` (the hierarchy and the scenes) and `animations`; `fields`
//! reads the typed JSON properties they all share.

mod animations;
mod buffers;
mod container;
mod fields;
mod meshes;
mod nodes;
#[cfg(test)]
mod tests;

use crate::error::Result;
use animations::check_animations;
use buffers::{check_accessors, check_buffer, check_buffer_views};
use container::{check_header, parse_document, split_chunks};
use fields::list;
use meshes::check_meshes;
use nodes::{check_nodes, check_scenes};

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
