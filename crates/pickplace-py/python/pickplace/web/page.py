"""The page: a viser server showing a scene, planning on clicks, playing plans back. What it
draws and asks (link meshes posed by forward kinematics, the surface under a click, the scene
file to save, the object's pose over a plan) comes from Rust: `pickplace.SceneView` and
`pickplace.Playback`; this module only lays out the page."""

from __future__ import annotations

import colorsys
import math
import os
import socket
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

import pickplace


#: Strategies offered in the page: the planner's names, as Rust spells them (`auto` first).
STRATEGIES = pickplace.STRATEGIES

#: The camera the page opens with (world frame, m): front-right of the robot, above the table.
CAMERA_POSITION = (1.95, -1.55, 1.85)
CAMERA_LOOK_AT = (0.30, -0.08, 0.85)
CAMERA_FOV = math.radians(50.0)

ENV_COLOR = (170, 150, 120)
OBJECT_COLOR = (200, 40, 40)
HIGHLIGHT_COLOR = (255, 200, 0)
TARGET_COLOR = (255, 0, 255)


def wxyz_of(m: np.ndarray) -> np.ndarray:
    """The rotation of a 4x4 pose as viser's quaternion (w, x, y, z)."""
    x, y, z, w = pickplace.pose_parts(m)["orientation"]
    return np.array([w, x, y, z])


def matrix_of(position: Any, wxyz: Any) -> np.ndarray:
    """The 4x4 pose of a viser position and (w, x, y, z) quaternion."""
    w, x, y, z = (float(v) for v in wxyz)
    return pickplace.pose_matrix(position, [x, y, z, w])


