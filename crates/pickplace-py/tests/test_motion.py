"""Motion queries from Python (issue 35): the same bytes as `pickplace motion`, obstacles as
dicts in the scene's form (4x4 poses too), reasons and errors."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest

import pickplace

SCENE = "scenes/motion/nx-hiro-table.toml"
START = [-0.5, -0.3, -2.0, 0.2, 0.3, 0.1]
GOAL = [0.2, -0.5, -1.5, 0.0, 0.0, 0.0]


@pytest.fixture(scope="module")
def world(root):
    return pickplace.MotionWorld.load(root / SCENE)


def test_a_motion_is_the_clis_byte_for_byte(world, root, cli):
    motion = pickplace.plan_motion(world, GOAL, START, group="right_arm")
    assert motion.group == "right_arm"
    assert motion.joint_names[0] == "RARM_JOINT0"
    assert motion.positions.shape == (len(motion.times), 6)
    assert np.allclose(motion.positions[0], START) and np.allclose(motion.positions[-1], GOAL)
    assert np.all(np.diff(motion.times) > 0)
    assert motion.duration == pytest.approx(motion.times[-1])
    out = subprocess.run(
        [str(cli), "motion", SCENE, "--group", "right_arm", "--from=" + ",".join(map(str, START)),
         "--to", ",".join(map(str, GOAL)), "--no-timings"],
        cwd=root, capture_output=True, text=True, check=True,
    ).stdout
    assert motion.to_json() == out


def test_obstacles_are_dicts_in_the_scenes_form(world):
    free = pickplace.plan_motion(world, GOAL, START, group="right_arm")
    # A ball on the hand at the goal: the goal now collides, named.
    blocked = world.with_obstacles([
        {"name": "block", "box": [0.05, 0.05, 0.05], "pose": pickplace.pose_matrix([0.45, -0.25, 1.0])},
    ])
    assert "block" in blocked.obstacles and "block" not in world.obstacles
    # Joints by name; the others of the group stay at the world's start.
    by_name = pickplace.plan_motion(world, {"RARM_JOINT0": 0.1}, START, group="right_arm")
    assert by_name.positions[-1][0] == pytest.approx(0.1)
    assert free.stats["attempts"] >= 1
    sphere = world.with_obstacles([
        {"name": "s", "sphere": {"radius": 0.3}, "pose": {"position": [0.3, -0.25, 0.9]}},
    ])
    with pytest.raises(pickplace.NoPlanError) as e:
        pickplace.plan_motion(sphere, GOAL, START, group="right_arm")
    assert "in collision" in str(e.value) and "s" in e.value.reasons[0]


def test_a_robot_alone_plans_with_primitive_obstacles(root):
    world = pickplace.MotionWorld.for_robot(
        root / "robots/nx-hiro/nx-hiro.urdf",
        root / "robots/nx-hiro/nx-hiro.srdf",
        obstacles=[{"name": "post", "cylinder": {"radius": 0.03, "length": 0.4},
                    "pose": {"position": [0.45, -0.25, 0.0]}}],
    )
    assert world.obstacles == ["post"]
    motion = pickplace.plan_motion(world, GOAL, START, group="right_arm", seed=3)
    again = pickplace.plan_motion(world, GOAL, START, group="right_arm", seed=3)
    assert motion.to_json() == again.to_json()


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"group": "tail"}, "right_arm (6 joints)"),
        ({"group": "right_arm", "goal": [1, 2]}, "2 values for the 6 joints"),
        ({"group": "right_arm", "goal": "dance"}, 'no group_state "dance"'),
        ({"group": "right_arm", "margin": -1.0}, "options.margin"),
        ({"group": "right_arm", "time_limit": -1.0}, "time_limit"),
    ],
)
def test_bad_queries_are_input_errors(world, kwargs, needle):
    args = {"goal": GOAL, **kwargs}
    with pytest.raises(pickplace.InputError, match=None) as e:
        pickplace.plan_motion(world, args.pop("goal"), START, **args)
    assert needle in str(e.value)


@pytest.mark.parametrize(
    ("obstacle", "needle"),
    [
        ({"name": "x", "box": [1, 1, 1], "sphere": {"radius": 1}}, "exactly one of"),
        ({"name": "x", "box": [1, 0, 1]}, "obstacles[0].box[1]"),
        ({"name": "x", "cube": 1}, "unknown field"),
        ({"name": "x", "box": [1, 1, 1], "pose": [[1, 0], [0, 1]]}, "4x4"),
        ({"name": "table", "sphere": {"radius": 0.1}}, "two obstacles"),
        ({"name": "x", "mesh": "no/such.stl"}, "no/such.stl"),
        ({"name": "x", "sphere": {"radius": 0.1}, "pose": {"position": [1e300, 0, 0]}}, "obstacles[0].pose.position"),
    ],
)
def test_bad_obstacles_are_input_errors(world, obstacle, needle):
    with pytest.raises(pickplace.InputError) as e:
        world.with_obstacles([obstacle])
    assert needle in str(e.value)
