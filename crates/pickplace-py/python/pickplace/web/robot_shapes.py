"""The robot's shapes from its URDF, triangulated in each link's frame."""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .meshes import read_mesh


def _origin(el: ET.Element | None) -> np.ndarray:
    m = np.eye(4)
    if el is None:
        return m
    xyz = [float(v) for v in el.get("xyz", "0 0 0").split()]
    r, p, y = (float(v) for v in el.get("rpy", "0 0 0").split())
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    m[:3, :3] = [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
    m[:3, 3] = xyz
    return m


def resolve_package_path(filename: str, urdf_dir: Path, package_dirs: list[str]) -> Path | None:
    if filename.startswith("package://"):
        rest = filename[len("package://") :]
        dirs = list(package_dirs) + os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep)
        for d in filter(None, dirs):
            for candidate in (Path(d) / rest, Path(d) / rest.split("/", 1)[-1]):
                if candidate.is_file():
                    return candidate
        return None
    if filename.startswith("file://"):
        filename = filename[len("file://") :]
    path = urdf_dir / filename
    return path if path.is_file() else None


def _shape(geometry: ET.Element, urdf_dir: Path, package_dirs: list[str]):
    import trimesh

    for child in geometry:
        tag = child.tag
        if tag == "box":
            return trimesh.creation.box(extents=[float(v) for v in child.get("size", "0 0 0").split()])
        if tag == "cylinder":
            return trimesh.creation.cylinder(
                radius=float(child.get("radius", 0)), height=float(child.get("length", 0)), sections=24
            )
        if tag == "capsule":
            return trimesh.creation.capsule(
                radius=float(child.get("radius", 0)), height=float(child.get("length", 0)), count=[24, 12]
            )
        if tag == "sphere":
            return trimesh.creation.icosphere(subdivisions=2, radius=float(child.get("radius", 0)))
        if tag == "mesh":
            path = resolve_package_path(child.get("filename", ""), urdf_dir, package_dirs)
            if path is None:
                return None
            try:
                vertices, faces = read_mesh(path)
            except Exception:  # noqa: BLE001 - an unreadable visual is skipped, not fatal
                return None
            scale = [float(v) for v in child.get("scale", "1 1 1").split()]
            return trimesh.Trimesh(vertices * scale, faces, process=False)
    return None


@dataclass
class LinkShape:
    link: str
    vertices: np.ndarray
    faces: np.ndarray
    link_from_shape: np.ndarray
    color: tuple[int, int, int]


def robot_shapes(urdf: Path, package_dirs: list[str]) -> list[LinkShape]:
    """Every link's visual shapes (else its collision shapes), triangulated, in the link frame."""
    root = ET.parse(urdf).getroot()
    colors = {}
    for mat in root.findall("material"):
        c = mat.find("color")
        if c is not None:
            colors[mat.get("name")] = tuple(int(255 * float(v)) for v in c.get("rgba").split()[:3])
    shapes = []
    for link in root.findall("link"):
        loaded = []
        for tag in ("visual", "collision"):  # collision shapes when no visual can be read
            for el in link.findall(tag):
                geometry = el.find("geometry")
                mesh = None if geometry is None else _shape(geometry, urdf.parent, package_dirs)
                if mesh is not None and len(mesh.faces) > 0:
                    loaded.append((el, mesh))
            if loaded:
                break
        for el, mesh in loaded:
            color = (200, 200, 200)
            mat = el.find("material")
            if mat is not None:
                c = mat.find("color")
                if c is not None:
                    color = tuple(int(255 * float(v)) for v in c.get("rgba").split()[:3])
                else:
                    color = colors.get(mat.get("name"), color)
            shapes.append(
                LinkShape(
                    link.get("name"),
                    np.asarray(mesh.vertices, dtype=np.float64),
                    np.asarray(mesh.faces),
                    _origin(el.find("origin")),
                    color,
                )
            )
    return shapes
