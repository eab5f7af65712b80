//! Cluster and placement pictures of the shipped meshes.

use crate::{decode_png, distinct_colours};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::math::{Isometry3, Point3};
use pickplace_geometry::mesh::{self, MeshOptions, TriMesh};
use pickplace_view::{PictureOptions, RenderOptions, render_clusters, render_placements};
use std::path::PathBuf;

fn shipped(name: &str) -> TriMesh {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name);
    mesh::load(&path, &MeshOptions::default()).expect("a shipped mesh")
}

fn options(width: u32, height: u32) -> PictureOptions {
    PictureOptions {
        render: RenderOptions {
            width,
            height,
            ..RenderOptions::default()
        },
        ..PictureOptions::default()
    }
}

#[test]
fn cluster_picture_of_the_can_shows_several_cluster_colours() {
    let can = shipped("can.stl");
    let clustering = cluster_surface(&can, &ClusterParams::finger()).expect("clusters");
    let image = render_clusters(&can, &clustering, &options(240, 180)).expect("render");
    let (w, h, rgba) = decode_png(&image.encode_png().expect("png"));
    assert_eq!((w, h), (240, 180));
    let background = [250, 250, 250, 255];
    let drawn = rgba.chunks_exact(4).filter(|p| *p != background).count();
    assert!(drawn > 240 * 180 / 10, "{drawn} pixels drawn");
    // Several strongly saturated hues (cluster colours), not just greys.
    let saturated: Vec<[u8; 4]> = distinct_colours(&image)
        .into_iter()
        .filter(|p| {
            p[..3].iter().max().copied().unwrap_or(0) - p[..3].iter().min().copied().unwrap_or(0)
                > 60
        })
        .collect();
    assert!(
        saturated.len() > 10,
        "{} saturated colours",
        saturated.len()
    );
}

#[test]
fn placement_picture_shows_the_environment_the_copies_and_the_target() {
    let can = shipped("can.stl");
    let table = shipped("table.stl");
    let (lo, hi) = table.aabb();
    let top = hi.z;
    let (clo, _) = can.aabb();
    let poses: Vec<Isometry3> = (0..4)
        .map(|i| Isometry3::translation(lo.x * 0.5 + 0.08 * i as f64, 0.0, top - clo.z))
        .collect();
    // Beside the row of copies, so that none hides it.
    let target = Point3::new(lo.x * 0.5, hi.y * 0.5, top);
    let image = render_placements(
        &can,
        &table,
        &Isometry3::identity(),
        &poses,
        Some(target),
        &options(200, 150),
    )
    .expect("render");
    let (w, h, rgba) = decode_png(&image.encode_png().expect("png"));
    assert_eq!((w, h), (200, 150));
    assert!(distinct_colours(&image).len() > 20);
    assert!(
        rgba.chunks_exact(4)
            .any(|p| p[0] > 180 && p[1] < 80 && p[2] < 80),
        "red target marker"
    );
}
