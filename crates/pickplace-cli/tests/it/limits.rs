//! Input limits and small faults of issue 18 (points 10 and 11): every limit is exit 2 with a
//! message naming the file (or argument) and the limit, refused before the memory is taken.

use crate::root;
use crate::support::{Scratch, stderr};
use std::path::Path;
use std::process::{Command, Output};

/// `pickplace ARGS…` from the repository's root, with the cache of the plan tests.
fn run(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(args)
        .current_dir(root())
        .env(
            "PICKPLACE_CACHE",
            Path::new(env!("CARGO_TARGET_TMPDIR")).join("plan-cache"),
        )
        .output()
        .expect("the pickplace binary runs")
}

/// Asserts exit 2, no panic, and every `needle` in the standard error.
fn assert_refused(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for needle in needles {
        assert!(err.contains(needle), "`{needle}` not in: {err}");
    }
}

#[test]
fn a_binary_stl_claiming_four_billion_triangles_is_refused_from_its_header() {
    let scratch = Scratch::new("limits-stl");
    let mut bytes = vec![b' '; 80];
    bytes.extend_from_slice(&4_000_000_000u32.to_le_bytes());
    let path = scratch.file("huge.stl", &bytes);
    let o = run(crate::args!["mesh-info", path]);
    assert_refused(
        &o,
        &[
            "huge.stl",
            "4000000000 triangles declared in the binary STL header, over the limit of 2000000",
        ],
    );
}

#[test]
fn a_ply_claiming_a_trillion_vertices_is_refused_from_its_header() {
    let scratch = Scratch::new("limits-ply");
    let path = scratch.file(
        "huge.ply",
        b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
    );
    let o = run(crate::args!["mesh-info", path]);
    assert_refused(
        &o,
        &[
            "huge.ply",
            "1000000000000 vertices declared in the PLY header, over the limit of 6000000",
        ],
    );
}

#[test]
fn a_picture_over_the_pixel_limit_is_refused_before_anything_is_read() {
    // Regression: `view --size 16384x16384` needed 9.5 GB. The plan file does not even
    // exist: the size is checked first.
    let o = run(crate::args![
        "view",
        "no-such-plan.json",
        "--scene",
        "scenes/fig9-near.toml",
        "--size",
        "16384x16384"
    ]);
    assert_refused(
        &o,
        &[
            "--size `16384x16384`",
            "268435456 pixels, over the limit of 67108864",
        ],
    );
    let o = run(crate::args![
        "placements",
        "meshes/can.stl",
        "--png",
        "x.png",
        "--size",
        "9000x9000"
    ]);
    assert_refused(&o, &["--size `9000x9000`", "over the limit of 67108864"]);
}
