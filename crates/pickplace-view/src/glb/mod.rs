//! A glTF 2.0 binary (`.glb`) writer: flat-shaded meshes, a node hierarchy with local
//! transforms, and one animation of per-node translation and rotation tracks; plus a validator
//! that reads a `.glb` back ([`validate_glb`]).
//!
//! Layout of the file written: the 12-byte header (`glTF`, version 2, total length), a JSON
//! chunk padded with spaces to 4 bytes, and a BIN chunk (when there is any data) padded with
//! zeros. Every accessor has its own buffer view, 4-byte aligned, tightly packed. Meshes are
//! flat: each triangle gets its own three vertices, so that its normal (and, for per-triangle
//! paint, its `COLOR_0`) is constant over it.

mod validate;

pub use validate::{AnimationSummary, ChannelSummary, GlbSummary, validate_glb};

use crate::error::{Error, GltfErrorKind, Result};
use crate::image::Colour;
use crate::scene::{Geometry, Paint, Scene, check_pose};
use pickplace_geometry::export::write_atomic;
use pickplace_geometry::math::{Isometry3, UnitQuaternion, Vector3};
use serde_json::{Value, json};
use std::path::Path;
use std::sync::Arc;

/// `glTF` in little-endian.
pub(crate) const GLB_MAGIC: u32 = 0x4654_6C67;
/// `JSON` chunk type.
pub(crate) const CHUNK_JSON: u32 = 0x4E4F_534A;
/// `BIN\0` chunk type.
pub(crate) const CHUNK_BIN: u32 = 0x004E_4942;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

/// Index of a mesh in a [`GltfBuilder`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MeshId(usize);

impl MeshId {
    /// The index in the glTF `meshes` array.
    pub fn index(self) -> usize {
        self.0
    }
}

/// Index of a node in a [`GltfBuilder`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(usize);

impl NodeId {
    /// The index in the glTF `nodes` array.
    pub fn index(self) -> usize {
        self.0
    }
}

/// A mesh flattened for glTF: three vertices per triangle.
#[derive(Debug, Clone)]
struct FlatMesh {
    name: String,
    positions: Vec<f32>,
    normals: Vec<f32>,
    /// Linear-light RGB per vertex, for per-triangle paint.
    colours: Option<Vec<f32>>,
    /// Linear-light base colour.
    base_colour: [f64; 3],
    /// For sharing between instances of [`GltfBuilder::from_scene`].
    source: Option<(Arc<Geometry>, Paint)>,
}

#[derive(Debug, Clone)]
struct Node {
    name: String,
    mesh: Option<MeshId>,
    parent: Option<NodeId>,
    translation: [f64; 3],
    rotation: [f64; 4],
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TrackPath {
    Translation,
    Rotation,
}

impl TrackPath {
    fn name(self) -> &'static str {
        match self {
            TrackPath::Translation => "translation",
            TrackPath::Rotation => "rotation",
        }
    }
}

#[derive(Debug, Clone)]
struct Track {
    node: NodeId,
    path: TrackPath,
    times: Vec<f32>,
    /// 3 (translation) or 4 (rotation, xyzw) floats per keyframe.
    values: Vec<f32>,
}

/// Builds a glTF 2.0 document and encodes it as `.glb`.
///
/// # Example
/// ```
/// use pickplace_geometry::math::{Isometry3, UnitQuaternion, Vector3};
/// use pickplace_geometry::shapes::box_mesh;
/// use pickplace_view::glb::{GltfBuilder, validate_glb};
/// use pickplace_view::{Colour, Geometry, Paint};
///
/// let mut gltf = GltfBuilder::new("plan");
/// let cube = Geometry::from_trimesh(&box_mesh([0.05, 0.05, 0.05]));
/// let mesh = gltf.add_mesh("cube", &cube, &Paint::Uniform(Colour::ORANGE))?;
/// let node = gltf.add_node("object", Some(mesh), None, &Isometry3::identity())?;
/// let poses: Vec<Isometry3> =
///     (0..5).map(|i| Isometry3::translation(0.1 * i as f64, 0.0, 0.0)).collect();
/// gltf.animate_poses(node, &[0.0, 0.5, 1.0, 1.5, 2.0], &poses)?;
/// let summary = validate_glb(&gltf.encode()?)?;
/// assert_eq!(summary.animations[0].channels[0].samples, 5);
/// # Ok::<(), pickplace_view::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct GltfBuilder {
    animation_name: String,
    meshes: Vec<FlatMesh>,
    nodes: Vec<Node>,
    tracks: Vec<Track>,
}

