//! Reading and writing a plan: its JSON text, the one reader of plan files
//! ([`Plan::load`]) and the rules of its form.

use super::*;

impl Plan {
    /// The plan as pretty JSON (with a final newline).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a plan always serialises");
        s.push('\n');
        s
    }

    /// Checks every pose of the plan (the object's, events', rests', grasps', the base's, the
    /// arms' tool frames' and key poses'): finite numbers and a non-zero quaternion.
    ///
    /// # Errors
    /// The first invalid pose, by its field (`key_poses[3].world_from_tcp: orientation
    /// quaternion is zero`).
    pub fn check_poses(&self) -> Result<(), PlanFormError> {
        let check = |field: String, pose: &PoseSpec| {
            pose.to_isometry()
                .map(|_| ())
                .map_err(|r| format!("{field}: {r}"))
        };
        check("object.start_pose".into(), &self.object.start_pose)?;
        check("object.placed_pose".into(), &self.object.placed_pose)?;
        for (i, e) in self.events.iter().enumerate() {
            check(format!("events[{i}].link_from_object"), &e.link_from_object)?;
        }
        for (i, r) in self.rests.iter().enumerate() {
            check(
                format!("rests[{i}].world_from_object"),
                &r.world_from_object,
            )?;
        }
        for (i, g) in self.grasps.iter().enumerate() {
            check(format!("grasps[{i}].object_from_tcp"), &g.object_from_tcp)?;
        }
        if let Some(base) = &self.base {
            check("base.world_from_root".into(), &base.world_from_root)?;
        }
        for (i, a) in self.arms.iter().enumerate() {
            if let Some(tool) = &a.tool {
                check(
                    format!("arms[{i}].tool.parent_from_tool"),
                    &tool.parent_from_tool,
                )?;
            }
        }
        for (i, k) in self.key_poses.iter().enumerate() {
            check(format!("key_poses[{i}].world_from_tcp"), &k.world_from_tcp)?;
            check(
                format!("key_poses[{i}].world_from_object"),
                &k.world_from_object,
            )?;
        }
        Ok(())
    }

    /// Checks the rules of `docs/plan-format.md` that need no robot ("Form of a plan"): the
    /// trajectory starts at time 0; events are in time order, from time 0 on, each
    /// release after a grasp by the same link and no grasp by a link already holding, by the
    /// strategy's arms (the first grasp by the picking arm, the last release by the placing
    /// arm), each by its arm's tool link where the plan states it (`arms[].tool`); one grasp,
    /// or two with a handover or a regrasp by placing, the first by the picking arm and the
    /// last by the placing arm; `rests` exactly in a regrasp by placing;
    /// key poses with the documented names, in time order from time 0 on, by the
    /// strategy's arms; contacts `face-face` or `edge-face`; finite numbers everywhere.
    ///
    /// # Errors
    /// The first rule broken, by its field (`events[2]: …`).
    pub fn check_form(&self) -> Result<(), PlanFormError> {
        let Some(first) = self.trajectory.first() else {
            return Err("trajectory: empty (it starts at the scene's start state)".into());
        };
        if first.time_from_start != 0.0 {
            return Err(format!(
                "trajectory[0]: time_from_start {} s, the trajectory starts at time 0",
                fmt_real(first.time_from_start)
            )
            .into());
        }
        // An event or key pose after the end of the trajectory is a problem `validate`
        // reports (exit 1), not a matter of form.
        let within = |field: String, t: Real| -> Result<(), PlanFormError> {
            if !t.is_finite() || t < 0.0 {
                return Err(format!(
                    "{field}: time {} s is not a finite time from 0 on",
                    fmt_real(t)
                )
                .into());
            }
            Ok(())
        };
        let arms = self.strategy.arms();
        let by_strategy = |field: String, arm: Arm| -> Result<(), PlanFormError> {
            if !arms.contains(&arm) {
                return Err(format!(
                    "{field}: arm {arm} is not an arm of the strategy {}",
                    self.strategy
                )
                .into());
            }
            Ok(())
        };
        let mut holding: Vec<&str> = Vec::new();
        let mut previous = 0.0;
        for (i, e) in self.events.iter().enumerate() {
            let field = format!("events[{i}]");
            within(field.clone(), e.time)?;
            if e.time < previous {
                return Err(format!(
                    "{field}: before the event above it (events are in time order)"
                )
                .into());
            }
            previous = e.time;
            by_strategy(field.clone(), e.arm)?;
            match e.kind {
                EventKind::Grasp => {
                    if holding.contains(&e.link.as_str()) {
                        return Err(format!(
                            "{field}: grasp by {:?}, which already holds the object",
                            e.link
                        )
                        .into());
                    }
                    holding.push(&e.link);
                }
                EventKind::Release => {
                    let Some(k) = holding.iter().position(|l| *l == e.link) else {
                        return Err(format!(
                            "{field}: release by {:?} without a grasp before it",
                            e.link
                        )
                        .into());
                    };
                    holding.remove(k);
                }
            }
        }
        crate::tool_frame::check_events(&self.arms, &self.events).map_err(|e| e.to_string())?;
        let first_grasp = self.events.iter().find(|e| e.kind == EventKind::Grasp);
        let last_release = self
            .events
            .iter()
            .rev()
            .find(|e| e.kind == EventKind::Release);
        if let Some(g) = first_grasp
            && g.arm != self.strategy.pick_arm()
        {
            return Err(format!(
                "events: the first grasp is by the {} arm, the strategy {} picks with the {} arm",
                g.arm,
                self.strategy,
                self.strategy.pick_arm()
            )
            .into());
        }
        if let Some(r) = last_release
            && r.arm != self.strategy.place_arm()
        {
            return Err(format!(
                "events: the last release is by the {} arm, the strategy {} places with the {} arm",
                r.arm,
                self.strategy,
                self.strategy.place_arm()
            )
            .into());
        }
        // A regrasp by placing takes one more grasp than it has rests (one per transfer).
        let expected = if self.strategy.has_regrasp() {
            self.rests.len() + 1
        } else if self.strategy.has_handover() {
            2
        } else {
            1
        };
        if self.strategy.has_regrasp() && !(1..=2).contains(&self.rests.len()) {
            return Err(format!(
                "rests: {} given; a regrasp by placing has one or two (strategy {})",
                self.rests.len(),
                self.strategy
            )
            .into());
        }
        if self.grasps.len() != expected {
            let with = if self.strategy.has_regrasp() {
                format!(" with {} rest(s)", self.rests.len())
            } else {
                String::new()
            };
            return Err(format!(
                "grasps: {} given, the strategy {}{with} uses {expected}",
                self.grasps.len(),
                self.strategy
            )
            .into());
        }
        for (i, g) in self.grasps.iter().enumerate() {
            if !(g.width.is_finite() && g.score.is_finite()) {
                return Err(format!("grasps[{i}]: a non-finite width or score").into());
            }
        }
        let arm_of = |i: usize| self.grasps[i].arm;
        if arm_of(0) != self.strategy.pick_arm()
            || arm_of(expected - 1) != self.strategy.place_arm()
        {
            return Err(format!(
                "grasps: by the {} then the {} arm, the strategy {} picks with the {} and places with the {}",
                arm_of(0),
                arm_of(expected - 1),
                self.strategy,
                self.strategy.pick_arm(),
                self.strategy.place_arm()
            ).into());
        }
        if self.strategy.has_regrasp() == self.rests.is_empty() {
            return Err(format!(
                "rests: {} given; there is at least one exactly in a regrasp by placing (strategy {})",
                self.rests.len(),
                self.strategy
            ).into());
        }
        let contact = |field: String, p: &PlacementInfo| -> Result<(), PlanFormError> {
            if !matches!(p.contact.as_str(), "face-face" | "edge-face") {
                return Err(format!(
                    "{field}.contact: {:?} is neither \"face-face\" nor \"edge-face\"",
                    clip(&p.contact)
                )
                .into());
            }
            if !p.stability_margin.is_finite() {
                return Err(format!("{field}.stability_margin: not a finite number").into());
            }
            Ok(())
        };
        contact("placement".into(), &self.placement)?;
        for (i, r) in self.rests.iter().enumerate() {
            contact(format!("rests[{i}].placement"), &r.placement)?;
        }
        let mut previous = 0.0;
        for (i, k) in self.key_poses.iter().enumerate() {
            let field = format!("key_poses[{i}]");
            if !KEY_POSE_NAMES.contains(&k.name.as_str()) {
                return Err(format!(
                    "{field}: {:?} is not a key pose name (docs/plan-format.md)",
                    clip(&k.name)
                )
                .into());
            }
            within(field.clone(), k.time)?;
            if k.time < previous {
                return Err(format!(
                    "{field}: before the key pose above it (key poses are in time order)"
                )
                .into());
            }
            previous = k.time;
            by_strategy(field, k.arm)?;
        }
        Ok(())
    }

    /// Reads a plan file (at most the size [`super::PLAN_FILE`]
    /// allows) and checks its form as [`Plan::from_json`] does: the one reader of plan files
    /// for the CLI and Python.
    ///
    /// # Errors
    /// [`crate::Error::BadPlan`] naming the file: `cannot read the plan: …` (missing, not a
    /// file, too large, not UTF-8) or `not a valid plan: …` ([`PlanFormError`]).
    pub fn load(path: &std::path::Path) -> crate::Result<Self> {
        let bad = |reason: String| crate::Error::BadPlan {
            path: path.to_path_buf(),
            reason,
        };
        let text = pickplace_geometry::io::read_text(path, super::PLAN_FILE)
            .map_err(|e| bad(format!("cannot read the plan: {e}")))?;
        Self::from_json(&text).map_err(|e| bad(format!("not a valid plan: {e}")))
    }

    /// Reads a plan from JSON and checks its form: one position per joint name, finite
    /// numbers, times from 0 on that never decrease, valid poses ([`Plan::check_poses`]).
    /// The other rules of the form ([`Plan::check_form`]) are `validate`'s: `view` plays any
    /// trajectory with events.
    ///
    /// # Errors
    /// The parser's message (line and column) when the text is not a plan of this format, or
    /// the first sample or pose whose form is wrong.
    pub fn from_json(text: &str) -> Result<Self, PlanFormError> {
        let plan: Plan = serde_json::from_str(text)
            .map_err(|e| pickplace_geometry::io::short_message(&e.to_string()))?;
        let current = plan.format == PLAN_FORMAT;
        if !current && plan.format != PLAN_FORMAT_1 {
            return Err(format!(
                "format {:?} is not {PLAN_FORMAT:?} (or the earlier {PLAN_FORMAT_1:?})",
                plan.format
            )
            .into());
        }
        let n = plan.joint_names.len();
        for (i, p) in plan.trajectory.iter().enumerate() {
            if p.positions.len() != n {
                return Err(format!(
                    "trajectory[{i}] has {} positions for {n} joints",
                    p.positions.len()
                )
                .into());
            }
            for (what, values) in [
                ("velocities", &p.velocities),
                ("accelerations", &p.accelerations),
            ] {
                if current && values.len() != n {
                    return Err(format!(
                        "trajectory[{i}] has {} {what} for {n} joints",
                        values.len()
                    )
                    .into());
                }
                if !current && !values.is_empty() {
                    return Err(format!(
                        "trajectory[{i}] has {what}, which format {PLAN_FORMAT_1:?} does not have (write format {PLAN_FORMAT:?})"
                    ).into());
                }
            }
            if !p.time_from_start.is_finite()
                || p.positions
                    .iter()
                    .chain(&p.velocities)
                    .chain(&p.accelerations)
                    .any(|v| !v.is_finite())
            {
                return Err(format!("trajectory[{i}] has a non-finite number").into());
            }
            if p.time_from_start < 0.0 {
                return Err(format!(
                    "trajectory[{i}]: time_from_start {} s is negative (times start at 0)",
                    fmt_real(p.time_from_start)
                )
                .into());
            }
            if i > 0 && p.time_from_start < plan.trajectory[i - 1].time_from_start {
                return Err(format!("trajectory[{i}] goes back in time").into());
            }
        }
        if let Some(l) = &plan.limits {
            if !current {
                return Err(format!(
                    "limits: format {PLAN_FORMAT_1:?} has no limits (write format {PLAN_FORMAT:?})"
                )
                .into());
            }
            if l.velocities.len() != n || l.accelerations.len() != n {
                return Err(
                    format!("limits: one velocity and one acceleration per joint ({n})").into(),
                );
            }
            if l.velocities
                .iter()
                .chain(&l.accelerations)
                .chain([&l.velocity_scaling, &l.acceleration_scaling])
                .any(|v| !(v.is_finite() && *v > 0.0))
            {
                return Err("limits: every limit and factor is a positive number".into());
            }
        }
        for (i, a) in plan.arms.iter().enumerate() {
            if !current {
                return Err(format!(
                    "arms: format {PLAN_FORMAT_1:?} has no arms (write format {PLAN_FORMAT:?})"
                )
                .into());
            }
            if plan.arms[..i].iter().any(|b| b.arm == a.arm) {
                return Err(format!("arms[{i}]: arm {} is listed twice", a.arm).into());
            }
            if let Some(j) = a
                .joints
                .iter()
                .chain(&a.gripper_joints)
                .find(|j| !plan.joint_names.contains(j))
            {
                return Err(format!("arms[{i}]: joint {:?} is not in joint_names", clip(j)).into());
            }
        }
        plan.check_poses()?;
        Ok(plan)
    }
}
