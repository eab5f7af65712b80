"""Meshes for the page: files read in triangle order, poses as viser wants them, and the
click's ray against triangles."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

import pickplace


def read_mesh(path: str | os.PathLike[str], scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (3T, 3) float64, faces (T, 3) int) of a mesh file, triangles in file order
    (the order `pickplace.clusters` numbers them in). STL (binary or ASCII) is read here; other
    formats through trimesh (a dependency of viser), unprocessed."""
    path = Path(path)
    data = path.read_bytes()
    if path.suffix.lower() == ".stl":
        tris = _stl_triangles(data)
    else:
        import trimesh

        mesh = trimesh.load(path, force="mesh", process=False)
        tris = np.asarray(mesh.vertices, dtype=np.float64)[np.asarray(mesh.faces)]
    vertices = tris.reshape(-1, 3) * scale
    faces = np.arange(len(vertices)).reshape(-1, 3)
    return vertices, faces


def _stl_triangles(data: bytes) -> np.ndarray:
    if len(data) >= 84:
        count = int(np.frombuffer(data, dtype="<u4", count=1, offset=80)[0])
        if 84 + 50 * count == len(data):
            rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
            return np.frombuffer(data, dtype=rec, count=count, offset=84)["v"].astype(np.float64)
    text = data.decode("ascii", errors="replace").split()
    values = [float(text[i + 1 : i + 4][k]) for i, w in enumerate(text) if w == "vertex" for k in range(3)]
    return np.asarray(values, dtype=np.float64).reshape(-1, 3, 3)


def transform_points(m: np.ndarray, points: np.ndarray) -> np.ndarray:
    return points @ m[:3, :3].T + m[:3, 3]


def wxyz_of(m: np.ndarray) -> np.ndarray:
    x, y, z, w = pickplace.pose_parts(m)["orientation"]
    return np.array([w, x, y, z])


def matrix_of(position: Any, wxyz: Any) -> np.ndarray:
    w, x, y, z = (float(v) for v in wxyz)
    return pickplace.pose_matrix(position, [x, y, z, w])


def ray_triangles(origin: np.ndarray, direction: np.ndarray, tris: np.ndarray) -> tuple[int, float]:
    """Möller–Trumbore on every triangle (T, 3, 3): (index of the nearest hit, distance along
    the ray), or (-1, inf). Both faces count."""
    d = np.asarray(direction, dtype=np.float64)
    d = d / np.linalg.norm(d)
    v0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - v0
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
    if not hit.any():
        return -1, math.inf
    t = np.where(hit, t, np.inf)
    i = int(np.argmin(t))
    return i, float(t[i])
