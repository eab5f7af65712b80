"""The browser view (`pickplace.web`, issue 21) in a real headless browser: Debian's Chromium
driven by Playwright for Python (no browser download). The server runs in this process; the
page is clicked where the 3-D points project with the camera the browser reports (the one the
server set). Screenshots go to target/web-screenshots/ for a person to look at.

Skipped when viser, Playwright or Chromium is missing, unless PICKPLACE_REQUIRE_WEB=1 (then
they fail). PICKPLACE_CHROMIUM names the browser (default: chromium on PATH)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest

import pickplace

REQUIRED = os.environ.get("PICKPLACE_REQUIRE_WEB") == "1"
if REQUIRED:
    import playwright.sync_api as pw
    import viser  # noqa: F401
else:
    pytest.importorskip("viser")
    pw = pytest.importorskip("playwright.sync_api")

from pickplace import web  # noqa: E402

CHROMIUM = os.environ.get("PICKPLACE_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
if not Path(CHROMIUM).is_file():
    if REQUIRED:
        raise RuntimeError(f"no Chromium at {CHROMIUM} (set PICKPLACE_CHROMIUM)")
    pytest.skip(f"no Chromium at {CHROMIUM}", allow_module_level=True)

#: Chromium's flags for WebGL without a GPU (SwiftShader through ANGLE).
CHROMIUM_ARGS = [
    "--headless=new",
    "--no-sandbox",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--ignore-gpu-blocklist",
]
VIEWPORT = {"width": 1280, "height": 800}

#: The large dent of the pallet in scenes/fig9-near.toml (the scene's own target), world frame.
DENT = np.array([0.40, -0.20, 0.745])
#: A point on the table top at its far corner, out of both arms' reach.
OUT_OF_REACH = np.array([0.80, 0.38, 0.72])
#: A point of the robot's chest box (NX-HIRO's CHEST_JOINT0_Link visual, base at z 0.92).
CHEST = np.array([-0.05, 0.0, 0.92 + 0.39])


@pytest.fixture(scope="module")
def shots(root: Path) -> Path:
    out = root / "target" / "web-screenshots"
    out.mkdir(parents=True, exist_ok=True)
    return out


@pytest.fixture(scope="module")
def browser():
    with pw.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            yield b
        finally:
            b.close()


def wait_for(predicate, timeout: float, what: str):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def open_page(browser, view: web.WebView, url: str):
    """A page on `url` whose client has connected and reported its camera."""
    page = browser.new_page(viewport=VIEWPORT)
    page.goto(url)
    page.wait_for_selector("canvas", timeout=30_000)
    clients = wait_for(lambda: list(view.server.get_clients().values()), 30, "the client")
    camera = clients[-1].camera
    wait_for(lambda: camera.image_width == VIEWPORT["width"], 30, "the camera's state")
    # Close the "Software WebGL rendering detected" notice: it covers a corner of the view.
    close = page.locator(".mantine-Notification-root button")
    if close.count():
        close.first.click()
    time.sleep(2.0)  # the first frames under SwiftShader
    return page, camera


def project(camera, point) -> tuple[float, float]:
    """Pixel (x, y) of a world point seen by a viser camera (OpenCV frame: x right, y down,
    z forward; `fov` vertical)."""
    r = web.matrix_of([0, 0, 0], camera.wxyz)[:3, :3]
    p = r.T @ (np.asarray(point, dtype=np.float64) - camera.position)
    assert p[2] > 0, "the point is behind the camera"
    f = camera.image_height / 2 / np.tan(camera.fov / 2)
    return camera.image_width / 2 + f * p[0] / p[2], camera.image_height / 2 + f * p[1] / p[2]


def answer(view: web.WebView, before: int, timeout: float = 60) -> str:
    """Waits for the page's answer to a request made after `before` answers; its status."""
    wait_for(lambda: view.answered > before and view.status != "planning", timeout, "the planner's answer")
    return view.status


def screenshot(page, path: Path) -> np.ndarray:
    from PIL import Image  # viser depends on Pillow

    page.mouse.move(300, 20)  # over the background: no hover outline
    time.sleep(0.5)
    page.screenshot(path=str(path))
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)


@pytest.fixture(scope="module")
def view(root: Path, cache_dir: Path):
    v = web.WebView(root / "scenes/fig9-near.toml", cache_dir=cache_dir)
    url = v.serve()
    assert url.startswith("http://127.0.0.1:")
    try:
        yield v, url
    finally:
        v.stop()


