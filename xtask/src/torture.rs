//! `cargo xtask torture`: the project's own suite of hostile and careless use (issue 18), run
//! against the release `pickplace` binary the way a user's shell would run it.
//!
//! Every parser and command gets FIFOs, `/dev/zero`, folders, symlinks, huge (sparse), empty,
//! truncated, garbage, NaN and deeply nested inputs; `kill -9` lands during every kind of write
//! (plan, pictures, SRDF, cluster databases, roadmaps) and the next run must find no partial
//! file and no broken cache; several runs share one cache at once; the cache folder is
//! read-only, full (a 64 KiB tmpfs, mounted when the machine allows it) or damaged entry by
//! entry; standard output and error are closed pipes. Each case asserts the exit status, the
//! message and what is left on disk, and a case that does not end within its time limit is a
//! failure ("hung"). Everything happens under `target/torture/`, made anew each run.
//!
//! Exit status 1 when a case fails, with each failure's command, status and message.

mod numbers;

use anyhow::{Context, bail};
use std::ffi::{OsStr, OsString};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// How long one command may run before the case counts as hung.
const CASE_TIMEOUT: Duration = Duration::from_secs(30);

/// Runs the suite.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    if let Some(a) = args.first() {
        bail!("unknown argument {a:?}; usage: cargo xtask torture");
    }
    let started = Instant::now();
    let status = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .current_dir(root)
        .args(["build", "--release", "--quiet", "-p", "pickplace-cli"])
        .status()
        .context("cannot run cargo build")?;
    if !status.success() {
        bail!("cargo build --release -p pickplace-cli failed ({status})");
    }
    let scratch = root.join("target/torture");
    if scratch.exists() {
        // A tmpfs left mounted by an interrupted run would make the removal fail.
        for m in ["full-cache", "ro-cache"] {
            let _ = Command::new("umount").arg(scratch.join(m)).output();
        }
        std::fs::remove_dir_all(&scratch)
            .with_context(|| format!("cannot remove {}", scratch.display()))?;
    }
    std::fs::create_dir_all(&scratch)?;
    let mut t = Torture::new(root, &scratch)?;
    t.prepare()?;
    t.inputs()?;
    t.numbers()?;
    t.outputs()?;
    t.damaged_cache()?;
    t.kills()?;
    t.concurrent()?;
    t.cache_folders()?;
    t.closed_pipes()?;
    let secs = started.elapsed().as_secs_f64();
    let report = t.report(secs);
    std::fs::write(scratch.join("report.txt"), &report)?;
    print!("{report}");
    if !t.failures.is_empty() {
        bail!(
            "{} of {} torture cases failed (target/torture/report.txt)",
            t.failures.len(),
            t.cases
        );
    }
    Ok(())
}

/// What a finished command gave.
struct Out {
    code: Option<i32>,
    stderr: String,
}

impl Out {
    fn describe(&self) -> String {
        format!(
            "exit {:?}, stderr: {}",
            self.code,
            self.stderr.trim().chars().take(600).collect::<String>()
        )
    }
}

struct Torture {
    root: PathBuf,
    scratch: PathBuf,
    bin: PathBuf,
    /// The warm cache most cases share.
    cache: PathBuf,
    /// `scenes/fig9-near.toml` planned with a fresh cache: the bytes every run must give.
    reference_plan: Vec<u8>,
    /// The cache entries the reference plan wrote (other cases add entries of their own).
    entries: Vec<PathBuf>,
    cases: usize,
    failures: Vec<String>,
    groups: Vec<(String, usize, usize)>,
}

impl Torture {
    fn new(root: &Path, scratch: &Path) -> anyhow::Result<Self> {
        let bin = root.join("target/release/pickplace");
        if !bin.is_file() {
            bail!("{} was not built", bin.display());
        }
        Ok(Self {
            root: root.to_path_buf(),
            scratch: scratch.to_path_buf(),
            bin,
            cache: scratch.join("cache"),
            reference_plan: Vec::new(),
            entries: Vec::new(),
            cases: 0,
            failures: Vec::new(),
            groups: Vec::new(),
        })
    }

    fn path(&self, name: &str) -> PathBuf {
        self.scratch.join(name)
    }

    fn repo(&self, rel: &str) -> PathBuf {
        self.root.join(rel)
    }

    /// `pickplace ARGS…` in the scratch folder with the shared cache.
    fn cmd<S: AsRef<OsStr>>(&self, args: &[S]) -> Command {
        self.cmd_with_cache(args, &self.cache)
    }

    fn cmd_with_cache<S: AsRef<OsStr>>(&self, args: &[S], cache: &Path) -> Command {
        let mut c = Command::new(&self.bin);
        c.args(args)
            .current_dir(&self.scratch)
            .env("PICKPLACE_CACHE", cache)
            .env_remove("PICKPLACE_MAX_FILE_BYTES")
            .env_remove("RUST_BACKTRACE")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        c
    }

    /// Runs a command to its end (or kills it after [`CASE_TIMEOUT`]: `None`).
    fn run(&self, mut c: Command) -> anyhow::Result<Option<Out>> {
        let child = c.spawn().context("cannot start pickplace")?;
        wait_with_timeout(child, CASE_TIMEOUT)
    }

    fn begin_group(&mut self, name: &str) {
        self.groups.push((name.to_owned(), 0, 0));
        println!("torture: {name}");
    }

    /// Records one case.
    fn check(&mut self, name: &str, ok: bool, detail: impl FnOnce() -> String) {
        self.cases += 1;
        if let Some(g) = self.groups.last_mut() {
            g.1 += 1;
            if !ok {
                g.2 += 1;
            }
        }
        if !ok {
            let d = detail();
            println!("  FAILED {name}: {d}");
            self.failures.push(format!("{name}: {d}"));
        }
    }

