"""Plans the demo scene (the paper's Fig. 9: NX-HIRO puts a can into a dent of a pallet) from
Python and plots every arm's joint trajectories with matplotlib.

    pip install ./crates/pickplace-py matplotlib
    python docs/examples/plan_demo.py [--scene scenes/fig9-near.toml] [--out plan_demo.png]

Without matplotlib the plan is still made and summarised, and the plot is skipped with a
message.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pickplace

ROOT = Path(__file__).resolve().parents[2]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes/fig9-near.toml")
    parser.add_argument("--out", type=Path, default=Path("plan_demo.png"))
    parser.add_argument("--seed", type=int, default=None)
    args = parser.parse_args()

    scene = pickplace.Scene.load(args.scene)
    try:
        plan = pickplace.plan(scene, seed=args.seed)
    except pickplace.NoPlanError as e:
        print("no plan:", *e.reasons, sep="\n  ")
        return 1
    report = pickplace.validate(scene, plan)
    print(
        f"{args.scene.name}: {plan.strategy}, {len(plan.times)} samples over "
        f"{plan.duration:.2f} s, {len(plan.key_poses)} key poses, "
        f"validation {'passed' if report.ok else 'FAILED'}"
    )

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (pip install matplotlib)")
        return 0 if report.ok else 1

    arms = plan.arms
    fig, axes = plt.subplots(len(arms), 1, sharex=True, figsize=(10, 3.2 * len(arms)))
    axes = [axes] if len(arms) == 1 else list(axes)
    for ax, arm in zip(axes, arms):
        for name in arm["joints"] + arm["gripper_joints"]:
            column = plan.joint_names.index(name)
            style = "--" if name in arm["gripper_joints"] else "-"
            ax.plot(plan.times, plan.positions[:, column], style, label=name)
        for event in plan.events:
            ax.axvline(event["time"], color="grey", linewidth=0.8)
            ax.text(event["time"], ax.get_ylim()[1], f" {event['kind']} ({event['arm']})",
                    va="top", fontsize=8, color="grey")  # fmt: skip
        ax.set_title(f"{arm['arm']} arm ({arm['group']})")
        ax.set_ylabel("position (rad or m)")
        ax.legend(fontsize=7, ncol=2, loc="lower left")
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(f"{args.scene.name}: {plan.strategy}")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")
    return 0 if report.ok else 1


if __name__ == "__main__":
    sys.exit(main())
