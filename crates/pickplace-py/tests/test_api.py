"""The package's surface: every public name documented, stubs shipped, abi3 build."""

from __future__ import annotations

import inspect
from pathlib import Path

import pickplace


def test_every_public_name_has_a_docstring():
    missing = []
    for name in pickplace.__all__:
        obj = getattr(pickplace, name)
        if isinstance(obj, str):
            continue
        if not (obj.__doc__ or "").strip():
            missing.append(name)
        if inspect.isclass(obj) and not issubclass(obj, Exception):
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if not (getattr(member, "__doc__", None) or "").strip():
                    missing.append(f"{name}.{attr}")
    assert missing == []


def test_stubs_and_marker_are_in_the_package():
    folder = Path(pickplace.__file__).parent
    assert (folder / "_pickplace.pyi").is_file()
    assert (folder / "py.typed").is_file()


def test_the_stubs_spell_the_strategies_as_rust_does():
    import ast

    stub = Path(pickplace.__file__).with_name("_pickplace.pyi")
    literal = next(
        node.value
        for node in ast.parse(stub.read_text()).body
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") == "_Strategy"
    )
    names = tuple(elt.value for elt in literal.slice.elts)
    assert names == pickplace.STRATEGIES
    assert pickplace.STRATEGIES[0] == "auto" and len(pickplace.STRATEGIES) == 9


def test_exceptions():
    assert issubclass(pickplace.InputError, ValueError)
    assert issubclass(pickplace.NoPlanError, Exception)
    assert not issubclass(pickplace.NoPlanError, ValueError)
    assert pickplace.__version__


def test_the_demo_script_plans_and_plots_or_says_why_not(root, cache_dir, tmp_path):
    import importlib.util
    import os
    import subprocess
    import sys

    out = tmp_path / "demo.png"
    done = subprocess.run(
        [sys.executable, root / "docs/examples/plan_demo.py", "--out", out],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PICKPLACE_CACHE": str(cache_dir)},
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "fig9-near.toml: right-right" in done.stdout and "validation passed" in done.stdout
    if importlib.util.find_spec("matplotlib") is None:
        assert "matplotlib is not installed" in done.stdout
    else:
        assert out.read_bytes().startswith(b"\x89PNG")
