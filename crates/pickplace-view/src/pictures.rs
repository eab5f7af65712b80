//! The paper's pictures: clustered surfaces (Harada et al., Figs. 3–5: each cluster in its own
//! colour, the two clusters of a parallel finger pair in one hue) and candidate placements
//! (Fig. 6: the environment with translucent copies of the object at the candidate poses and
//! the target point).

use crate::camera::{Camera, OBLIQUE_VIEW};
use crate::error::Result;
use crate::image::{Colour, Image};
use crate::raster::{RenderOptions, render};
use crate::scene::{Geometry, Instance, Paint, Scene};
use pickplace_geometry::cluster::Clustering;
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_geometry::mesh::TriMesh;
use std::sync::Arc;

/// Colour of triangles that belong to no cluster.
pub const UNCLUSTERED: Colour = Colour::new(120, 120, 120);

/// Colour of the environment in placement pictures.
pub const ENVIRONMENT: Colour = Colour::new(185, 180, 170);

/// Hue (turns) of the `k`-th colour group: golden-ratio steps, so neighbours differ strongly.
fn hue(k: usize) -> Real {
    (k as Real * 0.618_033_988_749_894_9).fract()
}

/// One colour per triangle of the (welded) mesh that was clustered: each cluster a distinct
/// colour; in finger mode the clusters of a parallel pair share a hue, the first lighter and
/// the second darker (a cluster in several pairs keeps the hue of its first pair); triangles
/// in no cluster are [`UNCLUSTERED`]. Deterministic.
pub fn cluster_colours(clustering: &Clustering, triangle_count: usize) -> Vec<Colour> {
    let mut by_id: std::collections::BTreeMap<u32, Colour> = std::collections::BTreeMap::new();
    let mut group = 0;
    for pair in &clustering.pairs {
        let (first, second) = (pair.first, pair.second);
        let known = by_id.contains_key(&first) || by_id.contains_key(&second);
        if known {
            continue;
        }
        let h = hue(group);
        group += 1;
        by_id.insert(first, Colour::from_hsv(h, 0.55, 0.95));
        by_id.insert(second, Colour::from_hsv(h, 0.85, 0.6));
    }
    for cluster in &clustering.clusters {
        by_id.entry(cluster.id).or_insert_with(|| {
            let c = Colour::from_hsv(
                hue(group),
                [0.7, 0.5][group % 2],
                [0.92, 0.75][(group / 2) % 2],
            );
            group += 1;
            c
        });
    }
    clustering
        .cluster_of_triangles(triangle_count)
        .into_iter()
        .map(|id| {
            id.and_then(|id| by_id.get(&id).copied())
                .unwrap_or(UNCLUSTERED)
        })
        .collect()
}

/// Options of [`render_clusters`] and [`render_placements`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PictureOptions {
    /// Image size, background, shading and anti-aliasing (default: [`RenderOptions::default`],
    /// 800x600).
    pub render: RenderOptions,
    /// Direction the camera looks along; the camera frames the whole picture (default:
    /// [`OBLIQUE_VIEW`], from the front-left and above).
    pub view_direction: Vector3,
}

impl Default for PictureOptions {
    fn default() -> Self {
        Self {
            render: RenderOptions::default(),
            view_direction: OBLIQUE_VIEW,
        }
    }
}

fn fitted(scene: &Scene, options: &PictureOptions) -> Camera {
    let bounds = scene
        .bounds()
        .unwrap_or((Point3::origin(), Point3::origin()));
    let aspect = f64::from(options.render.width) / f64::from(options.render.height.max(1));
    Camera::fit_with_aspect(bounds, options.view_direction, aspect)
}

/// The clusters of a mesh as a scene (the mesh at the origin, [`cluster_colours`]).
///
/// # Errors
/// None in practice (one colour per triangle by construction).
pub fn clusters_scene(mesh: &TriMesh, clustering: &Clustering) -> Result<Scene> {
    let mut scene = Scene::new();
    scene.add_mesh_per_triangle(
        mesh,
        Isometry3::identity(),
        cluster_colours(clustering, mesh.triangle_count()),
    )?;
    Ok(scene)
}