    /// Runs `c` and checks its exit status and that stderr holds every needle (and no panic).
    fn expect(
        &mut self,
        name: &str,
        c: Command,
        code: i32,
        needles: &[&str],
    ) -> anyhow::Result<Option<Out>> {
        let out = self.run(c)?;
        match &out {
            None => self.check(name, false, || {
                format!("hung (killed after {} s)", CASE_TIMEOUT.as_secs())
            }),
            Some(o) => {
                let ok = o.code == Some(code)
                    && !o.stderr.contains("panicked")
                    && needles.iter().all(|n| o.stderr.contains(n));
                self.check(name, ok, || {
                    format!("expected exit {code} and {needles:?}; got {}", o.describe())
                });
            }
        }
        Ok(out)
    }

    fn report(&self, secs: f64) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "\ntorture suite: {} cases in {secs:.1} s", self.cases);
        for (g, n, failed) in &self.groups {
            let _ = writeln!(s, "  {g:<44} {n:>4} cases, {failed} failed");
        }
        if self.failures.is_empty() {
            let _ = writeln!(s, "all passed");
        } else {
            let _ = writeln!(s, "{} failed:", self.failures.len());
            for f in &self.failures {
                let _ = writeln!(s, "  {f}");
            }
        }
        s
    }

    /// A scene like `scenes/fig9-near.toml` with every path absolute, some replaced.
    fn scene_text(&self, replace: &[(&str, &str)]) -> String {
        let mut fields = [
            ("URDF", self.repo("robots/nx-hiro/nx-hiro.urdf")),
            ("SRDF", self.repo("robots/nx-hiro/nx-hiro.srdf")),
            ("GRIPPER", self.repo("robots/nx-hiro/gripper.toml")),
            ("OBJECT", self.repo("meshes/can.stl")),
            ("TABLE", self.repo("meshes/table.stl")),
            ("PALLET", self.repo("meshes/pallet.stl")),
        ];
        for (k, v) in replace {
            if let Some(f) = fields.iter_mut().find(|f| f.0 == *k) {
                f.1 = PathBuf::from(v);
            }
        }
        let get = |k: &str| {
            fields
                .iter()
                .find(|f| f.0 == k)
                .map(|f| toml_string(&f.1))
                .unwrap_or_default()
        };
        format!(
            "format = 1\n\n[robot]\nurdf = {}\nsrdf = {}\ngripper = {}\n\
             base_pose = {{ position = [0.0, 0.0, 0.92] }}\n\n[object]\nmesh = {}\n\
             start_pose = {{ position = [0.42, -0.04, 0.72] }}\n\n[[environment]]\n\
             name = \"table\"\nmesh = {}\npose = {{ position = [0.55, 0.0, 0.02], \
             orientation = [0.0, 0.0, -0.70710678, 0.70710678] }}\n\n[[environment]]\n\
             name = \"pallet\"\nmesh = {}\npose = {{ position = [0.50, -0.25, 0.72] }}\n\n\
             [target]\npoint = [0.40, -0.20, 0.745]\n\n[planner]\nseed = 1\n",
            get("URDF"),
            get("SRDF"),
            get("GRIPPER"),
            get("OBJECT"),
            get("TABLE"),
            get("PALLET")
        )
    }

    fn write_scene(&self, name: &str, replace: &[(&str, &str)]) -> anyhow::Result<PathBuf> {
        let p = self.path(name);
        std::fs::write(&p, self.scene_text(replace))?;
        Ok(p)
    }

    /// The reference plan, made with a fresh cache, and the warm cache the cases share.
    fn prepare(&mut self) -> anyhow::Result<()> {
        self.begin_group("reference plan and warm cache");
        let scene = self.write_scene("scene.toml", &[])?;
        let out = self.path("reference.json");
        let mut args: Vec<OsString> = vec!["plan".into(), scene.into(), "--out".into()];
        args.push(out.clone().into());
        args.push("--no-timings".into());
        let o = self.expect("plan with a fresh cache", self.cmd(&args), 0, &[])?;
        if o.is_none() || !out.is_file() {
            bail!("the reference plan could not be made; every other case needs it");
        }
        self.reference_plan = std::fs::read(&out)?;
        self.entries = std::fs::read_dir(&self.cache)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && !is_hidden(p))
            .collect();
        self.entries.sort();
        let again = self.path("again.json");
        args[3] = again.clone().into();
        self.expect("plan with the warm cache", self.cmd(&args), 0, &[])?;
        let same = std::fs::read(&again).ok() == Some(self.reference_plan.clone());
        self.check("warm cache gives the same bytes", same, || {
            "plan bytes differ between a fresh and a warm cache".into()
        });
        Ok(())
    }

    /// Bad files in every input slot of every parser.
    fn inputs(&mut self) -> anyhow::Result<()> {
        self.begin_group("bad inputs (every parser, every kind)");
        let bad = self.path("bad");
        std::fs::create_dir_all(&bad)?;
        // Slots: (name, extension, how to run pickplace with the file in that slot).
        let slots: [(&str, &str); 10] = [
            ("scene", "toml"),
            ("mesh-info mesh", "stl"),
            ("object mesh", "stl"),
            ("environment mesh", "obj"),
            ("urdf", "urdf"),
            ("scene urdf", "urdf"),
            ("srdf", "srdf"),
            ("gripper", "toml"),
            ("validate plan", "json"),
            ("view plan", "json"),
        ];
        let kinds = [
            "fifo",
            "dev-zero",
            "folder",
            "dangling-symlink",
            "symlink-to-dev-zero",
            "huge",
            "empty",
            "garbage",
            "truncated",
            "nan",
            "nested",
        ];
        for (si, (slot, ext)) in slots.iter().enumerate() {
            for kind in kinds {
                let file = bad.join(format!("s{si}-{kind}.{ext}"));
                let expected: &[&str] = match self.make_bad(&file, slot, kind)? {
                    Some(e) => e,
                    None => continue,
                };
                let name = format!("{slot} / {kind}");
                let file_name = file
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let out = self.path("bad-out.json");
                let _ = std::fs::remove_file(&out);
                let c = self.slot_command(slot, &file, &out)?;
                let mut needles = vec![file_name.as_str()];
                needles.extend_from_slice(expected);
                if *slot == "srdf" && kind == "nested" {
                    // Valid XML: the group that includes itself is left out with a warning,
                    // as MoveIt leaves it out (issue 32), so it is read (fast, no panic), not
                    // refused.
                    self.expect(&name, c, 0, &[])?;
                } else {
                    self.expect(&name, c, 2, &needles)?;
                }
                let left = out.exists() || self.path("bad-view").exists();
                self.check(&format!("{name}: no output left"), !left, || {
                    "an output was written for a failed command".into()
                });
                let _ = std::fs::remove_dir_all(self.path("bad-view"));
            }
        }
        Ok(())
    }

    /// Writes one bad file; returns what the message must say, or `None` when the kind does not
    /// apply to the slot.
    fn make_bad(
        &self,
        file: &Path,
        slot: &str,
        kind: &str,
    ) -> anyhow::Result<Option<&'static [&'static str]>> {
        let good = self.good_file(slot)?;
        // Every field of the gripper file is optional (overrides of what the URDF measures), so
        // an empty file, or one cut at a line's end, is a valid file there.
        if slot == "gripper" && matches!(kind, "empty" | "truncated") {
            return Ok(None);
        }
        Ok(Some(match kind {
            "fifo" => {
                mkfifo(file)?;
                &["FIFO"]
            }
            "dev-zero" => {
                // The slot names the device itself through a symlink with the right extension
                // (a scene can name /dev/zero directly; the extension picks the parser).
                std::os::unix::fs::symlink("/dev/zero", file)?;
                &["character device"]
            }
            "folder" => {
                std::fs::create_dir_all(file)?;
                &["folder"]
            }
            "dangling-symlink" => {
                std::os::unix::fs::symlink(self.scratch.join("nowhere/at/all"), file)?;
                &["No such file"]
            }
            "symlink-to-dev-zero" => {
                let link = self.scratch.join("bad/zero-link");
                if !link.exists() {
                    std::os::unix::fs::symlink("/dev/zero", &link)?;
                }
                std::os::unix::fs::symlink(&link, file)?;
                &["character device"]
            }
            "huge" => {
                // Sparse: 2 GiB (over every limit) costs no disk.
                let f = std::fs::File::create(file)?;
                f.set_len(2 << 30)?;
                &["over the limit"]
            }
            "empty" => {
                std::fs::write(file, b"")?;
                &[]
            }
            "garbage" => {
                let mut bytes = Vec::with_capacity(4096);
                let mut x: u32 = 0x9e37_79b9;
                for _ in 0..4096 {
                    x ^= x << 13;
                    x ^= x >> 17;
                    x ^= x << 5;
                    bytes.push((x >> 24) as u8);
                }
                std::fs::write(file, bytes)?;
                &[]
            }
            "truncated" => {
                let bytes = std::fs::read(&good)?;
                std::fs::write(file, &bytes[..bytes.len() * 2 / 5])?;
                &[]
            }
            "nan" => {
                let text = std::fs::read_to_string(&good).unwrap_or_default();
                let Some(nan) = nan_version(slot, &text) else {
                    return Ok(None);
                };
                std::fs::write(file, nan)?;
                &[]
            }
            "nested" => {
                let Some(n) = nested_version(slot) else {
                    return Ok(None);
                };
                std::fs::write(file, n)?;
                &[]
            }
            _ => return Ok(None),
        }))
    }

    /// A valid file for the slot (the one the bad file stands in for).
    fn good_file(&self, slot: &str) -> anyhow::Result<PathBuf> {
        Ok(match slot {
            "scene" => self.path("scene.toml"),
            "mesh-info mesh" | "object mesh" => self.repo("meshes/can.stl"),
            "environment mesh" => {
                let p = self.path("pallet.obj");
                if !p.exists() {
                    stl_to_obj(&self.repo("meshes/pallet.stl"), &p)?;
                }
                p
            }
            "urdf" | "scene urdf" => self.repo("robots/nx-hiro/nx-hiro.urdf"),
            "srdf" => self.repo("robots/nx-hiro/nx-hiro.srdf"),
            "gripper" => self.repo("robots/nx-hiro/gripper.toml"),
            _ => self.path("reference.json"),
        })
    }

    fn slot_command(&self, slot: &str, file: &Path, out: &Path) -> anyhow::Result<Command> {
        let f = file.to_string_lossy().into_owned();
        let scene_with = |key: &str| -> anyhow::Result<PathBuf> {
            self.write_scene("bad-scene.toml", &[(key, f.as_str())])
        };
        let plan = |scene: PathBuf| {
            self.cmd(&[
                OsString::from("plan"),
                scene.into(),
                "--out".into(),
                out.into(),
            ])
        };
        Ok(match slot {
            "scene" => plan(file.to_path_buf()),
            "mesh-info mesh" => self.cmd(&[OsStr::new("mesh-info"), file.as_os_str()]),
            "object mesh" => plan(scene_with("OBJECT")?),
            "environment mesh" => plan(scene_with("PALLET")?),
            "urdf" => self.cmd(&[OsStr::new("robot"), "check".as_ref(), file.as_os_str()]),
            "scene urdf" => plan(scene_with("URDF")?),
            "srdf" => self.cmd(&[
                OsString::from("robot"),
                "check".into(),
                self.repo("robots/nx-hiro/nx-hiro.urdf").into(),
                "--srdf".into(),
                file.into(),
            ]),
            "gripper" => plan(scene_with("GRIPPER")?),
            "validate plan" => self.cmd(&[
                OsString::from("validate"),
                self.path("scene.toml").into(),
                file.into(),
            ]),
            _ => self.cmd(&[
                OsString::from("view"),
                file.into(),
                "--scene".into(),
                self.path("scene.toml").into(),
                "--out".into(),
                self.path("bad-view").into(),
            ]),
        })
    }

    /// Destinations that must not be written.
    fn outputs(&mut self) -> anyhow::Result<()> {
        self.begin_group("output destinations");
        let scene = self.path("scene.toml");
        let scene_bytes = std::fs::read(&scene)?;
        let victim = self.path("victim.txt");
        std::fs::write(&victim, b"keep me")?;
        let link = self.path("link.json");
        std::os::unix::fs::symlink(&victim, &link)?;
        let folder = self.path("a-folder.json");
        std::fs::create_dir_all(&folder)?;
        let fifo = self.path("out-fifo.json");
        mkfifo(&fifo)?;
        let cases: [(&str, PathBuf, &str); 5] = [
            ("--out a symlink", link.clone(), "symbolic link"),
            ("--out the scene itself", scene.clone(), "input"),
            ("--out a folder", folder.clone(), "folder"),
            ("--out a FIFO", fifo.clone(), "FIFO"),
            ("--out a device", PathBuf::from("/dev/null"), "device"),
        ];
        for (name, dest, needle) in cases {
            let c = self.cmd(&[
                OsString::from("plan"),
                scene.clone().into(),
                "--out".into(),
                dest.into(),
            ]);
            self.expect(name, c, 2, &[needle])?;
        }
        let victim_kept = std::fs::read(&victim).ok().as_deref() == Some(&b"keep me"[..]);
        let link_kept = std::fs::symlink_metadata(&link).is_ok_and(|m| m.file_type().is_symlink());
        let scene_kept = std::fs::read(&scene).ok() == Some(scene_bytes);
        let null_kept = std::fs::metadata("/dev/null").is_ok_and(|m| {
            use std::os::unix::fs::FileTypeExt;
            m.file_type().is_char_device()
        });
        self.check(
            "symlink and its target untouched",
            victim_kept && link_kept,
            || "the symlink or the file it names was changed".into(),
        );
        self.check("scene untouched", scene_kept, || {
            "--out the scene changed it".into()
        });
        self.check("/dev/null still a device", null_kept, || {
            "/dev/null was replaced".into()
        });
        // Long names: 255 bytes is the longest a Linux file name can be.
        for len in [244usize, 250, 255] {
            let stem = "n".repeat(len - ".json".len());
            let dest = self.path(&format!("{stem}.json"));
            let c = self.cmd(&[
                OsString::from("plan"),
                scene.clone().into(),
                "--out".into(),
                dest.clone().into(),
                "--no-timings".into(),
            ]);
            self.expect(&format!("--out a {len}-byte name"), c, 0, &[])?;
            let ok = std::fs::read(&dest).ok().as_ref() == Some(&self.reference_plan);
            self.check(&format!("{len}-byte name written whole"), ok, || {
                "missing or different bytes".into()
            });
        }
        self.batch_and_export_outputs(&scene, &victim, &folder)
    }

    /// `pickplace batch SCENE --out OUT --no-timings --quiet`.
    fn batch_cmd(&self, scene: &Path, out: &Path) -> Command {
        self.cmd(&[
            OsString::from("batch"),
            scene.into(),
            "--out".into(),
            out.into(),
            "--no-timings".into(),
            "--quiet".into(),
        ])
    }

    /// `pickplace export` of the reference plan as ROS 2 JSON into `dest`.
    fn export_cmd(&self, dest: &Path) -> Command {
        self.cmd(&[
            OsString::from("export"),
            self.path("reference.json").into(),
            "--format".into(),
            "ros2-json".into(),
            "--out".into(),
            dest.into(),
        ])
    }

    /// `pickplace batch` and `pickplace export` at destinations that must not be written:
    /// an `--out` that is a file, a summary or a plan file that is a symlink, an export into
    /// a symlink; what the links name is untouched.
    fn batch_and_export_outputs(
        &mut self,
        scene: &Path,
        victim: &Path,
        folder: &Path,
    ) -> anyhow::Result<()> {
        self.expect(
            "batch --out a file",
            self.batch_cmd(scene, victim),
            2,
            &["not a folder"],
        )?;
        let out = self.path("batch-summary-link");
        std::fs::create_dir_all(&out)?;
        std::os::unix::fs::symlink(victim, out.join("summary.jsonl"))?;
        self.expect(
            "batch: summary.jsonl a symlink",
            self.batch_cmd(scene, &out),
            2,
            &["summary.jsonl", "symbolic link"],
        )?;
        let out = self.path("batch-plan-link");
        std::fs::create_dir_all(&out)?;
        std::os::unix::fs::symlink(victim, out.join("scene.json"))?;
        self.expect(
            "batch: the plan file a symlink",
            self.batch_cmd(scene, &out),
            2,
            &[],
        )?;
        let summary = std::fs::read_to_string(out.join("summary.jsonl")).unwrap_or_default();
        self.check(
            "batch: the symlinked plan is the scene's error",
            summary.contains("\"status\":\"error\"") && summary.contains("symbolic link"),
            || format!("summary: {summary}"),
        );
        self.expect(
            "export --out a symlink",
            self.export_cmd(&self.path("link.json")),
            2,
            &["symbolic link"],
        )?;
        self.expect(
            "export --out a folder",
            self.export_cmd(folder),
            2,
            &["folder"],
        )?;
        let kept = std::fs::read(victim).ok().as_deref() == Some(&b"keep me"[..]);
        self.check(
            "batch and export left the links' target untouched",
            kept,
            || "the file a symlink names was changed".into(),
        );
        Ok(())
    }

    /// Every cache entry damaged in every way: the plan is still made, with the same bytes.
    fn damaged_cache(&mut self) -> anyhow::Result<()> {
        self.begin_group("damaged cache entries");
        let entries = self.entries.clone();
        if entries.is_empty() {
            let shown = self.cache.display().to_string();
            self.check("the reference plan wrote cache entries", false, || {
                format!("{shown} is empty")
            });
        }
        let scene = self.path("scene.toml");
        for entry in entries {
            let name = entry
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let good = std::fs::read(&entry)?;
            for kind in [
                "truncated",
                "garbage",
                "empty",
                "fifo",
                "folder",
                "dev-zero",
            ] {
                std::fs::remove_file(&entry)?;
                match kind {
                    "truncated" => std::fs::write(&entry, &good[..good.len() / 2])?,
                    "garbage" => {
                        let mut g = good.clone();
                        let n = g.len();
                        for b in &mut g[n / 3..n / 3 + 64.min(n / 3)] {
                            *b ^= 0x5a;
                        }
                        std::fs::write(&entry, g)?
                    }
                    "empty" => std::fs::write(&entry, b"")?,
                    "fifo" => mkfifo(&entry)?,
                    "folder" => std::fs::create_dir(&entry)?,
                    _ => std::os::unix::fs::symlink("/dev/zero", &entry)?,
                }
                let out = self.path("damaged.json");
                let _ = std::fs::remove_file(&out);
                let c = self.cmd(&[
                    OsString::from("plan"),
                    scene.clone().into(),
                    "--out".into(),
                    out.clone().into(),
                    "--no-timings".into(),
                ]);
                let case = format!("{kind} {name}");
                let o = self.expect(&case, c, 0, &[])?;
                let same = std::fs::read(&out).ok().as_ref() == Some(&self.reference_plan);
                self.check(&format!("{case}: same plan"), same, || {
                    "the plan differs from the reference".into()
                });
                // On disk: a folder cannot be replaced, so the plan is made in memory with one
                // warning; anything else is rebuilt in place, byte for byte, silently.
                let warnings = o
                    .as_ref()
                    .map_or(0, |o| o.stderr.matches("warning").count());
                let meta = std::fs::symlink_metadata(&entry);
                let left_ok = if kind == "folder" {
                    meta.as_ref().is_ok_and(|m| m.is_dir()) && warnings == 1
                } else {
                    meta.as_ref().is_ok_and(|m| m.is_file())
                        && std::fs::read(&entry).ok().as_ref() == Some(&good)
                        && warnings == 0
                };
                self.check(&format!("{case}: what is left"), left_ok, || {
                    format!(
                        "{} warnings; the entry is now {}",
                        warnings,
                        match &meta {
                            Ok(m) if m.is_dir() => "a folder",
                            Ok(m) if m.is_file() => "a file (other bytes)",
                            Ok(_) => "neither file nor folder",
                            Err(_) => "gone",
                        }
                    )
                });
                // Put the good entry back, whatever the run left there.
                let meta = std::fs::symlink_metadata(&entry);
                if meta.as_ref().is_ok_and(|m| m.is_dir()) {
                    std::fs::remove_dir_all(&entry)?;
                } else if meta.is_ok() {
                    std::fs::remove_file(&entry)?;
                }
                std::fs::write(&entry, &good)?;
            }
        }
        Ok(())
    }

    /// `kill -9` during every kind of write, then the same command again: the outputs are whole
    /// and equal to an uninterrupted run's, the cache loads, no temporary file is left.
    fn kills(&mut self) -> anyhow::Result<()> {
        self.begin_group("kill -9 during writes");
        let scene = self.path("scene.toml");
        // (name, output to check, arguments, a fresh cache each time?)
        let view_dir = self.path("kill-view");
        let srdf = self.path("kill.srdf");
        let plan_out = self.path("kill-plan.json");
        let kinds: Vec<(&str, PathBuf, Vec<OsString>, bool)> = vec![
            (
                "plan --out",
                plan_out.clone(),
                vec![
                    "plan".into(),
                    scene.clone().into(),
                    "--out".into(),
                    plan_out.clone().into(),
                    "--no-timings".into(),
                ],
                false,
            ),
            (
                "plan with a fresh cache (databases and roadmaps)",
                plan_out.clone(),
                vec![
                    "plan".into(),
                    scene.clone().into(),
                    "--out".into(),
                    plan_out.clone().into(),
                    "--no-timings".into(),
                ],
                true,
            ),
            (
                "view --out",
                view_dir.clone(),
                vec![
                    "view".into(),
                    self.path("reference.json").into(),
                    "--scene".into(),
                    scene.clone().into(),
                    "--out".into(),
                    view_dir.clone().into(),
                    "--size".into(),
                    "320x240".into(),
                ],
                false,
            ),
            (
                "robot srdf --out",
                srdf.clone(),
                vec![
                    "robot".into(),
                    "srdf".into(),
                    self.repo("robots/nx-hiro/nx-hiro.urdf").into(),
                    "--samples".into(),
                    "2000".into(),
                    "--out".into(),
                    srdf.clone().into(),
                ],
                false,
            ),
            (
                "precompute (cluster databases)",
                self.path("kill-cache"),
                vec![
                    "precompute".into(),
                    self.repo("meshes/mug.stl").into(),
                    self.repo("meshes/can.stl").into(),
                    "--out".into(),
                    self.path("kill-cache").into(),
                ],
                true,
            ),
        ];
        for (name, dest, args, fresh) in kinds {
            let cache = if fresh {
                self.path("kill-fresh-cache")
            } else {
                self.cache.clone()
            };
            remove_any(&dest)?;
            remove_any(&self.path("kill-fresh-cache"))?;
            // An uninterrupted run: its time spaces the kills, its output is the reference.
            let t = Instant::now();
            let full = self.run(self.cmd_with_cache(&args, &cache))?;
            let full_time = t.elapsed();
            let Some(full) = full.filter(|o| o.code == Some(0)) else {
                self.check(name, false, || "the uninterrupted run failed".into());
                continue;
            };
            drop(full);
            let reference = snapshot(&dest)?;
            let mut killed_during = 0;
            for fraction in [0.1, 0.3, 0.5, 0.7, 0.85, 0.95] {
                remove_any(&dest)?;
                if fresh {
                    remove_any(&cache)?;
                }
                let mut c = self.cmd_with_cache(&args, &cache);
                c.stdout(Stdio::null()).stderr(Stdio::null());
                let mut child = c.spawn()?;
                std::thread::sleep(full_time.mul_f64(fraction));
                if child.try_wait()?.is_none() {
                    killed_during += 1;
                }
                let _ = child.kill(); // SIGKILL
                let _ = child.wait();
                // What the kill left: each file whole (as the reference) or absent.
                let left = snapshot(&dest)?;
                let partial: Vec<&String> = left
                    .iter()
                    .filter(|(f, bytes)| {
                        !is_hidden(Path::new(f))
                            && reference.iter().all(|(rf, rb)| rf != f || rb != bytes)
                            // Databases and roadmaps: other runs write other bytes (timings
                            // are not in them, so the same), the loader checks them anyway.
                            && !fresh
                    })
                    .map(|(f, _)| f)
                    .collect();
                self.check(
                    &format!("{name}: killed at {:.0} %", fraction * 100.0),
                    partial.is_empty(),
                    || format!("partial files left: {partial:?}"),
                );
                // The next run completes, gives the reference output and leaves no temporary.
                let out = self.run(self.cmd_with_cache(&args, &cache))?;
                let ok = out.as_ref().is_some_and(|o| o.code == Some(0));
                let after = snapshot(&dest)?;
                let temporaries: Vec<&String> = after
                    .iter()
                    .map(|(f, _)| f)
                    .filter(|f| is_hidden(Path::new(f)))
                    .collect();
                let same = after
                    .iter()
                    .filter(|(f, _)| !is_hidden(Path::new(f)))
                    .eq(reference.iter());
                self.check(
                    &format!("{name}: run after the kill at {:.0} %", fraction * 100.0),
                    ok && same && temporaries.is_empty(),
                    || {
                        format!(
                            "status ok {ok}, same output {same}, temporaries left {temporaries:?}, {}",
                            out.map(|o| o.describe()).unwrap_or_default()
                        )
                    },
                );
                if fresh && name.starts_with("plan") {
                    // The cache the killed run left must load: a third run builds nothing.
                    let o = self.run(self.cmd_with_cache(&args, &cache))?;
                    let loads = o.as_ref().is_some_and(|o| {
                        o.code == Some(0)
                            && !o.stderr.contains("built")
                            && !o.stderr.contains("warning")
                    });
                    self.check(
                        &format!(
                            "{name}: cache whole after the kill at {:.0} %",
                            fraction * 100.0
                        ),
                        loads,
                        || o.map(|o| o.describe()).unwrap_or_default(),
                    );
                }
            }
            self.check(
                &format!("{name}: some kills landed during the run"),
                killed_during > 0,
                || "every kill came after the command had ended".into(),
            );
        }
        Ok(())
    }

    /// Four plans at once on one fresh cache, then four on the warm one.
    fn concurrent(&mut self) -> anyhow::Result<()> {
        self.begin_group("concurrent runs on one cache");
        let scene = self.path("scene.toml");
        let cache = self.path("shared-cache");
        for round in ["fresh", "warm"] {
            let mut children: Vec<(PathBuf, Child)> = Vec::new();
            for i in 0..4 {
                let out = self.path(&format!("concurrent-{round}-{i}.json"));
                let mut c = self.cmd_with_cache(
                    &[
                        OsString::from("plan"),
                        scene.clone().into(),
                        "--out".into(),
                        out.clone().into(),
                        "--no-timings".into(),
                    ],
                    &cache,
                );
                c.stdout(Stdio::null());
                children.push((out, c.spawn()?));
            }
            for (i, (out, child)) in children.into_iter().enumerate() {
                let o = wait_with_timeout(child, CASE_TIMEOUT)?;
                let ok = o.as_ref().is_some_and(|o| o.code == Some(0));
                let same = std::fs::read(&out).ok().as_ref() == Some(&self.reference_plan);
                self.check(&format!("{round} cache, run {i}"), ok && same, || {
                    format!(
                        "status ok {ok}, same plan {same}: {}",
                        o.map(|o| o.describe()).unwrap_or_default()
                    )
                });
            }
        }
        let leftovers: Vec<PathBuf> = std::fs::read_dir(&cache)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| is_hidden(p))
            .collect();
        self.check(
            "no temporary left in the shared cache",
            leftovers.is_empty(),
            || format!("{leftovers:?}"),
        );
        Ok(())
    }

    /// Unusable cache folders: the plan is made in memory with one warning.
    fn cache_folders(&mut self) -> anyhow::Result<()> {
        self.begin_group("unusable cache folders");
        let scene = self.path("scene.toml");
        let plan_args = |out: &Path| -> Vec<OsString> {
            vec![
                "plan".into(),
                scene.clone().into(),
                "--out".into(),
                out.into(),
                "--no-timings".into(),
            ]
        };
        let a_file = self.path("cache-is-a-file");
        std::fs::write(&a_file, b"not a folder")?;
        let mut folders: Vec<(String, PathBuf)> = vec![
            ("a regular file".into(), a_file.clone()),
            ("under a regular file".into(), a_file.join("cache")),
        ];
        let is_root = Command::new("id")
            .arg("-u")
            .output()
            .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
        let full = self.path("full-cache");
        let ro = self.path("ro-cache");
        let mut mounted = Vec::new();
        if is_root {
            std::fs::create_dir_all(&full)?;
            std::fs::create_dir_all(&ro)?;
            let m1 = Command::new("mount")
                .args(["-t", "tmpfs", "-o", "size=64k", "torture-full"])
                .arg(&full)
                .output();
            if m1.is_ok_and(|o| o.status.success()) {
                folders.push(("full (a 64 KiB tmpfs)".into(), full.clone()));
                mounted.push(full.clone());
            }
            let m2 = Command::new("mount")
                .args(["-t", "tmpfs", "-o", "ro,size=64k", "torture-ro"])
                .arg(&ro)
                .output();
            if m2.is_ok_and(|o| o.status.success()) {
                folders.push(("read-only (a read-only tmpfs)".into(), ro.clone()));
                mounted.push(ro.clone());
            }
        } else {
            std::fs::create_dir_all(&ro)?;
            let _ = Command::new("chmod").arg("555").arg(&ro).status();
            folders.push(("read-only (mode 555)".into(), ro.clone()));
        }
        if mounted.len() < 2 && is_root {
            println!("  (tmpfs could not be mounted here: full and read-only tmpfs cases skipped)");
        }
        for (what, folder) in folders {
            let out = self.path("cache-folder.json");
            let _ = std::fs::remove_file(&out);
            let o = self.expect(
                &format!("cache folder {what}"),
                self.cmd_with_cache(&plan_args(&out), &folder),
                0,
                &["warning"],
            )?;
            let warnings = o
                .as_ref()
                .map_or(0, |o| o.stderr.matches("warning").count());
            self.check(
                &format!("cache folder {what}: one warning"),
                warnings == 1,
                || format!("{warnings} warnings"),
            );
            let same = std::fs::read(&out).ok().as_ref() == Some(&self.reference_plan);
            self.check(&format!("cache folder {what}: same plan"), same, || {
                "plan missing or different".into()
            });
        }
        // --no-cache: nothing written anywhere.
        let out = self.path("no-cache.json");
        let untouched = self.path("untouched-cache");
        let mut args = plan_args(&out);
        args.push("--no-cache".into());
        self.expect("--no-cache", self.cmd_with_cache(&args, &untouched), 0, &[])?;
        let same = std::fs::read(&out).ok().as_ref() == Some(&self.reference_plan);
        self.check(
            "--no-cache: same plan, no cache folder made",
            same && !untouched.exists(),
            || {
                format!(
                    "same plan {same}, cache folder exists {}",
                    untouched.exists()
                )
            },
        );
        for m in mounted {
            let _ = Command::new("umount").arg(&m).status();
        }
        Ok(())
    }

    /// Closed standard output and error.
    fn closed_pipes(&mut self) -> anyhow::Result<()> {
        self.begin_group("closed pipes");
        let scene = self.path("scene.toml");
        let urdf = self.repo("robots/nx-hiro/nx-hiro.urdf");
        let can = self.repo("meshes/can.stl");
        let cases: Vec<(&str, Vec<OsString>)> = vec![
            ("plan", vec!["plan".into(), scene.clone().into()]),
            (
                "robot check",
                vec!["robot".into(), "check".into(), urdf.clone().into()],
            ),
            (
                "robot fk",
                vec![
                    "robot".into(),
                    "check".into(),
                    urdf.clone().into(),
                    "--json".into(),
                ],
            ),
            ("placements", vec!["placements".into(), can.clone().into()]),
            (
                "clusters --json",
                vec!["clusters".into(), can.clone().into(), "--json".into()],
            ),
            ("mesh-info", vec!["mesh-info".into(), can.clone().into()]),
            (
                "validate",
                vec![
                    "validate".into(),
                    scene.clone().into(),
                    self.path("reference.json").into(),
                ],
            ),
        ];
        for (name, args) in cases {
            for closed in ["stdout", "stdout and stderr"] {
                let mut child = self.cmd(&args).spawn()?;
                drop(child.stdout.take());
                if closed != "stdout" {
                    drop(child.stderr.take());
                }
                let o = wait_with_timeout(child, CASE_TIMEOUT)?;
                let ok = o.as_ref().is_some_and(|o| {
                    o.code == Some(0)
                        && !o.stderr.contains("panicked")
                        && !o.stderr.contains("error")
                });
                self.check(&format!("{name} with {closed} closed"), ok, || {
                    o.map(|o| o.describe()).unwrap_or_else(|| "hung".into())
                });
            }
        }
        Ok(())
    }
}

