//! Rendering: PNG output, coverage, clipping, occlusion, shading, determinism.

use crate::{decode_png, distinct_colours, temp_dir};
use pickplace_geometry::math::{Isometry3, Point3, Vector3};
use pickplace_geometry::shapes::{box_mesh, cylinder};
use pickplace_view::{
    AntiAliasing, Camera, Colour, Geometry, Image, Instance, MontageOptions, Paint, Projection,
    RenderOptions, Scene, montage, render, render_to_png,
};
use proptest::prelude::*;
use std::sync::Arc;

const BACKGROUND: Colour = Colour::new(250, 250, 250);

fn small(width: u32, height: u32) -> RenderOptions {
    RenderOptions {
        width,
        height,
        ..RenderOptions::default()
    }
}

fn box_scene() -> Scene {
    let mut scene = Scene::new();
    scene
        .add_mesh(
            &box_mesh([0.1, 0.1, 0.1]),
            Isometry3::identity(),
            Colour::ORANGE,
        )
        .expect("valid box");
    scene
}

fn is_background(p: [u8; 4]) -> bool {
    p == [BACKGROUND.r, BACKGROUND.g, BACKGROUND.b, 255]
}

fn count(image: &Image, pred: impl Fn([u8; 4]) -> bool) -> usize {
    image
        .as_rgba()
        .chunks_exact(4)
        .filter(|p| pred([p[0], p[1], p[2], p[3]]))
        .count()
}

#[test]
fn box_png_decodes_with_the_requested_size_and_is_not_blank() {
    let scene = box_scene();
    let camera = Camera::fit(
        scene.bounds().expect("non-empty"),
        Vector3::new(-1.0, -0.7, -0.5),
    );
    let image = render(&scene, &camera, &small(200, 150)).expect("render");
    let (w, h, rgba) = decode_png(&image.encode_png().expect("encode"));
    assert_eq!((w, h), (200, 150));
    assert_eq!(
        rgba,
        image.as_rgba(),
        "the PNG holds exactly the rendered pixels"
    );
    let background = count(&image, is_background);
    let object = count(&image, |p| !is_background(p));
    assert!(
        background > 1000 && object > 1000,
        "background {background}, object {object}"
    );
    // Three visible faces at different angles to the light, plus anti-aliased edges.
    assert!(
        distinct_colours(&image).len() >= 5,
        "{} colours",
        distinct_colours(&image).len()
    );
    assert!(
        !is_background(image.pixel(100, 75).expect("centre")),
        "the box is at the centre"
    );
    assert!(is_background(image.pixel(0, 0).expect("corner")));
}

#[test]
fn camera_inside_a_closed_box_sees_walls_everywhere() {
    let scene = box_scene();
    for target in [
        Point3::new(1.0, 0.2, 0.1),
        Point3::new(0.0, 0.0, -1.0),
        Point3::new(-0.3, 1.0, 2.0),
    ] {
        let camera = Camera::look_at(Point3::new(0.01, -0.02, 0.03), target, Vector3::z());
        let image = render(&scene, &camera, &small(64, 48)).expect("render");
        assert_eq!(
            count(&image, is_background),
            0,
            "every pixel sees an inner wall (two-sided drawing)"
        );
    }
}

#[test]
fn camera_through_geometry_clips_at_the_near_plane() {
    // The eye sits in the middle of a long thin box looking along it: every triangle of the
    // side walls crosses the near plane. The far end cap must be visible through the walls'
    // clipped remains, and nothing may panic or smear.
    let mut scene = Scene::new();
    scene
        .add_mesh(
            &box_mesh([2.0, 0.1, 0.1]),
            Isometry3::identity(),
            Colour::GREY,
        )
        .expect("valid box");
    let mut camera = Camera::look_at(
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Vector3::z(),
    );
    camera.near = 0.05;
    let image = render(&scene, &camera, &small(80, 60)).expect("render");
    assert_eq!(count(&image, is_background), 0);
    assert!(
        distinct_colours(&image).len() >= 3,
        "walls and end cap are shaded differently"
    );
}