impl GltfBuilder {
    /// An empty document whose animation (if any track is added) is called `animation_name`.
    pub fn new(animation_name: &str) -> Self {
        Self {
            animation_name: animation_name.to_owned(),
            meshes: Vec::new(),
            nodes: Vec::new(),
            tracks: Vec::new(),
        }
    }

    /// A document with one mesh and one root node per scene instance (instances sharing a
    /// geometry and paint share the mesh), named `instance-<i>`.
    ///
    /// # Errors
    /// None in practice (scenes are validated when built); propagated from
    /// [`GltfBuilder::add_mesh`] and [`GltfBuilder::add_node`].
    pub fn from_scene(scene: &Scene, animation_name: &str) -> Result<Self> {
        let mut builder = Self::new(animation_name);
        for (i, instance) in scene.instances().iter().enumerate() {
            if instance.geometry().triangle_count() == 0 {
                builder.add_node(
                    &format!("instance-{i}"),
                    None,
                    None,
                    instance.world_from_mesh(),
                )?;
                continue;
            }
            let existing = builder.meshes.iter().position(|m| {
                m.source.as_ref().is_some_and(|(g, p)| {
                    Arc::ptr_eq(g, instance.geometry()) && p == instance.paint()
                })
            });
            let mesh = match existing {
                Some(k) => MeshId(k),
                None => {
                    let id = builder.add_mesh(
                        &format!("mesh-{i}"),
                        instance.geometry(),
                        instance.paint(),
                    )?;
                    builder.meshes[id.0].source =
                        Some((instance.geometry().clone(), instance.paint().clone()));
                    id
                }
            };
            builder.add_node(
                &format!("instance-{i}"),
                Some(mesh),
                None,
                instance.world_from_mesh(),
            )?;
        }
        Ok(builder)
    }

    /// Number of nodes so far.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Adds a mesh (flat-shaded, double-sided material).
    ///
    /// # Errors
    /// [`crate::GeometryErrorKind::Empty`] for a geometry without triangles (glTF accessors
    /// cannot be empty); [`crate::GeometryErrorKind::ColourCount`] when a per-triangle paint
    /// does not have one colour per triangle.
    pub fn add_mesh(&mut self, name: &str, geometry: &Geometry, paint: &Paint) -> Result<MeshId> {
        let n = geometry.triangle_count();
        if n == 0 {
            return Err(Error::Geometry {
                kind: crate::error::GeometryErrorKind::Empty,
            });
        }
        if let Paint::PerTriangle(cs) = paint
            && cs.len() != n
        {
            return Err(Error::Geometry {
                kind: crate::error::GeometryErrorKind::ColourCount {
                    expected: n,
                    found: cs.len(),
                },
            });
        }
        let mut positions = Vec::with_capacity(9 * n);
        let mut normals = Vec::with_capacity(9 * n);
        for (t, tri) in geometry.triangles().iter().enumerate() {
            let normal = geometry.triangle_normal(t);
            // A degenerate triangle gets an arbitrary unit normal: glTF requires unit normals.
            let normal = if normal.norm() > 0.5 {
                normal
            } else {
                Vector3::z()
            };
            for &v in tri {
                let p = geometry.positions()[v as usize];
                positions.extend([p.x as f32, p.y as f32, p.z as f32]);
                normals.extend([normal.x as f32, normal.y as f32, normal.z as f32]);
            }
        }
        let (colours, base_colour) = match paint {
            Paint::Uniform(c) => (None, c.to_linear()),
            Paint::PerTriangle(cs) => {
                let mut colours = Vec::with_capacity(9 * n);
                for c in cs.iter() {
                    let [r, g, b] = c.to_linear().map(|x| x as f32);
                    for _ in 0..3 {
                        colours.extend([r, g, b]);
                    }
                }
                (Some(colours), Colour::WHITE.to_linear())
            }
        };
        self.meshes.push(FlatMesh {
            name: name.to_owned(),
            positions,
            normals,
            colours,
            base_colour,
            source: None,
        });
        Ok(MeshId(self.meshes.len() - 1))
    }

