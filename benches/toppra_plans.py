#!/usr/bin/env python3
"""Our motion durations against the `toppra` package from PyPI, motion by motion, on the plans
of the shipped scenes and of the scene suite (issue 19). Not a dependency of any crate.

    python3 -m venv target/toppra-venv && target/toppra-venv/bin/pip install toppra numpy
    cargo build --release -p pickplace-cli
    target/toppra-venv/bin/python benches/toppra_plans.py target/release/pickplace \
        scenes/*.toml scenes/suite/*.toml

Each scene is planned with `--sample-period 0.002 --no-timings` (the sampling does not change
the timing). The plan is cut into its motions where the robot stops (grasps, releases and
wherever the velocities are all 0: `Plan::motions`); each motion's samples lie on our blended path, and toppra times
the cubic spline through them, parameterized by joint-space arc length as ours, under the
plan's own limits (`limits` of the plan: URDF velocities, 3 rad/s², scaling applied).

`--max-ratio R` exits 1 when a motion takes more than R times toppra's time, or when no
plan was made (`cargo xtask test` runs it on the shipped scenes with R = 1.05).

Prints one line per scene (motions, our total, toppra's, the largest ratio ours/toppra of a
motion) and a summary; `--json FILE` also writes every motion's figures.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import toppra as ta
import toppra.algorithm as algo
import toppra.constraint as constraint


def motions(plan):
    """Sample index ranges between the robot's stops (as Plan::motions in Rust)."""
    traj = plan["trajectory"]
    times = np.array([p["time_from_start"] for p in traj])

    def index_at(t):
        return max(int(np.searchsorted(times, t + 1e-9, side="right")) - 1, 0)

    def at_rest(i):
        return all(v == 0.0 for v in traj[i].get("velocities", []))

    cuts = sorted({i for i in (index_at(k["time"]) for k in plan["key_poses"]) if at_rest(i)}
                  | {index_at(e["time"]) for e in plan["events"]}
                  | {i for i in range(1, len(traj) - 1) if traj[i].get("velocities") and at_rest(i)}
                  | {len(traj) - 1})
    out, first = [], 0
    for last in cuts:
        if last > first:
            out.append((first, last))
            first = last
    return out


def toppra_duration(q, v, a):
    """toppra's time-optimal duration along the spline through the rows of q."""
    keep = [0]
    for i in range(1, len(q)):
        if np.linalg.norm(q[i] - q[keep[-1]]) > 1e-9:
            keep.append(i)
    q = q[keep]
    if len(q) < 2:
        return 0.0
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(q, axis=0), axis=1))])
    path = ta.SplineInterpolator(s, q)
    pc_vel = constraint.JointVelocityConstraint(np.vstack([-v, v]).T)
    pc_acc = constraint.JointAccelerationConstraint(np.vstack([-a, a]).T)
    grid = max(100, int(s[-1] / 0.002))
    instance = algo.TOPPRA([pc_vel, pc_acc], path, parametrizer="ParametrizeConstAccel",
                           gridpoints=np.linspace(0, s[-1], grid + 1))
    traj = instance.compute_trajectory(0, 0)
    return None if traj is None else traj.duration


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    json_out = None
    if "--json" in argv:
        i = argv.index("--json")
        json_out = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    max_ratio = None
    if "--max-ratio" in argv:
        i = argv.index("--max-ratio")
        max_ratio = float(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    binary, scenes = argv[1], argv[2:]
    ta.setup_logging("WARNING")
    rows, worst = [], (0.0, None)
    total_ours = total_theirs = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            out = os.path.join(tmp, "plan.json")
            r = subprocess.run([binary, "plan", scene, "--sample-period", "0.002", "--no-timings",
                                "--out", out], capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{scene}: no plan (exit {r.returncode}), skipped")
                if max_ratio is not None:
                    sys.exit(f"{scene}: no plan: {r.stderr.strip()[-400:]}")
                continue
            with open(out) as f:
                plan = json.load(f)
            v = np.array(plan["limits"]["velocities"])
            a = np.array(plan["limits"]["accelerations"])
            traj = plan["trajectory"]
            scene_ours = scene_theirs = 0.0
            scene_worst = 0.0
            for k, (i, j) in enumerate(motions(plan)):
                q = np.array([p["positions"] for p in traj[i:j + 1]])
                ours = traj[j]["time_from_start"] - traj[i]["time_from_start"]
                theirs = toppra_duration(q, v, a)
                if theirs is None or theirs <= 1e-6 or ours <= 1e-6:
                    continue
                ratio = ours / theirs
                rows.append({"scene": scene, "motion": k, "ours": ours, "toppra": theirs,
                             "ratio": ratio})
                scene_ours += ours
                scene_theirs += theirs
                scene_worst = max(scene_worst, ratio)
                if ratio > worst[0]:
                    worst = (ratio, f"{scene} motion {k}")
            total_ours += scene_ours
            total_theirs += scene_theirs
            print(f"{scene}: {plan['strategy']}, plan {traj[-1]['time_from_start']:.2f} s; "
                  f"motions ours {scene_ours:.2f} s, toppra {scene_theirs:.2f} s, "
                  f"ratio {scene_ours / max(scene_theirs, 1e-9):.3f}, worst motion {scene_worst:.3f}")
    ratios = np.array([r["ratio"] for r in rows])
    if len(ratios):
        print(f"{len(rows)} motions: ratio ours/toppra median {np.median(ratios):.3f}, "
              f"p95 {np.percentile(ratios, 95):.3f}, max {worst[0]:.3f} ({worst[1]}); "
              f"total ours {total_ours:.1f} s, toppra {total_theirs:.1f} s "
              f"({total_ours / total_theirs:.3f}); "
              f"{int((ratios <= 1.05).sum())} of {len(ratios)} motions within 1.05")
    if json_out:
        with open(json_out, "w") as f:
            json.dump(rows, f, indent=1)
    if max_ratio is not None:
        if not len(ratios):
            sys.exit("no motion was compared")
        if worst[0] > max_ratio:
            sys.exit(f"a motion takes {worst[0]:.3f} times toppra's time ({worst[1]}), "
                     f"more than {max_ratio}")


if __name__ == "__main__":
    main(sys.argv)
