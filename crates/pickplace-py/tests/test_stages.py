"""clusters, placements and grasps return the documents of the CLI's --json."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pickplace


def cli_json(run_cli, *args):
    status, out, err = run_cli(*args, "--json")
    assert status == 0, err
    return json.loads(out)


def test_clusters_are_the_cli_document(run_cli, root, monkeypatch):
    monkeypatch.chdir(root)
    for mode in ("env", "finger"):
        doc = pickplace.clusters("meshes/can.stl", mode=mode)
        assert doc == cli_json(run_cli, "clusters", "meshes/can.stl", "--mode", mode), mode
    assert pickplace.clusters("meshes/can.stl", mode="finger")["pairs"]
    with pytest.raises(pickplace.InputError, match="h_max"):
        pickplace.clusters("meshes/can.stl", h_max=-1.0)
    with pytest.raises(pickplace.InputError, match="mode"):
        pickplace.clusters("meshes/can.stl", mode="sideways")
    with pytest.raises(pickplace.InputError, match="none.stl"):
        pickplace.clusters("meshes/none.stl")


def test_placements_are_the_cli_document(run_cli, root, monkeypatch):
    monkeypatch.chdir(root)
    resting = pickplace.placements("meshes/can.stl")
    assert resting == cli_json(run_cli, "placements", "meshes/can.stl")
    pose = np.eye(4)
    pose[:3, 3] = [0.4, 0.0, 0.0]
    on = pickplace.placements("meshes/box.stl", on="meshes/table.stl", env_pose=pose, max=5)
    expected = cli_json(
        run_cli, "placements", "meshes/box.stl", "--on", "meshes/table.stl",
        "--env-pose", "0.4,0,0", "--max", "5",
    )  # fmt: skip
    assert on == expected and on["placements"]
    with pytest.raises(pickplace.InputError, match="target"):
        pickplace.placements("meshes/can.stl", target=[0, 0, 0])


def test_grasps_are_the_cli_document(run_cli, root, monkeypatch):
    monkeypatch.chdir(root)
    doc = pickplace.grasps("meshes/can.stl", "robots/nx-hiro", grid_step=0.02, approaches=4)
    expected = cli_json(
        run_cli, "grasps", "meshes/can.stl", "--robot", "robots/nx-hiro",
        "--grid-step", "0.02", "--approaches", "4",
    )  # fmt: skip
    assert doc == expected and doc["grasps"]
    with pytest.raises(pickplace.InputError, match="meshes/gripper.toml"):
        pickplace.grasps("meshes/can.stl", "meshes")
