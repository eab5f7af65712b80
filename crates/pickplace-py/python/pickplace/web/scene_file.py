"""The scene the page plans, as a dict and as a scene file (TOML) to save."""

from __future__ import annotations

import math
import os
import stat
import tempfile
from pathlib import Path
from typing import Any


def write_atomic(path: Path, text: str) -> None:
    """Writes `text` to `path` as the CLI writes its outputs: into an exclusive temporary
    file beside it (an unpredictable name, never through a symlink), then renamed over
    `path`; a `path` that is a symlink, a folder or not a regular file is refused with
    ValueError, and a failure leaves `path` as it was."""
    try:
        kind = os.lstat(path).st_mode
    except FileNotFoundError:
        kind = None
    if kind is not None and not stat.S_ISREG(kind):
        what = "a symbolic link" if stat.S_ISLNK(kind) else "not a regular file"
        raise ValueError(f"{path}: is {what}; the page writes regular files only")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def absolute_paths(d: Any, keys=("urdf", "srdf", "gripper", "joint_limits", "mesh")) -> Any:
    if isinstance(d, dict):
        out = {}
        for k, v in d.items():
            if v is None:
                continue
            if k in keys and isinstance(v, str) and not v.startswith("package://"):
                v = str(Path(v).resolve())
            elif k == "package_dirs" and isinstance(v, list):
                v = [str(Path(p).resolve()) for p in v]
            else:
                v = absolute_paths(v, keys)
            out[k] = v
        return out
    if isinstance(d, list):
        return [absolute_paths(v, keys) for v in d]
    return d


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"no TOML for {v!r}")


def _toml_key(k: str) -> str:
    return k if k.replace("_", "").replace("-", "").isalnum() else _toml_value(k)


def scene_toml(d: dict[str, Any]) -> str:
    """A scene dict (`Scene.to_dict()`'s shape, paths absolute, no None) as scene-file TOML."""
    d = dict(d)
    robots = d.pop("robots", None)
    lines = ["# Written by pickplace-view-web", f"format = {_toml_value(d.pop('format', 1))}"]
    tables: list[tuple[str, dict[str, Any], bool]] = []
    if robots is not None:
        if len(robots) == 1 and not robots[0].get("prefix"):
            r = {k: v for k, v in robots[0].items() if k != "prefix"}
            tables.append(("robot", r, False))
        else:
            tables.extend(("robots", r, True) for r in robots)
    for k, v in d.items():
        if isinstance(v, dict):
            tables.append((k, v, False))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            tables.extend((k, x, True) for x in v)
        else:
            lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
    for name, table, array in tables:
        lines.append("")
        lines.append(f"[[{name}]]" if array else f"[{name}]")
        for k, v in table.items():
            if v == {} and k != "start_state":
                continue
            lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
    return "\n".join(lines) + "\n"
