"""Independent reach check of the suite's far-left stone (issue 31), with pybullet.

The scanned stone (meshes/suite/scan-stone.stl, 8 x 6 cm, 4.4 cm tall) lies flat on the
table at (0.457, 0.341) in scan-stone-handover. The planner finds no way to pick it there:
its grasps from the side put the hand into the table, and its grasps from above have no IK.
This script checks that verdict with tools that share no code with pickplace: pybullet's
URDF loader, its forward kinematics and Jacobians (driven by a damped-least-squares loop
written here, restarted from random joint values within the limits) and its collision
queries (Bullet's GJK).

It sweeps every hand orientation on a grid (approach tilted 0-90 degrees from straight down
in 10-degree steps, the tilt's direction and the roll about the approach in 30-degree steps)
with the tool point over the stone (centre and 1 cm either way along its length, 1.5 and 3 cm
above the table). A pose counts as a grasp when the left arm reaches it (1 mm, 1 degree),
with the fingers fully open no link touches the table and no link but the two fingers
touches the stone, and, closing them, both pads (the last 2.5 cm of each finger) meet the
stone within 2 mm of travel of each other before any other part of the hand does, at points
where the line between them lies within the friction cone (coefficient 0.5) of the stone's
normal at both (an antipodal grasp, which holds the stone when lifted).

Usage: python stone_reach.py [X Y] [--tilts 0,10,...] [--list]
(X Y: the stone's position on the table, default the scene's; --list prints every grasp)
Needs `pip install pybullet==3.2.7 numpy`. Prints one line per tilt and a summary.
"""

import argparse
import math
import os
import random

import numpy as np
import pybullet as p

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
URDF = os.path.join(ROOT, "robots", "nx-hiro", "nx-hiro.urdf")
STONE = os.path.join(ROOT, "meshes", "suite", "scan-stone.stl")
TABLE = os.path.join(ROOT, "meshes", "suite", "table.stl")
BASE_Z = 0.92
TABLE_POSE = (0.55, 0.0, 0.02)
STONE_Z = 0.7209672
ARM = [f"LARM_JOINT{i}" for i in range(6)]
FINGERS = ["LARM_FINGER0_JOINT", "LARM_FINGER1_JOINT"]
TOOL = "LARM_TCP"
# Friction coefficient between pad and stone (rubber on stone, a cautious value).
MU = 0.5


