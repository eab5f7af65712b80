"""Robot: forward kinematics against the CLI, Jacobians against finite differences, IK
against FK."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pickplace


@pytest.fixture(scope="module")
def nx(root):
    return pickplace.Robot.load(
        root / "robots/nx-hiro/nx-hiro.urdf", root / "robots/nx-hiro/nx-hiro.srdf"
    )


def test_model_names_and_limits(nx):
    j = len(nx.joint_names)
    assert nx.name == "nx-hiro" and j == 17
    assert nx.lower_limits.shape == nx.upper_limits.shape == nx.velocity_limits.shape == (j,)
    assert np.all(nx.lower_limits <= nx.upper_limits)
    assert "right_arm" in nx.groups and "Robot(" in repr(nx)
    assert nx.zero_configuration().shape == (j,)


def test_fk_matches_the_cli(nx, run_cli):
    q = nx.zero_configuration()
    values = {"RARM_JOINT2": -1.0, "LARM_JOINT1": 0.3, "CHEST_JOINT0": 0.5}
    for name, value in values.items():
        q[nx.joint_names.index(name)] = value
    joints = ",".join(f"{k}={v}" for k, v in values.items())
    status, out, err = run_cli(
        "robot", "fk", "robots/nx-hiro/nx-hiro.urdf", "--joints", joints, "--json"
    )
    assert status == 0, err
    links = json.loads(out)["links"]
    poses = nx.fk(q)
    assert poses.shape == (len(nx.link_names), 4, 4)
    for name, pose in zip(nx.link_names, poses):
        expected = pickplace.pose_matrix(**links[name])
        np.testing.assert_allclose(pose, expected, atol=1e-12, err_msg=name)
        np.testing.assert_array_equal(nx.fk(q, "RARM_JOINT5_Link"), poses[nx.link_names.index("RARM_JOINT5_Link")])
    # Lists work as well as arrays.
    np.testing.assert_array_equal(nx.fk(list(q), "RARM_JOINT5_Link"), nx.fk(q, "RARM_JOINT5_Link"))


def test_jacobian_matches_finite_differences(nx):
    rng = np.random.default_rng(3)
    q = rng.uniform(np.maximum(nx.lower_limits, -1), np.minimum(nx.upper_limits, 1))
    link, point = "RARM_JOINT5_Link", np.array([0.0, 0.0, -0.1])
    jac = nx.jacobian(q, link, point)
    assert jac.shape == (6, len(q))
    h = 1e-6

    def world_point(q):
        m = nx.fk(q, link)
        return m[:3, :3] @ point + m[:3, 3]

    for i in range(len(q)):
        dq = np.zeros_like(q)
        dq[i] = h
        numeric = (world_point(q + dq) - world_point(q - dq)) / (2 * h)
        np.testing.assert_allclose(jac[:3, i], numeric, atol=1e-6)
    arm = [n for n in nx.joint_names if n.startswith("RARM")]
    sub = nx.jacobian(q, link, point, joints=arm)
    np.testing.assert_array_equal(sub, jac[:, [nx.joint_names.index(n) for n in arm]])


def test_ik_reaches_an_fk_pose(nx):
    home = nx.state("home")
    target_q = home.copy()
    for name, delta in {"RARM_JOINT1": -0.2, "RARM_JOINT2": -0.3, "RARM_JOINT4": 0.2}.items():
        target_q[nx.joint_names.index(name)] += delta
    target = nx.tcp_pose(target_q, "right_arm")
    solution = nx.ik(target, "right_arm", home)
    assert solution.success and bool(solution), solution
    assert solution.positions.shape == home.shape
    np.testing.assert_allclose(nx.tcp_pose(solution.positions, "right_arm"), target, atol=1e-3)
    assert solution.position_error < 1e-4 and solution.orientation_error < 1e-3
    far = target.copy()
    far[:3, 3] += [5.0, 0.0, 0.0]
    assert not nx.ik(far, "right_arm", home).success


def test_ik_matches_the_cli(nx, run_cli):
    target_q = nx.state("home")
    for name, delta in {"RARM_JOINT0": 0.3, "RARM_JOINT2": -0.4, "RARM_JOINT5": 0.5}.items():
        target_q[nx.joint_names.index(name)] += delta
    pose = pickplace.pose_parts(nx.tcp_pose(target_q, "right_arm"))
    text = ",".join(repr(v) for v in pose["position"] + pose["orientation"])
    status, out, err = run_cli(
        "robot", "ik", "robots/nx-hiro/nx-hiro.urdf", "--srdf", "robots/nx-hiro/nx-hiro.srdf",
        "--group", "right_arm", "--pose", text, "--json",
    )  # fmt: skip
    assert status == 0, err
    cli = json.loads(out)
    ours = nx.ik(pickplace.pose_matrix(**pose), "right_arm")
    assert ours.success and cli["success"]
    expected = np.array([cli["positions"][n] for n in nx.joint_names])
    np.testing.assert_allclose(ours.positions, expected, atol=1e-9)
    assert ours.attempts == cli["attempts"]


def test_robot_errors(nx, root):
    with pytest.raises(pickplace.InputError, match="nope.urdf"):
        pickplace.Robot.load(root / "nope.urdf")
    with pytest.raises(pickplace.InputError, match="17 joints"):
        nx.fk(np.zeros(3))
    with pytest.raises(pickplace.InputError, match="not finite"):
        nx.fk(np.full(17, np.nan))
    skewed = np.eye(4)
    skewed[0, 1] = 0.5
    with pytest.raises(pickplace.InputError, match="not a rotation matrix"):
        nx.ik(skewed, "right_arm")
    with pytest.raises(pickplace.InputError, match=r"last row must be \[0, 0, 0, 1\]"):
        nx.ik(np.ones((4, 4)), "right_arm")
    with pytest.raises(pickplace.InputError, match="no_such_group"):
        nx.ik(np.eye(4), "no_such_group")
    with pytest.raises(pickplace.InputError, match="NOPE"):
        nx.fk(nx.zero_configuration(), "NOPE")
    bare = pickplace.Robot.load(root / "robots/nx-hiro/nx-hiro.urdf")
    with pytest.raises(pickplace.InputError, match="no SRDF"):
        bare.ik(np.eye(4), "right_arm")


def test_pose_helpers_round_trip():
    d = {"position": [0.1, -0.2, 0.3], "orientation": [0.0, 0.38268343236508984, 0.0, 0.9238795325112867]}
    m = pickplace.pose_matrix(**d)
    back = pickplace.pose_parts(m)
    np.testing.assert_allclose(back["position"], d["position"])
    np.testing.assert_allclose(back["orientation"], d["orientation"], atol=1e-12)