@pytest.fixture(scope="module")
def page(browser, view):
    v, url = view
    page, camera = open_page(browser, v, url)
    yield page, camera
    page.close()


def test_camera_is_the_one_set(page):
    _, camera = page
    assert np.allclose(camera.position, web.CAMERA_POSITION, atol=1e-6)
    assert np.allclose(camera.look_at, web.CAMERA_LOOK_AT, atol=1e-6)
    assert camera.fov == pytest.approx(web.CAMERA_FOV)


def test_scene_renders_with_the_robot_where_it_should_be(view, page, shots):
    v, _ = view
    page, camera = page
    image = screenshot(page, shots / "scene.png")
    assert image.std() > 20, "the page is blank"
    v.set_robot_visible(False)
    try:
        time.sleep(1.5)
        without = screenshot(page, shots / "scene-without-robot.png")
    finally:
        v.set_robot_visible(True)
    x, y = (int(round(c)) for c in project(camera, CHEST))
    changed = np.abs(image - without).sum(axis=2) > 30
    assert changed[y - 8 : y + 9, x - 8 : x + 9].mean() > 0.9, "no robot pixels at the chest"
    # The robot's pixels are the robot's: grey, not the environment's or the background's.
    r, g, b = image[y - 4 : y + 5, x - 4 : x + 5].reshape(-1, 3).mean(axis=0)
    assert abs(r - g) < 12 and abs(g - b) < 12, (r, g, b)
    # The bottom-left corner (floor grid, far from the robot) does not change.
    assert changed[-120:, :120].mean() < 0.05


def test_clusters_toggle_in_the_page(view, page, shots):
    v, _ = view
    page, _ = page
    before = screenshot(page, shots / "before-clusters.png")
    page.get_by_label("Show clusters").check()
    wait_for(lambda: all(n.visible for n in v.cluster_nodes), 10, "the clusters shown")
    time.sleep(1.5)
    after = screenshot(page, shots / "clusters.png")
    assert (np.abs(after - before).sum(axis=2) > 30).mean() > 0.02, "no clusters drawn"
    page.get_by_label("Show clusters").uncheck()
    wait_for(lambda: not any(n.visible for n in v.cluster_nodes), 10, "the clusters hidden")


def test_click_on_the_dent_plans_and_plays(view, page, shots, tmp_path, run_cli):
    v, _ = view
    page, camera = page
    x, y = project(camera, DENT)
    before = v.answered
    page.mouse.click(x, y)
    assert answer(v, before) == "planned", v.reasons
    part, cluster_id, point = v.picked
    assert part == "pallet" and cluster_id is not None and v.highlight_node is not None
    assert np.linalg.norm(point - DENT) < 0.005, point
    plan = v.plan
    assert pickplace.validate(v.plan_scene, plan).ok
    assert plan.strategy == "right-right"
    page.get_by_text("Plan: right-right").wait_for(timeout=10_000)
    page.get_by_text("Validated: ok").wait_for(timeout=10_000)
    # Playback: the object rides in the hand and ends where the plan places it.
    pb = v.playback
    _, _, placed = pb.at(pb.duration)
    expected = pickplace.pose_matrix(**plan.object["placed_pose"])
    assert np.linalg.norm(placed[:3, 3] - expected[:3, 3]) < 0.002
    middle = next(k for k in plan.key_poses if k["name"] == "pre-place")
    _, _, carried = pb.at(middle["time"])
    want = pickplace.pose_matrix(**middle["world_from_object"])
    assert np.linalg.norm(carried[:3, 3] - want[:3, 3]) < 0.003  # m
    assert np.allclose(carried[:3, :3], want[:3, :3], atol=0.01)  # about 0.6 degrees
    # Play / pause from the page; the key pose list jumps to a key pose's time.
    v.pause()
    play = page.get_by_role("button", name="Play / pause")
    play.click()
    wait_for(lambda: v._playing, 10, "playing")
    play.click()
    wait_for(lambda: not v._playing, 10, "paused")
    place = next(k for k in plan.key_poses if k["name"] == "place")
    v.keypose_box.value = v._keypose_label(place)
    assert v.time_slider.value == pytest.approx(place["time"], abs=0.01)
    # Scrub to the pre-place pose and look at it.
    v.set_time(middle["time"])
    time.sleep(1.5)
    screenshot(page, shots / "planned-pre-place.png")
    # Saved files reproduce the plan byte for byte.
    plan_path, scene_path = v.save(tmp_path / "saved")
    again = pickplace.plan(pickplace.Scene.load(scene_path, cache_dir=v.cache_dir))
    assert again.to_json() == plan_path.read_text() == plan.to_json()
    status, _, stderr = run_cli(
        "plan", scene_path, "--no-timings", "--cache", v.cache_dir, "--out", tmp_path / "cli.json"
    )
    assert status == 0, stderr
    assert (tmp_path / "cli.json").read_bytes() == plan_path.read_bytes()
    # A save never writes through a symlink: refused, what the link names untouched.
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    linked = tmp_path / "linked"
    linked.mkdir()
    (linked / "plan.json").symlink_to(victim)
    with pytest.raises(ValueError, match="symbolic link"):
        v.save(linked)
    assert victim.read_text() == "keep me"
    assert sorted(p.name for p in linked.iterdir()) == ["plan.json"]


