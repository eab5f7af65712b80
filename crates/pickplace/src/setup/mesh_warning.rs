//! What a scene's meshes look like they got wrong (issue 31): not errors, the plan goes on,
//! but a user handing the planner a scanned or exported mesh wants to know.

use pickplace_geometry::math::Real;
use pickplace_geometry::mesh::TriMesh;
use std::path::{Path, PathBuf};

/// An object this large (m, its bounding box's longest side) looks like a mesh in millimetres
/// read as metres: no object a dual-arm robot picks is a metre across.
pub const MILLIMETRE_SUSPECT_SIZE: Real = 1.0;

/// Something a mesh of the scene looks like it got wrong.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum MeshWarning {
    /// Triangles stored twice in the same winding were welded into one.
    DuplicateTriangles {
        /// The scene field that names the mesh (`object.mesh`, `environment[0] "table"`).
        what: String,
        /// The mesh file.
        path: PathBuf,
        /// Copies dropped.
        count: usize,
        /// Triangles of the file.
        of: usize,
    },
    /// The object is over [`MILLIMETRE_SUSPECT_SIZE`] across at its scale.
    LooksLikeMillimetres {
        /// The mesh file.
        path: PathBuf,
        /// Its longest side (m) at the scale given.
        size: Real,
        /// The scene field or command-line flag that sets the scale.
        scale_field: &'static str,
    },
}

impl std::fmt::Display for MeshWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::DuplicateTriangles {
                what,
                path,
                count,
                of,
            } => write!(
                f,
                "{what} {}: {count} of its {of} triangles are stored twice; each copy was welded into the first",
                path.display()
            ),
            Self::LooksLikeMillimetres {
                path,
                size,
                scale_field,
            } => write!(
                f,
                "the object {} is {} m across: if the file is in millimetres, {} 0.001",
                path.display(),
                pickplace_geometry::io::fmt_real_fixed(*size, 2),
                if scale_field.starts_with("--") {
                    format!("give {scale_field}")
                } else {
                    format!("set {scale_field} =")
                }
            ),
        }
    }
}

/// The warnings a mesh loaded for `what` from `path` deserves; `object_scale_field` is set for
/// the object (the size check is for objects only: an environment may be large).
pub fn check(
    mesh: &TriMesh,
    what: &str,
    path: &Path,
    object_scale_field: Option<&'static str>,
) -> Vec<MeshWarning> {
    let mut out = Vec::new();
    let report = mesh.report();
    if report.duplicate_triangles > 0 {
        out.push(MeshWarning::DuplicateTriangles {
            what: what.to_owned(),
            path: path.to_path_buf(),
            count: report.duplicate_triangles,
            of: report.input_triangles,
        });
    }
    if let Some(scale_field) = object_scale_field {
        let (lo, hi) = mesh.aabb();
        let size = (hi - lo).max();
        if size > MILLIMETRE_SUSPECT_SIZE {
            out.push(MeshWarning::LooksLikeMillimetres {
                path: path.to_path_buf(),
                size,
                scale_field,
            });
        }
    }
    out
}
