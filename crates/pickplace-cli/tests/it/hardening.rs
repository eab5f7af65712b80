//! Hostile and careless use (issue 18): closed pipes, `--out` destinations that must not be
//! written, validate on plans edited by hand.

use crate::root;
use crate::support::{Scratch, stderr};
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// `pickplace ARGS…` from the repository's root, with the cache of the plan tests.
fn command(args: &[&std::ffi::OsStr]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_pickplace"));
    c.args(args).current_dir(root()).env(
        "PICKPLACE_CACHE",
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("plan-cache"),
    );
    c
}

/// Runs `pickplace ARGS…` with standard output a pipe whose reading end is closed at once.
fn with_closed_stdout(args: &[&std::ffi::OsStr]) -> Output {
    let mut child = command(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the pickplace binary runs");
    drop(child.stdout.take());
    child.wait_with_output().expect("pickplace ends")
}

#[test]
fn a_closed_standard_output_ends_quietly() {
    let urdf = root().join("robots/nx-hiro/nx-hiro.urdf");
    let scene = root().join("scenes/fig9-near.toml");
    let cases: [&[&std::ffi::OsStr]; 7] = [
        crate::args!["plan", scene],
        crate::args!["robot", "check", urdf],
        crate::args!["robot", "check", urdf, "--json"],
        crate::args!["placements", "meshes/can.stl", "--on", "meshes/pallet.stl"],
        crate::args!["placements", "meshes/can.stl", "--json"],
        crate::args!["clusters", "meshes/can.stl"],
        crate::args!["mesh-info", "meshes/can.stl"],
    ];
    for args in cases {
        let o = with_closed_stdout(args);
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!err.contains("error:"), "{args:?}: {err}");
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
    }
}

#[test]
fn closed_standard_output_and_error_end_with_the_command_status() {
    // `pickplace plan … 2>&1 | head -1`: progress on stderr met a closed pipe (exit 101).
    let scene = root().join("scenes/fig9-near.toml");
    let run = |args: &[&std::ffi::OsStr]| {
        let mut child = command(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the pickplace binary runs");
        drop(child.stdout.take());
        drop(child.stderr.take());
        child.wait().expect("pickplace ends").code()
    };
    assert_eq!(run(crate::args!["plan", scene]), Some(0));
    assert_eq!(run(crate::args!["plan", "no-such-scene.toml"]), Some(2));
    assert_eq!(
        run(crate::args![
            "placements",
            "meshes/can.stl",
            "--on",
            "meshes/pallet.stl"
        ]),
        Some(0)
    );
}

#[test]
fn a_run_with_open_standard_output_still_prints_everything() {
    let o = command(crate::args![
        "robot",
        "check",
        root().join("robots/nx-hiro/nx-hiro.urdf")
    ])
    .output()
    .expect("runs");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.starts_with("robot \"nx-hiro\""), "{out}");
    assert!(
        out.trim_end()
            .lines()
            .last()
            .is_some_and(|l| l.starts_with("warnings: ")),
        "{out}"
    );
}

/// A real plan of `fig9-near` (planned once per test run into `dir`), as JSON.
fn near_plan(dir: &Scratch) -> serde_json::Value {
    let out = dir.join("near.json");
    let o = command(crate::args![
        "plan",
        root().join("scenes/fig9-near.toml"),
        "--out",
        out,
        "--no-timings"
    ])
    .output()
    .expect("runs");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    serde_json::from_slice(&std::fs::read(&out).expect("plan written")).expect("plan JSON")
}

/// Validates `plan` (written into `dir` as `name`) against `fig9-near`.
fn validate(dir: &Scratch, name: &str, plan: &serde_json::Value) -> Output {
    let path = dir.file(name, plan.to_string().as_bytes());
    command(crate::args![
        "validate",
        root().join("scenes/fig9-near.toml"),
        path
    ])
    .output()
    .expect("runs")
}