/// A picture of the clusters of a mesh (Figs. 3–5), framed by a fitted camera.
///
/// # Errors
/// As [`render`] (image size, options).
pub fn render_clusters(
    mesh: &TriMesh,
    clustering: &Clustering,
    options: &PictureOptions,
) -> Result<Image> {
    let scene = clusters_scene(mesh, clustering)?;
    render(&scene, &fitted(&scene, options), &options.render)
}

/// Opacity of the object copies in placement pictures.
pub const PLACEMENT_OPACITY: Real = 0.6;

/// Candidate placements as a scene (Fig. 6): the environment at `world_from_env` in
/// [`ENVIRONMENT`] colour, one translucent copy of the object per pose in
/// `world_from_object` (best first, the best opaque, each in its own colour), and the target
/// point as a red sphere.
///
/// # Errors
/// [`crate::GeometryErrorKind::NonFinitePose`] for a non-finite pose or target.
pub fn placements_scene(
    object: &TriMesh,
    environment: &TriMesh,
    world_from_env: &Isometry3,
    world_from_object: &[Isometry3],
    target: Option<Point3>,
) -> Result<Scene> {
    let mut scene = Scene::new();
    scene.add_mesh(environment, *world_from_env, ENVIRONMENT)?;
    let geometry = Arc::new(Geometry::from_trimesh(object));
    for (i, pose) in world_from_object.iter().enumerate() {
        let colour = Colour::from_hsv(hue(i + 1), 0.75, 0.9);
        let instance = Instance::new(geometry.clone(), *pose, Paint::Uniform(colour))?;
        scene.push(if i == 0 {
            instance
        } else {
            instance.with_opacity(PLACEMENT_OPACITY)?
        });
    }
    if let Some(p) = target {
        let (lo, hi) = object.aabb();
        let radius = ((hi - lo).norm() * 0.06).max(1e-3);
        scene.add_point_marker(p, radius, Colour::RED)?;
    }
    Ok(scene)
}

/// A picture of candidate placements (Fig. 6), framed on the object copies, the target and
/// the environment.
///
/// # Errors
/// As [`placements_scene`] and [`render`].
pub fn render_placements(
    object: &TriMesh,
    environment: &TriMesh,
    world_from_env: &Isometry3,
    world_from_object: &[Isometry3],
    target: Option<Point3>,
    options: &PictureOptions,
) -> Result<Image> {
    let scene = placements_scene(
        object,
        environment,
        world_from_env,
        world_from_object,
        target,
    )?;
    render(&scene, &fitted(&scene, options), &options.render)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
    use pickplace_geometry::shapes::box_mesh;

    #[test]
    fn every_cluster_gets_its_own_colour_and_pairs_share_a_hue() {
        let mesh = box_mesh([0.03, 0.04, 0.05]);
        for params in [ClusterParams::environment(), ClusterParams::finger()] {
            let clustering = cluster_surface(&mesh, &params).expect("box clusters");
            assert_eq!(clustering.clusters.len(), 6);
            let colours = cluster_colours(&clustering, mesh.triangle_count());
            let mut distinct: Vec<Colour> = clustering
                .clusters
                .iter()
                .map(|c| colours[c.triangles[0] as usize])
                .collect();
            for c in &clustering.clusters {
                assert!(
                    c.triangles
                        .iter()
                        .all(|&t| colours[t as usize] == colours[c.triangles[0] as usize])
                );
            }
            distinct.sort();
            distinct.dedup();
            assert_eq!(distinct.len(), 6, "six faces, six colours");
            for pair in &clustering.pairs {
                let colour_of = |id: u32| {
                    let c = clustering
                        .clusters
                        .iter()
                        .find(|c| c.id == id)
                        .expect("pair member");
                    colours[c.triangles[0] as usize]
                };
                let (a, b) = (colour_of(pair.first), colour_of(pair.second));
                // Same hue: the channel order (which is largest, which smallest) agrees.
                let order = |c: Colour| {
                    let v = [c.r, c.g, c.b];
                    let max = (0..3).max_by_key(|&k| v[k]).expect("three channels");
                    let min = (0..3).min_by_key(|&k| v[k]).expect("three channels");
                    (max, min)
                };
                assert_eq!(order(a), order(b), "{a:?} {b:?}");
            }
        }
    }
}
