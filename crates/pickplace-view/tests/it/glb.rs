//! glTF binary output: structure, buffer sizes, hierarchy, animation sample counts, and the
//! validator's rejection of broken files.

use crate::temp_dir;
use pickplace_geometry::math::{Isometry3, Point3, UnitQuaternion, Vector3};
use pickplace_geometry::shapes::{box_mesh, cylinder};
use pickplace_view::glb::{GltfBuilder, NodeId, validate_glb};
use pickplace_view::{Colour, Error, Geometry, GlbErrorKind, GltfErrorKind, Paint, Scene};
use serde_json::Value;

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Splits a .glb into its JSON value and BIN bytes (no checks beyond the layout).
fn split(glb: &[u8]) -> (Value, Vec<u8>) {
    let json_len = u32_at(glb, 12) as usize;
    let json: Value = serde_json::from_slice(&glb[20..20 + json_len]).expect("JSON chunk");
    let bin = if glb.len() > 20 + json_len {
        glb[28 + json_len..].to_vec()
    } else {
        Vec::new()
    };
    (json, bin)
}

/// Packs a JSON value and BIN bytes into a .glb with correct header and padding.
fn pack(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).expect("serialise");
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let total = 12 + 8 + j.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&j);
    if !bin.is_empty() {
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
    }
    out
}

/// A three-link arm (base, upper, lower with a cylinder each) animated over `samples`
/// keyframes, and an object node with a box.
fn arm(samples: usize) -> (GltfBuilder, [NodeId; 4]) {
    let mut gltf = GltfBuilder::new("plan");
    let link = Geometry::from_trimesh(&cylinder(0.03, 0.3, 16));
    let link_mesh = gltf
        .add_mesh("link", &link, &Paint::Uniform(Colour::GREY))
        .expect("mesh");
    let cube = Geometry::from_trimesh(&box_mesh([0.04, 0.04, 0.04]));
    let colours: Vec<Colour> = (0..cube.triangle_count())
        .map(|t| Colour::palette(t / 2))
        .collect();
    let cube_mesh = gltf
        .add_mesh("object", &cube, &Paint::PerTriangle(colours.into()))
        .expect("mesh");
    let base = gltf
        .add_node("base", Some(link_mesh), None, &Isometry3::identity())
        .expect("node");
    let upper = gltf
        .add_node(
            "upper",
            Some(link_mesh),
            Some(base),
            &Isometry3::translation(0.0, 0.0, 0.3),
        )
        .expect("node");
    let lower = gltf
        .add_node(
            "lower",
            Some(link_mesh),
            Some(upper),
            &Isometry3::translation(0.0, 0.0, 0.3),
        )
        .expect("node");
    let object = gltf
        .add_node(
            "object",
            Some(cube_mesh),
            None,
            &Isometry3::translation(0.4, 0.0, 0.04),
        )
        .expect("node");
    let times: Vec<f64> = (0..samples).map(|i| 0.1 * i as f64).collect();
    let bend = |i: usize, axis: Vector3| -> Vec<UnitQuaternion> {
        (0..samples)
            .map(|k| UnitQuaternion::from_scaled_axis(axis * (0.02 * (k + i) as f64)))
            .collect()
    };
    gltf.animate_rotation(upper, &times, &bend(0, Vector3::y()))
        .expect("track");
    gltf.animate_rotation(lower, &times, &bend(3, Vector3::x()))
        .expect("track");
    let poses: Vec<Isometry3> = (0..samples)
        .map(|k| {
            Isometry3::new(
                Vector3::new(0.4, 0.0, 0.04 + 0.01 * k as f64),
                Vector3::z() * 0.05 * k as f64,
            )
        })
        .collect();
    gltf.animate_poses(object, &times, &poses).expect("track");
    (gltf, [base, upper, lower, object])
}

