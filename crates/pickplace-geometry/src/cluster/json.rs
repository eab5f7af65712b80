//! The "clusters" JSON output (docs/clustering.md, /DESIGN.md "JSON outputs").

use super::{Clustering, ContactMode};
use crate::math::Real;
use crate::mesh::TriMesh;

/// Value of the `format` field of [`ClustersJson`]. Documents written before November 2026 say
/// `pickplace.clusters.v1`, with the same content.
pub const CLUSTERS_JSON_FORMAT: &str = "pickplace.clusters/1";

/// The `pickplace clusters --json` document.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClustersJson {
    /// Always [`CLUSTERS_JSON_FORMAT`].
    pub format: String,
    /// The mesh file as given by the user.
    pub mesh: String,
    /// "env" or "finger".
    pub mode: String,
    /// Maximum cluster thickness (m).
    pub h_max: Real,
    /// Triangles in the input file (degenerate ones included; they belong to no cluster).
    pub triangle_count: usize,
    /// Clusters.
    pub clusters: Vec<ClusterJson>,
    /// Opposite cluster pairs (finger mode only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pairs: Option<Vec<ClusterPairJson>>,
}

/// One cluster in [`ClustersJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClusterJson {
    /// Cluster id.
    pub id: u32,
    /// Indices of the input file's triangles, increasing.
    pub triangles: Vec<u32>,
    /// Unit outer normal of the contact plane.
    pub normal: [Real; 3],
    /// A point of the contact plane (m).
    pub point: [Real; 3],
    /// Thickness along the normal (m).
    pub h: Real,
    /// Surface area (m²).
    pub area: Real,
    /// Outer boundary on the contact plane, counter-clockwise seen from outside (m).
    pub outer_boundary: Vec<[Real; 3]>,
    /// Holes on the contact plane (m).
    pub holes: Vec<Vec<[Real; 3]>>,
}

/// One pair in [`ClustersJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClusterPairJson {
    /// The two cluster ids (seed first).
    pub clusters: [u32; 2],
    /// Distance between the contact planes (m).
    pub width: Real,
    /// Area of the overlap of the two regions (m²).
    pub overlap_area: Real,
    /// Centre of the overlap on the mid-plane (m).
    pub center: [Real; 3],
}

fn arr(v: &nalgebra::Vector3<Real>) -> [Real; 3] {
    [v.x, v.y, v.z]
}

impl ClustersJson {
    /// The JSON document of a clustering of `mesh` (read from `mesh_path`). Triangle indices
    /// are mapped back to the input file's numbering with [`TriMesh::source_triangle`].
    pub fn new(clustering: &Clustering, mesh: &TriMesh, mesh_path: &str) -> Self {
        let clusters = clustering
            .clusters
            .iter()
            .map(|c| {
                let mut triangles: Vec<u32> = c
                    .triangles
                    .iter()
                    .map(|&t| mesh.source_triangle(t as usize))
                    .collect();
                triangles.sort_unstable();
                ClusterJson {
                    id: c.id,
                    triangles,
                    normal: arr(&c.normal),
                    point: arr(&c.point.coords),
                    h: c.h,
                    area: c.area,
                    outer_boundary: c
                        .outer_boundary_3d()
                        .iter()
                        .map(|p| arr(&p.coords))
                        .collect(),
                    holes: c
                        .holes_3d()
                        .iter()
                        .map(|h| h.iter().map(|p| arr(&p.coords)).collect())
                        .collect(),
                }
            })
            .collect();
        let pairs = (clustering.params.mode == ContactMode::Finger).then(|| {
            clustering
                .pairs
                .iter()
                .map(|p| ClusterPairJson {
                    clusters: [p.first, p.second],
                    width: p.width,
                    overlap_area: p.overlap_area,
                    center: arr(&p.center.coords),
                })
                .collect()
        });
        Self {
            format: CLUSTERS_JSON_FORMAT.to_owned(),
            mesh: mesh_path.to_owned(),
            mode: clustering.params.mode.name().to_owned(),
            h_max: clustering.params.h_max,
            triangle_count: mesh.report().input_triangles,
            clusters,
            pairs,
        }
    }
}
