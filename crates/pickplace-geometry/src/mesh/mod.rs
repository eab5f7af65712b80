//! Triangle meshes: welding, degenerate-triangle removal, edge adjacency.
//!
//! A [`TriMesh`] is built from a triangle soup (positions and index triples, as a file gives
//! them). Construction welds vertices closer than a tolerance, drops degenerate triangles and
//! keeps, for every kept triangle, its index in the input's triangle order
//! ([`TriMesh::source_triangle`]), so that results (clusters, say) can be reported in the
//! numbering of the user's file. Open boundaries and non-manifold edges are allowed: they are
//! counted in the [`MeshReport`] and never make a query panic.
//!
//! # Files
//! [`load`] reads STL (binary and ASCII), OBJ and PLY (ASCII, binary little- and big-endian)
//! with our own readers, and COLLADA (`.dae`) through the `mesh-loader` crate (every mesh of
//! the file, node transforms and `<unit meter>` applied), chosen by the file extension
//! (case-insensitive: `.DAE` is COLLADA); [`read_stl`], [`read_obj`], [`read_ply`] and
//! [`read_mesh`] parse bytes already in memory. Coordinates are taken as metres times [`MeshOptions::scale`]. Polygons
//! with more than three corners (OBJ, PLY, and ASCII STL loops) are fan-triangulated: corners
//! `a b c d …` give `a b c`, `a c d`, …, so **the input file's triangle order** (the numbering of
//! [`TriMesh::source_triangle`]) is the order of the file's faces with each polygon replaced by
//! its fan. Every error names the file and what is wrong ([`Error::Mesh`]); no byte input
//! makes a reader panic.
//!
//! [`write_stl_binary`] writes a mesh atomically; [`MassProperties`] gives volume, centre of
//! gravity and inertia.

mod dae;
mod mass;
mod obj;
mod ply;
mod stl;
mod topology;
mod weld;

pub use mass::{MassMethod, MassProperties};
pub use stl::{encode_stl_binary, write_stl_binary};
pub use topology::Adjacency;

use crate::error::{Error, MeshErrorKind, Result, memory_path};
use crate::math::{Point3, Real, Vector3};
use std::path::Path;
use weld::{IntSet, weld};

/// The most triangles a mesh file may hold (after fan triangulation of its polygons). A file
/// with more, or whose header declares more (binary STL, PLY), is refused with
/// [`MeshErrorKind::OverLimit`] before its triangles are allocated: 2 000 000 triangles take
/// about 0.5 GB while the planner works on them.
pub const MAX_MESH_TRIANGLES: usize = 2_000_000;
/// The most vertices a mesh file may hold: three per triangle of [`MAX_MESH_TRIANGLES`] (an
/// unwelded soup).
pub const MAX_MESH_VERTICES: usize = 3 * MAX_MESH_TRIANGLES;

/// The three coordinates after a text format's vertex keyword (`v` in OBJ, `vertex` in ASCII
/// STL) on line `line_no`, pushed onto `positions` within [`MAX_MESH_VERTICES`]; its index.
///
/// # Errors
/// [`MeshErrorKind::Malformed`] of `format` naming the line: a coordinate missing or not a
/// number, or one vertex too many.
pub(crate) fn push_text_vertex<'a>(
    words: &mut impl Iterator<Item = &'a str>,
    (format, keyword, line_no): (&'static str, &str, usize),
    positions: &mut Vec<Point3>,
) -> std::result::Result<u32, MeshErrorKind> {
    let malformed = |detail: String| MeshErrorKind::Malformed {
        format,
        detail: format!("line {line_no}: {detail}"),
    };
    let mut xyz = [0.0; 3];
    for c in &mut xyz {
        let word = words
            .next()
            .ok_or_else(|| malformed(format!("`{keyword}` needs three coordinates")))?;
        *c = word
            .parse::<Real>()
            .map_err(|_| malformed(format!("`{word}` is not a number")))?;
    }
    check_limit("vertices", positions.len() as u64 + 1, MAX_MESH_VERTICES)
        .map_err(|e| malformed(e.to_string()))?;
    positions.push(Point3::new(xyz[0], xyz[1], xyz[2]));
    Ok((positions.len() - 1) as u32)
}