def test_click_out_of_reach_shows_the_reasons(view, page, shots):
    v, _ = view
    page, camera = page
    x, y = project(camera, OUT_OF_REACH)
    before = v.answered
    page.mouse.click(x, y)
    assert answer(v, before) == "no-plan"
    assert v.picked[0] == "table"
    assert np.linalg.norm(v.picked[2] - OUT_OF_REACH) < 0.005
    assert v.reasons
    page.get_by_text("No plan", exact=True).wait_for(timeout=10_000)
    first = v.reasons[0]
    page.get_by_text(first[:40]).first.wait_for(timeout=10_000)
    screenshot(page, shots / "no-plan.png")


def test_object_start_strategy_and_seed_from_the_page(view, page):
    v, _ = view
    page, camera = page
    moved = pickplace.pose_matrix([0.40, 0.0, 0.72], [0.0, 0.0, np.sin(0.25), np.cos(0.25)])
    v.move_object_start(moved)  # what the transform handle does when dragged
    v.strategy_box.value = "right-right"
    v.seed_box.value = 2
    x, y = project(camera, DENT)
    before = v.answered
    page.mouse.click(x, y)
    assert answer(v, before) == "planned", v.reasons
    plan = v.plan
    assert (plan.strategy, plan.seed) == ("right-right", 2)
    assert np.allclose(pickplace.pose_matrix(**plan.object["start_pose"]), moved, atol=1e-9)
    assert pickplace.validate(v.plan_scene, plan).ok
    # "Plan again" in the page, with another seed.
    v.seed_box.value = 3
    before = v.answered
    page.get_by_role("button", name="Plan again").click()
    assert answer(v, before) == "planned", v.reasons
    assert v.plan.seed == 3 and pickplace.validate(v.plan_scene, v.plan).ok


def test_command_prints_the_url_and_serves(root, cache_dir):
    script = Path(sys.executable).parent / "pickplace-view-web"
    command = [str(script)] if script.is_file() else [sys.executable, "-m", "pickplace.web"]
    proc = subprocess.Popen(
        [*command, str(root / "scenes/fig9-near.toml"), "--cache", str(cache_dir)],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )
    try:
        url = proc.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), url
        with urllib.request.urlopen(url, timeout=10) as response:
            assert response.status == 200
            assert b"<html" in response.read().lower()
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def test_plan_viewer_plays_a_given_plan(root, cache_dir, browser, near_plan, tmp_path, shots):
    path = tmp_path / "plan.json"
    path.write_text(near_plan.to_json())
    v = web.WebView(root / "scenes/fig9-near.toml", plan_path=path, cache_dir=cache_dir)
    url = v.serve()
    try:
        page, _ = open_page(browser, v, url)
        page.get_by_text("Plan viewer").wait_for(timeout=10_000)
        page.get_by_text(f"Plan: {near_plan.strategy}").wait_for(timeout=10_000)
        assert v.playback is not None and v.playback.duration == pytest.approx(near_plan.duration)
        screenshot(page, shots / "plan-viewer.png")
        page.close()
    finally:
        v.stop()


