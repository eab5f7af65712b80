"""pickplace: pick-and-place planning for dual-arm robots (Harada et al., "Pick and Place
Planning for Dual-Arm Manipulators"), from Python.

The classes and functions mirror the Rust façade (crate ``pickplace``) and the ``pickplace``
command; the API is described in docs/python.md::

    import pickplace
    scene = pickplace.Scene.load("scenes/fig9-near.toml")
    plan = pickplace.plan(scene, seed=1)
    print(plan.strategy, plan.positions.shape)          # e.g. right-right (N, J)
    assert pickplace.validate(scene, plan).ok

Bad input raises :class:`InputError` (a ``ValueError``) with the message the CLI prints; a
scene with no solution raises :class:`NoPlanError` with ``reasons`` and ``stats``. Planning and
validation release the GIL, and every object is immutable and safe to share between threads.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from . import batch
from ._pickplace import (
    PLAN_FORMAT,
    STRATEGIES,
    IkSolution,
    InputError,
    Motion,
    MotionWorld,
    NoPlanError,
    Plan,
    Playback,
    Robot,
    Scene,
    SceneView,
    ValidationReport,
    __version__,
    clusters,
    grasps,
    placements,
    plan,
    plan_motion,
    validate,
)

__all__ = [
    "PLAN_FORMAT",
    "STRATEGIES",
    "IkSolution",
    "InputError",
    "Motion",
    "MotionWorld",
    "NoPlanError",
    "Plan",
    "Playback",
    "Robot",
    "Scene",
    "SceneView",
    "ValidationReport",
    "__version__",
    "batch",
    "clusters",
    "grasps",
    "placements",
    "plan",
    "plan_motion",
    "pose_matrix",
    "pose_parts",
    "validate",
]


def pose_matrix(
    position: Sequence[float] | npt.ArrayLike,
    orientation: Sequence[float] | npt.ArrayLike = (0.0, 0.0, 0.0, 1.0),
) -> npt.NDArray[np.float64]:
    """The 4x4 homogeneous matrix of a pose given as in the plan and scene files:
    ``position`` [x, y, z] (m) and ``orientation`` as a quaternion [x, y, z, w] (ROS order;
    normalised here). Accepts a pose dict of a plan too: ``pose_matrix(**d)``."""
    p = np.asarray(position, dtype=np.float64).reshape(3)
    q = np.asarray(orientation, dtype=np.float64).reshape(4)
    norm = float(np.linalg.norm(q))
    if not np.isfinite(norm) or norm == 0.0 or not np.all(np.isfinite(p)):
        raise InputError(f"pose: position {p.tolist()} / orientation {q.tolist()} is not a pose")
    x, y, z, w = q / norm
    m = np.eye(4)
    m[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    m[:3, 3] = p
    return m


def pose_parts(matrix: npt.ArrayLike) -> dict[str, list[float]]:
    """The ``{"position": [x, y, z], "orientation": [x, y, z, w]}`` dict of a 4x4
    homogeneous matrix (the inverse of :func:`pose_matrix`; ``w >= 0``)."""
    m = np.asarray(matrix, dtype=np.float64).reshape(4, 4)
    r = m[:3, :3]
    t = float(np.trace(r))
    # Shepperd's method: the largest of w, x, y, z first, for accuracy.
    if t > max(r[0, 0], r[1, 1], r[2, 2]):
        s = 2.0 * np.sqrt(1.0 + t)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
    elif r[0, 0] >= r[1, 1] and r[0, 0] >= r[2, 2]:
        s = 2.0 * np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = [s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s]
    elif r[1, 1] >= r[2, 2]:
        s = 2.0 * np.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = [(r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = [(r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4, (r[1, 0] - r[0, 1]) / s]
    qa = np.asarray(q)
    if qa[3] < 0:
        qa = -qa
    return {"position": m[:3, 3].tolist(), "orientation": qa.tolist()}