/// Refuses `count` of `what` when over `limit`.
pub(crate) fn check_limit(
    what: &'static str,
    count: u64,
    limit: usize,
) -> std::result::Result<(), MeshErrorKind> {
    if count > limit as u64 {
        return Err(MeshErrorKind::OverLimit {
            what,
            count,
            limit: limit as u64,
        });
    }
    Ok(())
}

/// Options for building a mesh from a file or a triangle soup.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshOptions {
    /// Factor applied to every coordinate, for files not in metres (default: 1.0).
    pub scale: Real,
    /// Vertices closer than this distance (m, after scaling) are merged (default: 1e-7).
    pub weld_tolerance: Real,
    /// Triangles whose area is below this value (m²) are dropped as degenerate (default: 1e-14).
    pub degenerate_area: Real,
}

impl Default for MeshOptions {
    fn default() -> Self {
        Self {
            scale: 1.0,
            weld_tolerance: 1e-7,
            degenerate_area: 1e-14,
        }
    }
}

/// What construction did to the input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct MeshReport {
    /// Vertices in the input.
    pub input_vertices: usize,
    /// Triangles in the input.
    pub input_triangles: usize,
    /// Vertices after welding.
    pub vertices: usize,
    /// Triangles kept.
    pub triangles: usize,
    /// Triangles dropped because their area was below [`MeshOptions::degenerate_area`]
    /// (or two of their corners welded together).
    pub degenerate_triangles: usize,
    /// Triangles dropped because an earlier triangle has the same corners in the same
    /// winding order (a mesh exported twice into one file): the copy is welded into the first.
    pub duplicate_triangles: usize,
    /// Edges used by one triangle only (open boundary).
    pub boundary_edges: usize,
    /// Edges shared by more than two triangles.
    pub non_manifold_edges: usize,
}

impl MeshReport {
    /// True when every edge is shared by exactly two triangles.
    pub fn is_closed(&self) -> bool {
        self.boundary_edges == 0 && self.non_manifold_edges == 0
    }
}

/// An indexed triangle mesh with edge adjacency. Immutable once built.
#[derive(Debug, Clone)]
pub struct TriMesh {
    vertices: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
    source_triangles: Vec<u32>,
    adjacency: Adjacency,
    report: MeshReport,
}

impl TriMesh {
    /// Builds a mesh from a triangle soup.
    ///
    /// # Arguments
    /// * `positions`: vertex positions in the input's units (scaled by `options.scale`).
    /// * `triangles`: index triples into `positions`, in the input's order.
    ///
    /// # Errors
    /// [`MeshErrorKind::Empty`], [`MeshErrorKind::NonFiniteCoordinate`],
    /// [`MeshErrorKind::IndexOutOfRange`], [`MeshErrorKind::ZeroArea`] or
    /// [`MeshErrorKind::InvalidScale`], with the path `<memory>`; the file loaders replace it
    /// with the file's path.
    pub fn from_soup(
        positions: &[Point3],
        triangles: &[[u32; 3]],
        options: &MeshOptions,
    ) -> Result<Self> {
        Self::from_soup_inner(positions, triangles, options).map_err(|kind| Error::Mesh {
            path: memory_path(),
            kind,
        })
    }

