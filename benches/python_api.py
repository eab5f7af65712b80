#!/usr/bin/env python3
"""The Python package's costs (issue 20), measured in one run:

1. the overhead of `pickplace.plan` over the Rust planner it wraps: the wall time of the Python
   call minus the planner's own total (`plan.stats["timings"]["total"]`, measured inside the
   Rust call), on the shipped scenes;
2. forward kinematics, Jacobians and inverse kinematics called from Python, against
   pinocchio's Python bindings (the `pin` package from PyPI) on the same URDF (NX-HIRO), the
   same configurations and the same tool link. Pinocchio has no IK of its own: its side is
   the closed-loop IK (damped least squares on the SE(3) error, `pin.log6`) that pinocchio's
   documentation teaches, written here.

    python3 -m venv target/pybench-venv
    target/pybench-venv/bin/pip install ./crates/pickplace-py pin
    target/pybench-venv/bin/python benches/python_api.py [--json FILE] [--quick]

Not a dependency of any crate. Prints medians; `--json FILE` writes them too.
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

import pickplace

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
URDF = os.path.join(ROOT, "robots", "nx-hiro", "nx-hiro.urdf")
SRDF = os.path.join(ROOT, "robots", "nx-hiro", "nx-hiro.srdf")
SCENES = ["fig9-near", "fig9-far-left", "fig10a-edge", "fig10b-mug"]


def median_time(f, repeat, inner=1):
    """Median over `repeat` runs of the time of one call of `f` (each run `inner` calls)."""
    runs = []
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(inner):
            f()
        runs.append((time.perf_counter() - t) / inner)
    return statistics.median(runs)


def quiet(f, *args):
    """`f(*args)` with the C++ libraries' messages on standard error silenced (urdfdom
    complains about the meshes' `package://` paths, which a kinematic model does not need)."""
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
            return f(*args)
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def plan_overhead(repeat):
    rows = {}
    for name in SCENES:
        scene = pickplace.Scene.load(os.path.join(ROOT, "scenes", name + ".toml"))
        pickplace.plan(scene, seed=1)  # the cache and the roadmaps are warm from here on
        diffs, totals = [], []
        for _ in range(repeat):
            t = time.perf_counter()
            p = pickplace.plan(scene, seed=1, timings=True)
            wall = time.perf_counter() - t
            inner = p.stats["timings"]["total"]
            diffs.append(wall - inner)
            totals.append(inner)
        rows[name] = {
            "rust_ms": statistics.median(totals) * 1e3,
            "overhead_ms": statistics.median(diffs) * 1e3,
        }
    return rows


