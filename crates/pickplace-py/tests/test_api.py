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


def test_exceptions():
    assert issubclass(pickplace.InputError, ValueError)
    assert issubclass(pickplace.NoPlanError, Exception)
    assert not issubclass(pickplace.NoPlanError, ValueError)
    assert pickplace.__version__