#[test]
fn validate_checks_values_times_and_poses_before_interpolating() {
    let dir = Scratch::new("hardening-validate");
    let plan = near_plan(&dir);
    // A joint value far outside its limits: reported at once (it used to hang).
    for value in [1e4, 1e300, -1e12] {
        let mut far = plan.clone();
        far["trajectory"][10]["positions"][3] = serde_json::json!(value);
        let started = std::time::Instant::now();
        let o = validate(&dir, "far.json", &far);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(
            err.contains("LARM_JOINT0 = ")
                && err.contains("is outside its limits [-1.5359, 1.5359] (trajectory[10]"),
            "{err}"
        );
        assert!(err.contains("checked 0 states"), "{err}");
        assert!(!err.contains("0000000000"), "a long number: {err}");
        assert!(started.elapsed().as_secs() < 30, "{:?}", started.elapsed());
    }
    // A negative time, a zero or non-finite quaternion in a key pose: the plan is malformed.
    let mut negative = plan.clone();
    negative["trajectory"][0]["time_from_start"] = serde_json::json!(-1.0);
    let mut zero = plan.clone();
    zero["key_poses"][2]["world_from_tcp"]["orientation"] = serde_json::json!([0, 0, 0, 0]);
    let mut zero_base = plan.clone();
    zero_base["base"]["world_from_root"]["orientation"] = serde_json::json!([0, 0, 0, 0]);
    let mut huge = plan.clone();
    huge["key_poses"][0]["world_from_object"]["orientation"] =
        serde_json::json!([1e308, 1e308, 1e308, 1e308]);
    let mut backwards = plan.clone();
    backwards["trajectory"][5]["time_from_start"] =
        plan["trajectory"][3]["time_from_start"].clone();
    for (name, faulty, expected) in [
        (
            "negative.json",
            &negative,
            "trajectory[0]: time_from_start -1 s is negative",
        ),
        (
            "zero.json",
            &zero,
            "key_poses[2].world_from_tcp: orientation quaternion is zero",
        ),
        (
            "zero-base.json",
            &zero_base,
            "base.world_from_root: orientation quaternion is zero",
        ),
        (
            "backwards.json",
            &backwards,
            "trajectory[5] goes back in time",
        ),
    ] {
        let o = validate(&dir, name, faulty);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        let last = err.trim_end().lines().last().unwrap_or_default();
        assert!(last.starts_with("error: "), "{err}");
        assert!(last.contains(name) && last.contains(expected), "{err}");
    }
    // Huge but finite components are a valid (normalised) quaternion.
    let o = validate(&dir, "huge.json", &huge);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // A plan made for a robot standing 5 mm higher: a problem of the report (exit 1), by its
    // field (issue 33).
    let mut moved = plan.clone();
    moved["base"]["world_from_root"]["position"][2] = serde_json::json!(0.925);
    let o = validate(&dir, "moved-base.json", &moved);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("  base.world_from_root: 5.0000 mm / 0.0000° from where the scene's robot stands (position [0, 0, 0.92], orientation [0, 0, 0, 1]): the plan's world poses are for another base pose"),
        "{err}"
    );
}

/// `fig9-near` copied into `dir` with its object mesh (so that a test that fails cannot
/// overwrite a shipped file); returns the scene's path.
fn scratch_scene(dir: &Scratch) -> std::path::PathBuf {
    let text = std::fs::read_to_string(root().join("scenes/fig9-near.toml")).expect("scene");
    let robots = root().join("robots");
    let meshes = root().join("meshes");
    let text = text
        .replace("../robots", &robots.to_string_lossy())
        .replace("../meshes/can.stl", "can.stl")
        .replace("../meshes", &meshes.to_string_lossy());
    std::fs::copy(meshes.join("can.stl"), dir.join("can.stl")).expect("mesh");
    dir.file("scene.toml", text.as_bytes())
}

/// Exit 2 with one `error:` line naming every string of `expected`, and no planning done.
fn refused(o: &Output, expected: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!err.contains("set up in"), "work was done first: {err}");
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(last.starts_with("error: "), "{err}");
    for e in expected {
        assert!(last.contains(e), "{e:?} not in {err}");
    }
}

