//! Torture cases of issue 33: numbers out of range in every place a user gives one (scene
//! fields, flags, a URDF's limits, a gripper-overrides file), a URDF mesh that is a device or
//! a dangling link, and a budget too small to print in full. Each must end with exit 2 (1
//! for a budget that runs out) and a message naming the field, no panic and no output file.

use super::Torture;
use std::ffi::OsString;

/// Scene edits: (name, replace `from` by `to` in the reference scene, the message's needles).
const SCENE_CASES: [(&str, &str, &str, &[&str]); 16] = [
    (
        "time_budget 1e300",
        "seed = 1\n",
        "seed = 1\ntime_budget = 1e300\n",
        &["planner.time_budget: 1e300 is not in"],
    ),
    (
        "time_budget -1",
        "seed = 1\n",
        "seed = 1\ntime_budget = -1.0\n",
        &["planner.time_budget: -1 is not in"],
    ),
    (
        "time_budget nan",
        "seed = 1\n",
        "seed = 1\ntime_budget = nan\n",
        &["planner.time_budget: NaN is not in"],
    ),
    (
        "time_budget inf",
        "seed = 1\n",
        "seed = 1\ntime_budget = inf\n",
        &["planner.time_budget: inf is not in"],
    ),
    (
        "h_max_finger 1e-300",
        "seed = 1\n",
        "seed = 1\nh_max_finger = 1e-300\n",
        &["planner.h_max_finger: 1e-300 is not in"],
    ),
    (
        "h_max_environment 1e300",
        "seed = 1\n",
        "seed = 1\nh_max_environment = 1e300\n",
        &["planner.h_max_environment"],
    ),
    (
        "object position 1e300",
        "position = [0.42, -0.04, 0.72]",
        "position = [1e300, -0.04, 0.72]",
        &["object.start_pose.position: 1e300 is not in"],
    ),
    (
        "base position -1e300",
        "position = [0.0, 0.0, 0.92]",
        "position = [0.0, -1e300, 0.92]",
        &["robot.base_pose.position"],
    ),
    (
        "target point 1e300",
        "point = [0.40, -0.20, 0.745]",
        "point = [0.40, -0.20, 1e300]",
        &["target.point: 1e300 is not in"],
    ),
    (
        "object scale 1e300",
        "[object]\n",
        "[object]\nscale = 1e300\n",
        &["object.scale: 1e300 is not in"],
    ),
    (
        "object scale 5e-320",
        "[object]\n",
        "[object]\nscale = 5e-320\n",
        &["object.scale: 5e-320 is not in"],
    ),
    (
        "object mass 0",
        "[object]\n",
        "[object]\nmass = 0.0\n",
        &["object.mass: 0 is not in"],
    ),
    (
        "target tolerance 1e300",
        "[target]\n",
        "[target]\ntolerance = 1e300\n",
        &["target.tolerance"],
    ),
    (
        "velocity_scaling 1e-300",
        "[planner]\n",
        "[trajectory]\nvelocity_scaling = 1e-300\n\n[planner]\n",
        &["trajectory.velocity_scaling: 1e-300 is not in"],
    ),
    (
        "max_acceleration 1e300",
        "[planner]\n",
        "[trajectory]\nmax_acceleration = 1e300\n\n[planner]\n",
        &["trajectory.max_acceleration"],
    ),
    (
        "matrix samples 0",
        "[planner]\n",
        "[collision_matrix]\nsamples = 0\n\n[planner]\n",
        &["collision_matrix.samples: 0 is not in"],
    ),
];

