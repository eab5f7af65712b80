"""Fixtures of the bindings' tests: the repository's root, a cache folder shared with the
Rust tests, the `pickplace` binary to compare against, and the demo scene planned once."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

import pickplace

ROOT = Path(__file__).resolve().parents[3]


def _cli() -> Path | None:
    """`$PICKPLACE_CLI`, else the release binary, else the debug one."""
    given = os.environ.get("PICKPLACE_CLI")
    if given:
        return Path(given)
    for profile in ("release", "debug"):
        path = ROOT / "target" / profile / "pickplace"
        if path.is_file():
            return path
    return None


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def cache_dir() -> Path:
    """`$PICKPLACE_TEST_CACHE`, else `target/pickplace-cache` (the façade's doctest uses it)."""
    return Path(os.environ.get("PICKPLACE_TEST_CACHE", ROOT / "target" / "pickplace-cache"))


@pytest.fixture(scope="session")
def cli() -> Path:
    path = _cli()
    if path is None or not path.is_file():
        pytest.fail(
            "no pickplace binary: build it (cargo build -p pickplace-cli) or set PICKPLACE_CLI"
        )
    return path


@pytest.fixture(scope="session")
def run_cli(cli: Path):
    """Runs the CLI from the repository's root: (exit status, stdout, stderr)."""

    def run(*args: str | os.PathLike[str]) -> tuple[int, str, str]:
        done = subprocess.run(
            [str(cli), *map(str, args)],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=300,
            check=False,
        )
        return done.returncode, done.stdout, done.stderr

    return run


@pytest.fixture(scope="session")
def near(cache_dir: Path) -> pickplace.Scene:
    """The demo scene (the paper's Fig. 9, can near the right hand)."""
    return pickplace.Scene.load(ROOT / "scenes/fig9-near.toml", cache_dir=cache_dir)


@pytest.fixture(scope="session")
def near_plan(near: pickplace.Scene) -> pickplace.Plan:
    return pickplace.plan(near)


def cli_error(stderr: str) -> str:
    """The message of the CLI's `error: …` line."""
    lines = [line for line in stderr.splitlines() if line.startswith("error: ")]
    assert lines, stderr
    return lines[-1].removeprefix("error: ")


@pytest.fixture(scope="session")
def cli_plans(run_cli, cache_dir: Path, tmp_path_factory) -> dict[str, bytes]:
    """The shipped scenes planned by `pickplace plan --no-timings`: name -> plan bytes."""
    out = tmp_path_factory.mktemp("cli-plans")
    plans = {}
    for scene in SHIPPED:
        path = out / f"{scene}.json"
        status, _, stderr = run_cli(
            "plan", f"scenes/{scene}.toml", "--no-timings", "--cache", cache_dir, "--out", path
        )
        assert status == 0, stderr
        plans[scene] = path.read_bytes()
    return plans


#: The scenes shipped in `scenes/`.
SHIPPED = ["fig9-near", "fig9-far-left", "fig10a-edge", "fig10b-mug"]