#[cfg(unix)]
#[test]
fn out_destinations_that_must_not_be_written_are_refused_before_any_work() {
    let dir = Scratch::new("hardening-out");
    let scene = scratch_scene(&dir);
    let mesh = dir.join("can.stl");
    let target = dir.file("target.json", b"kept");
    let link = dir.join("link.json");
    std::os::unix::fs::symlink(&target, &link).expect("symlink");
    std::fs::create_dir_all(dir.join("folder")).expect("folder");
    let scene_before = std::fs::read(&scene).expect("scene");
    let mesh_before = std::fs::read(&mesh).expect("mesh");
    let plan = |out: &Path| {
        command(crate::args!["plan", scene, "--out", out])
            .output()
            .expect("runs")
    };
    for (out, expected) in [
        (link.clone(), "is a symbolic link"),
        (Path::new("/dev/stdout").to_path_buf(), "is a symbolic link"),
        (Path::new("/dev/null").to_path_buf(), "is a device"),
        (dir.join("folder"), "is a folder"),
        (scene.clone(), "is the scene"),
        (dir.join(".").join("scene.toml"), "is the scene"),
        (mesh.clone(), "is the object mesh"),
        (
            root().join("robots/nx-hiro/nx-hiro.urdf"),
            "is the robot's URDF",
        ),
    ] {
        let o = plan(&out);
        refused(&o, &["--out", &out.display().to_string(), expected]);
    }
    assert_eq!(std::fs::read(&target).expect("target"), b"kept");
    assert!(
        std::fs::symlink_metadata(&link)
            .expect("link")
            .file_type()
            .is_symlink()
    );
    assert_eq!(std::fs::read(&scene).expect("scene"), scene_before);
    assert_eq!(std::fs::read(&mesh).expect("mesh"), mesh_before);
    assert!(
        Path::new("/dev/null")
            .metadata()
            .is_ok_and(|m| !m.is_file())
    );

    // The other commands that write files.
    let urdf = dir.file(
        "robot.urdf",
        &std::fs::read(root().join("robots/nx-hiro/nx-hiro.urdf")).expect("urdf"),
    );
    let urdf_before = std::fs::read(&urdf).expect("urdf");
    let cases: Vec<(Vec<&std::ffi::OsStr>, String)> = vec![
        (
            crate::args!["clusters", mesh, "--ply", mesh].to_vec(),
            "--ply".into(),
        ),
        (
            crate::args!["clusters", mesh, "--png", "/dev/null"].to_vec(),
            "is a device".into(),
        ),
        (
            crate::args!["clusters", mesh, "--png", link].to_vec(),
            "is a symbolic link".into(),
        ),
        (
            crate::args![
                "placements",
                mesh,
                "--on",
                "meshes/pallet.stl",
                "--png",
                mesh
            ]
            .to_vec(),
            "is the object mesh".into(),
        ),
        (
            crate::args!["robot", "srdf", urdf, "--out", urdf].to_vec(),
            "is the URDF".into(),
        ),
        (
            crate::args!["precompute", mesh, "--out", mesh].to_vec(),
            "is a mesh".into(),
        ),
        (
            crate::args!["demo", "--out", target].to_vec(),
            "is not a folder".into(),
        ),
    ];
    for (args, expected) in &cases {
        let o = command(args).output().expect("runs");
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(expected.as_str()), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    assert_eq!(std::fs::read(&mesh).expect("mesh"), mesh_before);
    assert_eq!(std::fs::read(&urdf).expect("urdf"), urdf_before);
    assert_eq!(std::fs::read(&scene).expect("scene"), scene_before);
    assert_eq!(std::fs::read(&target).expect("target"), b"kept");
}

#[cfg(unix)]
#[test]
fn view_refuses_a_link_among_its_output_files() {
    let dir = Scratch::new("hardening-view");
    let scene = scratch_scene(&dir);
    let plan = dir.join("plan.json");
    let o = command(crate::args!["plan", scene, "--out", plan, "--no-timings"])
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = dir.join("pictures");
    std::fs::create_dir_all(&out).expect("folder");
    let victim = dir.file("victim", b"kept");
    std::os::unix::fs::symlink(&victim, out.join("plan.glb")).expect("symlink");
    let o = command(crate::args!["view", plan, "--scene", scene, "--out", out])
        .output()
        .expect("runs");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("plan.glb: is a symbolic link"), "{err}");
    assert_eq!(std::fs::read(&victim).expect("victim"), b"kept");
    // The plan given to view as its own output folder.
    let o = command(crate::args!["view", plan, "--scene", scene, "--out", plan])
        .output()
        .expect("runs");
    assert!(stderr(&o).contains("is the plan"), "{}", stderr(&o));
}

#[test]
fn scene_arrays_have_exact_lengths() {
    let dir = Scratch::new("hardening-arrays");
    let scene = scratch_scene(&dir);
    let text = std::fs::read_to_string(&scene).expect("scene");
    for (from, to, expected) in [
        (
            "position = [0.42, -0.04, 0.72]",
            "position = [0.42, -0.04, 0.72, 1.0]",
            "position: expected exactly 3 numbers [x, y, z], got 4",
        ),
        (
            "orientation = [0.0, 0.0, -0.70710678, 0.70710678]",
            "orientation = [0.0, 0.0, -0.70710678, 0.70710678, 0.0, 0.0]",
            "orientation: expected exactly 4 numbers [x, y, z, w], got 6",
        ),
        (
            "point = [0.40, -0.20, 0.745]",
            "point = [0.40, -0.20]",
            "point: expected exactly 3 numbers [x, y, z], got 2",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let bad = dir.file("bad.toml", text.replace(from, to).as_bytes());
        let o = command(crate::args!["plan", bad, "--out", dir.join("plan.json")])
            .output()
            .expect("runs");
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("bad.toml") && err.contains(expected), "{err}");
        assert!(!dir.join("plan.json").exists());
    }
}