/// Waits for `child`, collecting its output; kills it after `limit` (`None`).
fn wait_with_timeout(mut child: Child, limit: Duration) -> anyhow::Result<Option<Out>> {
    let stdout = child.stdout.take();
    let stderr = child.stderr.take();
    let out_reader = std::thread::spawn(move || read_all(stdout));
    let err_reader = std::thread::spawn(move || read_all(stderr));
    let t = Instant::now();
    let status: Option<ExitStatus> = loop {
        if let Some(s) = child.try_wait()? {
            break Some(s);
        }
        if t.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    // Standard output is drained (a full pipe would block the command) and dropped.
    let _ = out_reader.join();
    let stderr = err_reader.join().unwrap_or_default();
    Ok(status.map(|s| Out {
        code: s.code(),
        stderr: String::from_utf8_lossy(&stderr).into_owned(),
    }))
}

fn read_all<R: std::io::Read>(r: Option<R>) -> Vec<u8> {
    let mut v = Vec::new();
    if let Some(mut r) = r {
        let _ = r.read_to_end(&mut v);
    }
    v
}

fn mkfifo(path: &Path) -> anyhow::Result<()> {
    let s = Command::new("mkfifo")
        .arg(path)
        .status()
        .context("cannot run mkfifo")?;
    if !s.success() {
        bail!("mkfifo {} failed", path.display());
    }
    Ok(())
}

fn is_hidden(p: &Path) -> bool {
    p.file_name()
        .is_some_and(|n| n.to_string_lossy().starts_with('.'))
}

fn remove_any(p: &Path) -> anyhow::Result<()> {
    match std::fs::symlink_metadata(p) {
        Ok(m) if m.is_dir() => std::fs::remove_dir_all(p)?,
        Ok(_) => std::fs::remove_file(p)?,
        Err(_) => {}
    }
    Ok(())
}

/// The files at `p` (itself, or the files of the folder), sorted, with their bytes.
fn snapshot(p: &Path) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let mut v = Vec::new();
    match std::fs::symlink_metadata(p) {
        Ok(m) if m.is_dir() => {
            for e in std::fs::read_dir(p)? {
                let e = e?;
                let name = e.file_name().to_string_lossy().into_owned();
                v.push((name, std::fs::read(e.path()).unwrap_or_default()));
            }
        }
        Ok(_) => v.push((
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            std::fs::read(p)?,
        )),
        Err(_) => {}
    }
    v.sort();
    Ok(v)
}