def test_a_scene_of_primitives_is_drawn_and_picked(root, cache_dir, tmp_path):
    # fig9-near with the table's top as a box: the page draws the parts the planner has.
    text = (root / "scenes/fig9-near.toml").read_text().replace('"../', f'"{root}/')
    text = text.replace(f'mesh = "{root}/meshes/table.stl"', "box = [0.6, 0.9, 0.04]").replace(
        "pose = { position = [0.55, 0.0, 0.02], orientation = [0.0, 0.0, -0.70710678, 0.70710678] }",
        "pose = { position = [0.55, 0.0, 0.70] }",
    )
    assert "box = " in text
    scene = tmp_path / "boxes.toml"
    scene.write_text(text)
    v = web.WebView(scene, cache_dir=cache_dir)
    assert [p["name"] for p in v.env] == ["table", "pallet"]
    assert len(v.env[0]["faces"]) == 12
    hit = v.pick(np.array([0.3, 0.3, 1.5]), np.array([0.0, 0.0, -1.0]))
    assert hit["part"] == "table" and hit["part_index"] == 0
    assert hit["point"][2] == pytest.approx(0.72)
    assert hit["cluster"] is not None


def fk_in_world(run_cli, urdf, q: dict[str, float], world_from_root, *args) -> dict[str, np.ndarray]:
    """`pickplace robot fk URDF` at `q`, every link's pose moved into the world."""
    joints = ",".join(f"{name}={float(value)!r}" for name, value in q.items())
    status, out, stderr = run_cli("robot", "fk", urdf, "--joints", joints, *args)
    assert status == 0, stderr
    links = json.loads(out)["links"]
    return {name: world_from_root @ pickplace.pose_matrix(**pose) for name, pose in links.items()}


def test_what_rust_gives_the_page(near, near_plan, cache_dir, run_cli):
    view = pickplace.SceneView(near)
    # The click: a ray straight down onto the table top's free corner meets it at the top's
    # height (0.72 m); upwards it meets nothing.
    hit = view.cast_ray([0.80, 0.38, 1.5], [0.0, 0.0, -2.0])
    assert hit["part"] == "table" and hit["cluster"] is not None
    assert hit["point"] == pytest.approx([0.80, 0.38, 0.72], abs=1e-6)  # an STL: float32
    assert hit["distance"] == pytest.approx(0.78, abs=1e-6)
    assert view.cast_ray([0.80, 0.38, 1.5], [0.0, 0.0, 1.0]) is None
    with pytest.raises(pickplace.InputError, match="direction"):
        view.cast_ray([0.0, 0.0, 1.0], [0.0, 0.0, 0.0])
    # The links: the scene's base pose times `pickplace robot fk` of its URDF, at the start.
    q = dict(zip(near.joint_names, near.start))
    want = fk_in_world(run_cli, "robots/nx-hiro/nx-hiro.urdf", q, pickplace.pose_matrix([0.0, 0.0, 0.92]))
    got = dict(zip(view.link_names, view.link_poses(near.start)))
    assert want and set(want) <= set(got)
    for name, pose in want.items():
        assert np.allclose(got[name], pose, atol=1e-9), name
    meshes = view.link_meshes()
    assert {m["link"] for m in meshes} <= set(view.link_names) and len(meshes) > 10
    assert all(m["faces"].max() < len(m["vertices"]) for m in meshes)
    vertices, faces = view.object_mesh()
    assert faces.shape[1] == 3 and faces.max() < len(vertices)
    # The plan played back: the object starts at the scene's start pose, rides in the hand,
    # and ends at the plan's placed pose; the robot starts at the start configuration.
    pb = pickplace.Playback(near, near_plan)
    assert pb.duration == pytest.approx(near_plan.duration) and len(pb.times) == len(near_plan.times)
    q0, links0, object0 = pb.at(0.0)
    assert np.allclose(object0, near.object_start, atol=1e-12)
    assert np.allclose(q0, near.start, atol=1e-12)
    assert np.allclose(links0, view.link_poses(q0))
    placed = pickplace.pose_matrix(**near_plan.object["placed_pose"])
    assert np.allclose(pb.at(pb.duration)[2], placed, atol=2e-3)
    assert np.allclose(pb.at(pb.duration + 5.0)[2], pb.at(pb.duration)[2])
    # The scene file: Rust's TOML, paths absolute, reads back as the scene with the changes.
    moved = pickplace.pose_matrix([0.40, 0.0, 0.72], [0.0, 0.0, np.sin(0.25), np.cos(0.25)])
    text = view.scene_toml(target=[0.4, -0.2, 0.745], object_start=moved, seed=7, strategy="right-right")
    again = pickplace.Scene.from_toml(text, "/nonexistent", cache_dir=cache_dir)
    assert again.seed == 7 and again.to_dict()["planner"]["strategy"] == "right-right"
    assert np.allclose(again.object_start, moved, atol=1e-12)
    assert again.target == pytest.approx([0.4, -0.2, 0.745])
    assert again.joint_names == near.joint_names and np.array_equal(again.start, near.start)
    with pytest.raises(pickplace.InputError, match="strategy"):
        view.scene_toml(strategy="both-hands")


