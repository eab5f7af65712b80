//! Malformed URDFs give clear errors naming what is wrong.

use pickplace_robot::RobotModel;
use pickplace_robot::error::{Error, MeshProblem, ModelErrorKind};
use pickplace_robot::model::{LoadOptions, LoadWarning, UnreadableMesh};
use std::path::Path;

fn urdf(body: &str) -> String {
    format!("<robot name=\"t\">{body}</robot>")
}

fn load(body: &str) -> Result<RobotModel, Error> {
    RobotModel::from_urdf_str(&urdf(body), Path::new("."), &LoadOptions::default())
}

fn kind(body: &str) -> ModelErrorKind {
    match load(body) {
        Err(Error::InvalidModel { kind, .. }) => kind,
        other => panic!("expected an invalid-model error, got {other:?}"),
    }
}

const JOINT: &str = r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>"#;

#[test]
fn a_valid_two_link_robot_loads() {
    let model = load(&format!(r#"<link name="a"/><link name="b"/>{JOINT}"#)).expect("valid");
    assert_eq!(model.variable_count(), 1);
    assert_eq!(model.links()[0].name, "a");
}

#[test]
fn cycle() {
    let body = r#"<link name="a"/><link name="b"/><link name="c"/>
        <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
        <joint name="bc" type="fixed"><parent link="b"/><child link="c"/></joint>
        <joint name="ca" type="fixed"><parent link="c"/><child link="a"/></joint>"#;
    assert!(matches!(kind(body), ModelErrorKind::Cycle { .. }));
    // A cycle hanging off a valid root.
    let body = r#"<link name="r"/><link name="b"/><link name="c"/>
        <joint name="bc" type="fixed"><parent link="b"/><child link="c"/></joint>
        <joint name="cb" type="fixed"><parent link="c"/><child link="b"/></joint>"#;
    let k = kind(body);
    assert!(
        matches!(k, ModelErrorKind::Cycle { ref link } if link == "b" || link == "c"),
        "{k:?}"
    );
}

#[test]
fn missing_link() {
    let k = kind(&format!(r#"<link name="a"/>{JOINT}"#));
    assert_eq!(
        k,
        ModelErrorKind::MissingLink {
            joint: "j".into(),
            link: "b".into()
        }
    );
    let message = load(&format!(r#"<link name="a"/>{JOINT}"#))
        .expect_err("invalid")
        .to_string();
    assert!(message.contains("missing link \"b\""), "{message}");
}

#[test]
fn lower_above_upper() {
    let j = JOINT.replace("lower=\"-1\"", "lower=\"2\"");
    assert_eq!(
        kind(&format!(r#"<link name="a"/><link name="b"/>{j}"#)),
        ModelErrorKind::LimitsInverted {
            joint: "j".into(),
            lower: 2.0,
            upper: 1.0
        }
    );
}

#[test]
fn nan_origin() {
    let j = JOINT.replace("<axis", r#"<origin xyz="0 NaN 0"/><axis"#);
    let k = kind(&format!(r#"<link name="a"/><link name="b"/>{j}"#));
    assert_eq!(
        k,
        ModelErrorKind::NonFinite {
            element: "joint",
            name: "j".into(),
            field: "origin xyz"
        }
    );
}

#[test]
fn zero_axis_two_roots_duplicate_and_unsupported() {
    let j = JOINT.replace("0 0 1", "0 0 0");
    assert!(matches!(
        kind(&format!(r#"<link name="a"/><link name="b"/>{j}"#)),
        ModelErrorKind::ZeroAxis { .. }
    ));
    assert!(matches!(
        kind(r#"<link name="a"/><link name="b"/>"#),
        ModelErrorKind::MultipleRoots { .. }
    ));
    assert!(matches!(
        kind(r#"<link name="a"/><link name="a"/>"#),
        ModelErrorKind::DuplicateLink { .. }
    ));
    let j = JOINT.replace("revolute", "floating");
    assert!(matches!(
        kind(&format!(r#"<link name="a"/><link name="b"/>{j}"#)),
        ModelErrorKind::UnsupportedJointType { .. }
    ));
    // A mimic of a mimic is still refused.
    let mimic = |name: &str, parent: &str, child: &str, of: &str| {
        JOINT
            .replace(r#"name="j""#, &format!(r#"name="{name}""#))
            .replace(
                r#"<parent link="a"/><child link="b"/>"#,
                &format!(r#"<parent link="{parent}"/><child link="{child}"/>"#),
            )
            .replace("<axis", &format!(r#"<mimic joint="{of}"/><axis"#))
    };
    let chained = format!(
        r#"<link name="a"/><link name="b"/><link name="c"/><link name="d"/>{JOINT}{}{}"#,
        mimic("k", "b", "c", "j"),
        mimic("m", "c", "d", "k"),
    );
    assert!(matches!(kind(&chained), ModelErrorKind::BadMimic { .. }));
}

#[test]
fn a_mimic_of_a_joint_the_urdf_lacks_moves_on_its_own_with_a_warning() {
    // Issue 32: example-robot-data's alex_psyonic_hands names `index_q1` for `Left_index_q1`;
    // MoveIt and Pinocchio load it, the joint moving on its own.
    let bad_mimic = JOINT.replace("<axis", r#"<mimic joint="nope"/><axis"#);
    let model = load(&format!(r#"<link name="a"/><link name="b"/>{bad_mimic}"#))
        .expect("loads with a warning");
    assert_eq!(model.variable_count(), 1);
    assert_eq!(model.warnings().len(), 1);
    let text = model.warnings()[0].to_string();
    assert!(
        text.contains("\"j\"") && text.contains("\"nope\""),
        "{text}"
    );
}

#[test]
fn not_xml_is_a_syntax_error() {
    let e = RobotModel::from_urdf_str("<robot name=", Path::new("."), &LoadOptions::default())
        .expect_err("bad");
    assert!(matches!(e, Error::UrdfSyntax { .. }), "{e:?}");
    let e = RobotModel::from_urdf_file(
        Path::new("/nonexistent/robot.urdf"),
        &LoadOptions::default(),
    )
    .expect_err("missing");
    assert!(matches!(e, Error::Io { .. }));
    assert!(e.to_string().contains("/nonexistent/robot.urdf"));
}

fn mesh_link(filename: &str) -> String {
    format!(
        r#"<link name="a"><collision><geometry><mesh filename="{filename}"/></geometry></collision></link>"#
    )
}

#[test]
fn missing_mesh_names_the_file() {
    let e = load(&mesh_link("meshes/nothing.stl")).expect_err("missing");
    match &e {
        Error::Mesh {
            link,
            uri,
            kind: MeshProblem::NotFound { .. },
            ..
        } => {
            assert_eq!(link, "a");
            assert_eq!(uri, "meshes/nothing.stl");
        }
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("nothing.stl"));
}

#[test]
fn unreadable_mesh_is_an_error_or_a_warning_on_request() {
    let dir = std::env::temp_dir().join(format!("pickplace-robot-3ds-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("mypkg/meshes")).expect("temp dir");
    std::fs::write(dir.join("mypkg/meshes/hand.3ds"), "<COLLADA/>").expect("write");
    let text = urdf(&mesh_link("package://mypkg/meshes/hand.3ds"));
    let options = LoadOptions {
        package_dirs: vec![dir.clone()],
        ..LoadOptions::default()
    };
    let e = RobotModel::from_urdf_str(&text, Path::new("."), &options).expect_err("3DS");
    assert!(
        matches!(
            e,
            Error::Mesh {
                kind: MeshProblem::UnsupportedFormat { .. },
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("hand.3ds"), "{e}");
    let skip = LoadOptions {
        unreadable_mesh: UnreadableMesh::Skip,
        ..options
    };
    let model = RobotModel::from_urdf_str(&text, Path::new("."), &skip).expect("skipped");
    assert!(model.links()[0].collisions.is_empty());
    assert!(
        matches!(&model.warnings()[0], LoadWarning::SkippedMesh { uri, .. } if uri.contains("hand.3ds"))
    );
    // An unknown package is its own error.
    let text = urdf(&mesh_link("package://otherpkg/hand.stl"));
    let e = RobotModel::from_urdf_str(&text, Path::new("."), &LoadOptions::default())
        .expect_err("no package");
    assert!(
        matches!(e, Error::Mesh { kind: MeshProblem::PackageNotFound { ref package }, .. } if package == "otherpkg"),
        "{e:?}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn primitive_geometry_is_read() {
    let body = r#"<link name="a"><collision><origin xyz="0 0 1"/><geometry><capsule radius="0.1" length="0.4"/></geometry></collision>
        <collision><geometry><cylinder radius="0.1" length="0.4"/></geometry></collision>
        <collision><geometry><sphere radius="0.2"/></geometry></collision>
        <collision><geometry><box size="1 2 3"/></geometry></collision></link>"#;
    let model = load(body).expect("valid");
    let kinds: Vec<&str> = model.links()[0]
        .collisions
        .iter()
        .map(|g| g.shape.kind())
        .collect();
    assert_eq!(kinds, ["capsule", "cylinder", "sphere", "box"]);
    assert_eq!(
        model.links()[0].collisions[0]
            .link_from_shape
            .translation
            .vector
            .z,
        1.0
    );
    let e = load(r#"<link name="a"><collision><geometry><sphere radius="-1"/></geometry></collision></link>"#).expect_err("negative");
    assert!(e.to_string().contains("sphere"), "{e}");
}

#[test]
fn package_mesh_resolves_through_package_dirs_with_scale() {
    // `meshes/` of this repository stands in for a ROS package named "meshes".
    let repo = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let link = r#"<link name="a"><collision><geometry><mesh filename="package://meshes/box.stl" scale="2 2 2"/></geometry></collision></link>"#;
    let options = LoadOptions {
        package_dirs: vec![repo],
        ..LoadOptions::default()
    };
    let model = RobotModel::from_urdf_str(&urdf(link), Path::new("/nonexistent"), &options)
        .expect("package resolves");
    let shape = &model.links()[0].collisions[0].shape;
    let pickplace_robot::model::Shape::Mesh { path, mesh, .. } = shape else {
        panic!("{shape:?}")
    };
    assert!(path.ends_with("meshes/box.stl"), "{path:?}");
    // box.stl is 0.06 × 0.04 × 0.10 m; scaled by 2.
    let (lo, hi) =
        mesh.vertices()
            .iter()
            .fold(([f64::MAX; 3], [f64::MIN; 3]), |(mut lo, mut hi), p| {
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
                (lo, hi)
            });
    for (i, size) in [0.12, 0.08, 0.20].into_iter().enumerate() {
        assert!(
            (hi[i] - lo[i] - size).abs() < 1e-6,
            "axis {i}: {lo:?} {hi:?}"
        );
    }
}

#[test]
fn a_visual_origin_that_is_not_finite_is_refused_even_when_visuals_are_not_loaded() {
    // Found by `cargo xtask torture`: NaN in a visual origin loaded with exit 0.
    let body = format!(
        r#"<link name="a"><visual><origin xyz="nan 0 0"/><geometry><box size="1 1 1"/></geometry></visual></link><link name="b"/>{JOINT}"#
    );
    assert_eq!(
        kind(&body),
        ModelErrorKind::NonFinite {
            element: "link",
            name: "a".into(),
            field: "visual origin",
        }
    );
}