#[test]
fn scene_export_is_valid_with_exact_buffer_sizes() {
    let mut scene = Scene::new();
    scene
        .add_mesh(
            &box_mesh([0.1, 0.2, 0.3]),
            Isometry3::translation(1.0, 0.0, 0.0),
            Colour::ORANGE,
        )
        .expect("box");
    scene
        .add_point_marker(Point3::new(0.0, 0.5, 0.0), 0.02, Colour::RED)
        .expect("marker");
    let glb = GltfBuilder::from_scene(&scene, "scene")
        .expect("builder")
        .encode()
        .expect("encode");
    assert_eq!(&glb[0..4], b"glTF");
    assert_eq!(u32_at(&glb, 4), 2);
    assert_eq!(u32_at(&glb, 8) as usize, glb.len());
    assert_eq!(glb.len() % 4, 0);
    let summary = validate_glb(&glb).expect("valid glb");
    assert_eq!(
        summary.buffer_length, summary.bin_length,
        "no padding needed: every array is 4-byte sized"
    );
    assert_eq!(summary.meshes, 2);
    assert_eq!(summary.materials, 2);
    assert_eq!(summary.node_names.len(), 2);
    assert_eq!(summary.triangles, 12 + 320);
    assert_eq!(
        summary.vertices,
        3 * (12 + 320),
        "flat: three vertices per triangle"
    );
    assert!(summary.animations.is_empty());
    // Positions, normals, indices per mesh: 3 accessors each, one view each.
    assert_eq!(summary.accessors, 6);
    assert_eq!(summary.buffer_views, 6);
    // Byte count: (36 + 960) vertices x (12 + 12) bytes + (36 + 960) indices x 4 bytes.
    assert_eq!(summary.bin_length, (36 + 960) * 24 + (36 + 960) * 4);
    // The JSON chunk is padded with spaces.
    let json_len = u32_at(&glb, 12) as usize;
    assert_eq!(json_len % 4, 0);
    let (json, _) = split(&glb);
    let position = &json["accessors"][0];
    // Vertices are in the mesh frame; the node carries the pose.
    let as_f32 = |v: &Value| -> Vec<f32> {
        v.as_array()
            .expect("array")
            .iter()
            .map(|x| x.as_f64().expect("number") as f32)
            .collect()
    };
    assert_eq!(as_f32(&position["min"]), vec![-0.1f32, -0.2, -0.3]);
    assert_eq!(as_f32(&position["max"]), vec![0.1f32, 0.2, 0.3]);
    assert_eq!(
        as_f32(&json["nodes"][0]["translation"]),
        vec![1.0f32, 0.0, 0.0]
    );
}

#[test]
fn instances_sharing_geometry_share_one_mesh() {
    let mut scene = Scene::new();
    scene
        .add_point_marker(Point3::origin(), 0.02, Colour::RED)
        .expect("marker");
    let geometry = scene.instances()[0].geometry().clone();
    for i in 1..4 {
        let pose = Isometry3::translation(0.1 * i as f64, 0.0, 0.0);
        scene.push(
            pickplace_view::Instance::new(geometry.clone(), pose, Paint::Uniform(Colour::RED))
                .expect("ok"),
        );
    }
    let summary = validate_glb(
        &GltfBuilder::from_scene(&scene, "s")
            .expect("b")
            .encode()
            .expect("e"),
    )
    .expect("valid");
    assert_eq!(summary.meshes, 1);
    assert_eq!(summary.node_names.len(), 4);
}

#[test]
fn animation_has_one_sample_per_trajectory_point() {
    for samples in [1usize, 2, 37] {
        let (gltf, [base, upper, lower, object]) = arm(samples);
        let glb = gltf.encode().expect("encode");
        let summary = validate_glb(&glb).expect("valid glb");
        assert_eq!(
            summary.node_parents,
            vec![None, Some(base.index()), Some(upper.index()), None]
        );
        assert_eq!(summary.node_names[lower.index()].as_deref(), Some("lower"));
        assert_eq!(summary.coloured_primitives, 1);
        assert_eq!(summary.animations.len(), 1);
        let animation = &summary.animations[0];
        assert_eq!(animation.name.as_deref(), Some("plan"));
        let targets: Vec<(usize, &str, u64)> = animation
            .channels
            .iter()
            .map(|c| (c.node, c.path.as_str(), c.samples))
            .collect();
        let n = samples as u64;
        assert_eq!(
            targets,
            vec![
                (upper.index(), "rotation", n),
                (lower.index(), "rotation", n),
                (object.index(), "translation", n),
                (object.index(), "rotation", n),
            ]
        );
        assert!((animation.duration - 0.1 * (samples - 1) as f64).abs() < 1e-6);
        // The four tracks share one time accessor.
        let (json, _) = split(&glb);
        let inputs: Vec<&Value> = json["animations"][0]["samplers"]
            .as_array()
            .expect("samplers")
            .iter()
            .map(|s| &s["input"])
            .collect();
        assert!(inputs.iter().all(|&i| i == inputs[0]));
        assert_eq!(
            json["nodes"][base.index()]["children"],
            serde_json::json!([upper.index()])
        );
    }
}