impl Torture {
    /// Writes `text` as the scene `file` (in the scratch folder), runs `pickplace plan` on it
    /// into `numbers-out.json` and expects exit `code`, the needles, and no plan left unless
    /// it exits 0.
    fn plan_text(
        &mut self,
        name: &str,
        file: &str,
        text: &str,
        code: i32,
        needles: &[&str],
    ) -> anyhow::Result<Option<super::Out>> {
        let scene = self.path(file);
        std::fs::write(&scene, text)?;
        let out = self.path("numbers-out.json");
        let _ = std::fs::remove_file(&out);
        let args: Vec<OsString> = vec![
            "plan".into(),
            scene.into(),
            "--out".into(),
            out.clone().into(),
        ];
        let o = self.expect(name, self.cmd(&args), code, needles)?;
        if code != 0 {
            self.check(&format!("{name}: no plan left"), !out.exists(), || {
                "a plan was written".into()
            });
        }
        Ok(o)
    }

    /// The cases of issue 33 (hardening, round three).
    pub(super) fn numbers(&mut self) -> anyhow::Result<()> {
        self.begin_group("numbers out of range, paths that are not files");
        let base = self.scene_text(&[]);
        for (name, from, to, needles) in SCENE_CASES {
            anyhow::ensure!(
                base.contains(from),
                "{from:?} is not in the reference scene"
            );
            let text = base.replacen(from, to, 1);
            self.plan_text(
                &format!("scene {name}"),
                "numbers-scene.toml",
                &text,
                2,
                needles,
            )?;
        }
        // A budget too small for any strategy: a reason, printed compactly.
        let text = base.replacen("seed = 1\n", "seed = 1\ntime_budget = 5e-320\n", 1);
        let o = self.plan_text(
            "denormal budget: no plan, said compactly",
            "numbers-denormal.toml",
            &text,
            1,
            &["time budget of 5e-320 s is spent"],
        )?;
        if let Some(o) = o {
            self.check(
                "denormal budget: no long number",
                !o.stderr.contains("0.00000000"),
                || "the budget printed with hundreds of digits".into(),
            );
        }
        self.flags()?;
        self.files()?;
        Ok(())
    }

    /// Flags out of range: usage errors naming the flag.
    fn flags(&mut self) -> anyhow::Result<()> {
        let scene: OsString = self.path("scene.toml").into();
        let can: OsString = self.repo("meshes/can.stl").into();
        let robot: OsString = self.repo("robots/nx-hiro").into();
        let urdf: OsString = self.repo("robots/nx-hiro/nx-hiro.urdf").into();
        let out: OsString = self.path("numbers-flag-out").into();
        let srdf: OsString = self.path("numbers.srdf").into();
        let plan = vec!["plan".into(), scene.clone()];
        let batch = vec!["batch".into(), scene, "--out".into(), out];
        let grasps = vec!["grasps".into(), can.clone(), "--robot".into(), robot];
        let clusters = vec!["clusters".into(), can.clone()];
        let check = vec!["robot".into(), "check".into(), urdf.clone()];
        let write = vec!["robot".into(), "srdf".into(), urdf, "--out".into(), srdf];
        let motion_out: OsString = self.path("numbers-motion.json").into();
        let motion = vec![
            "motion".into(),
            self.repo("scenes/motion/nx-hiro-table.toml").into(),
            "--group".into(),
            "right_arm".into(),
            "--to".into(),
            "0.2,-0.5,-1.5,0,0,0".into(),
            "--out".into(),
            motion_out,
        ];
        // (command and its other arguments, the flag, its value out of range)
        let cases: [(&Vec<OsString>, &str, &str); 15] = [
            (&plan, "--velocity-scaling", "1e-300"),
            (&plan, "--sample-period", "1e300"),
            (&batch, "--time-budget", "1e300"),
            (&grasps, "--grid-step", "1e-300"),
            (&grasps, "--approaches", "1e12"),
            (&grasps, "--clearance", "1e300"),
            (&clusters, "--scale", "1e300"),
            (&clusters, "--h-max", "-1"),
            (&vec!["placements".into(), can], "--scale", "0"),
            (&check, "--min-collision-fraction", "5"),
            (&write, "--samples", "0"),
            (&motion, "--time-limit", "1e300"),
            (&motion, "--margin", "1e300"),
            (&motion, "--velocity-scaling", "0"),
            (&motion, "--sample-period", "0"),
        ];
        for (command, flag, value) in cases {
            let mut args = command.clone();
            args.extend([flag.into(), value.into()]);
            let name = format!("{} {flag} {value}", command[0].to_string_lossy());
            self.expect(&name, self.cmd(&args), 2, &[flag, "is not in"])?;
        }
        let left = self.path("numbers-flag-out").exists()
            || self.path("numbers.srdf").exists()
            || self.path("numbers-motion.json").exists();
        self.check("flags: no output left", !left, || {
            "an output was written".into()
        });
        Ok(())
    }