    pub(crate) fn from_soup_inner(
        positions: &[Point3],
        triangles: &[[u32; 3]],
        options: &MeshOptions,
    ) -> std::result::Result<Self, MeshErrorKind> {
        if !(options.scale.is_finite() && options.scale > 0.0) {
            return Err(MeshErrorKind::InvalidScale {
                scale: options.scale,
            });
        }
        if triangles.is_empty() {
            return Err(MeshErrorKind::Empty);
        }
        for (vertex, p) in positions.iter().enumerate() {
            if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
                return Err(MeshErrorKind::NonFiniteCoordinate { vertex });
            }
        }
        for (triangle, t) in triangles.iter().enumerate() {
            for &index in t {
                if index as usize >= positions.len() {
                    return Err(MeshErrorKind::IndexOutOfRange {
                        triangle,
                        index: u64::from(index),
                        vertex_count: positions.len(),
                    });
                }
            }
        }
        let scaled: Vec<Point3> = positions.iter().map(|p| p * options.scale).collect();
        let (vertices, remap) = weld(&scaled, options.weld_tolerance);

        let mut kept = Vec::with_capacity(triangles.len());
        let mut source_triangles = Vec::with_capacity(triangles.len());
        let mut seen: IntSet<[u32; 3]> = IntSet::default();
        seen.reserve(triangles.len());
        let mut duplicates = 0;
        for (i, t) in triangles.iter().enumerate() {
            let w = t.map(|v| remap[v as usize]);
            if w[0] == w[1] || w[1] == w[2] || w[0] == w[2] {
                continue;
            }
            // The same corners in the same winding, whichever corner comes first.
            let first = (0..3).min_by_key(|&k| w[k]).unwrap_or(0);
            let key = [w[first], w[(first + 1) % 3], w[(first + 2) % 3]];
            if !seen.insert(key) {
                duplicates += 1;
                continue;
            }
            let area = triangle_area(&vertices, w);
            // Also drops NaN areas (and everything when the threshold is NaN).
            if !matches!(
                area.partial_cmp(&options.degenerate_area),
                Some(std::cmp::Ordering::Greater | std::cmp::Ordering::Equal)
            ) {
                continue;
            }
            kept.push(w);
            source_triangles.push(i as u32);
        }
        if kept.is_empty() {
            return Err(MeshErrorKind::ZeroArea {
                triangles: triangles.len(),
            });
        }
        // Drop vertices no kept triangle uses, keeping first-use order stable.
        let mut used = vec![u32::MAX; vertices.len()];
        let mut compact = Vec::with_capacity(vertices.len());
        for t in &mut kept {
            for v in t.iter_mut() {
                if used[*v as usize] == u32::MAX {
                    used[*v as usize] = compact.len() as u32;
                    compact.push(vertices[*v as usize]);
                }
                *v = used[*v as usize];
            }
        }
        let adjacency = Adjacency::new(&kept, compact.len());
        let report = MeshReport {
            input_vertices: positions.len(),
            input_triangles: triangles.len(),
            vertices: compact.len(),
            triangles: kept.len(),
            degenerate_triangles: triangles.len() - kept.len() - duplicates,
            duplicate_triangles: duplicates,
            boundary_edges: adjacency.boundary_edges(),
            non_manifold_edges: adjacency.non_manifold_edges(),
        };
        Ok(Self {
            vertices: compact,
            triangles: kept,
            source_triangles,
            adjacency,
            report,
        })
    }

    /// Vertex positions (m).
    pub fn vertices(&self) -> &[Point3] {
        &self.vertices
    }

    /// Triangles as index triples into [`TriMesh::vertices`], counter-clockwise seen from outside.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Index, in the input's triangle order, of the kept triangle `triangle`.
    pub fn source_triangle(&self, triangle: usize) -> u32 {
        self.source_triangles[triangle]
    }

    /// For every kept triangle its index in the input's triangle order.
    pub fn source_triangles(&self) -> &[u32] {
        &self.source_triangles
    }

    /// Edge adjacency between triangles.
    pub fn adjacency(&self) -> &Adjacency {
        &self.adjacency
    }

    /// What construction did (welded vertices, dropped triangles, open and non-manifold edges).
    pub fn report(&self) -> &MeshReport {
        &self.report
    }

    /// The three corners of a triangle.
    pub fn triangle_points(&self, triangle: usize) -> [Point3; 3] {
        self.triangles[triangle].map(|v| self.vertices[v as usize])
    }

    /// Non-normalised normal of a triangle (length = twice its area).
    pub fn triangle_scaled_normal(&self, triangle: usize) -> Vector3 {
        let [a, b, c] = self.triangle_points(triangle);
        (b - a).cross(&(c - a))
    }

    /// Unit outward normal of a triangle (counter-clockwise winding).
    pub fn triangle_normal(&self, triangle: usize) -> Vector3 {
        self.triangle_scaled_normal(triangle).normalize()
    }

    /// Area of a triangle (m²).
    pub fn triangle_area(&self, triangle: usize) -> Real {
        0.5 * self.triangle_scaled_normal(triangle).norm()
    }

    /// Total surface area (m²).
    pub fn area(&self) -> Real {
        (0..self.triangles.len())
            .map(|t| self.triangle_area(t))
            .sum()
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn aabb(&self) -> (Point3, Point3) {
        let mut lo = self.vertices[0];
        let mut hi = self.vertices[0];
        for p in &self.vertices {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (lo, hi)
    }

    /// A copy scaled by `scale` along the mesh's own axes (URDF `<mesh scale="x y z">`),
    /// welded again with `options` (its `scale` is not applied). A scale with a negative
    /// product mirrors the mesh: the winding of every triangle is reversed so that normals
    /// stay outward and the volume positive. [`TriMesh::source_triangle`] still gives the
    /// index in the original file.
    ///
    /// # Errors
    /// [`MeshErrorKind::InvalidScaleVector`] when a component is zero or not finite;
    /// construction errors as [`TriMesh::from_soup`] (path `<memory>`).
    pub fn scaled(&self, scale: &Vector3, options: &MeshOptions) -> Result<Self> {
        let to_error = |kind| Error::Mesh {
            path: memory_path(),
            kind,
        };
        if scale.iter().any(|s| !s.is_finite() || *s == 0.0) {
            return Err(to_error(MeshErrorKind::InvalidScaleVector {
                scale: [scale.x, scale.y, scale.z],
            }));
        }
        let mirrored = scale.x * scale.y * scale.z < 0.0;
        let positions: Vec<Point3> = self
            .vertices
            .iter()
            .map(|p| Point3::from(p.coords.component_mul(scale)))
            .collect();
        let triangles: Vec<[u32; 3]> = self
            .triangles
            .iter()
            .map(|&[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] })
            .collect();
        let mut out = Self::from_soup_inner(
            &positions,
            &triangles,
            &MeshOptions {
                scale: 1.0,
                ..*options
            },
        )
        .map_err(to_error)?;
        for source in &mut out.source_triangles {
            *source = self.source_triangles[*source as usize];
        }
        Ok(out)
    }

    /// A copy transformed by `pose` (vertex positions only; indices and mapping are kept).
    pub fn transformed(&self, pose: &crate::math::Isometry3) -> Self {
        let mut out = self.clone();
        for p in &mut out.vertices {
            *p = pose * *p;
        }
        out
    }
}