    /// Adds a node with an optional mesh, under an optional parent, at `parent_from_node`
    /// (the world when there is no parent).
    ///
    /// # Errors
    /// [`GltfErrorKind::IndexOutOfRange`] for an unknown mesh or parent;
    /// [`crate::GeometryErrorKind::NonFinitePose`].
    pub fn add_node(
        &mut self,
        name: &str,
        mesh: Option<MeshId>,
        parent: Option<NodeId>,
        parent_from_node: &Isometry3,
    ) -> Result<NodeId> {
        if let Some(m) = mesh {
            check_index("mesh", m.0, self.meshes.len())?;
        }
        if let Some(p) = parent {
            check_index("parent", p.0, self.nodes.len())?;
        }
        check_pose(parent_from_node, "node")?;
        let t = parent_from_node.translation.vector;
        let q = parent_from_node.rotation.coords;
        self.nodes.push(Node {
            name: name.to_owned(),
            mesh,
            parent,
            translation: [t.x, t.y, t.z],
            rotation: [q.x, q.y, q.z, q.w],
        });
        Ok(NodeId(self.nodes.len() - 1))
    }

    /// Animates a node's local translation (relative to its parent), linearly interpolated
    /// between keyframes at `times` (s, non-negative, strictly increasing).
    ///
    /// # Errors
    /// See [`GltfErrorKind`]: unknown node, empty or mismatched track, times not strictly
    /// increasing in `f32`, non-finite values, or a second translation track for the node.
    pub fn animate_translation(
        &mut self,
        node: NodeId,
        times: &[f64],
        translations: &[Vector3],
    ) -> Result<()> {
        let path = TrackPath::Translation;
        let times = self.check_track(node, path, times, translations.len())?;
        let mut values = Vec::with_capacity(3 * translations.len());
        for (index, t) in translations.iter().enumerate() {
            check_finite_value(t.iter(), node, path, index)?;
            values.extend([t.x as f32, t.y as f32, t.z as f32]);
        }
        self.push_track(node, path, times, values);
        Ok(())
    }

    /// Adds a checked track (keyframe times and flattened values).
    fn push_track(&mut self, node: NodeId, path: TrackPath, times: Vec<f32>, values: Vec<f32>) {
        self.tracks.push(Track {
            node,
            path,
            times,
            values,
        });
    }

    /// Animates a node's local rotation, spherically interpolated between keyframes. Signs are
    /// chosen so that consecutive quaternions lie in the same hemisphere (shortest arcs).
    ///
    /// # Errors
    /// As [`GltfBuilder::animate_translation`].
    pub fn animate_rotation(
        &mut self,
        node: NodeId,
        times: &[f64],
        rotations: &[UnitQuaternion],
    ) -> Result<()> {
        let path = TrackPath::Rotation;
        let times = self.check_track(node, path, times, rotations.len())?;
        let mut values = Vec::with_capacity(4 * rotations.len());
        let mut previous: Option<[f64; 4]> = None;
        for (index, q) in rotations.iter().enumerate() {
            let c = q.coords;
            check_finite_value(c.iter(), node, path, index)?;
            let mut xyzw = [c.x, c.y, c.z, c.w];
            if let Some(p) = previous
                && p.iter().zip(&xyzw).map(|(a, b)| a * b).sum::<f64>() < 0.0
            {
                xyzw = xyzw.map(|x| -x);
            }
            previous = Some(xyzw);
            values.extend(xyzw.map(|x| x as f32));
        }
        self.push_track(node, path, times, values);
        Ok(())
    }