    /// A URDF's velocity limit far too small, a bad gripper override, URDF meshes that are not
    /// files.
    fn files(&mut self) -> anyhow::Result<()> {
        let dir = self.path("numbers-files");
        std::fs::create_dir_all(&dir)?;
        let urdf = std::fs::read_to_string(self.repo("robots/nx-hiro/nx-hiro.urdf"))?;
        let slow = urdf.replacen("velocity=\"3.7525\"", "velocity=\"1e-300\"", 1);
        anyhow::ensure!(slow != urdf, "RARM_JOINT2's limit is not in the URDF");
        let slow_path = dir.join("slow.urdf");
        std::fs::write(&slow_path, slow)?;
        let text = self.scene_text(&[("URDF", &slow_path.to_string_lossy())]);
        let needles = [
            "slow.urdf",
            "RARM_JOINT2",
            "velocity limit 1e-300 is not in",
        ];
        self.plan_text(
            "URDF velocity 1e-300",
            "numbers-slow.toml",
            &text,
            2,
            &needles,
        )?;
        for (name, file_text, needle) in [
            (
                "gripper pad_width nan",
                "# x\npad_width = nan\n",
                "g.toml: line 2: pad_width",
            ),
            (
                "gripper opening_max 0",
                "opening_max = 0.0\n",
                "g.toml: line 1: opening_max",
            ),
            (
                "gripper squeeze inf",
                "\n\nsqueeze = inf\n",
                "g.toml: line 3: squeeze",
            ),
        ] {
            let g = dir.join("g.toml");
            std::fs::write(&g, file_text)?;
            let text = self.scene_text(&[("GRIPPER", &g.to_string_lossy())]);
            self.plan_text(name, "numbers-gripper.toml", &text, 2, &[needle])?;
        }
        // URDF meshes that are not files: robot check says what they are.
        let zero = dir.join("zero.stl");
        let dangling = dir.join("dangling.stl");
        let _ = std::fs::remove_file(&zero);
        let _ = std::fs::remove_file(&dangling);
        std::os::unix::fs::symlink("/dev/zero", &zero)?;
        std::os::unix::fs::symlink(dir.join("gone.stl"), &dangling)?;
        let robot = dir.join("meshes.urdf");
        std::fs::write(
            &robot,
            "<robot name=\"r\">\n<link name=\"a\"><collision><geometry><mesh filename=\"zero.stl\"/></geometry></collision></link>\n\
             <link name=\"b\"><collision><geometry><mesh filename=\"dangling.stl\"/></geometry></collision></link>\n\
             <joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>\n",
        )?;
        let args: Vec<OsString> = vec!["robot".into(), "check".into(), robot.into()];
        let o = std::process::Command::new(&self.bin)
            .args(&args)
            .env("PICKPLACE_CACHE", &self.cache)
            .output()?;
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        self.check("URDF meshes: no panic", !text.contains("panicked"), || {
            text.clone()
        });
        self.check(
            "URDF mesh /dev/zero: said to be a character device",
            text.contains("zero.stl is a character device"),
            || text.clone(),
        );
        self.check(
            "URDF mesh dangling: said to be a link to a missing file",
            text.contains("dangling.stl is a symbolic link to a missing file"),
            || text.clone(),
        );
        Ok(())
    }
}
