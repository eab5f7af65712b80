"""A plan made ready to show: joints in the robot's order, the object's pose at any time."""

from __future__ import annotations

import numpy as np

import pickplace


class Playback:
    """A plan made ready to show: joint positions in the robot's order and the object's pose
    at any time (resting until a grasp, then riding on the grasping arm's tip until release)."""

    def __init__(self, plan: pickplace.Plan, robot: pickplace.Robot, world_from_root: np.ndarray,
                 object_start: np.ndarray) -> None:
        self.plan = plan
        self.robot = robot
        self.world_from_root = world_from_root
        self.times = plan.times
        columns = {name: i for i, name in enumerate(plan.joint_names)}
        missing = [n for n in robot.joint_names if n not in columns]
        if missing:
            raise pickplace.InputError(f"plan: joints {missing} of the robot are not in the plan")
        self.positions = plan.positions[:, [columns[n] for n in robot.joint_names]]
        groups = {a["arm"]: a["group"] for a in plan.arms}
        # Per sample: the holding group and tip_from_object, else the object's resting pose.
        self.held: list[tuple[str, np.ndarray] | None] = []
        self.resting: list[np.ndarray] = []
        events = list(plan.events)
        pose, holder, e = object_start, None, 0
        for i, t in enumerate(self.times):
            while e < len(events) and events[e]["time"] <= t + 1e-9:
                ev = events[e]
                q = self.positions[i]
                if holder is not None:
                    pose = self.world_from_tip(q, holder[0]) @ holder[1]
                if ev["kind"] == "grasp":
                    group = groups[ev["arm"]]
                    holder = (group, np.linalg.inv(self.world_from_tip(q, group)) @ pose)
                elif ev["kind"] == "release":
                    holder = None
                e += 1
            self.held.append(holder)
            self.resting.append(pose)

    def world_from_tip(self, q: np.ndarray, group: str) -> np.ndarray:
        return self.world_from_root @ self.robot.tcp_pose(q, group)

    @property
    def duration(self) -> float:
        return float(self.times[-1]) if len(self.times) else 0.0

    def at(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(joint positions, world_from_object) at time t (linear between samples)."""
        times = self.times
        k = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 1))
        if k + 1 < len(times) and times[k + 1] > times[k]:
            a = (t - times[k]) / (times[k + 1] - times[k])
            a = min(max(a, 0.0), 1.0)
            q = (1 - a) * self.positions[k] + a * self.positions[k + 1]
        else:
            q = self.positions[k]
        held = self.held[k]
        pose = self.world_from_tip(q, held[0]) @ held[1] if held else self.resting[k]
        return q, pose