    /// Animates both the translation and the rotation of a node from local poses
    /// (`parent_from_node` at each time): one sample per pose in each track.
    ///
    /// # Errors
    /// As [`GltfBuilder::animate_translation`].
    pub fn animate_poses(
        &mut self,
        node: NodeId,
        times: &[f64],
        parent_from_node: &[Isometry3],
    ) -> Result<()> {
        let translations: Vec<Vector3> = parent_from_node
            .iter()
            .map(|p| p.translation.vector)
            .collect();
        let rotations: Vec<UnitQuaternion> = parent_from_node.iter().map(|p| p.rotation).collect();
        // Check both before pushing either, so that a failure leaves the builder unchanged.
        self.check_track(node, TrackPath::Translation, times, translations.len())?;
        self.check_track(node, TrackPath::Rotation, times, rotations.len())?;
        self.animate_translation(node, times, &translations)?;
        self.animate_rotation(node, times, &rotations)
    }

    fn check_track(
        &self,
        node: NodeId,
        path: TrackPath,
        times: &[f64],
        values: usize,
    ) -> Result<Vec<f32>> {
        if node.0 >= self.nodes.len() {
            return Err(track_error(GltfErrorKind::IndexOutOfRange {
                what: "node",
                index: node.0,
                count: self.nodes.len(),
            }));
        }
        if times.is_empty() {
            return Err(track_error(GltfErrorKind::EmptyTrack { node: node.0 }));
        }
        if times.len() != values {
            return Err(track_error(GltfErrorKind::TrackLength {
                node: node.0,
                path: path.name(),
                times: times.len(),
                values,
            }));
        }
        if self.tracks.iter().any(|t| t.node == node && t.path == path) {
            return Err(track_error(GltfErrorKind::DuplicateTrack {
                node: node.0,
                path: path.name(),
            }));
        }
        let times: Vec<f32> = times.iter().map(|&t| t as f32).collect();
        for (index, &t) in times.iter().enumerate() {
            let ok = t.is_finite() && t >= 0.0 && (index == 0 || t > times[index - 1]);
            if !ok {
                return Err(track_error(GltfErrorKind::TimesNotIncreasing {
                    node: node.0,
                    index,
                }));
            }
        }
        Ok(times)
    }