fn toml_string(p: &Path) -> String {
    let s = p.to_string_lossy();
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The slot's valid text with one number made NaN (or not finite), where the format allows it.
fn nan_version(slot: &str, text: &str) -> Option<String> {
    match slot {
        "scene" => Some(text.replacen("position = [0.42,", "position = [nan,", 1)),
        "mesh-info mesh" | "object mesh" => Some(
            "solid nan\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\n\
             vertex 0 1 0\nendloop\nendfacet\nendsolid nan\n"
                .to_owned(),
        ),
        "environment mesh" => Some("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n".to_owned()),
        "urdf" | "scene urdf" => {
            let i = text.find("xyz=\"")?;
            let mut t = text.to_owned();
            t.insert_str(i + 5, "nan ");
            // "nan a b c" is four numbers; keep three.
            let j = i + 5 + 4;
            let end = t[j..].find(' ').map(|k| j + k)?;
            t.replace_range(j..=end, "");
            Some(t)
        }
        "gripper" => {
            let i = text.find("= ")?;
            let mut t = text.to_owned();
            let end = t[i..].find('\n').map(|k| i + k)?;
            t.replace_range(i + 2..end, "nan");
            Some(t)
        }
        "validate plan" | "view plan" => {
            // JSON has no NaN: the largest float literal overflows to infinity.
            let i = text.find("\"positions\"")?;
            let open = text[i..].find('[').map(|k| i + k)?;
            let mut t = text.to_owned();
            t.insert_str(open + 1, "1e999, ");
            Some(t)
        }
        _ => None,
    }
}

/// The slot's format nested 100 000 levels deep.
fn nested_version(slot: &str) -> Option<String> {
    const N: usize = 100_000;
    match slot {
        "scene" => Some(format!(
            "format = 1\nx = {}{}\n",
            "[".repeat(N),
            "]".repeat(N)
        )),
        "gripper" => Some(format!("x = {}{}\n", "[".repeat(N), "]".repeat(N))),
        "urdf" | "scene urdf" => Some(format!(
            "<robot name=\"r\">{}{}</robot>",
            "<link name=\"a\">".repeat(N),
            "</link>".repeat(N)
        )),
        "srdf" => Some(format!(
            "<robot name=\"r\">{}{}</robot>",
            "<group name=\"g\">".repeat(N),
            "</group>".repeat(N)
        )),
        "validate plan" | "view plan" => Some(format!("{}{}", "[".repeat(N), "]".repeat(N))),
        _ => None,
    }
}

/// Writes an STL mesh as OBJ (for the environment slot's OBJ parser).
fn stl_to_obj(stl: &Path, obj: &Path) -> anyhow::Result<()> {
    let mesh =
        pickplace_geometry::mesh::load(stl, &pickplace_geometry::mesh::MeshOptions::default())
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut s = String::new();
    for v in mesh.vertices() {
        let _ = writeln!(s, "v {} {} {}", v.x, v.y, v.z);
    }
    for t in mesh.triangles() {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(obj, s)?;
    Ok(())
}