fn triangle_area(vertices: &[Point3], t: [u32; 3]) -> Real {
    let [a, b, c] = t.map(|v| vertices[v as usize]);
    0.5 * (b - a).cross(&(c - a)).norm()
}

/// A triangle soup as a parser produces it: positions and index triples in file order.
#[derive(Debug, Clone, Default)]
pub(crate) struct Soup {
    pub(crate) positions: Vec<Point3>,
    pub(crate) triangles: Vec<[u32; 3]>,
}

impl Soup {
    fn with_capacity(vertices: usize, triangles: usize) -> Self {
        Self {
            positions: Vec::with_capacity(vertices),
            triangles: Vec::with_capacity(triangles),
        }
    }
}

/// Appends the fan `p0 p1 p2`, `p0 p2 p3`, … of a polygon (at least three corners).
pub(crate) fn fan_triangulate(polygon: &[u32], out: &mut Vec<[u32; 3]>) {
    for k in 1..polygon.len().saturating_sub(1) {
        out.push([polygon[0], polygon[k], polygon[k + 1]]);
    }
}

/// Anything that is positions plus index triples: a [`TriMesh`], a
/// [`MeshBuilder`](crate::shapes::MeshBuilder). Used by the writers.
pub trait TriangleSource {
    /// Vertex positions (m).
    fn soup_positions(&self) -> &[Point3];
    /// Index triples into [`TriangleSource::soup_positions`], counter-clockwise seen from outside.
    fn soup_triangles(&self) -> &[[u32; 3]];
}

