"""`pickplace.batch.plan_many`: the CLI's `pickplace batch` from Python."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import pickplace
from conftest import SHIPPED, cli_error


def test_plans_are_the_cli_plans_and_the_summary_is_in_order(root, cache_dir, cli_plans, tmp_path):
    scenes = [root / "scenes" / f"{s}.toml" for s in reversed(SHIPPED)]
    seen = []
    summaries = pickplace.batch.plan_many(
        scenes, tmp_path, workers=2, cache_dir=cache_dir, progress=seen.append
    )
    assert [s["scene"] for s in summaries] == [str(p) for p in scenes]
    assert sorted(s["scene"] for s in seen) == sorted(str(p) for p in scenes)
    for name, s in zip(reversed(SHIPPED), summaries):
        assert s["status"] == "planned", s
        assert s["time"] is None and s["reasons"] == [] and s["error"] is None
        assert Path(s["plan"]) == tmp_path / f"{name}.json"
        assert (tmp_path / f"{name}.json").read_bytes() == cli_plans[name], name
        assert s["duration"] == pytest.approx(json.loads(cli_plans[name])["stats"]["duration"])
    lines = (tmp_path / "summary.jsonl").read_text().splitlines()
    assert [json.loads(line) for line in lines] == summaries


def test_resume_keeps_valid_plans_and_replans_broken_ones(root, cache_dir, cli_plans, tmp_path):
    scenes = [root / "scenes/fig9-near.toml", root / "scenes/fig10b-mug.toml"]
    pickplace.batch.plan_many(scenes, tmp_path, workers=1, cache_dir=cache_dir)
    (tmp_path / "fig10b-mug.json").write_text("{ not a plan")
    again = pickplace.batch.plan_many(scenes, tmp_path, workers=2, cache_dir=cache_dir, resume=True)
    assert [s["status"] for s in again] == ["skipped", "planned"]
    assert again[1]["replanned"], again[1]
    assert (tmp_path / "fig10b-mug.json").read_bytes() == cli_plans["fig10b-mug"]


def test_a_bad_scene_is_its_line_with_the_cli_message(root, cache_dir, run_cli, tmp_path):
    bad = tmp_path / "scenes" / "broken.toml"
    bad.parent.mkdir()
    bad.write_text("format = 1\n[robot\n")
    status, _, stderr = run_cli("plan", bad, "--no-timings")
    assert status == 2
    out = tmp_path / "out"
    summaries = pickplace.batch.plan_many(
        [bad, root / "scenes/fig9-near.toml"], out, cache_dir=cache_dir
    )
    assert [s["status"] for s in summaries] == ["bad-input", "planned"]
    assert summaries[0]["error"] == cli_error(stderr)
    assert not (out / "broken.json").exists()


def test_what_stops_a_whole_batch_is_an_input_error(root, tmp_path):
    near = root / "scenes/fig9-near.toml"
    other = tmp_path / "FIG9-NEAR.toml"
    other.write_bytes(near.read_bytes())
    with pytest.raises(pickplace.InputError, match="distinct file names"):
        pickplace.batch.plan_many([near, other], tmp_path / "out")
    with pytest.raises(pickplace.InputError, match="jobs"):
        pickplace.batch.plan_many([near], tmp_path / "out", workers=0)
    with pytest.raises(pickplace.InputError, match="strategy"):
        pickplace.batch.plan_many([near], tmp_path / "out", strategy="both-hands")
    (tmp_path / "file").write_text("")
    with pytest.raises(pickplace.InputError, match="not a folder"):
        pickplace.batch.plan_many([near], tmp_path / "file")