def kinematics(repeat, count):
    import pinocchio as pin

    ours = pickplace.Robot.load(URDF, SRDF)
    model = quiet(pin.buildModelFromUrdf, URDF)
    data = model.createData()
    names = ours.joint_names
    # Our joint order to pinocchio's configuration vector (revolute joints: one value each).
    index = {model.names[j]: model.joints[j].idx_q for j in range(1, model.njoints)}
    missing = [n for n in names if n not in index]
    if missing:
        sys.exit(f"pinocchio's model lacks joints {missing}")

    def to_pin(q):
        v = np.zeros(model.nq)
        for k, n in enumerate(names):
            v[index[n]] = q[k]
        return v

    group = "right_arm"
    tip = ours.tcp_pose(ours.zero_configuration(), group)  # checks the group exists
    del tip
    link = "RARM_TCP"  # the right arm group's tip (the SRDF's chain)
    fid = model.getFrameId(link)
    rng = np.random.default_rng(1)
    lo, hi = ours.lower_limits, ours.upper_limits
    qs = [lo + (hi - lo) * rng.random(len(names)) for _ in range(count)]
    pqs = [to_pin(q) for q in qs]

    # Same poses (the two libraries agree), then the timings.
    worst = 0.0
    for q, pq in zip(qs, pqs):
        a = ours.fk(q, link)
        pin.framesForwardKinematics(model, data, pq)
        b = data.oMf[fid].homogeneous
        worst = max(worst, float(np.abs(a - b).max()))
    if worst > 1e-9:
        sys.exit(f"FK disagrees with pinocchio by {worst}")

    it = iter(range(10**9))

    def our_fk():
        k = next(it) % count
        return ours.fk(qs[k], link)

    def pin_fk():
        k = next(it) % count
        pin.framesForwardKinematics(model, data, pqs[k])
        return data.oMf[fid].homogeneous

    def our_jac():
        k = next(it) % count
        return ours.jacobian(qs[k], link)

    def pin_jac():
        k = next(it) % count
        return pin.computeFrameJacobian(model, data, pqs[k], fid, pin.LOCAL_WORLD_ALIGNED)

    out = {
        "fk_ours_us": median_time(our_fk, repeat, 200) * 1e6,
        "fk_pinocchio_us": median_time(pin_fk, repeat, 200) * 1e6,
        "jacobian_ours_us": median_time(our_jac, repeat, 200) * 1e6,
        "jacobian_pinocchio_us": median_time(pin_jac, repeat, 200) * 1e6,
    }

    # IK: reach the tool pose of a random arm configuration from the zero configuration
    # (both sides: 1e-4 m and 1e-3 rad).
    arm = [names.index(n) for n in names if n.startswith("RARM_JOINT")]
    targets = []
    for q in qs[: min(count, 100)]:
        q0 = ours.zero_configuration()
        q0[arm] = q[arm]
        targets.append(ours.fk(q0, link))
    start = ours.zero_configuration()
    pin_start = to_pin(start)
    pin_arm = [index[names[k]] for k in arm]

    def pin_ik(target):
        goal = pin.SE3(target[:3, :3], target[:3, 3])
        q = pin_start.copy()
        for _ in range(500):
            pin.framesForwardKinematics(model, data, q)
            err = pin.log6(data.oMf[fid].actInv(goal)).vector
            if np.linalg.norm(err[:3]) < 1e-4 and np.linalg.norm(err[3:]) < 1e-3:
                return True
            j = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL)[:, pin_arm]
            j = -pin.Jlog6(data.oMf[fid].actInv(goal)) @ j
            dq = -j.T @ np.linalg.solve(j @ j.T + 1e-6 * np.eye(6), err)
            q[pin_arm] += 0.5 * dq
            q = np.clip(q, model.lowerPositionLimit, model.upperPositionLimit)
        return False

    t = time.perf_counter()
    pin_ok = sum(pin_ik(x) for x in targets)
    pin_time = (time.perf_counter() - t) / len(targets)
    t = time.perf_counter()
    our_ok = sum(bool(ours.ik(x, group, start)) for x in targets)
    our_time = (time.perf_counter() - t) / len(targets)
    out.update(
        ik_ours_us=our_time * 1e6,
        ik_ours_solved=f"{our_ok}/{len(targets)}",
        ik_pinocchio_us=pin_time * 1e6,
        ik_pinocchio_solved=f"{pin_ok}/{len(targets)}",
        pinocchio=pin.__version__,
    )
    return out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", help="also write the figures to this file")
    ap.add_argument("--quick", action="store_true", help="fewer repetitions")
    args = ap.parse_args(argv)
    repeat = 5 if args.quick else 30
    out = {
        "plan": plan_overhead(repeat),
        "kinematics": kinematics(repeat, 50 if args.quick else 500),
        "load": os.getloadavg(),
    }
    for name, row in out["plan"].items():
        print(f"plan {name}: Rust {row['rust_ms']:.2f} ms, Python overhead {row['overhead_ms']:.3f} ms")
    for k, v in out["kinematics"].items():
        print(f"{k}: {v:.2f}" if isinstance(v, float) else f"{k}: {v}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    worst = max(r["overhead_ms"] for r in out["plan"].values())
    return 0 if worst <= 1.0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