#[test]
fn a_deeply_nested_urdf_is_refused_without_a_stack_overflow() {
    let dir = Scratch::new("hardening-deep");
    let n = 200_000;
    let text = format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"r\">{}{}</robot>\n",
        "<a>".repeat(n),
        "</a>".repeat(n)
    );
    let urdf = dir.file("deep.urdf", text.as_bytes());
    let o = command(crate::args!["robot", "check", urdf])
        .output()
        .expect("runs");
    crate::support::fails_with(
        &o,
        &[
            "deep.urdf",
            "nested more than 256 deep at line 2",
            "MAX_XML_DEPTH",
        ],
    );
}

/// Runs `command` with a time limit, so that a reader that blocks again fails the test
/// instead of hanging the suite; the child is killed at the limit.
fn output_within(mut command: Command, limit: std::time::Duration) -> Output {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the pickplace binary runs");
    // Drain the pipes on threads so that a chatty child cannot block on a full pipe.
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let out = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = std::io::Read::read_to_end(&mut out, &mut v);
        v
    });
    let err = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = std::io::Read::read_to_end(&mut err, &mut v);
        v
    });
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("pickplace did not end within {limit:?}: a reader blocks");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    Output {
        status,
        stdout: out.join().expect("stdout thread"),
        stderr: err.join().expect("stderr thread"),
    }
}

fn mkfifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(made.success(), "mkfifo {}", path.display());
}

const READ_LIMIT: std::time::Duration = std::time::Duration::from_secs(60);

#[cfg(unix)]
#[test]
fn fifos_and_devices_as_inputs_are_refused_without_blocking() {
    let dir = Scratch::new("hardening-fifo");
    let scene = scratch_scene(&dir);
    // A FIFO as the scene.
    let fifo_scene = dir.join("fifo.toml");
    mkfifo(&fifo_scene);
    let o = output_within(command(crate::args!["plan", fifo_scene]), READ_LIMIT);
    refused(&o, &["fifo.toml", "is a FIFO", "not a regular file"]);
    // A folder as the scene.
    let folder = dir.join("folder.toml");
    std::fs::create_dir(&folder).expect("folder");
    let o = output_within(command(crate::args!["plan", folder]), READ_LIMIT);
    refused(&o, &["folder.toml", "is a folder, not a regular file"]);
    // A FIFO as the object mesh the scene names.
    let text = std::fs::read_to_string(&scene).expect("scene");
    mkfifo(&dir.join("pipe.stl"));
    let piped = dir.file(
        "piped.toml",
        text.replace("\"can.stl\"", "\"pipe.stl\"").as_bytes(),
    );
    let o = output_within(command(crate::args!["plan", piped]), READ_LIMIT);
    refused(&o, &["pipe.stl", "is a FIFO", "not a regular file"]);
    // `/dev/zero` as the object mesh (through a link with the mesh's extension).
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.stl")).expect("symlink");
    let zero = dir.file(
        "zero.toml",
        text.replace("\"can.stl\"", "\"zero.stl\"").as_bytes(),
    );
    let o = output_within(command(crate::args!["plan", zero]), READ_LIMIT);
    refused(
        &o,
        &["zero.stl", "is a character device", "not a regular file"],
    );
    let o = output_within(
        command(crate::args!["mesh-info", dir.join("zero.stl")]),
        READ_LIMIT,
    );
    crate::support::fails_with(&o, &["zero.stl", "is a character device"]);
    // A FIFO as the URDF of `robot check`, and as the gripper file a scene names.
    let fifo_urdf = dir.join("robot.urdf");
    mkfifo(&fifo_urdf);
    let o = output_within(
        command(crate::args!["robot", "check", fifo_urdf]),
        READ_LIMIT,
    );
    crate::support::fails_with(&o, &["robot.urdf", "is a FIFO", "not a regular file"]);
    let fifo_gripper = dir.join("gripper.toml");
    mkfifo(&fifo_gripper);
    let gripper_line = text
        .lines()
        .find(|l| l.starts_with("gripper = "))
        .expect("the scene names a gripper file");
    let gripped = dir.file(
        "gripped.toml",
        text.replace(
            gripper_line,
            &format!("gripper = {:?}", fifo_gripper.to_string_lossy()),
        )
        .as_bytes(),
    );
    let o = output_within(command(crate::args!["plan", gripped]), READ_LIMIT);
    refused(&o, &["gripper.toml", "is a FIFO", "not a regular file"]);
    // A FIFO as the plan given to `validate` and to `view`.
    let fifo_plan = dir.join("plan.json");
    mkfifo(&fifo_plan);
    let o = output_within(
        command(crate::args!["validate", scene, fifo_plan]),
        READ_LIMIT,
    );
    refused(&o, &["plan.json", "is a FIFO", "not a regular file"]);
    let o = output_within(
        command(crate::args![
            "view",
            "--scene",
            scene,
            fifo_plan,
            "--out",
            dir.join("view")
        ]),
        READ_LIMIT,
    );
    refused(&o, &["plan.json", "is a FIFO", "not a regular file"]);
}