def quat_from_axes(x, y, z):
    m = np.column_stack([x, y, z])
    w = math.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2.0
    if w > 1e-6:
        return [(m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w),
                (m[1, 0] - m[0, 1]) / (4 * w), w]
    # Near 180-degree turns: from the largest diagonal entry.
    i = int(np.argmax(np.diag(m)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(max(0.0, 1.0 + m[i, i] - m[j, j] - m[k, k])) * 2.0
    q = [0.0, 0.0, 0.0, 0.0]
    q[i] = s / 4.0
    q[j] = (m[j, i] + m[i, j]) / s
    q[k] = (m[k, i] + m[i, k]) / s
    q[3] = (m[k, j] - m[j, k]) / s
    return q


def main():
    ap = argparse.ArgumentParser(description="independent reach check of the far-left stone")
    ap.add_argument("xy", nargs="*", type=float, default=[0.4572718, 0.3405427])
    ap.add_argument("--tilts", default=",".join(str(t) for t in range(0, 91, 10)))
    ap.add_argument("--list", action="store_true")
    args = ap.parse_args()
    if len(args.xy) != 2:
        ap.error("give both X and Y, or neither")
    sx, sy = args.xy
    p.connect(p.DIRECT)
    robot = p.loadURDF(URDF, basePosition=[0, 0, BASE_Z], useFixedBase=True)
    names = {p.getJointInfo(robot, j)[1].decode(): j for j in range(p.getNumJoints(robot))}
    links = {p.getJointInfo(robot, j)[12].decode(): j for j in range(p.getNumJoints(robot))}
    movable = [j for j in range(p.getNumJoints(robot)) if p.getJointInfo(robot, j)[2] != p.JOINT_FIXED]
    arm = [names[n] for n in ARM]
    lower = [p.getJointInfo(robot, j)[8] for j in movable]
    upper = [p.getJointInfo(robot, j)[9] for j in movable]
    # Only the arm moves: every other joint stays at zero, as loaded.
    tool = links[TOOL]
    finger_links = {names[n] for n in FINGERS}
    table = p.createMultiBody(0, p.createCollisionShape(
        p.GEOM_MESH, fileName=TABLE, flags=p.GEOM_FORCE_CONCAVE_TRIMESH), basePosition=TABLE_POSE)
    stone = p.createMultiBody(0, p.createCollisionShape(p.GEOM_MESH, fileName=STONE),
                              basePosition=[sx, sy, STONE_Z])
    rng = random.Random(1)

    def pose_error(pos, quat):
        ls = p.getLinkState(robot, tool, computeForwardKinematics=True)
        dp = pos - np.array(ls[4])
        # Rotation error as a vector: the axis-angle of target * current^-1.
        qc = ls[5]
        inv = [-qc[0], -qc[1], -qc[2], qc[3]]
        _, qe = p.multiplyTransforms([0, 0, 0], quat, [0, 0, 0], inv)
        qe = np.array(qe) * (1.0 if qe[3] >= 0 else -1.0)
        s = np.linalg.norm(qe[:3])
        dr = qe[:3] / s * 2.0 * math.atan2(s, qe[3]) if s > 1e-12 else np.zeros(3)
        return dp, dr

    def solve(pos, quat):
        # Damped least squares on pybullet's Jacobian, restarted from random arm values;
        # an answer counts when forward kinematics meets the pose within 1 mm and 1 degree.
        for attempt in range(8):
            q = np.array([rng.uniform(lower[movable.index(j)], upper[movable.index(j)])
                          if attempt else 0.0 for j in arm])
            for _ in range(150):
                for j, v in zip(arm, q):
                    p.resetJointState(robot, j, float(v))
                dp, dr = pose_error(pos, quat)
                if np.linalg.norm(dp) < 1e-3 and np.linalg.norm(dr) < math.radians(1.0):
                    return True
                zeros = [0.0] * len(movable)
                states = [p.getJointState(robot, j)[0] for j in movable]
                jl, ja = p.calculateJacobian(robot, tool, [0, 0, 0], states, zeros, zeros)
                cols = [movable.index(j) for j in arm]
                jac = np.vstack([np.array(jl)[:, cols], np.array(ja)[:, cols]])
                e = np.concatenate([dp, dr])
                step = jac.T @ np.linalg.solve(jac @ jac.T + 1e-4 * np.eye(6), e)
                n = np.linalg.norm(step)
                if n > 0.3:
                    step *= 0.3 / n
                q = np.clip(q + step, [lower[movable.index(j)] for j in arm],
                            [upper[movable.index(j)] for j in arm])
        return False

    def clear(pos, approach):
        """Open fully, then close until a finger meets the stone; a grasp when both pads
        (the last 2.5 cm of each finger) meet it within 2 mm of each other, and no link
        touches the table and no other link the stone."""
        for n in FINGERS:
            p.resetJointState(robot, names[n], 0.04)
        if p.getClosestPoints(robot, table, 0.0):
            return False, False
        if any(c[3] not in finger_links for c in p.getClosestPoints(robot, stone, 0.0)):
            return False, False
        first = {}
        for step in range(81):
            v = 0.04 - 0.0005 * step
            for n in FINGERS:
                p.resetJointState(robot, names[n], v)
            for c in p.getClosestPoints(robot, stone, 0.0):
                if c[3] not in finger_links:
                    return True, False
                # On the pad: within half the pad depth of the tool point along the approach.
                along = float(np.dot(np.array(c[5]) - pos, approach))
                if abs(along) <= 0.0125 + 1e-9 and c[3] not in first:
                    # The point on the stone and the stone's outward normal there.
                    first[c[3]] = (v, np.array(c[6]), np.array(c[7]))
            if len(first) == 2 or any(v0 - v > 0.002 for v0, _, _ in first.values()):
                break
        if len(first) != 2:
            return True, False
        (v1, p1, n1), (v2, p2, n2) = first.values()
        if abs(v1 - v2) > 0.002:
            return True, False
        # Antipodal within the friction cone: the squeeze line lies within atan(MU) of
        # the inward normal at both contacts, else the stone slips out of the pads.
        u = p2 - p1
        u /= np.linalg.norm(u)
        cone = math.cos(math.atan(MU))
        return True, bool(np.dot(-n1, u) >= cone and np.dot(-n2, -u) >= cone)

    total_reach = total_clear = total_grasp = 0
    for tilt in (int(t) for t in args.tilts.split(",")):
        reach = clear_n = grasp_n = tried = 0
        for az in range(0, 360, 30 if tilt else 360):
            t, a = math.radians(tilt), math.radians(az)
            z = np.array([math.sin(t) * math.cos(a), math.sin(t) * math.sin(a), -math.cos(t)])
            ref = np.array([0.0, 0.0, 1.0]) if tilt else np.array([1.0, 0.0, 0.0])
            u = np.cross(z, ref)
            u /= np.linalg.norm(u)
            v = np.cross(z, u)
            for roll in range(0, 360, 30):
                r = math.radians(roll)
                y = math.cos(r) * u + math.sin(r) * v
                x = np.cross(y, z)
                quat = quat_from_axes(x, y, z)
                for dx in (-0.01, 0.0, 0.01):
                    for h in (0.015, 0.03):
                        tried += 1
                        pos = np.array([sx + dx, sy, STONE_Z + h])
                        if solve(pos, quat):
                            reach += 1
                            free, grasp = clear(pos, z)
                            clear_n += free
                            grasp_n += grasp
                            if grasp and args.list:
                                print(f"  grasp: tilt {tilt} az {az} roll {roll} dx {dx:+.3f} "
                                      f"height {h:.3f} approach {np.round(z, 3).tolist()} "
                                      f"closing {np.round(y, 3).tolist()}")
        total_reach += reach
        total_clear += clear_n
        total_grasp += grasp_n
        print(f"tilt {tilt:2d} deg: {tried:5d} poses, left arm reaches {reach:5d}, "
              f"{clear_n:5d} of them open clear of the table and stone, {grasp_n:5d} grasp it")
    print(f"stone at ({sx:.3f}, {sy:.3f}): the left arm reaches {total_reach} poses, "
          f"{total_clear} clear when open, {total_grasp} grasps")


if __name__ == "__main__":
    main()