impl TriangleSource for TriMesh {
    fn soup_positions(&self) -> &[Point3] {
        &self.vertices
    }
    fn soup_triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
}

impl TriangleSource for Soup {
    fn soup_positions(&self) -> &[Point3] {
        &self.positions
    }
    fn soup_triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
}

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum MeshFormat {
    /// STL, binary or ASCII (`.stl`).
    Stl,
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// PLY, ASCII or binary (`.ply`).
    Ply,
    /// COLLADA 1.4/1.5 text (`.dae`), read through `mesh-loader`.
    Collada,
}

impl MeshFormat {
    /// The format named by a path's extension (case-insensitive).
    ///
    /// # Errors
    /// [`MeshErrorKind::UnsupportedFormat`] (with `path`) for any other extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match extension.as_str() {
            "stl" => Ok(Self::Stl),
            "obj" => Ok(Self::Obj),
            "ply" => Ok(Self::Ply),
            "dae" => Ok(Self::Collada),
            _ => Err(Error::Mesh {
                path: path.to_path_buf(),
                kind: MeshErrorKind::UnsupportedFormat { extension },
            }),
        }
    }
}

/// Loads a mesh file (STL, OBJ, PLY or COLLADA, chosen by the extension); see the [module](self) doc.
/// What loading did (welded vertices, dropped degenerate triangles, open edges) is in
/// [`TriMesh::report`].
///
/// # Errors
/// [`Error::Io`] when the file cannot be read, is not a regular file or is larger than
/// [`crate::io::MAX_MESH_BYTES`] (see [`crate::io`]); [`Error::Mesh`] naming the file when the
/// extension is unknown, the file is empty, malformed (truncated binary STL, a bad number or
/// keyword, with its line), has a non-finite coordinate, an out-of-range face index, or only
/// zero-area triangles, has or declares more than [`MAX_MESH_TRIANGLES`] triangles or
/// [`MAX_MESH_VERTICES`] vertices, or when `options.scale` is not positive.
pub fn load(path: &Path, options: &MeshOptions) -> Result<TriMesh> {
    let format = MeshFormat::from_path(path)?;
    let bytes = crate::io::read_bytes(path, crate::io::MESH).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_format(format, &bytes, path, options)
}

/// Like [`load`], also returning the [`MeshReport`] (a copy of [`TriMesh::report`]).
///
/// # Errors
/// As [`load`].
pub fn load_with_report(path: &Path, options: &MeshOptions) -> Result<(TriMesh, MeshReport)> {
    let mesh = load(path, options)?;
    let report = *mesh.report();
    Ok((mesh, report))
}

/// Parses mesh bytes in the format named by `path`'s extension; `path` is used for the format
/// and in errors only.
///
/// # Errors
/// As [`load`], without the I/O errors.
pub fn read_mesh(bytes: &[u8], path: &Path, options: &MeshOptions) -> Result<TriMesh> {
    read_format(MeshFormat::from_path(path)?, bytes, path, options)
}

/// Parses binary or ASCII STL bytes; `path` is used in errors only.
///
/// # Errors
/// As [`load`], without the I/O errors.
pub fn read_stl(bytes: &[u8], path: &Path, options: &MeshOptions) -> Result<TriMesh> {
    read_format(MeshFormat::Stl, bytes, path, options)
}

