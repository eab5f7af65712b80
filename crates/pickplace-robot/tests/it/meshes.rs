//! Mesh geometry as robot makers ship it: COLLADA files, mirrored and non-uniform scales.

use pickplace_geometry::mesh::TriMesh;
use pickplace_robot::error::{Error, ModelErrorKind};
use pickplace_robot::model::Shape;
use pickplace_robot::{LoadOptions, RobotModel};
use std::path::PathBuf;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn mesh_robot(filename: &str, scale: &str) -> String {
    format!(
        r#"<robot name="m"><link name="box"><collision><geometry>
             <mesh filename="{filename}" scale="{scale}"/></geometry></collision></link></robot>"#
    )
}

fn load(text: &str) -> pickplace_robot::Result<RobotModel> {
    RobotModel::from_urdf_str(text, &data_dir(), &LoadOptions::default())
}

fn the_mesh(model: &RobotModel) -> &TriMesh {
    match &model.links()[0].collisions[0].shape {
        Shape::Mesh { mesh, .. } => mesh,
        other => panic!("not a mesh: {other:?}"),
    }
}

fn signed_volume(mesh: &TriMesh) -> f64 {
    (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.triangle_points(t);
            a.coords.dot(&b.coords.cross(&c.coords)) / 6.0
        })
        .sum()
}

#[test]
fn a_collada_mesh_in_millimetres_loads_in_metres() {
    let model = load(&mesh_robot("box_mm.dae", "1 1 1")).expect("DAE loads");
    let mesh = the_mesh(&model);
    assert_eq!(mesh.triangle_count(), 12);
    assert!(mesh.report().is_closed());
    let (lo, hi) = mesh.aabb();
    assert!((hi - lo - pickplace_geometry::math::Vector3::repeat(0.1)).norm() < 1e-6);
    assert!((signed_volume(mesh) - 1e-3).abs() < 1e-9, "outward normals");
    // The extension is case-insensitive, as Baxter's `.DAE` files need.
    let dir = std::env::temp_dir().join(format!("pickplace-robot-DAE-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::copy(data_dir().join("box_mm.dae"), dir.join("BOX.DAE")).expect("copy");
    let text = mesh_robot("BOX.DAE", "2 2 2");
    let model = RobotModel::from_urdf_str(&text, &dir, &LoadOptions::default()).expect("DAE");
    assert!((signed_volume(the_mesh(&model)) - 8e-3).abs() < 1e-9);
    // A broken DAE is an error naming the file.
    std::fs::write(dir.join("broken.dae"), "<COLLADA><oops").expect("write");
    let error = RobotModel::from_urdf_str(
        &mesh_robot("broken.dae", "1 1 1"),
        &dir,
        &LoadOptions::default(),
    )
    .expect_err("broken");
    assert!(matches!(error, Error::Mesh { .. }), "{error:?}");
    assert!(error.to_string().contains("broken.dae"), "{error}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_mirrored_mesh_keeps_outward_normals() {
    let model = load(&mesh_robot("box_mm.dae", "1 -1 1")).expect("mirrored");
    let mesh = the_mesh(&model);
    assert!(
        (signed_volume(mesh) - 1e-3).abs() < 1e-9,
        "volume stays positive"
    );
    let model = load(&mesh_robot("box_mm.dae", "1 2 0.5")).expect("non-uniform");
    assert!((signed_volume(the_mesh(&model)) - 1e-3).abs() < 1e-9);
    let (lo, hi) = the_mesh(&model).aabb();
    assert!(((hi - lo).y - 0.2).abs() < 1e-9 && ((hi - lo).z - 0.05).abs() < 1e-9);
}

#[test]
fn a_zero_scale_is_an_error_naming_the_link_and_the_file() {
    let error = load(&mesh_robot("box_mm.dae", "1 0 1")).expect_err("flat");
    assert!(
        matches!(&error, Error::InvalidModel { kind: ModelErrorKind::BadMeshScale { link, uri, .. }, .. }
            if link == "box" && uri == "box_mm.dae"),
        "{error:?}"
    );
    assert!(error.to_string().contains("box_mm.dae"), "{error}");
}
