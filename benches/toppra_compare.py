#!/usr/bin/env python3
"""Our TOPP-RA (pickplace_prm::toppra) against the `toppra` package from PyPI on the same path
and limits (issue 19). Not a dependency of any crate.

    python3 -m venv target/toppra-venv && target/toppra-venv/bin/pip install toppra numpy
    cargo run --release -q -p pickplace-prm --example toppra_path -- 50 19 > /tmp/path.json
    target/toppra-venv/bin/python benches/toppra_compare.py /tmp/path.json

The path is our blended path sampled every 5 mm of arc length; toppra interpolates those
samples with a cubic spline, so both time the same geometry up to that interpolation.
Prints, per part of the path, both durations and their ratio (ours / toppra).
"""
import json
import sys

import numpy as np
import toppra as ta
import toppra.algorithm as algo
import toppra.constraint as constraint


def main(path_file):
    with open(path_file) as f:
        doc = json.load(f)
    v = np.array(doc["max_velocities"])
    a = np.array(doc["max_accelerations"])
    ta.setup_logging("WARNING")
    total_ours = total_theirs = 0.0
    for k, part in enumerate(doc["parts"]):
        s = np.array(part["s"])
        q = np.array(part["q"])
        path = ta.SplineInterpolator(s, q)
        pc_vel = constraint.JointVelocityConstraint(np.vstack([-v, v]).T)
        pc_acc = constraint.JointAccelerationConstraint(np.vstack([-a, a]).T)
        grid = max(100, int(s[-1] / 0.005))
        instance = algo.TOPPRA(
            [pc_vel, pc_acc], path, parametrizer="ParametrizeConstAccel",
            gridpoints=np.linspace(0, s[-1], grid + 1),
        )
        jnt_traj = instance.compute_trajectory(0, 0)
        if jnt_traj is None:
            print(f"part {k}: toppra found no parameterization")
            continue
        theirs = jnt_traj.duration
        ours = part["duration"]
        total_ours += ours
        total_theirs += theirs
        print(
            f"part {k}: length {s[-1]:.3f}, ours {ours:.4f} s, toppra {theirs:.4f} s, "
            f"ratio {ours / theirs:.4f}; ours peaks at {part['max_velocity_ratio']:.3f} of a "
            f"velocity limit and {part['max_acceleration_ratio']:.3f} of an acceleration limit"
        )
    if total_theirs > 0:
        print(f"total: ours {total_ours:.4f} s, toppra {total_theirs:.4f} s, ratio {total_ours / total_theirs:.4f}")


if __name__ == "__main__":
    main(sys.argv[1])
