//! Mesh files: loaders' errors, the load report, the shipped meshes, the writer, and that no
//! byte input makes a reader panic.

use pickplace_geometry::Error;
use pickplace_geometry::error::MeshErrorKind;
use pickplace_geometry::math::{Matrix3, Point3, Vector3};
use pickplace_geometry::mesh::{
    self, MassMethod, MeshOptions, TriMesh, encode_stl_binary, read_obj, read_ply, read_stl,
    write_stl_binary,
};
use pickplace_geometry::shapes;
use pickplace_objects::{self as objects, shipped_meshes};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// A fresh scratch folder for this test (removed first if a previous run left it).
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pickplace-it-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir is writable");
    dir
}

fn meshes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes")
}

const TETRA_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";

fn ascii_ply(vertices: &str, faces: &str, vertex_count: usize, face_count: usize) -> String {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {vertex_count}\nproperty float x\nproperty float y\n\
         property float z\nelement face {face_count}\nproperty list uchar int vertex_indices\n\
         end_header\n{vertices}{faces}"
    )
}

fn tetra_ply() -> String {
    ascii_ply(
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n",
        "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n",
        4,
        4,
    )
}

/// A binary little-endian PLY of the tetrahedron, `float` coordinates, `uint` indices.
fn tetra_ply_binary(coordinate: impl Fn(usize, usize) -> f32) -> Vec<u8> {
    let mut out = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n\
        property float y\nproperty float z\nelement face 4\nproperty list uchar uint vertex_indices\n\
        end_header\n"
        .to_vec();
    for v in 0..4 {
        for c in 0..3 {
            out.extend_from_slice(&coordinate(v, c).to_le_bytes());
        }
    }
    for face in [[0u32, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]] {
        out.push(3);
        for i in face {
            out.extend_from_slice(&i.to_le_bytes());
        }
    }
    out
}

fn unit_corner(v: usize, c: usize) -> f32 {
    if v == c + 1 { 1.0 } else { 0.0 }
}

