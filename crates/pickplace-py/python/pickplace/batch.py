"""Many scenes planned in parallel on this machine: :func:`plan_many` is ``pickplace batch``
(docs/batch.md) from Python, with the same Rust code, files and summary.

Each scene's plan goes to ``out_dir/NAME.json`` (``NAME`` the scene file's stem), written
atomically, byte for byte what ``pickplace plan SCENE --no-timings`` writes with the same
options; ``out_dir/summary.jsonl`` gets one JSON object per scene, in the order given
(``scene, status, plan, strategy, seed, duration, time, reasons, error, replanned,
warnings``; ``status`` is ``planned``, ``no-plan``, ``bad-input``, ``skipped`` or ``error``).
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Sequence
from typing import Any, Union

from . import _pickplace

__all__ = ["SUMMARY_FILE", "plan_many"]

#: The summary's file name in the output folder.
SUMMARY_FILE = "summary.jsonl"

_Path = Union[str, "os.PathLike[str]"]


def plan_many(
    scenes: Sequence[_Path],
    out_dir: _Path,
    *,
    workers: int | None = None,
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
    progress: Callable[[dict[str, Any]], None] | None = None,
) -> list[dict[str, Any]]:
    """Plans `scenes` into `out_dir` on `workers` threads (default: the machine's cores), as
    ``pickplace batch SCENE… --out OUT_DIR`` does; returns the summaries, one dict per scene
    in the order given (the lines of ``summary.jsonl``).

    Options left at None are each scene's own (``planner.seed``, ``planner.strategy``, …).
    ``timings=False`` (the default, unlike the CLI) leaves wall-clock times out, so the plan
    files and the summary are the same bytes on every run. ``resume=True`` keeps a plan
    already in `out_dir` that reads, was made with the same options and validates. The cache
    is ``cache_dir``, else the default one (``$PICKPLACE_CACHE``, …); ``use_cache=False``
    builds everything in memory. ``progress(summary)`` is called as each scene ends.

    The GIL is released while planning. Raises InputError (a ValueError) for what stops the
    whole batch: two scenes with the same file name, an option out of range, an `out_dir`
    that cannot be written. One scene's bad input or failure is its summary's ``status``.
    """
    callback = None
    if progress is not None:
        user = progress

        def callback(line: str) -> None:
            user(json.loads(line))

    paths = [os.fspath(s) for s in scenes]
    folder = os.fspath(out_dir)
    options = _pickplace._batch_options(
        seed=seed,
        strategy=strategy,
        time_budget=time_budget,
        velocity_scaling=velocity_scaling,
        acceleration_scaling=acceleration_scaling,
        sample_period=sample_period,
        timings=timings,
        resume=resume,
        cache_dir=None if cache_dir is None else os.fspath(cache_dir),
        use_cache=use_cache,
        package_dirs=[os.fspath(p) for p in package_dirs],
    )
    lines = _pickplace._batch_plan_many(paths, folder, options, workers=workers, progress=callback)
    return [json.loads(line) for line in lines]