class WebView:
    """The page's state and its viser server. ``WebView(scene_path).serve(port)``; with
    ``plan_path`` it only plays that plan."""

    def __init__(self, scene_path: str | os.PathLike[str], *, plan_path: str | os.PathLike[str] | None = None,
                 cache_dir: str | os.PathLike[str] | None = None, out_dir: str | os.PathLike[str] = "pickplace-web",
                 package_dirs: list[str | os.PathLike[str]] = ()) -> None:
        self.scene_path = Path(scene_path)
        self.cache_dir = cache_dir
        self.package_dirs = [str(d) for d in package_dirs]
        self.out_dir = str(out_dir)
        self.scene = pickplace.Scene.load(self.scene_path, cache_dir=cache_dir, package_dirs=self.package_dirs)
        # Every robot of the scene (two with [[robots]]), as the planner has them.
        self.view = pickplace.SceneView(self.scene)
        self.start_q = self.scene.start
        self.object_vertices, self.object_faces = self.view.object_mesh()
        self.object_start = self.scene.object_start
        # The parts as the planner has them (mesh files' triangles, primitives' tessellations,
        # the environment-contact clusters of the setup).
        self.env = self.scene.environment_parts()
        self.target = np.asarray(self.scene.target, dtype=np.float64)
        self.seed = int(self.scene.seed)
        self.strategy = self.scene.to_dict()["planner"]["strategy"]
        # State the tests read.
        self.status = "idle"  # idle | planning | planned | no-plan | error
        self.plan: pickplace.Plan | None = None
        self.plan_scene: pickplace.Scene | None = None
        self.reasons: list[str] = []
        self.validation: pickplace.ValidationReport | None = None
        self.picked: tuple[str, int | None, np.ndarray] | None = None  # env part, cluster id, point
        self.playback: pickplace.Playback | None = None
        self.key_poses: list[dict[str, Any]] = []  # of the plan played back
        self.saved: list[Path] = []
        self.save_error: str | None = None
        self.requests = 0  # plans asked for (clicks, "Plan again")
        self.answered = 0  # the request the page's answer (plan, reasons) is for
        self._lock = threading.Lock()
        self._plan_request = threading.Event()
        self._stop = threading.Event()
        self._playing = False
        self._setting_time = False
        self.plan_only = plan_path is not None
        if plan_path is not None:
            self.plan = pickplace.Plan.load(plan_path)
        self.server = None

    # -- serving --

    def serve(self, port: int | None = None) -> str:
        """Starts the server on 127.0.0.1 (a free port unless given); returns the URL."""
        import viser

        if port is None:
            port = free_port()
        self.server = server = viser.ViserServer(host="127.0.0.1", port=port, verbose=False)
        server.scene.set_up_direction("+z")
        server.initial_camera.position = CAMERA_POSITION
        server.initial_camera.look_at = CAMERA_LOOK_AT
        server.initial_camera.fov = CAMERA_FOV
        self._build_scene()
        self._build_gui()
        self._show_robot(self.start_q)
        self._threads = [threading.Thread(target=self._player, daemon=True)]
        if not self.plan_only:
            self._threads.append(threading.Thread(target=self._planner, daemon=True))
        for t in self._threads:
            t.start()
        if self.plan is not None:
            self._show_plan(self.plan, None, self.scene)
        return f"http://127.0.0.1:{server.get_port()}"

    def stop(self) -> None:
        self._stop.set()
        self._plan_request.set()
        if self.server is not None:
            self.server.stop()

    def _build_scene(self) -> None:
        scene = self.server.scene
        scene.add_grid("/grid", width=3.0, height=3.0, cell_size=0.1, position=(0.3, 0.0, 0.0))
        self.link_frames = {}
        for name in self.view.link_names:
            self.link_frames[name] = scene.add_frame(f"/robot/{name}", show_axes=False)
        for m in self.view.link_meshes():
            scene.add_mesh_simple(
                f"/robot/{m['link']}/shape", m["vertices"], m["faces"], color=m["color"], flat_shading=True,
            )
        for part in self.env:
            world = part["world_from_mesh"]
            mesh = scene.add_mesh_simple(
                f"/env/{part['name']}", part["vertices"], part["faces"], color=ENV_COLOR, wxyz=wxyz_of(world),
                position=world[:3, 3], flat_shading=True, side="double",
            )
            if not self.plan_only:
                mesh.on_click(self._on_env_click)
        self.cluster_nodes = []
        for part in self.env:
            world = part["world_from_mesh"]
            rng = np.random.default_rng(7)
            for c in part["clusters"]:
                tri = part["faces"][np.asarray(c["triangles"], dtype=int)]
                hue = rng.random()
                color = tuple(int(255 * v) for v in _hsv(hue, 0.75, 0.95))
                node = scene.add_mesh_simple(
                    f"/clusters/{part['name']}/{c['id']}", part["vertices"], tri, color=color, wxyz=wxyz_of(world),
                    position=world[:3, 3] + [0, 0, 0.0005], flat_shading=True, side="double", visible=False,
                )
                if not self.plan_only:
                    node.on_click(self._on_env_click)
                self.cluster_nodes.append(node)
        self.object_node = scene.add_mesh_simple(
            "/object", self.object_vertices, self.object_faces, color=OBJECT_COLOR,
            wxyz=wxyz_of(self.object_start), position=self.object_start[:3, 3], flat_shading=True,
        )
        self.highlight_node = None
        self.target_node = scene.add_icosphere(
            "/target", radius=0.008, color=TARGET_COLOR, position=self.target, visible=not self.plan_only,
        )
        self.handle = None
        if not self.plan_only:
            self.handle = scene.add_transform_controls(
                "/object_start", scale=0.15, wxyz=wxyz_of(self.object_start),
                position=self.object_start[:3, 3], visible=False,
            )

            @self.handle.on_update
            def _(_event) -> None:
                self.move_object_start(matrix_of(self.handle.position, self.handle.wxyz))

    def _build_gui(self) -> None:
        gui = self.server.gui
        self.md_status = gui.add_markdown(self._status_text())
        self.clusters_box = gui.add_checkbox("Show clusters", initial_value=False)

        @self.clusters_box.on_update
        def _(_e) -> None:
            for n in self.cluster_nodes:
                n.visible = self.clusters_box.value

        if not self.plan_only:
            self.strategy_box = gui.add_dropdown("Strategy", STRATEGIES, initial_value=self.strategy)
            self.seed_box = gui.add_number("Seed", initial_value=self.seed, min=0, step=1)
            self.move_box = gui.add_checkbox("Move object start", initial_value=False)
            self.replan_button = gui.add_button("Plan again")
            self.folder_box = gui.add_text("Save folder", initial_value=self.out_dir)
            self.save_button = gui.add_button("Save plan + scene")

            @self.move_box.on_update
            def _(_e) -> None:
                self.handle.visible = self.move_box.value
                if self.move_box.value:
                    self._clear_plan()

            @self.replan_button.on_click
            def _(_e) -> None:
                self.request_plan()

            @self.save_button.on_click
            def _(_e) -> None:
                try:
                    self.save(self.folder_box.value)
                except (ValueError, OSError) as e:
                    self.save_error = str(e)
                    self._refresh_status()

        with gui.add_folder("Playback"):
            self.time_slider = gui.add_slider("Time (s)", min=0.0, max=1.0, step=0.01, initial_value=0.0, disabled=True)
            self.play_button = gui.add_button("Play / pause", disabled=True)
            self.keypose_box = gui.add_dropdown("Key pose", ("-",), disabled=True)

        @self.time_slider.on_update
        def _(_e) -> None:
            if not self._setting_time:
                self.show_time(self.time_slider.value)

        @self.play_button.on_click
        def _(_e) -> None:
            self._playing = not self._playing
            if self._playing and self.time_slider.value >= self.time_slider.max - 1e-6:
                self.set_time(0.0)

        @self.keypose_box.on_update
        def _(_e) -> None:
            if self.playback is None:
                return
            for kp in self.key_poses:
                if self._keypose_label(kp) == self.keypose_box.value:
                    self._playing = False
                    self.set_time(float(kp["time"]))

        self.md_plan = gui.add_markdown("")

    # -- drawing --

    def _show_robot(self, q: np.ndarray) -> None:
        self._pose_links(self.view.link_poses(q))

    def _pose_links(self, world_from_link: np.ndarray) -> None:
        with self.server.atomic():
            for name, m in zip(self.view.link_names, world_from_link):
                frame = self.link_frames[name]
                frame.position = m[:3, 3]
                frame.wxyz = wxyz_of(m)

    def _set_object(self, m: np.ndarray) -> None:
        self.object_node.position = m[:3, 3]
        self.object_node.wxyz = wxyz_of(m)

    def move_object_start(self, world_from_object: np.ndarray) -> None:
        """Sets the object's start pose (the transform handle calls this); the next plan
        starts from it ("Plan again" or a click)."""
        m = np.asarray(world_from_object, dtype=np.float64)
        self.object_start = m
        if self.handle is not None:
            self.handle.position = m[:3, 3]
            self.handle.wxyz = wxyz_of(m)
        if self.playback is not None:
            self._clear_plan()
        self._set_object(m)

    def set_robot_visible(self, visible: bool) -> None:
        for frame in self.link_frames.values():
            frame.visible = visible

    def show_time(self, t: float) -> None:
        pb = self.playback
        if pb is None:
            return
        _, world_from_link, pose = pb.at(t)
        self._pose_links(world_from_link)
        self._set_object(pose)

    def set_time(self, t: float) -> None:
        self._setting_time = True
        try:
            self.time_slider.value = t
        finally:
            self._setting_time = False
        self.show_time(t)

    def play(self) -> None:
        self._playing = True

    def pause(self) -> None:
        self._playing = False

    def _player(self) -> None:
        period = 1.0 / 30.0
        while not self._stop.is_set():
            time.sleep(period)
            pb = self.playback
            if not self._playing or pb is None:
                continue
            t = self.time_slider.value + period
            if t >= pb.duration:
                t = pb.duration
                self._playing = False
            self.set_time(t)

    def _status_text(self) -> str:
        if self.plan_only:
            head = f"**Plan viewer** · `{self.scene_path.name}`"
        else:
            head = f"**Click the environment** to place the object · `{self.scene_path.name}`"
        status = {
            "idle": "",
            "planning": "Planning…",
            "planned": "Planned.",
            "no-plan": "**No plan.**",
            "error": "**Error.**",
        }[self.status]
        target = ", ".join(f"{v:.3f}" for v in self.target)
        lines = [head, f"Target: ({target}) m", status]
        if self.picked is not None:
            lines.append(f"Surface: {self.picked[0]}, cluster {self.picked[1]}")
        if self.saved:
            lines.append("Saved: " + ", ".join(f"`{p}`" for p in self.saved))
        if self.save_error:
            lines.append(f"**Not saved:** {self.save_error}")
        return "\n\n".join(line for line in lines if line)

    def _refresh_status(self) -> None:
        self.md_status.content = self._status_text()

    @staticmethod
    def _keypose_label(kp: dict[str, Any]) -> str:
        return f"{kp['time']:.2f} s {kp['name']} ({kp['arm']})"

    def _clear_plan(self) -> None:
        self._playing = False
        self.playback = None
        self._show_robot(self.start_q)
        self._set_object(self.object_start)
        self.set_time(0.0)
        self.time_slider.disabled = True
        self.play_button.disabled = True
        self.keypose_box.disabled = True

    def _show_plan(self, plan: pickplace.Plan, report: pickplace.ValidationReport | None,
                   scene: pickplace.Scene) -> None:
        self._playing = False
        self.playback = pb = pickplace.Playback(scene, plan)
        self.key_poses = plan.key_poses
        self.time_slider.max = max(pb.duration, 0.01)
        self.time_slider.disabled = False
        self.play_button.disabled = False
        labels = tuple(self._keypose_label(kp) for kp in plan.key_poses) or ("-",)
        self.keypose_box.options = labels
        self.keypose_box.disabled = False
        self.set_time(0.0)
        lines = [f"### Plan: {plan.strategy}", f"Duration {pb.duration:.2f} s, {len(pb.times)} samples, seed {plan.seed}"]
        if report is not None:
            lines.append("Validated: ok" if report.ok else "Validation: " + "; ".join(report.problems[:5]))
        lines.append("| time (s) | key pose | arm |\n|---|---|---|\n" + "\n".join(
            f"| {kp['time']:.2f} | {kp['name']} | {kp['arm']} |" for kp in plan.key_poses))
        events = ", ".join(f"{e['kind']} {e['arm']} at {e['time']:.2f} s" for e in plan.events)
        if events:
            lines.append("Events: " + events)
        self.md_plan.content = "\n\n".join(lines)
        self._playing = True

    def _show_reasons(self, reasons: list[str], heading: str = "No plan") -> None:
        self.md_plan.content = f"### {heading}\n\n" + "\n".join(f"- {r}" for r in reasons)

    # -- clicking and planning --

    def pick(self, origin: np.ndarray, direction: np.ndarray) -> dict[str, Any] | None:
        """The environment surface under a ray (`SceneView.cast_ray`): part, triangle, cluster,
        point; None when the ray meets nothing."""
        return self.view.cast_ray(origin, direction)

    def _on_env_click(self, event) -> None:
        self.click(np.asarray(event.ray_origin), np.asarray(event.ray_direction))

    def click(self, origin: np.ndarray, direction: np.ndarray) -> bool:
        hit = self.pick(origin, direction)
        if hit is None:
            return False
        point, cluster_id = hit["point"], hit["cluster"]
        self.picked = (hit["part"], cluster_id, point)
        self.target = point
        self.target_node.position = point
        self.target_node.visible = True
        if self.highlight_node is not None:
            self.highlight_node.remove()
            self.highlight_node = None
        if cluster_id is not None:
            part = self.env[hit["part_index"]]
            world = part["world_from_mesh"]
            cluster = next(c for c in part["clusters"] if c["id"] == cluster_id)
            tris = part["faces"][np.asarray(cluster["triangles"], dtype=int)]
            self.highlight_node = self.server.scene.add_mesh_simple(
                "/highlight", part["vertices"], tris, color=HIGHLIGHT_COLOR, wxyz=wxyz_of(world),
                position=world[:3, 3] + [0, 0, 0.001], flat_shading=True, side="double",
            )
            self.highlight_node.on_click(self._on_env_click)  # it covers the surface: click through
        self.request_plan()
        return True

    def request_plan(self) -> None:
        with self._lock:
            self.requests += 1
            self.status = "planning"
            self.plan = None
        self._clear_plan()
        self.md_plan.content = ""
        self._refresh_status()
        self._plan_request.set()

    def scene_toml(self) -> str:
        """The scene file (from Rust, paths absolute) with the page's target, object start
        pose, seed and strategy."""
        if not self.plan_only:
            self.seed = int(self.seed_box.value)
            self.strategy = str(self.strategy_box.value)
        return self.view.scene_toml(
            target=self.target, object_start=self.object_start, seed=self.seed, strategy=self.strategy,
        )

    def _planner(self) -> None:
        while True:
            self._plan_request.wait()
            if self._stop.is_set():
                return
            self._plan_request.clear()
            request = self.requests
            try:
                scene = pickplace.Scene.from_toml(
                    self.scene_toml(), name=self.scene_path, cache_dir=self.cache_dir, package_dirs=self.package_dirs,
                )
                plan = pickplace.plan(scene)
                report = pickplace.validate(scene, plan)
            except pickplace.NoPlanError as e:
                if self._plan_request.is_set():
                    continue
                self.reasons = list(e.reasons)
                self.status = "no-plan"
                self._show_reasons(self.reasons)
                self._refresh_status()
                self.answered = request
                continue
            except Exception as e:  # noqa: BLE001 - shown in the page
                if self._plan_request.is_set():
                    continue
                self.reasons = [str(e)]
                self.status = "error"
                self._show_reasons(self.reasons, "Error")
                self._refresh_status()
                self.answered = request
                continue
            if self._plan_request.is_set():
                continue  # a newer request supersedes this plan
            self.plan, self.plan_scene, self.validation = plan, scene, report
            self.reasons = []
            self._show_plan(plan, report, scene)
            self.status = "planned"
            self._refresh_status()
            self.answered = request

    def save(self, folder: str | os.PathLike[str]) -> list[Path]:
        """Writes FOLDER/plan.json and FOLDER/scene.toml (the scene with the chosen target, seed
        and strategy: `pickplace plan FOLDER/scene.toml --no-timings` gives plan.json), both
        by Rust (`SceneView.save`)."""
        if self.plan is None or self.plan_scene is None:
            return []
        paths = [Path(p) for p in pickplace.SceneView(self.plan_scene).save(folder, self.plan)]
        self.saved = paths
        self.save_error = None
        self._refresh_status()
        return paths


def _hsv(h: float, s: float, v: float) -> tuple[float, float, float]:
    return colorsys.hsv_to_rgb(h, s, v)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]