    /// Encodes the document as `.glb` bytes. Deterministic: same document, same bytes.
    ///
    /// # Errors
    /// [`GltfErrorKind::TooLarge`] when the data exceeds what a `.glb` can address.
    pub fn encode(&self) -> Result<Vec<u8>> {
        let mut bin = BinWriter::default();
        let mut meshes = Vec::with_capacity(self.meshes.len());
        let mut materials = Vec::with_capacity(self.meshes.len());
        for (m, mesh) in self.meshes.iter().enumerate() {
            let vertex_count = mesh.positions.len() / 3;
            let position = bin.push_f32(&mesh.positions, "VEC3", Some(ARRAY_BUFFER), true);
            let normal = bin.push_f32(&mesh.normals, "VEC3", Some(ARRAY_BUFFER), false);
            let mut attributes = serde_json::Map::new();
            attributes.insert("POSITION".into(), json!(position));
            attributes.insert("NORMAL".into(), json!(normal));
            if let Some(colours) = &mesh.colours {
                attributes.insert(
                    "COLOR_0".into(),
                    json!(bin.push_f32(colours, "VEC3", Some(ARRAY_BUFFER), false)),
                );
            }
            let indices: Vec<u32> = (0..vertex_count as u32).collect();
            let indices = bin.push_indices(&indices);
            let [r, g, b] = mesh.base_colour;
            materials.push(json!({
                "name": format!("{}-material", mesh.name),
                "pbrMetallicRoughness": {
                    "baseColorFactor": [r, g, b, 1.0],
                    "metallicFactor": 0.0,
                    "roughnessFactor": 0.8
                },
                "doubleSided": true
            }));
            let mut primitive = json!({ "attributes": attributes, "mode": 4, "material": m });
            if let Some(indices) = indices {
                primitive["indices"] = json!(indices);
            }
            meshes.push(json!({ "name": mesh.name, "primitives": [primitive] }));
        }
        let mut nodes: Vec<Value> = self
            .nodes
            .iter()
            .map(|n| {
                let mut node =
                    json!({ "name": n.name, "translation": n.translation, "rotation": n.rotation });
                if let Some(mesh) = n.mesh {
                    node["mesh"] = json!(mesh.0);
                }
                node
            })
            .collect();
        for (i, n) in self.nodes.iter().enumerate() {
            if let Some(p) = n.parent {
                let children = nodes[p.0]
                    .as_object_mut()
                    .expect("nodes are JSON objects")
                    .entry("children");
                if let Value::Array(list) = children.or_insert_with(|| json!([])) {
                    list.push(json!(i));
                }
            }
        }
        let roots: Vec<usize> = (0..self.nodes.len())
            .filter(|&i| self.nodes[i].parent.is_none())
            .collect();

        let mut samplers = Vec::with_capacity(self.tracks.len());
        let mut channels = Vec::with_capacity(self.tracks.len());
        // Tracks with identical times share one input accessor.
        let mut inputs: Vec<(usize, usize)> = Vec::new(); // (track index, accessor)
        for (k, track) in self.tracks.iter().enumerate() {
            let input = match inputs
                .iter()
                .find(|&&(j, _)| self.tracks[j].times == track.times)
            {
                Some(&(_, accessor)) => accessor,
                None => {
                    let accessor = bin.push_f32(&track.times, "SCALAR", None, true);
                    inputs.push((k, accessor));
                    accessor
                }
            };
            let kind = if track.path == TrackPath::Translation {
                "VEC3"
            } else {
                "VEC4"
            };
            let output = bin.push_f32(&track.values, kind, None, false);
            samplers.push(json!({ "input": input, "output": output, "interpolation": "LINEAR" }));
            channels.push(json!({ "sampler": k, "target": { "node": track.node.0, "path": track.path.name() } }));
        }

        let mut root = serde_json::Map::new();
        root.insert(
            "asset".into(),
            json!({ "version": "2.0", "generator": "pickplace-view" }),
        );
        root.insert("scene".into(), json!(0));
        let scene = if roots.is_empty() {
            json!({ "name": "scene" })
        } else {
            json!({ "name": "scene", "nodes": roots })
        };
        root.insert("scenes".into(), json!([scene]));
        let mut put = |key: &str, list: Vec<Value>| {
            if !list.is_empty() {
                root.insert(key.into(), Value::Array(list));
            }
        };
        put("nodes", std::mem::take(&mut nodes));
        put("meshes", meshes);
        put("materials", materials);
        put("accessors", std::mem::take(&mut bin.accessors));
        put("bufferViews", std::mem::take(&mut bin.views));
        if !channels.is_empty() {
            put(
                "animations",
                vec![
                    json!({ "name": self.animation_name, "samplers": samplers, "channels": channels }),
                ],
            );
        }
        if !bin.data.is_empty() {
            root.insert("buffers".into(), json!([{ "byteLength": bin.data.len() }]));
        }
        let mut json_bytes =
            serde_json::to_vec(&Value::Object(root)).expect("a JSON value always serialises");
        while !json_bytes.len().is_multiple_of(4) {
            json_bytes.push(b' ');
        }
        let bin_bytes = bin.data;
        let total = 12
            + 8
            + json_bytes.len() as u64
            + if bin_bytes.is_empty() {
                0
            } else {
                8 + bin_bytes.len() as u64
            };
        let total = u32::try_from(total)
            .map_err(|_| track_error(GltfErrorKind::TooLarge { bytes: total }))?;
        let mut out = Vec::with_capacity(total as usize);
        out.extend(GLB_MAGIC.to_le_bytes());
        out.extend(2u32.to_le_bytes());
        out.extend(total.to_le_bytes());
        // Both chunk lengths are below `total`, which fits in u32.
        out.extend((json_bytes.len() as u32).to_le_bytes());
        out.extend(CHUNK_JSON.to_le_bytes());
        out.extend(&json_bytes);
        if !bin_bytes.is_empty() {
            out.extend((bin_bytes.len() as u32).to_le_bytes());
            out.extend(CHUNK_BIN.to_le_bytes());
            out.extend(&bin_bytes);
        }
        Ok(out)
    }