/// Parses OBJ bytes; `path` is used in errors only.
///
/// # Errors
/// As [`load`], without the I/O errors.
pub fn read_obj(bytes: &[u8], path: &Path, options: &MeshOptions) -> Result<TriMesh> {
    read_format(MeshFormat::Obj, bytes, path, options)
}

/// Parses PLY bytes (ASCII or binary); `path` is used in errors only.
///
/// # Errors
/// As [`load`], without the I/O errors.
pub fn read_ply(bytes: &[u8], path: &Path, options: &MeshOptions) -> Result<TriMesh> {
    read_format(MeshFormat::Ply, bytes, path, options)
}

fn read_format(
    format: MeshFormat,
    bytes: &[u8],
    path: &Path,
    options: &MeshOptions,
) -> Result<TriMesh> {
    let soup = match format {
        MeshFormat::Stl => stl::parse(bytes),
        MeshFormat::Obj => obj::parse(bytes),
        MeshFormat::Ply => ply::parse(bytes),
        MeshFormat::Collada => dae::parse(bytes),
    };
    soup.and_then(|s| {
        // Every reader checks as it goes; this is the one check that holds for all of them.
        check_limit("triangles", s.triangles.len() as u64, MAX_MESH_TRIANGLES)?;
        check_limit("vertices", s.positions.len() as u64, MAX_MESH_VERTICES)?;
        TriMesh::from_soup_inner(&s.positions, &s.triangles, options)
    })
    .map_err(|kind| Error::Mesh {
        path: path.to_path_buf(),
        kind,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> (Vec<Point3>, Vec<[u32; 3]>) {
        // Two triangles as a soup (6 vertices), sharing the diagonal.
        let p = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        (p, vec![[0, 1, 2], [3, 4, 5]])
    }

    #[test]
    fn welds_shared_corners_and_finds_the_neighbour() {
        let (p, t) = quad();
        let mesh = TriMesh::from_soup(&p, &t, &MeshOptions::default()).expect("valid quad");
        assert_eq!(mesh.vertices().len(), 4);
        assert_eq!(mesh.report().boundary_edges, 4);
        assert_eq!(mesh.adjacency().neighbours(0), &[1]);
        assert!((mesh.area() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn drops_degenerate_triangles_and_keeps_file_order() {
        let (mut p, mut t) = quad();
        p.push(Point3::new(2.0, 0.0, 0.0));
        t.insert(0, [0, 1, 6]); // collinear: zero area
        let mesh = TriMesh::from_soup(&p, &t, &MeshOptions::default()).expect("valid");
        assert_eq!(mesh.report().degenerate_triangles, 1);
        assert_eq!(mesh.source_triangles(), &[1, 2]);
    }

    #[test]
    fn triangles_stored_twice_are_welded_into_one_and_counted() {
        let (p, mut t) = quad();
        let copy = t.clone();
        // The same triangles again, starting at another corner (same winding), and one
        // reversed: the reversed one is another face (a two-sided sheet) and stays.
        t.extend(copy.iter().map(|c| [c[1], c[2], c[0]]));
        t.push([copy[0][0], copy[0][2], copy[0][1]]);
        let mesh = TriMesh::from_soup(&p, &t, &MeshOptions::default()).expect("valid");
        assert_eq!(mesh.report().duplicate_triangles, copy.len());
        assert_eq!(mesh.report().degenerate_triangles, 0);
        assert_eq!(mesh.triangles().len(), copy.len() + 1);
    }

    #[test]
    fn welding_huge_coordinates_does_not_overflow() {
        // Regression: cell indices saturate at i64::MAX and the neighbour scan overflowed.
        let p = [
            Point3::new(1e30, 0.0, 0.0),
            Point3::new(-1e30, 1.0, 0.0),
            Point3::new(0.0, 1e30, 0.0),
        ];
        let mesh = TriMesh::from_soup(&p, &[[0, 1, 2]], &MeshOptions::default()).expect("valid");
        assert_eq!(mesh.vertices().len(), 3);
    }

    #[test]
    fn rejects_bad_input_with_a_reason() {
        let (mut p, t) = quad();
        let err = TriMesh::from_soup(&p, &[[0, 1, 9]], &MeshOptions::default()).unwrap_err();
        assert!(err.to_string().contains("refers to vertex 9"), "{err}");
        p[2].x = f64::NAN;
        let err = TriMesh::from_soup(&p, &t, &MeshOptions::default()).unwrap_err();
        assert!(err.to_string().contains("non-finite"), "{err}");
        let err = TriMesh::from_soup(&p, &[], &MeshOptions::default()).unwrap_err();
        assert!(err.to_string().contains("no triangles"), "{err}");
        let flat = [Point3::origin(); 3];
        let err = TriMesh::from_soup(&flat, &[[0, 1, 2]], &MeshOptions::default()).unwrap_err();
        assert!(err.to_string().contains("degenerate"), "{err}");
    }

    /// A closed tetrahedron, counter-clockwise seen from outside.
    fn tetrahedron() -> TriMesh {
        let p = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        let t = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        TriMesh::from_soup(&p, &t, &MeshOptions::default()).expect("valid tetrahedron")
    }

    fn signed_volume(mesh: &TriMesh) -> Real {
        (0..mesh.triangle_count())
            .map(|t| {
                let [a, b, c] = mesh.triangle_points(t);
                a.coords.dot(&b.coords.cross(&c.coords)) / 6.0
            })
            .sum()
    }

    fn normals_point_away_from_centroid(mesh: &TriMesh) -> bool {
        let n = mesh.vertices().len() as Real;
        let centroid = mesh
            .vertices()
            .iter()
            .fold(Vector3::zeros(), |s, p| s + p.coords)
            / n;
        (0..mesh.triangle_count()).all(|t| {
            let [a, b, c] = mesh.triangle_points(t);
            let centre = (a.coords + b.coords + c.coords) / 3.0;
            mesh.triangle_normal(t).dot(&(centre - centroid)) > 0.0
        })
    }

    #[test]
    fn a_mirroring_scale_flips_the_winding_and_keeps_the_volume_positive() {
        let mesh = tetrahedron();
        assert!((signed_volume(&mesh) - 1.0 / 6.0).abs() < 1e-12);
        let mirrored = mesh
            .scaled(&Vector3::new(1.0, -1.0, 1.0), &MeshOptions::default())
            .expect("valid scale");
        assert!((signed_volume(&mirrored) - 1.0 / 6.0).abs() < 1e-12);
        assert!(normals_point_away_from_centroid(&mirrored));
        assert!(mirrored.vertices().iter().all(|p| p.y <= 0.0));
        assert_eq!(mirrored.source_triangles(), mesh.source_triangles());
        // Non-uniform, not mirrored: the volume multiplies by the scale's product.
        let stretched = mesh
            .scaled(&Vector3::new(2.0, 3.0, 0.5), &MeshOptions::default())
            .expect("valid scale");
        assert!((signed_volume(&stretched) - 3.0 / 6.0).abs() < 1e-12);
        assert!(normals_point_away_from_centroid(&stretched));
        // Two negative components: a rotation, no flip.
        let rotated = mesh
            .scaled(&Vector3::new(-1.0, -1.0, 1.0), &MeshOptions::default())
            .expect("valid scale");
        assert!((signed_volume(&rotated) - 1.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn a_zero_scale_component_is_an_error() {
        let error = tetrahedron()
            .scaled(&Vector3::new(1.0, 0.0, 1.0), &MeshOptions::default())
            .expect_err("zero scale");
        assert!(error.to_string().contains("scale"), "{error}");
    }
}
