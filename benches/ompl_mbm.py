"""OMPL 2.0.1's RRT-Connect on MotionBenchMaker's Panda problems, collisions by coal through
pinocchio: the side-by-side figures of `cargo xtask mbm --ompl` (issue 35).

Run by `cargo xtask mbm --ompl` (which unpacks the problems, makes the environment
`target/ompl-venv` with the pinned packages and runs this script); by hand:

    python benches/ompl_mbm.py --resources target/mbm/vamp_planner-0.6.4/resources/panda \
        --problems target/mbm/problems --out target/mbm/ompl.json [--sample N] [--seed S]

Each problem as `cargo xtask mbm` reads it: the Panda of vamp-planner 0.6.4's resources (its
URDF and collision meshes, loaded by pinocchio into coal's meshes; its SRDF's disabled pairs and
the scene's allowed pairs removed), the scene's boxes, cylinders and spheres, the request's
start and goal of `panda_arm`; the links as their convex hulls, as our checker has them. OMPL's `SimpleSetup` with `RRTConnect` (OMPL's default range),
states checked every 1° of joint motion (the state validity checking resolution set so that
the longest segment checked at once is 1° long in the space's metric), a time limit of 1 s,
one thread; the time is `solve()`'s wall time, its state checks calling coal through Python.
Every path found is checked again by coal at 1° (max-norm joint step), and the problems'
starts and goals are checked too (so that coal's and our own checker's verdicts can be put
side by side). Writes a JSON document of outcomes and per-scenario summaries.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import statistics
import time
from pathlib import Path

import numpy as np
import pinocchio as pin
import yaml
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

import coal

JOINTS = [f"panda_joint{i}" for i in range(1, 8)]
TIME_LIMIT = 1.0
STEP = math.pi / 180.0


def primitive(p: dict) -> coal.CollisionGeometry:
    """A shape_msgs/SolidPrimitive as coal's shape (cylinder axis z, as ROS's)."""
    d = p["dimensions"]
    kind = p["type"]
    if kind == "box" and len(d) == 3:
        return coal.Box(*d)
    if kind == "cylinder" and len(d) == 2:
        return coal.Cylinder(d[1], d[0])
    if kind == "sphere" and len(d) == 1:
        return coal.Sphere(d[0])
    raise ValueError(f"a primitive of type {kind!r} with {len(d)} dimensions is not supported")


def pose(msg: dict) -> pin.SE3:
    x, y, z, w = msg["orientation"]
    q = pin.Quaternion(w, x, y, z)
    q.normalize()
    return pin.SE3(q.matrix(), np.array(msg["position"], dtype=float))


class Robot:
    """The Panda's model and collision geometry, without obstacles."""

    def __init__(self, resources: Path):
        urdf = str(resources / "panda.urdf")
        self.model = pin.buildModelFromUrdf(urdf)
        self.geom = pin.buildGeomFromUrdf(self.model, urdf, pin.GeometryType.COLLISION, str(resources))
        # The links' convex hulls, as our checker uses them (coal's meshes checked triangle
        # by triangle cost 1.7 times as much here: 67 µs a state against 39 µs).
        for g in self.geom.geometryObjects:
            g.geometry.buildConvexHull(True, "Qt")
            g.geometry = g.geometry.convex
        self.geom.addAllCollisionPairs()
        pin.removeCollisionPairs(self.model, self.geom, str(resources / "panda.srdf"))
        self.robot_geoms = len(self.geom.geometryObjects)
        self.index = [self.model.getJointId(j) for j in JOINTS]
        self.lower = np.array([self.model.lowerPositionLimit[self.model.idx_qs[i]] for i in self.index])
        self.upper = np.array([self.model.upperPositionLimit[self.model.idx_qs[i]] for i in self.index])


def problem_world(robot: Robot, scene: dict):
    """The geometry model with the scene's obstacles and its allowed pairs removed."""
    geom = robot.geom.copy()
    link_of = [geom.geometryObjects[i].parentFrame for i in range(robot.robot_geoms)]
    names = [robot.model.frames[f].name for f in link_of]
    for obj in scene.get("world", {}).get("collision_objects", []):
        for k, (p, msg) in enumerate(zip(obj["primitives"], obj["primitive_poses"])):
            g = pin.GeometryObject(f"{obj['id']}/{k}", 0, 0, pose(msg), primitive(p))
            gid = geom.addGeometryObject(g)
            for r in range(robot.robot_geoms):
                geom.addCollisionPair(pin.CollisionPair(r, gid))
    acm = scene.get("allowed_collision_matrix") or {}
    entries = acm.get("entry_names", [])
    allowed = set()
    for i, row in enumerate(acm.get("entry_values", [])):
        for j, v in enumerate(row):
            if v:
                allowed.add((entries[i], entries[j]))
    for a in range(robot.robot_geoms):
        for b in range(a + 1, robot.robot_geoms):
            if (names[a], names[b]) in allowed:
                geom.removeCollisionPair(pin.CollisionPair(a, b))
    return geom


def joint_values(state: dict) -> dict:
    js = state["joint_state"]
    return dict(zip(js["name"], js["position"]))


