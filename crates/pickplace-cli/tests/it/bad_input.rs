//! Bad input: one clear message naming the file, exit status 2, no panic, no output file.

use crate::args;
use crate::support::{Scratch, fails_with, mesh, ok, run_in};

/// Bad meshes: (file name, content, what the message must say).
fn bad_meshes() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let can = std::fs::read(mesh("can.stl")).expect("can.stl");
    let ply_header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                      property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    vec![
        ("empty.stl", Vec::new(), "no triangles"),
        ("empty.obj", Vec::new(), "no triangles"),
        ("truncated.stl", can[..84 + 50 * 10 + 17].to_vec(), "truncated"),
        ("nan.obj", b"v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n".to_vec(), "non-finite"),
        (
            "nan.stl",
            b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 NaN\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n"
                .to_vec(),
            "non-finite",
        ),
        ("index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n".to_vec(), "refers to vertex 9"),
        ("index.ply", format!("{ply_header}0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n").into_bytes(), "refers to vertex 7"),
        ("flat.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n".to_vec(), "degenerate"),
        ("mesh.3ds", b"3ds".to_vec(), "unsupported mesh format"),
        ("mesh.dae", b"<COLLADA><oops".to_vec(), "malformed COLLADA"),
    ]
}

#[test]
fn bad_meshes_fail_clusters_with_status_2() {
    let dir = Scratch::new("bad-clusters");
    for (name, bytes, what) in bad_meshes() {
        let path = dir.file(name, &bytes);
        for mode in ["env", "finger"] {
            let o = run_in(
                dir.path(),
                args![
                    "clusters", path, "--mode", mode, "--json", "--ply", "out.ply"
                ],
            );
            fails_with(&o, &[name, what]);
            assert!(!dir.join("out.ply").exists(), "{name}: no picture written");
        }
    }
    let o = run_in(dir.path(), args!["clusters", "missing.stl", "--json"]);
    fails_with(&o, &["missing.stl", "No such file"]);
    // The source error is printed once, not repeated by the error chain.
    assert_eq!(
        crate::support::stderr(&o).matches("No such file").count(),
        1
    );
}

#[test]
fn a_bad_mesh_among_good_ones_writes_no_database() {
    let dir = Scratch::new("bad-precompute");
    for (name, bytes, what) in bad_meshes() {
        let path = dir.file(name, &bytes);
        let o = run_in(
            dir.path(),
            args!["precompute", mesh("box.stl"), path, "--out", "db"],
        );
        fails_with(&o, &[name, what]);
        assert!(dir.files("db").is_empty(), "{name}: {:?}", dir.files("db"));
    }
}

#[test]
fn bad_parameters_fail_with_status_2() {
    let dir = Scratch::new("bad-params");
    let can = mesh("can.stl");
    for (args, what) in [
        (vec!["--h-max", "-1"], "--h-max"),
        (vec!["--h-max", "NaN"], "--h-max"),
        (vec!["--h-max", "inf"], "--h-max"),
        (vec!["--scale", "0"], "--scale"),
        (vec!["--mode", "sideways"], "sideways"),
    ] {
        let mut argv = vec![
            std::ffi::OsString::from("clusters"),
            can.clone().into_os_string(),
        ];
        argv.extend(args.iter().map(std::ffi::OsString::from));
        let argv: Vec<&std::ffi::OsStr> = argv.iter().map(|a| a.as_os_str()).collect();
        let o = run_in(dir.path(), &argv);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{args:?}: {}",
            crate::support::stderr(&o)
        );
        assert!(o.stdout.is_empty());
        let err = crate::support::stderr(&o);
        assert!(
            err.contains(what) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
    }
    // Usage errors come from clap (several lines with a usage hint); still status 2.
    let o = run_in(dir.path(), args!["precompute", "--out", "db"]);
    assert_eq!(o.status.code(), Some(2));
}

