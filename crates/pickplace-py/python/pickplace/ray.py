"""Many scenes planned as Ray tasks: :func:`plan_many` is :func:`pickplace.batch.plan_many`
spread over a Ray cluster, one scene per task (docs/python.md, "Ray").

Ray is an optional extra (``pip install './crates/pickplace-py[ray]'``), imported only when
:func:`plan_many` is called. Each task plans one scene with the same Rust code as
``pickplace batch`` and writes its plan file itself, atomically, into ``out_dir``; the driver
gathers the summaries and writes ``out_dir/summary.jsonl`` in the order the scenes were
given. Plan files are byte for byte those of ``pickplace plan SCENE --no-timings`` and of
``pickplace batch`` with the same options.

On several machines, the scene files, their meshes and ``out_dir`` must be on storage every
node sees at the same path (NFS, a shared volume), and so should ``cache_dir`` (the cluster
databases and roadmaps, built once and then read by every task). Paths are made absolute on
the driver before they are sent.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Sequence
from typing import Any

from . import _pickplace
from .batch import SUMMARY_FILE, _Path

__all__ = ["plan_many"]


def _plan_one(
    scene: str, plan_path: str, display: str, threads: int, options: dict[str, Any]
) -> str:
    """The task: one scene planned into `plan_path` on `threads` threads (the CPUs Ray gave
    it); its summary line (JSON), the scene shown as `display`. `options` are the keywords of
    the batch's options, made here so that the default cache folder is this node's."""
    made = _pickplace._batch_options(**options)
    return _pickplace._batch_plan_one(scene, plan_path, made, display=display, threads=threads)


def plan_many(
    scenes: Sequence[_Path],
    out_dir: _Path,
    *,
    seed: int | None = None,
    strategy: str | None = None,
    time_budget: float | None = None,
    velocity_scaling: float | None = None,
    acceleration_scaling: float | None = None,
    sample_period: float | None = None,
    timings: bool = False,
    resume: bool = False,
    cache_dir: _Path | None = None,
    use_cache: bool = True,
    package_dirs: Sequence[_Path] = (),
    cpus_per_task: int = 1,
    progress: Callable[[dict[str, Any]], None] | None = None,
) -> list[dict[str, Any]]:
    """Plans `scenes` as Ray tasks, one scene per task, into `out_dir` (``NAME.json`` per
    scene and ``summary.jsonl``); returns the summaries, one dict per scene in the order
    given, as :func:`pickplace.batch.plan_many` does (same options, same files).

    Uses the Ray cluster this process is connected to (``ray.init(...)`` first, e.g.
    ``ray.init(address="auto")`` on a cluster's node), or starts a local one
    (``ray.init()``) when there is none. Each task asks Ray for `cpus_per_task` CPUs and
    plans on a thread pool of that many threads. The cache is `cache_dir` (put it on shared
    storage), else each node's default cache folder. ``progress(summary)`` is called on the
    driver as each task ends.

    Raises InputError (a ValueError) before any task runs for two scenes with the same file
    name, an option out of range, or an `out_dir` that cannot be written; one scene's bad
    input or failure is its summary's ``status``, never an exception.
    """
    try:
        import ray
    except ImportError as e:
        raise ImportError(
            "pickplace.ray needs Ray: pip install './crates/pickplace-py[ray]' (or: pip install ray)"
        ) from e
    if isinstance(cpus_per_task, bool) or not isinstance(cpus_per_task, int) or cpus_per_task < 1:
        raise _pickplace.InputError(
            f"cpus_per_task: {cpus_per_task!r} is not a number of CPUs (1 or more)"
        )
    given = [os.fspath(s) for s in scenes]
    absolute = [os.path.abspath(s) for s in given]
    out = os.path.abspath(os.fspath(out_dir))
    overrides: dict[str, Any] = {
        "seed": seed,
        "strategy": strategy,
        "time_budget": time_budget,
        "velocity_scaling": velocity_scaling,
        "acceleration_scaling": acceleration_scaling,
        "sample_period": sample_period,
    }
    # Names, options and the folder checked on the driver, before any task runs.
    checked = _pickplace._batch_options(**overrides)
    plan_paths = [os.fspath(p) for p in _pickplace._batch_prepare(absolute, out, checked)]
    options = dict(
        overrides,
        timings=timings,
        resume=resume,
        cache_dir=None if cache_dir is None else os.path.abspath(os.fspath(cache_dir)),
        use_cache=use_cache,
        package_dirs=[os.path.abspath(os.fspath(p)) for p in package_dirs],
    )
    if not ray.is_initialized():
        ray.init()
    task = ray.remote(_plan_one).options(num_cpus=cpus_per_task, max_retries=1)
    pending = {
        task.remote(scene, plan_path, shown, cpus_per_task, options): k
        for k, (scene, plan_path, shown) in enumerate(zip(absolute, plan_paths, given))
    }
    lines: list[str] = [""] * len(given)
    while pending:
        done, _ = ray.wait(list(pending), num_returns=1)
        for ref in done:
            k = pending.pop(ref)
            lines[k] = ray.get(ref)
            if progress is not None:
                progress(json.loads(lines[k]))
    _pickplace._batch_write_summary(os.path.join(out, SUMMARY_FILE), lines)
    return [json.loads(line) for line in lines]
