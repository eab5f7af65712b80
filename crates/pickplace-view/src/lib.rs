//! Pictures of clusters, placements and plans, without a GPU or a browser.
//!
//! # Example
//! ```
//! use pickplace_geometry::math::{Isometry3, Point3, Vector3};
//! use pickplace_geometry::shapes::box_mesh;
//! use pickplace_view::{Camera, Colour, RenderOptions, Scene, render};
//!
//! let mut scene = Scene::new();
//! let table = box_mesh([0.4, 0.3, 0.02]);
//! scene.add_mesh(&table, Isometry3::translation(0.0, 0.0, -0.02), Colour::GREY)?;
//! let object = box_mesh([0.05, 0.03, 0.08]);
//! let colours = (0..object.triangle_count()).map(|t| Colour::palette(t / 2)).collect();
//! scene.add_mesh_per_triangle(&object, Isometry3::translation(0.1, 0.0, 0.08), colours)?;
//! scene.add_point_marker(Point3::new(-0.2, 0.1, 0.0), 0.015, Colour::RED)?;
//! scene.add_arrow(Point3::new(-0.2, 0.1, 0.0), Vector3::new(0.0, 0.0, 0.15), 0.005, Colour::BLUE)?;
//!
//! let bounds = scene.bounds().expect("the scene is not empty");
//! let camera = Camera::fit(bounds, Vector3::new(-1.0, -0.7, -0.6));
//! let options = RenderOptions { width: 160, height: 120, draw_edges: true, ..RenderOptions::default() };
//! let image = render(&scene, &camera, &options)?;
//! assert_eq!((image.width(), image.height()), (160, 120));
//! let png = image.encode_png()?;
//! assert_eq!(&png[1..4], b"PNG");
//! # Ok::<(), pickplace_view::Error>(())
//! ```
//!
//! # Outputs
//!
//! - **PNG pictures** from a small software rasteriser ([`render`], [`render_to_png`]): a
//!   [`Scene`] of triangle meshes placed by poses (`world_from_mesh`) and coloured per
//!   instance or per triangle (cluster pictures, Harada et al. §III-A), seen by a look-at
//!   [`Camera`] (perspective or orthographic, [`Camera::fit`] frames a bounding box), with a
//!   z-buffer, near-plane clipping, two-sided flat Lambert shading, optional edge darkening and
//!   2x2 supersampling. Markers show target points and directions
//!   ([`Scene::add_point_marker`], [`Scene::add_arrow`], [`Scene::add_frame_axes`]);
//!   [`montage`] tiles several pictures (key poses, say) into one.
//! - **glTF 2.0 binary files** ([`glb::GltfBuilder`]): flat-shaded meshes, a node hierarchy
//!   with local transforms and one animation of per-node translation and rotation tracks, for
//!   any glTF viewer; [`glb::validate_glb`] reads a file back and checks it.
//! - **The paper's pictures** ([`pictures`]): clusters coloured like Harada et al. Figs. 3–5
//!   ([`render_clusters`]) and candidate placements like Fig. 6 ([`render_placements`]).
//! - **Plans played back** ([`plan::PlanView`]): robot links ([`RobotGeometry`], URDF
//!   primitives triangulated) posed by forward kinematics at every trajectory sample, the
//!   object following the link that holds it between grasp and release; rendered per frame
//!   or exported as an animated glTF with one keyframe per sample.
//!
//! Files are written atomically by [`pickplace_geometry::export::write_atomic`] (temporary
//! file, then rename): an output path is never left half-written.
//!
//! # Limitations
//! - Flat shading only: one normal per triangle, no smoothing, textures or shadows;
//!   a single directional light fixed in the camera frame.
//! - Anti-aliasing is 2x2 supersampling; thin features below half a pixel may still alias.
//! - No text: montages have no labels, and pictures carry no legend.
//! - Translucency is sorted per instance, not per triangle; the glTF export of a [`Scene`]
//!   writes translucent instances opaque.
//! - Robot links are coloured by name (hands and fingers darker), not by URDF materials.
//! - Single-threaded; memory grows with the sample count (9 bytes per sample).
//! - The glTF writer emits one buffer in the `.glb`, float accessors without compression or
//!   quantisation, flat (unwelded) vertices, `LINEAR` interpolation only, translation and
//!   rotation tracks only (no scale or morph weights), and one animation per file.
//! - The validator checks the rules this writer relies on, not the whole glTF specification
//!   (no textures, images, cameras, skins, sparse accessors or extensions).
#![warn(missing_docs)]

pub mod camera;
pub mod error;
pub mod glb;
pub mod image;
pub mod pictures;
pub mod plan;
pub mod raster;
pub mod robot;
pub mod scene;

pub use camera::{Camera, DEFAULT_FOV_Y, OBLIQUE_VIEW, Projection};
pub use error::{Error, GeometryErrorKind, GlbErrorKind, GltfErrorKind, MotionErrorKind, Result};
pub use image::{
    Colour, Image, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, MontageOptions, check_image_size, montage,
};
pub use pictures::{PictureOptions, cluster_colours, render_clusters, render_placements};
pub use plan::{Grip, Motion, PlanView, Prop};
pub use raster::{AntiAliasing, RenderOptions, render, render_to_png};
pub use robot::{LinkShapes, RobotGeometry, RobotGeometryOptions, shape_geometry};
pub use scene::{Geometry, Instance, Paint, Scene, arrow_geometry, sphere_geometry};