/// A database that does not belong to the mesh, version or parameters: each is refused by
/// name, never used.
#[test]
fn a_foreign_database_fails_with_status_2() {
    let dir = Scratch::new("bad-db");
    let can = mesh("can.stl");
    ok(&run_in(
        dir.path(),
        args!["precompute", can, mesh("box.stl"), "--out", "db"],
    ));
    let db = |prefix: &str| {
        dir.join("db").join(
            dir.files("db")
                .into_iter()
                .find(|f| f.starts_with(prefix))
                .expect("db"),
        )
    };
    let (can_env, can_finger, box_env) = (db("can.env."), db("can.finger."), db("box.env."));
    let bytes = std::fs::read(&can_env).expect("db");
    let mut other_version = bytes.clone();
    other_version[8..12].copy_from_slice(&99u32.to_le_bytes());
    let other_version = dir.file("version.ppdb", &other_version);
    let truncated = dir.file("truncated.ppdb", &bytes[..bytes.len() / 2]);
    let flipped = {
        let mut b = bytes.clone();
        let last = b.len() - 1;
        b[last] ^= 0x40;
        dir.file("flipped.ppdb", &b)
    };
    let not_a_db = dir.file("not-a-db.ppdb", b"hello");
    let cases: Vec<(Vec<&std::ffi::OsStr>, &std::path::Path, &str)> = vec![
        (args!["--db", box_env].to_vec(), &box_env, "mesh hash"),
        (
            args!["--mode", "finger", "--db", can_env].to_vec(),
            &can_env,
            "mode",
        ),
        (
            args!["--mode", "finger", "--h-max", "0.004", "--db", can_finger].to_vec(),
            &can_finger,
            "h_max",
        ),
        (
            args!["--db", other_version].to_vec(),
            &other_version,
            "version 99",
        ),
        (args!["--db", truncated].to_vec(), &truncated, "corrupt"),
        (args!["--db", flipped].to_vec(), &flipped, "corrupt"),
        (
            args!["--db", not_a_db].to_vec(),
            &not_a_db,
            "not a pickplace cluster database",
        ),
    ];
    for (extra, file, what) in cases {
        let mut argv: Vec<&std::ffi::OsStr> =
            args!["clusters", can, "--json", "--ply", "out.ply"].to_vec();
        argv.extend(extra);
        let o = run_in(dir.path(), &argv);
        let name = file
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        fails_with(&o, &[&name, what]);
        assert!(!dir.join("out.ply").exists());
    }
}

/// A scene of NX-HIRO's robot with `extra` robot or planner lines, in `dir`.
fn nx_scene(
    dir: &Scratch,
    name: &str,
    robot_extra: &str,
    planner_extra: &str,
) -> std::path::PathBuf {
    let root = crate::root();
    let text = format!(
        r#"[robot]
urdf = "{urdf}"
srdf = "{srdf}"
base_pose = {{ position = [0.0, 0.0, 0.92] }}
{robot_extra}
[object]
mesh = "{can}"
start_pose = {{ position = [0.42, -0.04, 0.72] }}
[[environment]]
name = "table"
mesh = "{table}"
pose = {{ position = [0.55, 0.0, 0.02], orientation = [0.0, 0.0, -0.70710678, 0.70710678] }}
[target]
point = [0.40, -0.20, 0.72]
[planner]
{planner_extra}
"#,
        urdf = root.join("robots/nx-hiro/nx-hiro.urdf").display(),
        srdf = root.join("robots/nx-hiro/nx-hiro.srdf").display(),
        can = mesh("can.stl").display(),
        table = mesh("table.stl").display(),
    );
    dir.file(name, text.as_bytes())
}

/// NX-HIRO's scene (as [`nx_scene`]) with its robot file `shipped` (`nx-hiro.urdf`,
/// `nx-hiro.srdf`) replaced by `file`, written as `name`.
fn nx_scene_with(
    dir: &Scratch,
    name: &str,
    shipped: &str,
    file: &std::path::Path,
) -> std::path::PathBuf {
    let s = nx_scene(dir, name, "", "");
    let text = std::fs::read_to_string(&s).expect("scene").replace(
        &crate::root()
            .join("robots/nx-hiro")
            .join(shipped)
            .display()
            .to_string(),
        &file.display().to_string(),
    );
    dir.file(name, text.as_bytes())
}