#[cfg(unix)]
#[test]
fn a_plan_over_the_limit_names_its_size_the_limit_and_the_variable() {
    let dir = Scratch::new("hardening-large");
    let scene = scratch_scene(&dir);
    // 1 GiB + 1 byte without writing it: a sparse file.
    let big = dir.join("big.json");
    let file = std::fs::File::create(&big).expect("create");
    file.set_len((1 << 30) + 1).expect("sparse file");
    let o = output_within(command(crate::args!["validate", scene, big]), READ_LIMIT);
    refused(
        &o,
        &[
            "big.json",
            "1073741825 bytes, over the limit of 1073741824 bytes for a plan",
            "PICKPLACE_MAX_FILE_BYTES",
        ],
    );
}

#[cfg(unix)]
#[test]
fn fifos_in_the_cache_folder_are_rebuilt_over_not_waited_on() {
    let dir = Scratch::new("hardening-cache-fifo");
    let scene = root().join("scenes/fig9-near.toml");
    let cache = dir.join("cache");
    let plan = |out: &str| {
        let mut c = command(crate::args![
            "plan",
            scene,
            "--out",
            dir.join(out),
            "--no-timings"
        ]);
        c.env("PICKPLACE_CACHE", &cache);
        output_within(c, std::time::Duration::from_secs(600))
    };
    let o = plan("first.json");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // Every cache entry (cluster databases, roadmaps) becomes a FIFO.
    let mut entries = Vec::new();
    let mut folders = vec![cache.clone()];
    while let Some(folder) = folders.pop() {
        for e in std::fs::read_dir(&folder).expect("cache folder") {
            let path = e.expect("entry").path();
            if path.is_dir() {
                folders.push(path);
            } else {
                entries.push(path);
            }
        }
    }
    assert!(
        entries
            .iter()
            .any(|e| e.to_string_lossy().contains("roadmap"))
            && entries.len() >= 2,
        "cluster databases and a roadmap expected: {entries:?}"
    );
    for entry in &entries {
        std::fs::remove_file(entry).expect("remove entry");
        mkfifo(entry);
    }
    let o = plan("second.json");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let first = std::fs::read(dir.join("first.json")).expect("first plan");
    let second = std::fs::read(dir.join("second.json")).expect("second plan");
    assert_eq!(first, second, "the rebuilt cache gives the same plan");
    // The entries were rebuilt as regular files.
    for entry in &entries {
        let meta = std::fs::symlink_metadata(entry).expect("entry");
        assert!(meta.is_file(), "{} is still not a file", entry.display());
    }
}

#[test]
fn a_bad_value_in_the_gripper_file_names_that_file() {
    // Found by `cargo xtask torture`: the message said `<memory>` instead of the file.
    let dir = Scratch::new("hardening-gripper-nan");
    let scene = scratch_scene(&dir);
    let gripper = std::fs::read_to_string(root().join("robots/nx-hiro/gripper.toml"))
        .expect("gripper")
        .replace("opening_min = 0.0", "opening_min = nan");
    let bad_gripper = dir.file("my-gripper.toml", gripper.as_bytes());
    let text = std::fs::read_to_string(&scene).expect("scene");
    let shipped = root().join("robots/nx-hiro/gripper.toml");
    let text = text.replace(&*shipped.to_string_lossy(), &bad_gripper.to_string_lossy());
    let bad = dir.file("bad.toml", text.as_bytes());
    let o = command(crate::args!["plan", bad, "--out", dir.join("plan.json")])
        .output()
        .expect("runs");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("my-gripper.toml") && err.contains("opening_min"),
        "{err}"
    );
    assert!(!err.contains("<memory>"), "{err}");
    assert!(!dir.join("plan.json").exists());
}
