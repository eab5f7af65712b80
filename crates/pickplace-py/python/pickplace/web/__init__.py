"""pickplace.web: the browser view (issue 21), built on viser.

``pickplace-view-web SCENE.toml [--port N] [--plan PLAN.json]`` serves a page on 127.0.0.1
showing the robots (one, or two with ``[[robots]]``: their links' shapes posed by forward
kinematics), the environment, the object at its start pose and, on request, the environment's
clusters. A click on an environment surface sets
the target, highlights the cluster under it, plans, and plays the plan back (timeline slider,
play/pause, strategy, key poses); with no plan, the planner's reasons appear in the page. With
``--plan`` the page only plays the given plan. docs/web.md describes it.

Everything the page draws or computes comes from Rust (``pickplace.SceneView``,
``pickplace.Playback``, ``Scene.environment_parts``); this package only lays out the page.

viser (the ``[web]`` extra) is imported only by this module; ``import pickplace`` does not.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time

import pickplace

from .page import CAMERA_FOV, CAMERA_LOOK_AT, CAMERA_POSITION, STRATEGIES, WebView, free_port, matrix_of, wxyz_of

__all__ = [
    "CAMERA_FOV",
    "CAMERA_LOOK_AT",
    "CAMERA_POSITION",
    "STRATEGIES",
    "WebView",
    "free_port",
    "main",
    "matrix_of",
    "wxyz_of",
]


def main(argv: list[str] | None = None) -> int:
    """`pickplace-view-web SCENE [--port N] [--plan PLAN.json] [--cache DIR] [--out DIR]
    [--package-dir DIR]…`:
    prints the page's URL on stdout and serves until interrupted; 2 on bad input."""
    parser = argparse.ArgumentParser(
        prog="pickplace-view-web",
        description="Serve the browser view of a scene: click the environment to place the object.",
    )
    parser.add_argument("scene", help="scene file (TOML)")
    parser.add_argument("--port", type=int, default=None, help="port (default: a free one)")
    parser.add_argument("--plan", default=None, help="only play this plan JSON (no planner)")
    parser.add_argument("--cache", default=None, help="cache folder (default: as pickplace)")
    parser.add_argument("--out", default="pickplace-web", help="default save folder")
    parser.add_argument(
        "--package-dir", action="append", default=[], dest="package_dirs",
        help="a folder searched for package:// paths (repeatable; ROS_PACKAGE_PATH after them)",
    )
    args = parser.parse_args(argv)
    try:
        view = WebView(
            args.scene, plan_path=args.plan, cache_dir=args.cache, out_dir=args.out, package_dirs=args.package_dirs
        )
        with contextlib.redirect_stdout(sys.stderr):  # viser's banner: stdout is the URL alone
            url = view.serve(args.port)
    except (pickplace.InputError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(url, flush=True)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        view.stop()
    return 0