    /// Encodes the document and writes it to `path` atomically (temporary file and rename).
    ///
    /// # Errors
    /// As [`GltfBuilder::encode`], or [`Error::Write`] naming `path`.
    pub fn write_glb(&self, path: &Path) -> Result<()> {
        Ok(write_atomic(path, &self.encode()?)?)
    }
}

fn track_error(kind: GltfErrorKind) -> Error {
    Error::Gltf { kind }
}

/// The BIN chunk under construction, with its buffer views and accessors.
#[derive(Debug, Default)]
struct BinWriter {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl BinWriter {
    fn components(kind: &str) -> usize {
        match kind {
            "SCALAR" => 1,
            "VEC3" => 3,
            _ => 4,
        }
    }

    /// Appends a buffer view for `bytes` at a 4-byte aligned offset; returns its index.
    fn push_view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.data.len().is_multiple_of(4) {
            self.data.push(0);
        }
        let mut view =
            json!({ "buffer": 0, "byteOffset": self.data.len(), "byteLength": bytes.len() });
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.data.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// Appends a float accessor (with `min`/`max` when asked); returns its index.
    fn push_f32(
        &mut self,
        values: &[f32],
        kind: &str,
        target: Option<u32>,
        min_max: bool,
    ) -> usize {
        let n = Self::components(kind);
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.push_view(&bytes, target);
        let mut accessor = json!({
            "bufferView": view,
            "byteOffset": 0,
            "componentType": FLOAT,
            "count": values.len() / n,
            "type": kind
        });
        if min_max {
            let mut lo = vec![f32::INFINITY; n];
            let mut hi = vec![f32::NEG_INFINITY; n];
            for chunk in values.chunks_exact(n) {
                for (k, &v) in chunk.iter().enumerate() {
                    lo[k] = lo[k].min(v);
                    hi[k] = hi[k].max(v);
                }
            }
            // f32 → f64 is exact, so the JSON numbers are the data's values.
            accessor["min"] = json!(lo.iter().map(|&v| f64::from(v)).collect::<Vec<_>>());
            accessor["max"] = json!(hi.iter().map(|&v| f64::from(v)).collect::<Vec<_>>());
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Appends an index accessor; `None` for an empty list (glTF accessors need `count >= 1`).
    fn push_indices(&mut self, indices: &[u32]) -> Option<usize> {
        if indices.is_empty() {
            return None;
        }
        let bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.push_view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view,
            "byteOffset": 0,
            "componentType": UNSIGNED_INT,
            "count": indices.len(),
            "type": "SCALAR"
        }));
        Some(self.accessors.len() - 1)
    }
}

/// [`GltfErrorKind::IndexOutOfRange`] unless `index < count`.
fn check_index(what: &'static str, index: usize, count: usize) -> Result<()> {
    if index < count {
        Ok(())
    } else {
        Err(Error::Gltf {
            kind: GltfErrorKind::IndexOutOfRange { what, index, count },
        })
    }
}

/// [`GltfErrorKind::NonFiniteValue`] unless every component of keyframe `index` of the
/// node's `path` track is finite.
fn check_finite_value<'a>(
    components: impl IntoIterator<Item = &'a f64>,
    node: NodeId,
    path: TrackPath,
    index: usize,
) -> Result<()> {
    if components.into_iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(track_error(GltfErrorKind::NonFiniteValue {
            node: node.0,
            path: path.name(),
            index,
        }))
    }
}