fn tetra_ascii_stl() -> String {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut s = String::from("solid tetra\n");
    for f in [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]] {
        s.push_str("  facet normal 0 0 0\n    outer loop\n");
        for v in f {
            let [x, y, z]: [f64; 3] = p[v];
            s.push_str(&format!("      vertex {x} {y} {z}\n"));
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid tetra\n");
    s
}

/// Writes `bytes` to `dir/name`, loads it, and returns the error; checks it names the file.
fn load_error(dir: &Path, name: &str, bytes: &[u8]) -> MeshErrorKind {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write test file");
    let err = mesh::load(&path, &MeshOptions::default()).expect_err("bad file must not load");
    let message = err.to_string();
    assert!(
        message.contains(&path.display().to_string()),
        "names the file: {message}"
    );
    match err {
        Error::Mesh { path: p, kind } => {
            assert_eq!(p, path);
            kind
        }
        other => panic!("expected a mesh error, got {other}"),
    }
}

#[test]
fn each_bad_input_gives_a_clear_error_naming_the_file() {
    let dir = scratch("bad");
    // Empty files.
    for name in ["empty.stl", "empty.obj", "empty.ply"] {
        assert_eq!(load_error(&dir, name, b""), MeshErrorKind::Empty, "{name}");
    }
    assert_eq!(
        load_error(&dir, "comments.obj", b"# no faces\nv 0 0 0\n"),
        MeshErrorKind::Empty
    );

    // Truncated binary STL.
    let good = encode_stl_binary(&shapes::box_builder([0.5; 3])).expect("encodable");
    let kind = load_error(&dir, "truncated.stl", &good[..good.len() - 7]);
    let text = kind.to_string();
    assert!(
        text.contains("truncated binary STL") && text.contains("declares 12 triangles"),
        "{text}"
    );
    let kind = load_error(&dir, "header-only.stl", &good[..50]);
    assert!(kind.to_string().contains("truncated binary STL"), "{kind}");

    // NaN coordinates, in every format.
    let nan_stl = tetra_ascii_stl().replacen("vertex 0 1 0", "vertex 0 NaN 0", 1);
    assert_eq!(
        load_error(&dir, "nan.stl", nan_stl.as_bytes()),
        MeshErrorKind::NonFiniteCoordinate { vertex: 1 }
    );
    let mut nan_binary = good.clone();
    nan_binary[84 + 12 + 4..84 + 12 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(
        load_error(&dir, "nan-binary.stl", &nan_binary),
        MeshErrorKind::NonFiniteCoordinate { vertex: 0 }
    );
    let nan_obj = TETRA_OBJ.replace("v 0 0 1", "v 0 0 nan");
    assert_eq!(
        load_error(&dir, "nan.obj", nan_obj.as_bytes()),
        MeshErrorKind::NonFiniteCoordinate { vertex: 3 }
    );
    let nan_ply = tetra_ply_binary(|v, c| {
        if v == 2 && c == 0 {
            f32::NAN
        } else {
            unit_corner(v, c)
        }
    });
    assert_eq!(
        load_error(&dir, "nan.ply", &nan_ply),
        MeshErrorKind::NonFiniteCoordinate { vertex: 2 }
    );

    // Out-of-range indices.
    let obj = TETRA_OBJ.replace("f 2 3 4", "f 2 3 5 4");
    assert_eq!(
        load_error(&dir, "range.obj", obj.as_bytes()),
        MeshErrorKind::IndexOutOfRange {
            triangle: 2,
            index: 5,
            vertex_count: 4
        }
    );
    let ply = tetra_ply().replace("3 0 3 2\n", "3 0 3 4\n");
    let kind = load_error(&dir, "range.ply", ply.as_bytes());
    assert_eq!(
        kind,
        MeshErrorKind::IndexOutOfRange {
            triangle: 3,
            index: 4,
            vertex_count: 4
        }
    );
    assert!(
        kind.to_string()
            .contains("refers to vertex 4, but the mesh has 4 vertices")
    );

    // Zero area: every triangle degenerate.
    let flat = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 0 0\nf 1 2 3\nf 1 2 4\n";
    assert_eq!(
        load_error(&dir, "flat.obj", flat.as_bytes()),
        MeshErrorKind::ZeroArea { triangles: 2 }
    );

    // Unknown extension (checked before reading, so the file need not exist).
    let path = dir.join("model.3ds");
    let err = mesh::load(&path, &MeshOptions::default()).expect_err("unknown format");
    let message = err.to_string();
    assert!(
        message.contains("model.3ds") && message.contains("\"3ds\""),
        "{message}"
    );
    let err = mesh::load(&dir.join("no-extension"), &MeshOptions::default()).expect_err("no ext");
    assert!(err.to_string().contains("unsupported mesh format"), "{err}");

    // A missing file is an I/O error naming it.
    let err = mesh::load(&dir.join("missing.stl"), &MeshOptions::default()).expect_err("missing");
    assert!(
        matches!(err, Error::Io { .. }) && err.to_string().contains("missing.stl"),
        "{err}"
    );

    // A malformed line is reported with its number.
    let kind = load_error(&dir, "word.obj", b"v 0 0 0\nv 1 zero 0\n");
    assert!(
        kind.to_string().contains("line 2: `zero` is not a number"),
        "{kind}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_report_counts_welded_vertices_and_dropped_triangles() {
    // An ASCII STL tetrahedron (12 corners, 4 distinct) plus a sliver facet whose corners
    // are within the weld tolerance (1e-7 m) of each other, and a collinear facet.
    let mut text = tetra_ascii_stl();
    let extra = "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 0.00000001 0 0\n      vertex 0 1 0\n    endloop\n  endfacet\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 0.5 0 0\n      vertex 1 0 0\n    endloop\n  endfacet\n";
    let at = text.find("  facet").expect("has facets");
    text.insert_str(at, extra);
    let dir = scratch("report");
    let path = dir.join("tetra.stl");
    std::fs::write(&path, &text).expect("write");
    let (mesh, report) = mesh::load_with_report(&path, &MeshOptions::default()).expect("valid");
    assert_eq!(report.input_vertices, 18);
    assert_eq!(report.input_triangles, 6);
    assert_eq!(report.vertices, 4);
    assert_eq!(report.triangles, 4);
    assert_eq!(report.degenerate_triangles, 2);
    assert!(report.is_closed());
    assert_eq!(&report, mesh.report());
    // The kept triangles keep their numbers in the file.
    assert_eq!(mesh.source_triangles(), &[2, 3, 4, 5]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn polygons_are_fanned_in_file_order() {
    // A cube as six OBJ quads: face k becomes triangles 2k and 2k + 1.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    let mesh = read_obj(
        text.as_bytes(),
        Path::new("cube.obj"),
        &MeshOptions::default(),
    )
    .expect("valid");
    assert_eq!(mesh.triangle_count(), 12);
    assert!(mesh.report().is_closed());
    // Triangle 3 is the second fan triangle of face 1 (`5 7 8`): normal +z.
    let t = (0..12)
        .find(|&t| mesh.source_triangle(t) == 3)
        .expect("kept");
    assert!((mesh.triangle_normal(t) - Vector3::z()).norm() < 1e-12);
    let m = mesh.mass_properties();
    assert!((m.volume - 1.0).abs() < 1e-12 && !m.inverted_winding);
}

#[test]
fn every_format_reads_the_same_tetrahedron_with_scale() {
    let options = MeshOptions {
        scale: 0.001,
        ..MeshOptions::default()
    };
    let meshes = [
        read_stl(tetra_ascii_stl().as_bytes(), Path::new("t.stl"), &options),
        read_obj(TETRA_OBJ.as_bytes(), Path::new("t.obj"), &options),
        read_ply(tetra_ply().as_bytes(), Path::new("t.ply"), &options),
        read_ply(&tetra_ply_binary(unit_corner), Path::new("t.ply"), &options),
        mesh::read_mesh(TETRA_OBJ.as_bytes(), Path::new("T.OBJ"), &options),
    ];
    for mesh in meshes {
        let mesh = mesh.expect("valid tetrahedron");
        assert!(mesh.report().is_closed());
        let m = mesh.mass_properties();
        assert_eq!(m.method, MassMethod::Volume);
        assert!((m.volume - 1e-9 / 6.0).abs() < 1e-20, "{}", m.volume);
        assert!((m.center_of_mass - Point3::new(0.25e-3, 0.25e-3, 0.25e-3)).norm() < 1e-15);
    }
    let err = read_obj(
        TETRA_OBJ.as_bytes(),
        Path::new("t.obj"),
        &MeshOptions {
            scale: -1.0,
            ..options
        },
    )
    .expect_err("negative scale");
    assert!(err.to_string().contains("scale -1"), "{err}");
}

#[test]
fn every_shipped_mesh_loads_closed() {
    for shipped in shipped_meshes() {
        let path = meshes_dir().join(shipped.file_name);
        let mesh = mesh::load(&path, &MeshOptions::default()).expect("shipped mesh loads");
        let report = mesh.report();
        assert!(report.is_closed(), "{}: {report:?}", shipped.file_name);
        assert_eq!(report.degenerate_triangles, 0, "{}", shipped.file_name);
        assert_eq!(report.triangles, shipped.builder.triangles.len());
        assert_eq!(
            mesh.mass_properties().method,
            MassMethod::Volume,
            "{}",
            shipped.file_name
        );
    }
}

#[test]
fn shipped_meshes_are_up_to_date() {
    for shipped in shipped_meshes() {
        let path = meshes_dir().join(shipped.file_name);
        let committed = std::fs::read(&path).unwrap_or_default();
        let fresh = encode_stl_binary(&shipped.builder).expect("shipped meshes encode");
        assert!(
            committed == fresh,
            "meshes/{} is stale: run `cargo xtask gen-meshes` and commit",
            shipped.file_name
        );
    }
}

#[test]
fn can_and_box_match_their_analytic_mass_properties() {
    let can = mesh::load(&meshes_dir().join("can.stl"), &MeshOptions::default()).expect("can");
    let m = can.mass_properties();
    let (r, h, n) = (objects::CAN_RADIUS, objects::CAN_HEIGHT, 64.0);
    // A regular 64-gon prism: base area n r² sin(2π/n) / 2.
    let volume = n * r * r * (std::f64::consts::TAU / n).sin() / 2.0 * h;
    // Coordinates went through f32: relative error ~1e-7.
    assert!(
        (m.volume - volume).abs() < 1e-6 * volume,
        "{} vs {volume}",
        m.volume
    );
    assert!((m.center_of_mass - Point3::new(0.0, 0.0, h / 2.0)).norm() < 1e-8);
    // Against the true cylinder (64 facets: 0.16 % less area).
    let cylinder = std::f64::consts::PI * r * r * h;
    assert!((m.volume - cylinder).abs() < 2e-3 * cylinder);

    let b = mesh::load(&meshes_dir().join("box.stl"), &MeshOptions::default()).expect("box");
    let m = b.mass_properties();
    let [hx, hy, hz] = objects::OBJECT_BOX_HALF_EXTENTS;
    let volume = 8.0 * hx * hy * hz;
    assert!((m.volume - volume).abs() < 1e-6 * volume, "{}", m.volume);
    assert!((m.center_of_mass - Point3::new(0.0, 0.0, hz)).norm() < 1e-8);
    let (a, bb, c) = (2.0 * hx, 2.0 * hy, 2.0 * hz);
    let inertia = Matrix3::from_diagonal(&Vector3::new(
        bb * bb + c * c,
        a * a + c * c,
        a * a + bb * bb,
    )) * (volume / 12.0);
    let got = m.inertia_per_unit_density.expect("closed");
    assert!((got - inertia).norm() < 1e-6 * inertia.norm(), "{got}");
}

#[test]
fn the_writer_round_trips_and_replaces_atomically() {
    let dir = scratch("writer");
    let path = dir.join("mug.stl");
    let mug = objects::mug_builder().build().expect("valid");
    std::fs::write(&path, b"old content").expect("write");
    write_stl_binary(&mug, &path).expect("writable");
    let back = mesh::load(&path, &MeshOptions::default()).expect("reads back");
    assert_eq!(back.triangle_count(), mug.triangle_count());
    assert_eq!(back.vertices().len(), mug.vertices().len());
    for (p, q) in back.vertices().iter().zip(mug.vertices()) {
        assert!((p - q).norm() < 1e-7, "{p} vs {q}");
    }
    // Only the output is left in the folder: no temporary file.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .expect("listable")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("mug.stl")]);
    // Writing into a missing folder fails with an I/O error naming the file.
    let err = write_stl_binary(&mug, &dir.join("missing/x.stl")).expect_err("no folder");
    assert!(
        matches!(err, Error::Io { .. }) && err.to_string().contains("x.stl"),
        "{err}"
    );
    // A builder with a bad index is refused, and the old file is kept.
    let mut bad = shapes::box_builder([1.0; 3]);
    bad.triangles.push([0, 1, 99]);
    assert!(write_stl_binary(&bad, &path).is_err());
    assert!(mesh::load(&path, &MeshOptions::default()).is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

fn seeds() -> Vec<(&'static str, Vec<u8>)> {
    let binary = encode_stl_binary(&shapes::box_builder([0.5, 1.0, 1.5])).expect("encodable");
    vec![
        ("stl", binary),
        ("stl", tetra_ascii_stl().into_bytes()),
        ("obj", TETRA_OBJ.as_bytes().to_vec()),
        ("ply", tetra_ply().into_bytes()),
        ("ply", tetra_ply_binary(unit_corner)),
    ]
}

/// Runs the reader of `format` on `bytes`; only "does not panic" matters (errors are fine),
/// and a success must be a usable mesh.
fn read_any(format: &str, bytes: &[u8]) {
    let path = PathBuf::from(format!("fuzz.{format}"));
    if let Ok(mesh) = mesh::read_mesh(bytes, &path, &MeshOptions::default()) {
        check_usable(&mesh);
    }
}

fn check_usable(mesh: &TriMesh) {
    assert!(mesh.triangle_count() > 0);
    let _ = mesh.mass_properties();
    let _ = mesh.aabb();
}

proptest! {

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400), format in 0usize..3) {
        read_any(["stl", "obj", "ply"][format], &bytes);
    }

    #[test]
    fn truncated_files_never_panic(seed in 0usize..5, cut in 0.0f64..1.0) {
        let (format, bytes) = &seeds()[seed];
        let len = (bytes.len() as f64 * cut) as usize;
        read_any(format, &bytes[..len]);
    }

    #[test]
    fn mutated_files_never_panic(
        seed in 0usize..5,
        edits in proptest::collection::vec((0.0f64..1.0, any::<u8>(), 0u8..3), 1..8),
    ) {
        let (format, bytes) = &seeds()[seed];
        let mut bytes = bytes.clone();
        for (at, value, op) in edits {
            let i = ((bytes.len() as f64 * at) as usize).min(bytes.len().saturating_sub(1));
            match op {
                0 if !bytes.is_empty() => bytes[i] = value,
                1 => bytes.insert(i, value),
                _ if !bytes.is_empty() => { bytes.remove(i); }
                _ => {}
            }
        }
        read_any(format, &bytes);
    }

    #[test]
    fn text_soup_round_trips_through_binary_stl(
        coords in proptest::collection::vec(-10.0f32..10.0, 9..90),
    ) {
        // Any f32 soup written as binary STL reads back with the same corners.
        let corners: Vec<Point3> = coords
            .chunks_exact(3)
            .map(|c| Point3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])))
            .collect();
        let triangles: Vec<[u32; 3]> = (0..corners.len() as u32 / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        let builder = shapes::MeshBuilder { positions: corners.clone(), triangles };
        let bytes = encode_stl_binary(&builder).expect("finite");
        let options = MeshOptions { weld_tolerance: 0.0, degenerate_area: 0.0, ..MeshOptions::default() };
        if let Ok(mesh) = read_stl(&bytes, Path::new("soup.stl"), &options) {
            for t in 0..mesh.triangle_count() {
                let source = mesh.source_triangle(t) as usize;
                let expected = &corners[3 * source..3 * source + 3];
                prop_assert_eq!(&mesh.triangle_points(t)[..], expected);
            }
        }
    }
}
