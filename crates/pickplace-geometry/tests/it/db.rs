//! Cluster database: round trip, keys, corruption, atomic writes, PLY export.

use pickplace_geometry::cluster::ClusterParams;
use pickplace_geometry::codec;
use pickplace_geometry::db::{CacheStatus, ClusterDatabase, cache_path};
use pickplace_geometry::error::{DatabaseErrorKind, Error};
use pickplace_geometry::export;
use pickplace_geometry::hash::mesh_hash;
use pickplace_geometry::shapes::{box_mesh, cylinder};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "pickplace-geometry-it-{name}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn kind(err: Error) -> DatabaseErrorKind {
    match err {
        Error::Database { kind, .. } => kind,
        other => panic!("expected a database error, got {other}"),
    }
}

#[test]
fn round_trip_and_keys() {
    let dir = temp_dir("keys");
    let path = dir.join("can.ppdb");
    let can = cylinder(0.033, 0.12, 64);
    let params = ClusterParams::finger();
    let db = ClusterDatabase::build(&can, &params).expect("valid");
    db.save(&path).expect("written");
    let back = ClusterDatabase::load(&path, mesh_hash(&can), &params).expect("readable");
    assert_eq!(back, db);
    assert_eq!(back.clustering.pairs.len(), 4);

    // Another mesh, other parameters: clear mismatch errors.
    let other = mesh_hash(&cylinder(0.033, 0.12, 65));
    match kind(ClusterDatabase::load(&path, other, &params).expect_err("other mesh")) {
        DatabaseErrorKind::Mismatch { what, .. } => assert_eq!(what, "mesh hash"),
        k => panic!("{k}"),
    }
    let env = ClusterParams {
        h_max: 0.005,
        ..ClusterParams::environment()
    };
    match kind(ClusterDatabase::load(&path, mesh_hash(&can), &env).expect_err("other mode")) {
        DatabaseErrorKind::Mismatch { what, .. } => assert_eq!(what, "mode"),
        k => panic!("{k}"),
    }
    let thinner = ClusterParams {
        h_max: 0.004,
        ..params
    };
    let err = ClusterDatabase::load(&path, mesh_hash(&can), &thinner).expect_err("other h_max");
    assert!(err.to_string().contains("h_max"), "{err}");
    assert!(err.to_string().contains("can.ppdb"), "{err}");

    // Another version.
    let mut bytes = std::fs::read(&path).expect("read");
    bytes[8..12].copy_from_slice(&(codec::FORMAT_VERSION + 1).to_le_bytes());
    match codec::decode(&bytes, mesh_hash(&can), &params).expect_err("version") {
        DatabaseErrorKind::Version { found, expected } => assert_eq!((found, expected), (4, 3)),
        k => panic!("{k}"),
    }
    // A flipped payload byte is caught by the checksum.
    let mut bytes = std::fs::read(&path).expect("read");
    let last = bytes.len() - 1;
    bytes[last] ^= 0x40;
    assert!(matches!(
        codec::decode(&bytes, mesh_hash(&can), &params),
        Err(DatabaseErrorKind::Corrupt { .. })
    ));
    assert!(matches!(
        codec::decode(b"hello world", 0, &params),
        Err(DatabaseErrorKind::BadMagic)
    ));
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn load_or_build_rebuilds_stale_files() {
    let dir = temp_dir("cache");
    let path = dir.join("box.ppdb");
    let mesh = box_mesh([0.05, 0.04, 0.03]);
    let params = ClusterParams::environment();
    let (db, status) = ClusterDatabase::load_or_build(&path, &mesh, &params).expect("built");
    assert_eq!(status, CacheStatus::Built { reason: None });
    let (again, status) = ClusterDatabase::load_or_build(&path, &mesh, &params).expect("loaded");
    assert_eq!(status, CacheStatus::Loaded);
    assert_eq!(again, db);
    let moved = box_mesh([0.05, 0.04, 0.031]);
    let (_, status) = ClusterDatabase::load_or_build(&path, &moved, &params).expect("rebuilt");
    match status {
        CacheStatus::Built { reason: Some(r) } => assert!(r.contains("mesh hash"), "{r}"),
        s => panic!("{s:?}"),
    }
    // No temporary file is left behind.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["box.ppdb".to_owned()]);
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn a_fifo_as_cache_entry_is_rebuilt_not_waited_on() {
    let dir = temp_dir("fifo");
    let path = dir.join("box.ppdb");
    let _ = std::fs::remove_file(&path);
    let made = std::process::Command::new("mkfifo")
        .arg(&path)
        .status()
        .expect("mkfifo");
    assert!(made.success());
    let mesh = box_mesh([0.05, 0.04, 0.03]);
    let params = ClusterParams::environment();
    let (_, status) = ClusterDatabase::load_or_build(&path, &mesh, &params).expect("rebuilt");
    match status {
        CacheStatus::Built { reason: Some(r) } => assert!(r.contains("is a FIFO"), "{r}"),
        s => panic!("{s:?}"),
    }
    // The FIFO was replaced by the database.
    assert!(std::fs::symlink_metadata(&path).expect("entry").is_file());
    let (_, status) = ClusterDatabase::load_or_build(&path, &mesh, &params).expect("loaded");
    assert_eq!(status, CacheStatus::Loaded);
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn saving_into_a_missing_directory_fails_cleanly() {
    let db = ClusterDatabase::build(&box_mesh([0.1, 0.1, 0.1]), &ClusterParams::default())
        .expect("valid");
    let path = temp_dir("missing").join("no/such/dir/x.ppdb");
    let err = db.save(&path).expect_err("no directory");
    assert!(matches!(err, Error::Io { .. }));
    assert!(err.to_string().contains("x.ppdb"));
}

#[test]
fn ply_export_colours_every_face() {
    let can = cylinder(0.033, 0.12, 16);
    let c = pickplace_geometry::cluster::cluster_surface(&can, &ClusterParams::finger())
        .expect("valid");
    let ply = export::clusters_ply(&can, &c);
    let lines: Vec<&str> = ply.lines().collect();
    let header_end = lines
        .iter()
        .position(|l| *l == "end_header")
        .expect("header");
    assert!(ply.contains(&format!("element face {}", can.triangle_count())));
    let faces = &lines[header_end + 1 + can.vertices().len()..];
    assert_eq!(faces.len(), can.triangle_count());
    let mut colours: Vec<String> = faces
        .iter()
        .map(|f| f.rsplitn(4, ' ').take(3).collect::<Vec<_>>().join(" "))
        .collect();
    colours.sort_unstable();
    colours.dedup();
    assert_eq!(colours.len(), c.clusters.len(), "one colour per cluster");
    let dir = temp_dir("ply");
    let path = dir.join("can.ply");
    export::write_clusters_ply(&path, &can, &c).expect("written");
    assert_eq!(std::fs::read_to_string(&path).expect("read"), ply);
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
        let _ = codec::decode(&bytes, 0, &ClusterParams::default());
        // Also behind a valid magic and version.
        let mut framed = codec::MAGIC.to_vec();
        framed.extend_from_slice(&codec::FORMAT_VERSION.to_le_bytes());
        framed.extend_from_slice(&bytes);
        prop_assert!(codec::decode(&framed, 0, &ClusterParams::default()).is_err());
    }

    #[test]
    fn truncated_or_mutated_databases_are_errors(cut in 0.0..1.0f64, flip in any::<usize>(), bit in 0u8..8) {
        let mesh = box_mesh([0.05, 0.04, 0.03]);
        let params = ClusterParams::finger();
        let db = ClusterDatabase::build(&mesh, &params).expect("valid");
        let bytes = db.to_bytes();
        let hash = mesh_hash(&mesh);
        let n = ((bytes.len() as f64) * cut) as usize;
        prop_assert!(codec::decode(&bytes[..n], hash, &params).is_err());
        let mut mutated = bytes.clone();
        let i = flip % mutated.len();
        mutated[i] ^= 1 << bit;
        // Either detected, or (a flip in a field that does not matter cannot exist here) never
        // garbage: anything decoded must equal the original.
        if let Ok(back) = codec::decode(&mutated, hash, &params) {
            prop_assert_eq!(back, db);
        }
    }
}

#[test]
fn cache_paths_separate_meshes_and_parameters() {
    let dir = Path::new("cache");
    let env = ClusterParams::environment();
    let finger = ClusterParams::finger();
    let can = cache_path(dir, Path::new("meshes/can.stl"), &env);
    assert!(can.starts_with(dir));
    let name = can
        .file_name()
        .and_then(|n| n.to_str())
        .expect("UTF-8 name");
    assert!(
        name.starts_with("can.env.") && name.ends_with(".ppdb"),
        "{name}"
    );
    // Same mesh name and parameters: same file, wherever the mesh is.
    assert_eq!(can, cache_path(dir, Path::new("/elsewhere/can.stl"), &env));
    let others = [
        cache_path(dir, Path::new("meshes/mug.stl"), &env),
        cache_path(dir, Path::new("meshes/can.stl"), &finger),
        cache_path(
            dir,
            Path::new("meshes/can.stl"),
            &ClusterParams {
                h_max: 0.002,
                ..env
            },
        ),
        cache_path(
            dir,
            Path::new("meshes/can.stl"),
            &ClusterParams {
                opposite_dot: -0.9,
                ..env
            },
        ),
        cache_path(
            dir,
            Path::new("meshes/can.stl"),
            &ClusterParams {
                max_facet_angle: 1.0,
                ..env
            },
        ),
    ];
    for (i, a) in others.iter().enumerate() {
        assert_ne!(a, &can);
        for b in &others[i + 1..] {
            assert_ne!(a, b);
        }
    }
    // No file name: still a usable path.
    assert!(
        cache_path(dir, Path::new(""), &env)
            .to_string_lossy()
            .contains("mesh.env.")
    );
}
