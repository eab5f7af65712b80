//! Benchmarks of pickplace-view: rendering an 800x600 picture of a ~50k-triangle scene.
//!
//! Scene: a table (box) and ten icospheres of 5,120 triangles each (51,212 triangles), seen by
//! a fitted perspective camera, with 2x2 supersampling (the default) and with edge darkening.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace_geometry::math::{Isometry3, Vector3};
use pickplace_geometry::shapes::box_mesh;
use pickplace_view::{Camera, Colour, Instance, Paint, RenderOptions, Scene, render, sphere_geometry};
use std::sync::Arc;

fn scene_50k() -> Scene {
    let mut scene = Scene::new();
    scene
        .add_mesh(&box_mesh([0.6, 0.4, 0.02]), Isometry3::translation(0.0, 0.0, -0.02), Colour::GREY)
        .expect("valid table");
    let sphere = Arc::new(sphere_geometry(0.09, 4).expect("valid sphere"));
    for i in 0..10 {
        let (x, y) = ((i % 5) as f64 * 0.22 - 0.44, (i / 5) as f64 * 0.3 - 0.15);
        let pose = Isometry3::translation(x, y, 0.09);
        let instance =
            Instance::new(sphere.clone(), pose, Paint::Uniform(Colour::palette(i))).expect("valid instance");
        scene.push(instance);
    }
    scene
}

fn render_800x600(c: &mut Criterion) {
    let scene = scene_50k();
    assert!(scene.triangle_count() >= 50_000);
    let camera = Camera::fit(scene.bounds().expect("non-empty scene"), Vector3::new(-1.0, -0.8, -0.7));
    let options = RenderOptions::default();
    c.bench_function("view/render_800x600_50k_tris_ssaa4", |b| b.iter(|| render(&scene, &camera, &options)));
    let edges = RenderOptions { draw_edges: true, ..options };
    c.bench_function("view/render_800x600_50k_tris_ssaa4_edges", |b| b.iter(|| render(&scene, &camera, &edges)));
}

criterion_group!(benches, render_800x600);
criterion_main!(benches);