#[test]
fn ground_plane_crossing_the_near_plane_ends_at_the_horizon() {
    // A huge ground square under an eye looking horizontally: its triangles reach behind the
    // camera. The lower half must be ground, the upper half background.
    let g = Geometry::new(
        vec![
            Point3::new(-100.0, -100.0, 0.0),
            Point3::new(100.0, -100.0, 0.0),
            Point3::new(100.0, 100.0, 0.0),
            Point3::new(-100.0, 100.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .expect("valid quad");
    let mut scene = Scene::new();
    scene.push(
        Instance::new(
            Arc::new(g),
            Isometry3::identity(),
            Paint::Uniform(Colour::GREEN),
        )
        .expect("valid"),
    );
    let camera = Camera::look_at(
        Point3::new(0.0, 0.0, 1.0),
        Point3::new(5.0, 0.0, 1.0),
        Vector3::z(),
    );
    let image = render(&scene, &camera, &small(80, 60)).expect("render");
    for x in [0, 40, 79] {
        assert!(
            is_background(image.pixel(x, 5).expect("top")),
            "sky at column {x}"
        );
        assert!(
            !is_background(image.pixel(x, 55).expect("bottom")),
            "ground at column {x}"
        );
    }
}

#[test]
fn nearer_surfaces_hide_farther_ones_whatever_the_drawing_order() {
    let front = (
        box_mesh([0.05, 0.05, 0.05]),
        Isometry3::translation(0.0, 0.0, 0.3),
        Colour::RED,
    );
    let back = (
        box_mesh([0.3, 0.3, 0.05]),
        Isometry3::identity(),
        Colour::BLUE,
    );
    let camera = Camera::look_at(Point3::new(0.0, 0.0, 2.0), Point3::origin(), Vector3::y());
    let mut pictures = Vec::new();
    for order in [[&front, &back], [&back, &front]] {
        let mut scene = Scene::new();
        for (mesh, pose, colour) in order {
            scene.add_mesh(mesh, *pose, *colour).expect("valid");
        }
        let image = render(&scene, &camera, &small(100, 100)).expect("render");
        let [r, g, b, _] = image.pixel(50, 50).expect("centre");
        assert!(
            r > 150 && g < 80 && b < 80,
            "centre shows the red front box: {r} {g} {b}"
        );
        // 15 px off centre: 0.21 m at the back box's top, outside the front box (about 4 px).
        let [r, _, b, _] = image.pixel(50, 35).expect("off centre");
        assert!(b > r, "around it the blue back box");
        pictures.push(image);
    }
    assert_eq!(pictures[0], pictures[1]);
}

#[test]
fn per_triangle_colours_show_on_their_faces() {
    // Colour the +z face (triangles 2 and 3 of the box builder) red, the rest blue, and look
    // down at it.
    let mesh = box_mesh([0.1, 0.1, 0.1]);
    let colours: Vec<Colour> = (0..mesh.triangle_count())
        .map(|t| {
            let n = mesh.triangle_normal(t);
            if n.z > 0.9 { Colour::RED } else { Colour::BLUE }
        })
        .collect();
    let mut scene = Scene::new();
    scene
        .add_mesh_per_triangle(&mesh, Isometry3::identity(), colours)
        .expect("one colour per triangle");
    let camera = Camera::look_at(Point3::new(0.0, 0.0, 1.0), Point3::origin(), Vector3::y());
    let image = render(&scene, &camera, &small(60, 60)).expect("render");
    let [r, g, b, _] = image.pixel(30, 30).expect("centre");
    assert!(r > 150 && g < 80 && b < 80, "{r} {g} {b}");
    let wrong = vec![Colour::RED; 3];
    assert!(
        scene
            .add_mesh_per_triangle(&mesh, Isometry3::identity(), wrong)
            .is_err()
    );
}

#[test]
fn lambert_shading_darkens_oblique_faces_and_treats_both_sides_alike() {
    // A single triangle facing the camera (light along the view) is brighter than the same
    // triangle tilted by 70°; seen from behind it is as bright as from the front.
    let tri = Arc::new(
        Geometry::new(
            vec![
                Point3::new(-1.0, -1.0, 0.0),
                Point3::new(1.0, -1.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2]],
        )
        .expect("valid"),
    );
    let options = RenderOptions {
        light_direction: Vector3::z(),
        anti_aliasing: AntiAliasing::None,
        ..small(40, 40)
    };
    let shade = |pose: Isometry3, eye_z: f64| -> u8 {
        let mut scene = Scene::new();
        scene.push(Instance::new(tri.clone(), pose, Paint::Uniform(Colour::WHITE)).expect("valid"));
        let camera = Camera::look_at(Point3::new(0.0, 0.0, eye_z), Point3::origin(), Vector3::y());
        render(&scene, &camera, &options)
            .expect("render")
            .pixel(20, 22)
            .expect("centre")[0]
    };
    let facing = shade(Isometry3::identity(), 5.0);
    let from_behind = shade(Isometry3::identity(), -5.0);
    let tilted = shade(Isometry3::rotation(Vector3::x() * 70f64.to_radians()), 5.0);
    assert_eq!(facing, 255);
    assert_eq!(from_behind, facing);
    assert!(tilted < facing - 40, "tilted {tilted}, facing {facing}");
}

#[test]
fn orthographic_size_does_not_depend_on_distance() {
    let scene = box_scene();
    let widths: Vec<usize> = [1.0, 3.0]
        .iter()
        .map(|&d| {
            let mut camera =
                Camera::look_at(Point3::new(0.0, 0.0, d), Point3::origin(), Vector3::y());
            camera.projection = Projection::Orthographic { half_height: 0.25 };
            let image = render(&scene, &camera, &small(100, 100)).expect("render");
            (0..100)
                .filter(|&x| !is_background(image.pixel(x, 50).expect("row")))
                .count()
        })
        .collect();
    assert_eq!(widths[0], widths[1]);
    assert!(
        (38..=42).contains(&widths[0]),
        "0.2 m of 0.5 m across 100 px: {}",
        widths[0]
    );
}

#[test]
fn edge_darkening_adds_dark_lines() {
    let scene = box_scene();
    let camera = Camera::fit(
        scene.bounds().expect("non-empty"),
        Vector3::new(-1.0, -0.7, -0.5),
    );
    let plain = render(&scene, &camera, &small(120, 90)).expect("render");
    let edged = render(
        &scene,
        &camera,
        &RenderOptions {
            draw_edges: true,
            ..small(120, 90)
        },
    )
    .expect("render");
    let sum = |p: &[u8]| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]);
    let pairs = || {
        plain
            .as_rgba()
            .chunks_exact(4)
            .zip(edged.as_rgba().chunks_exact(4))
    };
    let darker = pairs().filter(|(p, e)| sum(e) + 60 < sum(p)).count();
    let lighter = pairs().filter(|(p, e)| sum(e) > sum(p) + 60).count();
    // The box's 7 visible edges (silhouette and creases) are about 400 px long in all.
    assert!(darker > 150, "{darker} pixels darker with edges");
    assert_eq!(lighter, 0, "edges never lighten");
}

#[test]
fn rendering_is_deterministic() {
    let mut scene = box_scene();
    scene
        .add_mesh(
            &cylinder(0.05, 0.3, 40),
            Isometry3::translation(0.2, 0.1, -0.1),
            Colour::GREEN,
        )
        .expect("valid");
    scene
        .add_arrow(
            Point3::new(0.0, 0.0, 0.1),
            Vector3::new(0.0, 0.0, 0.2),
            0.005,
            Colour::BLUE,
        )
        .expect("valid");
    scene
        .add_point_marker(Point3::new(-0.2, 0.0, 0.0), 0.02, Colour::RED)
        .expect("valid");
    let camera = Camera::fit(
        scene.bounds().expect("non-empty"),
        Vector3::new(-1.0, -0.3, -0.5),
    );
    let options = RenderOptions {
        draw_edges: true,
        ..small(160, 120)
    };
    let a = render(&scene, &camera, &options)
        .expect("render")
        .encode_png()
        .expect("encode");
    let b = render(&scene.clone(), &camera, &options)
        .expect("render")
        .encode_png()
        .expect("encode");
    assert_eq!(a, b);
}

#[test]
fn render_to_png_writes_a_complete_file_atomically() {
    let dir = temp_dir("png");
    let path = dir.join("box.png");
    let scene = box_scene();
    let camera = Camera::fit(
        scene.bounds().expect("non-empty"),
        Vector3::new(-1.0, -0.7, -0.5),
    );
    render_to_png(&scene, &camera, &small(64, 48), &path).expect("write");
    let (w, h, _) = decode_png(&std::fs::read(&path).expect("read back"));
    assert_eq!((w, h), (64, 48));
    let entries: Vec<_> = std::fs::read_dir(&dir).expect("list").collect();
    assert_eq!(entries.len(), 1, "no temporary file left behind");
    let missing = dir.join("no-such-dir").join("x.png");
    assert!(matches!(
        render_to_png(&scene, &camera, &small(8, 8), &missing),
        Err(pickplace_view::Error::Write { .. })
    ));
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn invalid_options_are_errors_not_panics() {
    let scene = box_scene();
    let camera = Camera::look_at(Point3::new(1.0, 1.0, 1.0), Point3::origin(), Vector3::z());
    assert!(render(&scene, &camera, &small(0, 10)).is_err());
    assert!(
        render(
            &scene,
            &camera,
            &RenderOptions {
                ambient: 1.5,
                ..small(8, 8)
            }
        )
        .is_err()
    );
    assert!(
        render(
            &scene,
            &camera,
            &RenderOptions {
                light_direction: Vector3::zeros(),
                ..small(8, 8)
            }
        )
        .is_err()
    );
    let same = Camera::look_at(Point3::origin(), Point3::origin(), Vector3::z());
    assert!(render(&scene, &same, &small(8, 8)).is_err());
    let nan = Camera::look_at(
        Point3::new(f64::NAN, 0.0, 0.0),
        Point3::origin(),
        Vector3::z(),
    );
    assert!(render(&scene, &nan, &small(8, 8)).is_err());
    // An empty scene is a valid, blank picture.
    let blank = render(&Scene::new(), &camera, &small(8, 8)).expect("render");
    assert_eq!(count(&blank, is_background), 64);
}

#[test]
fn montage_of_key_poses_fits_in_one_png() {
    let scene = box_scene();
    let images: Vec<Image> = [
        Vector3::x(),
        Vector3::y(),
        -Vector3::z(),
        Vector3::new(1.0, 1.0, -1.0),
        -Vector3::x(),
    ]
    .iter()
    .map(|&dir| {
        let camera = Camera::fit(scene.bounds().expect("non-empty"), dir);
        render(&scene, &camera, &small(40, 30)).expect("render")
    })
    .collect();
    let m = montage(&images, &MontageOptions::default()).expect("montage");
    // Five images: 3 columns, 2 rows, 4 px gaps.
    assert_eq!((m.width(), m.height()), (3 * 44 + 4, 2 * 34 + 4));
    let (w, h, _) = decode_png(&m.encode_png().expect("encode"));
    assert_eq!((w, h), (m.width(), m.height()));
    assert_eq!(m.pixel(4 + 20, 4 + 15), images[0].pixel(20, 15));
    assert_eq!(m.pixel(4 + 44 + 20, 4 + 34 + 15), images[4].pixel(20, 15));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Any camera pose, inside, outside or grazing the geometry, gives an image of the
    /// requested size or a parameter error, never a panic.
    #[test]
    fn any_camera_pose_renders(
        eye in prop::array::uniform3(-0.6f64..0.6),
        target in prop::array::uniform3(-0.6f64..0.6),
        near in 1e-4f64..0.5,
        fov in 0.05f64..3.0,
        orthographic in any::<bool>(),
    ) {
        let mut scene = box_scene();
        scene.add_mesh(&cylinder(0.05, 0.4, 12), Isometry3::translation(0.1, 0.0, -0.2), Colour::GREEN).expect("valid");
        let mut camera = Camera::look_at(Point3::from(eye), Point3::from(target), Vector3::z());
        camera.near = near;
        camera.projection = if orthographic {
            Projection::Orthographic { half_height: fov * 0.2 }
        } else {
            Projection::Perspective { fov_y: fov }
        };
        let options = RenderOptions { draw_edges: true, ..small(24, 18) };
        match render(&scene, &camera, &options) {
            Ok(image) => prop_assert_eq!((image.width(), image.height()), (24, 18)),
            Err(e) => prop_assert!(matches!(e, pickplace_view::Error::InvalidParameter { .. }), "{}", e),
        }
    }
}

#[test]
fn translucent_instances_blend_over_what_is_behind_and_hide_behind_what_is_in_front() {
    let small_box = Arc::new(Geometry::from_trimesh(&box_mesh([0.05, 0.05, 0.05])));
    let back = Arc::new(Geometry::from_trimesh(&box_mesh([0.3, 0.3, 0.05])));
    let camera = Camera::look_at(Point3::new(0.0, 0.0, 2.0), Point3::origin(), Vector3::y());
    let centre = |front_z: f64, opacity: f64| -> [u8; 4] {
        let mut scene = Scene::new();
        let red = Instance::new(
            small_box.clone(),
            Isometry3::translation(0.0, 0.0, front_z),
            Paint::Uniform(Colour::RED),
        )
        .expect("valid")
        .with_opacity(opacity)
        .expect("opacity in range");
        // Translucent first in the scene: the renderer still draws it after the opaque box.
        scene.push(red);
        scene.push(
            Instance::new(
                back.clone(),
                Isometry3::identity(),
                Paint::Uniform(Colour::BLUE),
            )
            .expect("valid"),
        );
        render(&scene, &camera, &small(100, 100))
            .expect("render")
            .pixel(50, 50)
            .expect("centre")
    };
    let opaque_red = centre(0.3, 1.0);
    let blended = centre(0.3, 0.5);
    let hidden = centre(-0.3, 0.5);
    assert!(
        blended[0] > 60 && blended[2] > 60,
        "both colours show: {blended:?}"
    );
    assert!(blended[0] < opaque_red[0], "less red than the opaque box");
    assert!(
        hidden[2] > hidden[0],
        "behind the opaque box it does not show: {hidden:?}"
    );
    let invisible = centre(0.3, 0.0);
    assert_eq!(invisible, hidden, "opacity 0 draws nothing");
    let bad = Instance::new(
        small_box,
        Isometry3::identity(),
        Paint::Uniform(Colour::RED),
    )
    .expect("valid");
    assert!(bad.with_opacity(1.5).is_err());
}