#[test]
fn rotation_keyframes_stay_in_one_hemisphere() {
    let mut gltf = GltfBuilder::new("a");
    let node = gltf
        .add_node("n", None, None, &Isometry3::identity())
        .expect("node");
    let q = UnitQuaternion::from_scaled_axis(Vector3::z() * 0.3);
    let flipped = UnitQuaternion::new_unchecked(-q.into_inner());
    gltf.animate_rotation(node, &[0.0, 1.0, 2.0], &[q, flipped, q])
        .expect("track");
    let glb = gltf.encode().expect("encode");
    validate_glb(&glb).expect("valid");
    let (json, bin) = split(&glb);
    let output = json["animations"][0]["samplers"][0]["output"]
        .as_u64()
        .expect("output") as usize;
    let view = json["accessors"][output]["bufferView"]
        .as_u64()
        .expect("view") as usize;
    let offset = json["bufferViews"][view]["byteOffset"]
        .as_u64()
        .expect("offset") as usize;
    let w = |k: usize| {
        f32::from_le_bytes(
            bin[offset + 16 * k + 12..offset + 16 * k + 16]
                .try_into()
                .expect("4 bytes"),
        )
    };
    assert!(
        w(0) > 0.0 && w(1) > 0.0 && w(2) > 0.0,
        "{} {} {}",
        w(0),
        w(1),
        w(2)
    );
}

