"""`pickplace.ray.plan_many` on a real local Ray cluster started by the test: the shipped
scenes planned as Ray tasks give the CLI's plan files, byte for byte."""

from __future__ import annotations

import os

import pytest

import pickplace
from conftest import SHIPPED

if os.environ.get("PICKPLACE_REQUIRE_RAY") == "1":
    import ray  # `cargo xtask test` installs Ray: missing, the test fails
else:
    ray = pytest.importorskip("ray")

import pickplace.ray as pickplace_ray


@pytest.fixture(scope="module")
def cluster():
    """A local Ray cluster of 2 CPUs, for this module's tests."""
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    try:
        yield ray
    finally:
        ray.shutdown()


def test_ray_tasks_write_the_cli_plans(cluster, root, cache_dir, cli_plans, tmp_path):
    assert ray.cluster_resources().get("CPU") == 2
    scenes = [root / "scenes" / f"{s}.toml" for s in SHIPPED]
    ended = []
    summaries = pickplace_ray.plan_many(
        scenes, tmp_path, cache_dir=cache_dir, cpus_per_task=1, progress=ended.append
    )
    assert len(ended) == len(SHIPPED)
    assert [s["scene"] for s in summaries] == [str(p) for p in scenes]
    for name, s in zip(SHIPPED, summaries):
        assert s["status"] == "planned", s
        assert (tmp_path / f"{name}.json").read_bytes() == cli_plans[name], name
    # The same summary as the batch on this machine writes.
    local = tmp_path / "local"
    pickplace.batch.plan_many(scenes, local, workers=2, cache_dir=cache_dir)
    ray_lines = (tmp_path / "summary.jsonl").read_text().splitlines()
    local_lines = (local / "summary.jsonl").read_text().splitlines()
    strip = lambda line: line.replace(str(local), "OUT").replace(str(tmp_path), "OUT")  # noqa: E731
    assert [strip(x) for x in ray_lines] == [strip(x) for x in local_lines]


def test_resume_through_ray_skips_what_is_done(cluster, root, cache_dir, tmp_path):
    scenes = [root / "scenes/fig9-near.toml", root / "scenes/fig10b-mug.toml"]
    first = pickplace_ray.plan_many(scenes, tmp_path, cache_dir=cache_dir)
    assert [s["status"] for s in first] == ["planned", "planned"]
    again = pickplace_ray.plan_many(scenes, tmp_path, cache_dir=cache_dir, resume=True, cpus_per_task=2)
    assert [s["status"] for s in again] == ["skipped", "skipped"]


def test_bad_options_stop_before_any_task(cluster, root, tmp_path):
    near = root / "scenes/fig9-near.toml"
    with pytest.raises(pickplace.InputError, match="cpus_per_task"):
        pickplace_ray.plan_many([near], tmp_path, cpus_per_task=0)
    with pytest.raises(pickplace.InputError, match="distinct file names"):
        pickplace_ray.plan_many([near, near], tmp_path)
    assert not (tmp_path / "fig9-near.json").exists()