def solve(robot: Robot, scene: dict, request: dict, seed: int) -> dict:
    geom = problem_world(robot, scene)
    data = robot.model.createData()
    gdata = pin.GeometryData(geom)
    q = pin.neutral(robot.model)
    start_values = joint_values(request["start_state"])
    for name, v in start_values.items():
        if robot.model.existJointName(name):
            q[robot.model.idx_qs[robot.model.getJointId(name)]] = v
    template = q.copy()
    slots = [robot.model.idx_qs[i] for i in robot.index]

    def free(values) -> bool:
        for s, v in zip(slots, values):
            template[s] = v
        return not pin.computeCollisions(robot.model, data, geom, gdata, template, True)

    start = [start_values[j] for j in JOINTS]
    goal_values = {c["joint_name"]: c["position"] for c in request["goal_constraints"][0]["joint_constraints"]}
    goal = [goal_values[j] for j in JOINTS]
    out = {"start_valid": free(start), "goal_valid": free(goal)}

    space = ob.RealVectorStateSpace(len(JOINTS))
    bounds = ob.RealVectorBounds(len(JOINTS))
    for i in range(len(JOINTS)):
        bounds.setLow(i, float(robot.lower[i]))
        bounds.setHigh(i, float(robot.upper[i]))
    space.setBounds(bounds)
    ss = og.SimpleSetup(space)
    ss.setStateValidityChecker(lambda s: free([s[i] for i in range(len(JOINTS))]))
    si = ss.getSpaceInformation()
    si.setStateValidityCheckingResolution(STEP / space.getMaximumExtent())
    ss.setPlanner(og.RRTConnect(si))
    a, b = space.allocState(), space.allocState()
    for i in range(len(JOINTS)):
        a[i], b[i] = start[i], goal[i]
    ss.setStartAndGoalStates(a, b)
    t = time.perf_counter()
    status = ss.solve(TIME_LIMIT)
    seconds = time.perf_counter() - t
    found = bool(status) and ss.haveExactSolutionPath()
    out.update(seconds=seconds, found=found)
    if found:
        path = ss.getSolutionPath()
        points = [[path.getState(k)[i] for i in range(len(JOINTS))] for k in range(path.getStateCount())]
        length = sum(float(np.linalg.norm(np.subtract(q1, q0))) for q0, q1 in zip(points, points[1:]))
        collides = False
        for q0, q1 in zip(points, points[1:]):
            n = max(1, math.ceil(max(abs(x1 - x0) for x0, x1 in zip(q0, q1)) / STEP))
            if any(not free(np.add(q0, np.subtract(q1, q0) * (k / n))) for k in range(n + 1)):
                collides = True
                break
        out.update(length=length, waypoints=len(points), collides=collides)
    return out


def percentile(values: list[float], p: float) -> float:
    s = sorted(values)
    rank = min(len(s), max(1, math.ceil(p * len(s))))
    return s[rank - 1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--resources", type=Path, required=True)
    parser.add_argument("--problems", type=Path, required=True)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--sample", type=int, default=None)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    ou.setLogLevel(ou.LOG_ERROR)
    # Once, before any sampling: OMPL's generator cannot be reseeded per problem.
    ou.RNG.setSeed(args.seed)
    robot = Robot(args.resources)
    outcomes = {}
    summaries = []
    for folder in sorted(p for p in args.problems.iterdir() if p.is_dir() and p.name.endswith("_panda")):
        numbers = sorted(f.name[len("request"):-len(".yaml")] for f in folder.glob("request*.yaml"))
        if args.sample:
            numbers = numbers[: args.sample]
        rows = []
        for n in numbers:
            scene = yaml.safe_load((folder / f"scene{n}.yaml").read_text())
            request = yaml.safe_load((folder / f"request{n}.yaml").read_text())
            r = solve(robot, scene, request, args.seed)
            outcomes[f"{folder.name}/{n}"] = r
            rows.append(r)
        summaries.append(summary(folder.name, rows))
        s = summaries[-1]
        print(f"  {s['scenario']}: {s['solved']}/{s['problems']} solved, median {s['median'] * 1e3:.2f} ms, "
              f"95th percentile {s['p95'] * 1e3:.2f} ms, {s['colliding']} colliding", flush=True)
    summaries.append(summary("all panda", list(outcomes.values())))
    doc = {
        "machine": f"{platform.processor() or platform.machine()}, Python {platform.python_version()}",
        "tools": "OMPL 2.0.1 (RRTConnect, default range), pinocchio 4.1.0, coal 3.0.3",
        "seed": args.seed,
        "summaries": summaries,
        "outcomes": outcomes,
    }
    args.out.write_text(json.dumps(doc, indent=1) + "\n")


def summary(name: str, rows: list[dict]) -> dict:
    times = [r["seconds"] for r in rows]
    solved = [r for r in rows if r["found"] and r["seconds"] <= TIME_LIMIT]
    return {
        "scenario": name,
        "problems": len(rows),
        "solved": len(solved),
        "median": statistics.median(times) if times else 0.0,
        "p95": percentile(times, 0.95) if times else 0.0,
        "mean_length": sum(r["length"] for r in solved) / max(1, len(solved)),
        "colliding": sum(1 for r in rows if r.get("collides")),
        "invalid_starts": sum(1 for r in rows if not r["start_valid"]),
        "invalid_goals": sum(1 for r in rows if not r["goal_valid"]),
    }


if __name__ == "__main__":
    main()
