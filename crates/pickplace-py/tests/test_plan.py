"""Planning from Python: numpy arrays, round trips, validation, byte-identical plans with the
CLI, threads."""

from __future__ import annotations

import json
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import pickplace


def test_plan_arrays_have_the_documented_shapes_and_dtypes(near, near_plan):
    p = near_plan
    n, j = len(p.times), len(p.joint_names)
    assert p.joint_names == near.joint_names and j == 17
    assert p.times.shape == (n,) and p.times.dtype == np.float64 and n > 10
    assert p.positions.shape == (n, j) and p.positions.dtype == np.float64
    assert p.velocities is not None and p.velocities.shape == (n, j)
    assert p.accelerations is not None and p.accelerations.shape == (n, j)
    assert p.velocities.dtype == np.float64 and p.accelerations.dtype == np.float64
    assert p.times[0] == 0.0 and np.all(np.diff(p.times) > 0)
    assert p.duration == p.times[-1]
    np.testing.assert_array_equal(p.positions[0], near.start)
    # Arrays are copies: changing one changes nothing in the plan.
    p.positions[0, 0] = 99.0
    assert p.positions[0, 0] != 99.0


def test_plan_parts_are_the_json_document(near_plan):
    p = near_plan
    doc = json.loads(p.to_json())
    assert p.to_dict() == doc
    assert p.format == pickplace.PLAN_FORMAT == doc["format"]
    assert p.strategy == doc["strategy"] == "right-right"
    for field in ("events", "grasps", "placement", "key_poses", "object", "arms", "stats"):
        assert getattr(p, field) == doc[field], field
    assert [e["kind"] for e in p.events] == ["grasp", "release"]
    assert p.stats["strategies"][0]["success"] is True
    # Planned without timings by default: the same seed, the same bytes.
    assert "timings" not in p.stats or p.stats["timings"] == {}


def test_round_trip_through_json_and_files(near_plan, tmp_path):
    p = near_plan
    again = pickplace.Plan.from_json(p.to_json())
    assert again == p and again.to_json() == p.to_json()
    path = tmp_path / "plan.json"
    path.write_text(p.to_json())
    assert pickplace.Plan.load(path) == p
    with pytest.raises(pickplace.InputError, match="plan.json"):
        path.write_text(p.to_json()[:-20])
        pickplace.Plan.load(path)


def test_validate_passes_the_plan_and_reports_a_broken_one(near, near_plan):
    report = pickplace.validate(near, near_plan)
    assert report.ok and bool(report) and report.problems == []
    assert report.states_checked > 100
    assert report.to_dict()["format"] == "pickplace.validation/1"
    doc = near_plan.to_dict()
    # The first samples jump: LARM_JOINT2 moves 0.8 rad between two samples 40 ms apart,
    # beyond its velocity limit.
    column = doc["joint_names"].index("LARM_JOINT2")
    for point in doc["trajectory"][:3]:
        point["positions"][column] += 0.8
    broken = pickplace.Plan.from_json(json.dumps(doc))
    report = pickplace.validate(near, broken)
    assert not report.ok and report.problems
    assert any("LARM_JOINT2" in p for p in report.problems), report.problems


def test_plan_is_byte_identical_to_the_cli(near, near_plan, run_cli, cache_dir, tmp_path):
    out = tmp_path / "cli.json"
    status, _, stderr = run_cli(
        "plan", "scenes/fig9-near.toml", "--no-timings", "--cache", cache_dir, "--out", out
    )
    assert status == 0, stderr
    assert near_plan.to_json() == out.read_text()
    # Another seed and strategy, the same way.
    out2 = tmp_path / "cli2.json"
    status, _, stderr = run_cli(
        "plan", "scenes/fig9-near.toml", "--no-timings", "--cache", cache_dir,
        "--seed", "7", "--strategy", "left-right", "--out", out2,
    )  # fmt: skip
    p2 = pickplace.plan(near, seed=7, strategy="left-right")
    assert status == 0, stderr
    assert p2.to_json() == out2.read_text()
    assert p2.seed == 7 and p2.strategy == "left-right"


def test_timings_are_recorded_when_asked(near):
    p = pickplace.plan(near, timings=True)
    assert p.stats["timings"]["total"] > 0


def test_two_threads_plan_the_same_scene_to_the_same_bytes(near, near_plan):
    with ThreadPoolExecutor(max_workers=2) as pool:
        plans = list(pool.map(lambda _: pickplace.plan(near).to_json(), range(2)))
    assert plans == [near_plan.to_json()] * 2


def test_planning_releases_the_gil(near):
    """A Python thread keeps running while another plans (with the GIL held it could not
    tick at all during the call)."""
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.0005)

    counter = threading.Thread(target=count)
    counter.start()
    time.sleep(0.01)
    before = ticks
    plan = pickplace.plan(near, strategy="left-right", time_budget=5.0)
    during = ticks - before
    done.set()
    counter.join()
    assert plan.strategy == "left-right"
    assert during >= 5, during


def test_scene_from_dict_and_toml_plans_as_the_file(near, near_plan, root: Path, cache_dir):
    tomllib = pytest.importorskip("tomllib")
    text = (root / "scenes/fig9-near.toml").read_text()
    base = root / "scenes"
    from_toml = pickplace.Scene.from_toml(text, base, cache_dir=cache_dir)
    from_dict = pickplace.Scene.from_dict(tomllib.loads(text), base, cache_dir=cache_dir)
    assert pickplace.plan(from_toml).to_json() == near_plan.to_json()
    assert pickplace.plan(from_dict).to_json() == near_plan.to_json()
    assert str(from_dict.path) == "<dict>"
    np.testing.assert_array_equal(from_dict.target, near.target)


def test_scene_properties(near, root):
    assert near.path == root / "scenes/fig9-near.toml"
    assert near.start.shape == (17,) and near.target.shape == (3,)
    assert near.object_start.shape == (4, 4)
    assert near.environment and near.seed == 1 and near.time_budget > 0
    assert near.to_dict()["object"]["mesh"].endswith("can.stl")
    assert near.log and "Scene(" in repr(near)
