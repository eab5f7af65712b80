//! Benchmarks of pickplace-view: rendering pictures on the CPU and encoding an animated glb.
//!
//! - `render_800x600_50k_tris*`: a table (box) and ten icospheres of 5,120 triangles each
//!   (51,212 triangles), seen by a fitted perspective camera, with 2x2 supersampling (the
//!   default) and with edge darkening.
//! - `robot_scene_640x480`: the shipped NX-HIRO (primitive shapes), the shipped table, pallet
//!   and can, as in a key-pose picture of `pickplace view`, PNG encoding included.
//! - `robot_glb_200_frames`: the animated glb of a 200-sample right-arm motion.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace_geometry::math::{Isometry3, Vector3};
use pickplace_geometry::mesh::{self, MeshOptions};
use pickplace_geometry::shapes::box_mesh;
use pickplace_robot::{LoadOptions, RobotModel};
use pickplace_view::{
    Camera, Colour, Geometry, Grip, Instance, Motion, Paint, PlanView, Prop, RenderOptions,
    RobotGeometry, RobotGeometryOptions, Scene, render, sphere_geometry,
};
use std::path::PathBuf;
use std::sync::Arc;

fn scene_50k() -> Scene {
    let mut scene = Scene::new();
    scene
        .add_mesh(
            &box_mesh([0.6, 0.4, 0.02]),
            Isometry3::translation(0.0, 0.0, -0.02),
            Colour::GREY,
        )
        .expect("valid table");
    let sphere = Arc::new(sphere_geometry(0.09, 4).expect("valid sphere"));
    for i in 0..10 {
        let (x, y) = ((i % 5) as f64 * 0.22 - 0.44, (i / 5) as f64 * 0.3 - 0.15);
        let pose = Isometry3::translation(x, y, 0.09);
        let instance = Instance::new(sphere.clone(), pose, Paint::Uniform(Colour::palette(i)))
            .expect("valid instance");
        scene.push(instance);
    }
    scene
}

fn render_800x600(c: &mut Criterion) {
    let scene = scene_50k();
    assert!(scene.triangle_count() >= 50_000);
    let camera = Camera::fit(
        scene.bounds().expect("non-empty scene"),
        Vector3::new(-1.0, -0.8, -0.7),
    );
    let options = RenderOptions::default();
    c.bench_function("view/render_800x600_50k_tris_ssaa4", |b| {
        b.iter(|| render(&scene, &camera, &options))
    });
    let edges = RenderOptions {
        draw_edges: true,
        ..options
    };
    c.bench_function("view/render_800x600_50k_tris_ssaa4_edges", |b| {
        b.iter(|| render(&scene, &camera, &edges))
    });
}

fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(path)
}

fn prop(name: &str, file: &str, pose: Isometry3, colour: Colour) -> Prop {
    let m = mesh::load(&repo(file), &MeshOptions::default()).expect("a shipped mesh");
    Prop {
        name: name.into(),
        geometry: Arc::new(Geometry::from_trimesh(&m)),
        world_from_mesh: pose,
        colour,
    }
}

fn robot_view(frames: usize) -> PlanView {
    let robot = RobotModel::from_urdf_file(
        &repo("robots/nx-hiro/nx-hiro.urdf"),
        &LoadOptions::default(),
    )
    .expect("the shipped robot");
    let geometry = RobotGeometry::new(&robot, &RobotGeometryOptions::default()).expect("shapes");
    let elbow = robot.variable_index("RARM_JOINT2").expect("elbow");
    let times: Vec<f64> = (0..frames).map(|i| 0.02 * i as f64).collect();
    let configurations = (0..frames)
        .map(|i| {
            let mut q = vec![0.0; robot.variable_count()];
            q[elbow] = -1.7 + 0.8 * i as f64 / frames as f64;
            q
        })
        .collect();
    let tcp = robot.link_index("RARM_TCP").expect("tcp");
    let motion = Motion {
        world_from_root: Isometry3::translation(0.0, 0.0, 0.97),
        times: times.clone(),
        configurations,
        grips: vec![Grip {
            link: tcp,
            link_from_object: Isometry3::translation(0.0, 0.0, -0.06),
            grasp_time: times[frames / 3],
            release_time: Some(times[2 * frames / 3]),
        }],
    };
    let object = prop(
        "object",
        "meshes/can.stl",
        Isometry3::translation(0.35, -0.2, 0.72),
        Colour::ORANGE,
    );
    let environment = vec![
        prop(
            "table",
            "meshes/table.stl",
            Isometry3::translation(0.45, 0.0, 0.0),
            Colour::new(150, 160, 175),
        ),
        prop(
            "pallet",
            "meshes/pallet.stl",
            Isometry3::translation(0.45, 0.0, 0.70),
            Colour::new(176, 140, 100),
        ),
    ];
    PlanView::new(&robot, geometry, &motion, object, environment).expect("valid motion")
}

fn robot_scene(c: &mut Criterion) {
    let view = robot_view(200);
    let options = RenderOptions {
        width: 640,
        height: 480,
        ..RenderOptions::default()
    };
    let camera = view.camera(640.0 / 480.0).expect("camera");
    c.bench_function("view/robot_scene_640x480_png", |b| {
        b.iter(|| {
            view.render_frame(100, Some(&camera), &options)
                .and_then(|i| i.encode_png())
        })
    });
    c.bench_function("view/robot_glb_200_frames", |b| {
        b.iter(|| view.gltf("plan").and_then(|g| g.encode()))
    });
}

criterion_group!(benches, render_800x600, robot_scene);
criterion_main!(benches);