#[test]
fn encoding_is_deterministic_and_written_atomically() {
    let (gltf, _) = arm(10);
    let a = gltf.encode().expect("encode");
    assert_eq!(a, gltf.clone().encode().expect("encode"));
    let dir = temp_dir("glb");
    let path = dir.join("plan.glb");
    gltf.write_glb(&path).expect("write");
    assert_eq!(std::fs::read(&path).expect("read"), a);
    assert_eq!(std::fs::read_dir(&dir).expect("list").count(), 1);
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn bad_tracks_and_references_are_errors() {
    let (mut gltf, [_, upper, _, object]) = arm(3);
    let gltf_kind = |r: pickplace_view::Result<()>| match r {
        Err(Error::Gltf { kind }) => kind,
        other => panic!("expected a glTF error, got {other:?}"),
    };
    let q = [UnitQuaternion::identity(); 3];
    assert!(matches!(
        gltf_kind(gltf.animate_rotation(upper, &[0.0, 1.0, 2.0], &q)),
        GltfErrorKind::DuplicateTrack { .. }
    ));
    let fresh = gltf
        .add_node("fresh", None, Some(object), &Isometry3::identity())
        .expect("node");
    assert!(matches!(
        gltf_kind(gltf.animate_rotation(fresh, &[0.0, 2.0, 1.0], &q)),
        GltfErrorKind::TimesNotIncreasing { index: 2, .. }
    ));
    assert!(
        matches!(
            gltf_kind(gltf.animate_rotation(fresh, &[1.0, 1.0 + 1e-12, 2.0], &q)),
            GltfErrorKind::TimesNotIncreasing { index: 1, .. }
        ),
        "times equal in f32 are rejected"
    );
    assert!(matches!(
        gltf_kind(gltf.animate_rotation(fresh, &[-1.0, 0.0, 1.0], &q)),
        GltfErrorKind::TimesNotIncreasing { index: 0, .. }
    ));
    assert!(matches!(
        gltf_kind(gltf.animate_rotation(fresh, &[0.0, 1.0], &q)),
        GltfErrorKind::TrackLength { .. }
    ));
    assert!(matches!(
        gltf_kind(gltf.animate_rotation(fresh, &[], &[])),
        GltfErrorKind::EmptyTrack { .. }
    ));
    let nan = [Vector3::new(f64::NAN, 0.0, 0.0)];
    assert!(matches!(
        gltf_kind(gltf.animate_translation(fresh, &[0.0], &nan)),
        GltfErrorKind::NonFiniteValue { .. }
    ));
    // A failed animate_poses leaves no half-added track behind.
    let poses = [Isometry3::identity(); 2];
    assert!(gltf.animate_poses(fresh, &[0.0], &poses).is_err());
    gltf.animate_poses(fresh, &[0.0, 1.0], &poses)
        .expect("both tracks now");
    let bogus = gltf
        .add_node("x", None, None, &Isometry3::identity())
        .expect("node");
    let mut other = GltfBuilder::new("o");
    assert!(
        other
            .add_node("orphan", None, Some(bogus), &Isometry3::identity())
            .is_err(),
        "unknown parent"
    );
    assert!(
        other
            .animate_translation(bogus, &[0.0], &[Vector3::zeros()])
            .is_err(),
        "unknown node"
    );
    let empty = Geometry::new(vec![], vec![]).expect("valid empty geometry");
    assert!(
        other
            .add_mesh("empty", &empty, &Paint::Uniform(Colour::RED))
            .is_err()
    );
    validate_glb(&gltf.encode().expect("encode")).expect("still valid");
}

fn glb_kind(bytes: &[u8]) -> GlbErrorKind {
    match validate_glb(bytes) {
        Err(Error::InvalidGlb { kind }) => kind,
        other => panic!("expected an invalid-glb error, got {other:?}"),
    }
}

#[test]
fn validator_rejects_broken_containers() {
    let (gltf, _) = arm(4);
    let good = gltf.encode().expect("encode");
    assert!(matches!(
        glb_kind(&good[..10]),
        GlbErrorKind::Truncated { .. }
    ));
    let mut bad = good.clone();
    bad[0] = b'x';
    assert_eq!(glb_kind(&bad), GlbErrorKind::BadMagic);
    let mut bad = good.clone();
    bad[4] = 1;
    assert_eq!(glb_kind(&bad), GlbErrorKind::Version { version: 1 });
    assert!(matches!(
        glb_kind(&good[..good.len() - 4]),
        GlbErrorKind::LengthMismatch { .. }
    ));
    let mut bad = good.clone();
    bad[16..20].copy_from_slice(b"JSoN");
    assert!(matches!(
        glb_kind(&bad),
        GlbErrorKind::Chunk { index: 0, .. }
    ));
    let mut bad = good.clone();
    bad[20] = b'#';
    assert!(matches!(glb_kind(&bad), GlbErrorKind::Json { .. }));
}

#[test]
fn validator_rejects_broken_json_rules() {
    let (gltf, _) = arm(4);
    let (json, bin) = split(&gltf.encode().expect("encode"));
    validate_glb(&pack(&json, &bin)).expect("repacking keeps it valid");
    let check = |edit: &dyn Fn(&mut Value, &mut Vec<u8>),
                 expected: &dyn Fn(&GlbErrorKind) -> bool| {
        let (mut j, mut b) = (json.clone(), bin.clone());
        edit(&mut j, &mut b);
        let kind = glb_kind(&pack(&j, &b));
        assert!(expected(&kind), "unexpected error {kind:?}");
    };
    // Buffer length disagreeing with the BIN chunk.
    check(
        &|j, _| j["buffers"][0]["byteLength"] = (bin.len() + 4).into(),
        &|k| {
            matches!(
                k,
                GlbErrorKind::Rule {
                    element: "buffer",
                    ..
                }
            )
        },
    );
    // An accessor overrunning its buffer view.
    check(
        &|j, _| {
            let c = j["accessors"][1]["count"].as_u64().expect("count");
            j["accessors"][1]["count"] = (c + 1).into();
        },
        &|k| {
            matches!(
                k,
                GlbErrorKind::Range {
                    element: "accessor",
                    index: 1,
                    ..
                }
            )
        },
    );
    // A buffer view past the buffer.
    check(
        &|j, _| j["bufferViews"][0]["byteOffset"] = (bin.len() as u64).into(),
        &|k| {
            matches!(
                k,
                GlbErrorKind::Range {
                    element: "bufferView",
                    ..
                }
            )
        },
    );
    // Position min/max that do not match the data.
    check(&|j, _| j["accessors"][0]["max"][0] = 10.0.into(), &|k| {
        matches!(
            k,
            GlbErrorKind::Rule {
                rule: "min/max do not match the data",
                ..
            }
        )
    });
    // Sampler output count different from input count.
    check(
        &|j, _| {
            let out = j["animations"][0]["samplers"][0]["output"]
                .as_u64()
                .expect("output") as usize;
            let c = j["accessors"][out]["count"].as_u64().expect("count");
            j["accessors"][out]["count"] = (c - 1).into();
        },
        &|k| {
            matches!(
                k,
                GlbErrorKind::SamplerCounts {
                    output: 3,
                    input: 4,
                    ..
                }
            )
        },
    );
    // Times going backwards.
    check(
        &|j, b| {
            let input = j["animations"][0]["samplers"][0]["input"]
                .as_u64()
                .expect("input") as usize;
            let view = j["accessors"][input]["bufferView"].as_u64().expect("view") as usize;
            let at = j["bufferViews"][view]["byteOffset"]
                .as_u64()
                .expect("offset") as usize;
            b[at + 4..at + 8].copy_from_slice(&5.0f32.to_le_bytes());
            j["accessors"][input]["max"] = serde_json::json!([5.0]);
        },
        &|k| {
            matches!(
                k,
                GlbErrorKind::Rule {
                    element: "animation sampler",
                    ..
                }
            )
        },
    );
    // A node with two parents, and a cycle.
    check(
        &|j, _| j["nodes"][3]["children"] = serde_json::json!([2]),
        &|k| {
            matches!(
                k,
                GlbErrorKind::Rule {
                    rule: "a node has more than one parent",
                    ..
                }
            )
        },
    );
    check(
        &|j, _| j["nodes"][2]["children"] = serde_json::json!([0]),
        &|k| matches!(k, GlbErrorKind::Rule { .. }),
    );
    // Dangling references.
    check(&|j, _| j["nodes"][0]["mesh"] = 99.into(), &|k| {
        matches!(
            k,
            GlbErrorKind::Reference {
                property: "mesh",
                value: 99,
                ..
            }
        )
    });
    check(
        &|j, _| j["animations"][0]["channels"][0]["target"]["node"] = 99.into(),
        &|k| matches!(k, GlbErrorKind::Reference { .. }),
    );
    // An index past the vertex count.
    check(
        &|j, b| {
            let indices = j["meshes"][0]["primitives"][0]["indices"]
                .as_u64()
                .expect("indices") as usize;
            let view = j["accessors"][indices]["bufferView"]
                .as_u64()
                .expect("view") as usize;
            let at = j["bufferViews"][view]["byteOffset"]
                .as_u64()
                .expect("offset") as usize;
            b[at..at + 4].copy_from_slice(&1_000_000u32.to_le_bytes());
        },
        &|k| {
            matches!(
                k,
                GlbErrorKind::Rule {
                    rule: "an index is not below the vertex count",
                    ..
                }
            )
        },
    );
    // Wrong output type for the path.
    check(
        &|j, _| j["animations"][0]["channels"][0]["target"]["path"] = "translation".into(),
        &|k| {
            matches!(
                k,
                GlbErrorKind::Rule {
                    element: "animation channel",
                    ..
                }
            )
        },
    );
    check(&|j, _| j["asset"]["version"] = "1.0".into(), &|k| {
        matches!(
            k,
            GlbErrorKind::Property {
                element: "asset",
                ..
            }
        )
    });
}