@pytest.fixture(scope="module")
def robot_packages() -> Path:
    """The folder that holds example-robot-data/ (`PICKPLACE_ROBOTS_PACKAGES`, which `cargo
    xtask test` sets for the Rust tests); the test is skipped, saying so, without it."""
    given = os.environ.get("PICKPLACE_ROBOTS_PACKAGES")
    if not given or not (Path(given) / "example-robot-data/robots").is_dir():
        pytest.skip("PICKPLACE_ROBOTS_PACKAGES does not name the folder that holds example-robot-data/")
    return Path(given)


def test_a_scene_with_two_robots_opens_plans_and_plays(root, cache_dir, browser, robot_packages, run_cli, shots,
                                                         tmp_path):
    # Two Pandas side by side ([[robots]] with prefixes right_ and left_), table top at z 0.
    v = web.WebView(root / "scenes/robots/two-pandas.toml", cache_dir=cache_dir, package_dirs=[robot_packages])
    names = v.view.link_names
    assert "right_panda_link7" in names and "left_panda_link7" in names
    # Each robot's links are its base pose times `pickplace robot fk` of the one URDF.
    urdf = robot_packages / "example-robot-data/robots/panda_description/urdf/panda.urdf"
    got = dict(zip(names, v.view.link_poses(v.start_q)))
    for prefix, y in (("right_", -0.35), ("left_", 0.35)):
        q = {n.removeprefix(prefix): x for n, x in zip(v.scene.joint_names, v.start_q) if n.startswith(prefix)}
        want = fk_in_world(run_cli, urdf, q, pickplace.pose_matrix([0.0, y, 0.0]), "--package-dir", robot_packages)
        for name, pose in want.items():
            assert np.allclose(got[prefix + name], pose, atol=1e-9), prefix + name
    url = v.serve()
    try:
        page, camera = open_page(browser, v, url)
        image = screenshot(page, shots / "two-robots.png")
        v.set_robot_visible(False)
        time.sleep(1.5)
        without = screenshot(page, shots / "two-robots-without-robots.png")
        v.set_robot_visible(True)
        changed = np.abs(image - without).sum(axis=2) > 30
        for link in ("right_panda_link4", "left_panda_link4"):  # the elbows, in view of the camera
            x, y = (int(round(c)) for c in project(camera, got[link][:3, 3]))
            assert changed[y - 6 : y + 7, x - 6 : x + 7].mean() > 0.5, f"no robot pixels at {link}"
        # A click on the table at the scene's target plans with both arms and plays the plan.
        target = v.target.copy()
        x, y = project(camera, target)
        before = v.answered
        page.mouse.click(x, y)
        assert answer(v, before) == "planned", v.reasons
        assert v.picked[0] == "table" and np.linalg.norm(v.picked[2] - target) < 0.005
        plan = v.plan
        assert pickplace.validate(v.plan_scene, plan).ok
        page.get_by_text(f"Plan: {plan.strategy}").wait_for(timeout=10_000)
        pb = v.playback
        assert np.allclose(pb.at(0.0)[2], v.object_start, atol=1e-9)
        placed = pickplace.pose_matrix(**plan.object["placed_pose"])
        assert np.linalg.norm(pb.at(pb.duration)[2][:3, 3] - placed[:3, 3]) < 0.002
        v.set_time(pb.duration / 2)
        time.sleep(1.5)
        screenshot(page, shots / "two-robots-planned.png")
        # The saved scene keeps both robots and reproduces the plan.
        plan_path, scene_path = v.save(tmp_path / "saved")
        assert scene_path.read_text().count("[[robots]]") == 2
        again = pickplace.Scene.load(scene_path, cache_dir=cache_dir, package_dirs=[robot_packages])
        assert pickplace.plan(again).to_json() == plan_path.read_text() == plan.to_json()
        v.pause()
        page.close()
    finally:
        v.stop()
