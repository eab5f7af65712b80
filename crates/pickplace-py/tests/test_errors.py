"""Errors: bad input raises InputError (a ValueError) with the CLI's message; a scene with no
solution raises NoPlanError with its reasons."""

from __future__ import annotations

import pytest

import pickplace

from conftest import cli_error


def test_a_missing_scene_file_has_the_cli_message(run_cli, tmp_path):
    missing = tmp_path / "nope.toml"
    with pytest.raises(pickplace.InputError) as caught:
        pickplace.Scene.load(missing, use_cache=False)
    assert isinstance(caught.value, ValueError)
    status, _, stderr = run_cli("plan", missing, "--no-cache")
    assert status == 2
    assert str(caught.value) == cli_error(stderr)
    assert "nope.toml" in str(caught.value)


def test_bad_toml_has_the_cli_message(run_cli, root, tmp_path):
    bad = tmp_path / "bad.toml"
    text = (root / "scenes/fig9-near.toml").read_text().replace("[target]", "[target", 1)
    bad.write_text(text)
    with pytest.raises(pickplace.InputError) as caught:
        pickplace.Scene.load(bad, use_cache=False)
    status, _, stderr = run_cli("plan", bad, "--no-cache")
    assert status == 2
    assert str(caught.value) == cli_error(stderr)
    with pytest.raises(pickplace.InputError, match="<scene>"):
        pickplace.Scene.from_toml(text, root / "scenes", use_cache=False)


def test_a_wrong_value_names_the_field(root):
    text = (root / "scenes/fig9-near.toml").read_text()
    with pytest.raises(pickplace.InputError, match="unknown field"):
        pickplace.Scene.from_toml(text + "\n[planner2]\nx = 1\n", root / "scenes")
    with pytest.raises(pickplace.InputError, match="None is not allowed"):
        pickplace.Scene.from_dict({"object": None}, root / "scenes")


def test_bad_plan_options(near):
    with pytest.raises(pickplace.InputError, match="strategy \"sideways\" is not one of auto"):
        pickplace.plan(near, strategy="sideways")
    with pytest.raises(pickplace.InputError, match="velocity_scaling"):
        pickplace.plan(near, velocity_scaling=1.5)
    with pytest.raises(pickplace.InputError, match=r"sample_period: 5 is not in \[0.001, 1\] s"):
        pickplace.plan(near, sample_period=5.0)
    with pytest.raises(pickplace.InputError, match="time_budget"):
        pickplace.plan(near, time_budget=-1.0)
    # Issue 33: a budget no duration holds was a panic in the planner.
    with pytest.raises(pickplace.InputError, match=r"time_budget: 1e300 is not in \[0, 604800\] s"):
        pickplace.plan(near, time_budget=1e300)
    with pytest.raises(pickplace.InputError, match="velocity_scaling: 1e-300 is not in"):
        pickplace.plan(near, velocity_scaling=1e-300)
    with pytest.raises(pickplace.InputError, match="missing field `format`"):
        pickplace.Plan.from_json("{}")


def test_no_plan_carries_reasons_per_strategy_and_stage(root, cache_dir, run_cli):
    scene = pickplace.Scene.load(root / "scenes/suite/target-out-of-reach.toml", cache_dir=cache_dir)
    with pytest.raises(pickplace.NoPlanError) as caught:
        pickplace.plan(scene)
    e = caught.value
    assert e.reasons and all(isinstance(r, str) for r in e.reasons)
    assert e.stats is not None and e.stats["strategies"]
    stages = e.stats["strategies"][0]["stages"]
    assert any(s["rejected"] for s in stages.values()), stages
    status, _, stderr = run_cli(
        "plan", "scenes/suite/target-out-of-reach.toml", "--cache", cache_dir
    )
    assert status == 1
    for reason in e.reasons:
        assert reason in stderr


def test_an_infeasible_start_is_no_plan_with_the_cli_message(root, cache_dir, run_cli):
    with pytest.raises(pickplace.NoPlanError) as caught:
        scene = pickplace.Scene.load(
            root / "scenes/suite/start-in-collision.toml", cache_dir=cache_dir
        )
        pickplace.plan(scene)
    status, _, stderr = run_cli("plan", "scenes/suite/start-in-collision.toml", "--cache", cache_dir)
    assert status == 1
    assert caught.value.reasons == [cli_error(stderr)]
    assert caught.value.stats is None


def test_tool_numbers_out_of_range_name_the_keyword(root):
    can = root / "meshes/can.stl"
    robot = root / "robots/nx-hiro"
    with pytest.raises(pickplace.InputError, match="grid_step: 1e-300 is not in"):
        pickplace.grasps(can, robot, grid_step=1e-300)
    with pytest.raises(pickplace.InputError, match="approaches: 1e9 is not in"):
        pickplace.grasps(can, robot, approaches=10**9)
    with pytest.raises(pickplace.InputError, match="scale: 1e300 is not in"):
        pickplace.clusters(can, scale=1e300)
    with pytest.raises(pickplace.InputError, match="h_max: 1e-300 is not in"):
        pickplace.clusters(can, h_max=1e-300)
