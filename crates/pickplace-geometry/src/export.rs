//! Pictures of clusters: a mesh with one colour per cluster, as an ASCII PLY with per-face
//! colours (MeshLab, Blender and CloudCompare show them), like the paper's Figs. 3-5.
//! Files are written atomically.

use crate::cluster::Clustering;
use crate::error::Result;
use crate::mesh::TriMesh;
use std::fmt::Write as _;
use std::path::Path;

/// The workspace's atomic writer ([`pickplace_base::io::write_atomic`]), under its old path.
pub use pickplace_base::io::write_atomic;

/// Colour of triangles that belong to no cluster.
pub const UNCLUSTERED_COLOR: [u8; 3] = [128, 128, 128];

/// A distinct, deterministic colour for cluster `id`: hues stepped by the golden ratio (so
/// neighbouring ids differ strongly), with three alternating brightness levels.
pub fn cluster_color(id: u32) -> [u8; 3] {
    let hue = (0.13 + f64::from(id) * 0.618_033_988_749_895).fract();
    let (s, v) = match id % 3 {
        0 => (0.70, 0.95),
        1 => (0.55, 0.80),
        _ => (0.85, 0.65),
    };
    hsv_to_rgb(hue, s, v)
}

fn hsv_to_rgb(h: f64, s: f64, v: f64) -> [u8; 3] {
    let h6 = h * 6.0;
    let i = h6.floor();
    let f = h6 - i;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let (r, g, b) = match i as i64 % 6 {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    };
    let c = |x: f64| (x * 255.0).round().clamp(0.0, 255.0) as u8;
    [c(r), c(g), c(b)]
}

/// The coloured mesh as ASCII PLY text: the welded mesh's vertices and triangles, each face
/// with the colour of its cluster ([`cluster_color`]) or [`UNCLUSTERED_COLOR`].
pub fn clusters_ply(mesh: &TriMesh, clustering: &Clustering) -> String {
    let owner = clustering.cluster_of_triangles(mesh.triangle_count());
    let mut s = String::with_capacity(64 * (mesh.vertices().len() + mesh.triangle_count()) + 256);
    // Writing into a String cannot fail; the results are ignored on purpose.
    let _ = write!(
        s,
        "ply\nformat ascii 1.0\ncomment pickplace clusters: mode {} h_max {} clusters {}\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar int vertex_indices\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n",
        clustering.params.mode.name(),
        clustering.params.h_max,
        clustering.clusters.len(),
        mesh.vertices().len(),
        mesh.triangle_count()
    );
    for p in mesh.vertices() {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let [r, g, b] = owner[t].map_or(UNCLUSTERED_COLOR, cluster_color);
        let _ = writeln!(s, "3 {} {} {} {r} {g} {b}", tri[0], tri[1], tri[2]);
    }
    s
}

/// Writes [`clusters_ply`] to `path` atomically.
///
/// # Errors
/// [`Error::Io`] when the file cannot be written.
pub fn write_clusters_ply(path: &Path, mesh: &TriMesh, clustering: &Clustering) -> Result<()> {
    Ok(write_atomic(
        path,
        clusters_ply(mesh, clustering).as_bytes(),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbouring_ids_get_distinct_colours() {
        let colours: Vec<[u8; 3]> = (0..64).map(cluster_color).collect();
        for i in 0..64 {
            for j in i + 1..(i + 8).min(64) {
                let d: i32 = (0..3)
                    .map(|k| (i32::from(colours[i][k]) - i32::from(colours[j][k])).abs())
                    .sum();
                assert!(d > 40, "{i} {j} {:?} {:?}", colours[i], colours[j]);
            }
        }
    }
}