/// Exit 2, a message naming `expected`, no panic, no plan written.
fn refused(dir: &Scratch, scene: &std::path::Path, expected: &[&str]) {
    let o = run_in(dir.path(), args!["plan", scene, "--out", "plan.json"]);
    let err = crate::support::stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for e in expected {
        assert!(err.contains(e), "{e:?} not in {err}");
    }
    assert!(!dir.join("plan.json").exists());
}

#[test]
fn a_broken_srdf_is_named_once() {
    // Regression (issue 32): the message printed the SRDF's path twice (`error: P: P: …`).
    let dir = Scratch::new("bad-srdf-once");
    let broken = dir.file(
        "broken.srdf",
        b"<robot name=\"x\"><group name=\"a\"></robot>",
    );
    let s = nx_scene_with(&dir, "scene.toml", "nx-hiro.srdf", &broken);
    refused(&dir, &s, &["broken.srdf", "malformed XML"]);
    let o = run_in(dir.path(), args!["plan", &s, "--out", "plan.json"]);
    let err = crate::support::stderr(&o);
    let error_line = err
        .lines()
        .find(|l| l.starts_with("error:"))
        .expect("error line");
    assert_eq!(error_line.matches("broken.srdf").count(), 1, "{error_line}");
}

#[test]
fn arms_and_grippers_that_cannot_work_exit_2_naming_what_is_wrong() {
    let dir = Scratch::new("bad-arms");
    // An arm group whose end has no gripper.
    let s = nx_scene(&dir, "head.toml", "", r#"right_arm = "head""#);
    refused(&dir, &s, &["planner.right_arm", "head", "no gripper"]);
    // An arm group with no joints (a chain from a link to itself).
    let s = nx_scene(
        &dir,
        "empty.toml",
        "[robot.groups]\nnothing = { base_link = \"WAIST\", tip_link = \"WAIST\" }",
        r#"right_arm = "nothing""#,
    );
    refused(&dir, &s, &["nothing"]);
    // A group naming a link the URDF does not have.
    let s = nx_scene(
        &dir,
        "nolink.toml",
        "[robot.groups]\nghost = { base_link = \"WAIST\", tip_link = \"NO_SUCH_LINK\" }",
        r#"right_arm = "ghost""#,
    );
    refused(&dir, &s, &["NO_SUCH_LINK"]);
    // A gripper whose fingers cannot move (equal limits): it can neither open nor close.
    let urdf = std::fs::read_to_string(crate::root().join("robots/nx-hiro/nx-hiro.urdf"))
        .expect("urdf")
        .replace(
            r#"<limit lower="0" upper="0.04" velocity="0.1" effort="20"/>"#,
            r#"<limit lower="0.02" upper="0.02" velocity="0.1" effort="20"/>"#,
        );
    let stuck = dir.file("stuck.urdf", urdf.as_bytes());
    let s = nx_scene_with(&dir, "stuck.toml", "nx-hiro.urdf", &stuck);
    refused(&dir, &s, &["FINGER", "cannot move"]);
    // A URDF joint naming a link that does not exist.
    let broken = std::fs::read_to_string(crate::root().join("robots/nx-hiro/nx-hiro.urdf"))
        .expect("urdf")
        .replacen(
            r#"<child link="RARM_TCP"/>"#,
            r#"<child link="NOWHERE"/>"#,
            1,
        );
    let broken_path = dir.file("broken.urdf", broken.as_bytes());
    let s = nx_scene_with(&dir, "broken.toml", "nx-hiro.urdf", &broken_path);
    refused(&dir, &s, &["broken.urdf", "NOWHERE"]);
}
