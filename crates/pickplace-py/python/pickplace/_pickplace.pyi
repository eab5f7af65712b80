"""Type stubs of the extension module `pickplace._pickplace` (Rust, PyO3)."""

import builtins
import pathlib
from collections.abc import Sequence
from os import PathLike
from typing import Any, Literal, final

import numpy as np
import numpy.typing as npt

_Path = str | PathLike[str]
_F64_1 = npt.NDArray[np.float64]
_F64_2 = npt.NDArray[np.float64]
_Vector = npt.ArrayLike | Sequence[float]
_Strategy = Literal[
    "auto",
    "right-right",
    "left-left",
    "right-left",
    "left-right",
    "right-place-right",
    "left-place-left",
    "right-place-left",
    "left-place-right",
]

__all__ = [
    "__version__",
    "PLAN_FORMAT",
    "STRATEGIES",
    "InputError",
    "NoPlanError",
    "Scene",
    "SceneView",
    "Playback",
    "Plan",
    "ValidationReport",
    "Robot",
    "IkSolution",
    "MotionWorld",
    "Motion",
    "plan_motion",
    "plan",
    "validate",
    "clusters",
    "placements",
    "grasps",
]

__version__: str
PLAN_FORMAT: str
STRATEGIES: tuple[str, ...]
"""The strategy names `plan`, `plan_many` and the browser page accept, `auto` first (the
Rust `StrategyChoice`'s; `_Strategy` spells them for type checkers, and a test keeps the two
equal)."""

class InputError(ValueError):
    """Bad input; the message is the one `pickplace` prints after `error: `."""

class NoPlanError(Exception):
    """A well-formed scene with no solution."""

    reasons: list[str]
    """Why, one line per reason (per strategy, the most frequent rejections per stage)."""
    stats: dict[str, Any] | None
    """Counts per strategy and stage; None for a scene refused before the search."""

@final
class Scene:
    """A scene set up for planning (robot, object, environment, target)."""

    @staticmethod
    def load(
        path: _Path,
        *,
        cache_dir: _Path | None = None,
        use_cache: bool = True,
        package_dirs: Sequence[_Path] = ...,
    ) -> Scene:
        """Reads a scene file (TOML) and sets it up."""
    @staticmethod
    def from_toml(
        text: str,
        base_dir: _Path = ...,
        *,
        name: _Path = ...,
        cache_dir: _Path | None = None,
        use_cache: bool = True,
        package_dirs: Sequence[_Path] = ...,
    ) -> Scene:
        """A scene from TOML text; relative paths are relative to `base_dir`."""
    @staticmethod
    def from_dict(
        scene: dict[str, Any],
        base_dir: _Path = ...,
        *,
        name: _Path = ...,
        cache_dir: _Path | None = None,
        use_cache: bool = True,
        package_dirs: Sequence[_Path] = ...,
    ) -> Scene:
        """A scene from a dict with the TOML file's tables and keys."""
    @property
    def path(self) -> pathlib.Path:
        """The scene file (or the name given)."""
    def to_dict(self) -> dict[str, Any]:
        """The scene as a dict (paths resolved)."""
    @property
    def joint_names(self) -> list[str]:
        """Every actuated joint, model order."""
    @property
    def start(self) -> _F64_1:
        """Start configuration, shape (J,)."""
    @property
    def object_start(self) -> _F64_2:
        """The object's start pose, 4x4."""
    @property
    def target(self) -> _F64_1:
        """The target point, shape (3,)."""
    @property
    def seed(self) -> int:
        """The scene's planner seed."""
    @property
    def time_budget(self) -> float:
        """The scene's time budget, s."""
    @property
    def environment(self) -> list[str]:
        """The environment parts' names."""
    def environment_parts(self) -> list[dict[str, Any]]:
        """The environment parts as the planner has them: name, vertices, faces, world_from_mesh, clusters."""
    @property
    def log(self) -> list[str]:
        """What setting up did."""
    @property
    def warnings(self) -> list[str]:
        """Why the cache could not be used."""

@final
class SceneView:
    """What the browser view draws and asks of a set-up scene, computed in Rust: the links of
    every robot of the scene posed by forward kinematics, the object's mesh, the environment
    surface under a ray, the scene as a scene file and saving it with a plan."""

    def __init__(self, scene: Scene) -> None:
        """Triangulates the robots' link shapes (visual, else collision) once."""
    @property
    def link_names(self) -> list[str]:
        """Every link of the scene's robots (prefixed with `[[robots]]`), model order."""
    def link_meshes(self) -> list[dict[str, Any]]:
        """The links with shapes: link, index, vertices (V, 3) and faces (F, 3) in the link
        frame, color (r, g, b)."""
    def link_poses(self, q: _Vector) -> npt.NDArray[np.float64]:
        """Every link's world pose at `q` (`Scene.joint_names` order), shape (L, 4, 4)."""
    def object_mesh(self) -> tuple[_F64_2, npt.NDArray[np.int64]]:
        """The object's (vertices (V, 3), faces (F, 3)) in its frame."""
    def cast_ray(self, origin: _Vector, direction: _Vector) -> dict[str, Any] | None:
        """The nearest environment surface on the ray: part, part_index, triangle, cluster
        (id or None), point (3,), distance (m); None when it meets nothing."""
    def scene_toml(
        self,
        *,
        target: _Vector | None = None,
        object_start: npt.ArrayLike | None = None,
        seed: int | None = None,
        strategy: _Strategy | None = None,
    ) -> str:
        """The scene file (TOML, paths absolute) with the given changes."""
    def save(self, folder: _Path, plan: Plan) -> list[pathlib.Path]:
        """Writes FOLDER/plan.json and FOLDER/scene.toml atomically; their paths."""

@final
class Playback:
    """A plan played back in its scene: configuration, link poses and object pose at any time."""

    def __init__(self, scene: Scene, plan: Plan) -> None:
        """Raises InputError when the plan's joints or links are not the scene's robots'."""
    @property
    def times(self) -> _F64_1:
        """Sample times, s, shape (N,)."""
    @property
    def duration(self) -> float:
        """Time of the last sample, s."""
    def at(self, t: float) -> tuple[_F64_1, npt.NDArray[np.float64], _F64_2]:
        """(q (J,), world_from_links (L, 4, 4), world_from_object (4, 4)) at time `t`."""

@final
class Plan:
    """A pick-and-place plan (docs/plan-format.md)."""

    @staticmethod
    def from_json(text: str) -> Plan:
        """Reads a plan from its JSON text."""
    @staticmethod
    def load(path: _Path) -> Plan:
        """Reads a plan file."""
    def to_json(self) -> str:
        """The plan file's exact text (pretty JSON, final newline)."""
    def to_dict(self) -> dict[str, Any]:
        """The JSON document as a dict."""
    @property
    def format(self) -> str:
        """`pickplace.plan/2`."""
    @property
    def seed(self) -> int:
        """The seed of every random choice."""
    @property
    def strategy(self) -> str:
        """The strategy that succeeded."""
    @property
    def joint_names(self) -> list[str]:
        """The columns of the trajectory arrays."""
    @property
    def times(self) -> _F64_1:
        """Sample times, shape (N,), s."""
    @property
    def positions(self) -> _F64_2:
        """Joint positions, shape (N, J)."""
    @property
    def velocities(self) -> _F64_2 | None:
        """Joint velocities, shape (N, J), or None."""
    @property
    def accelerations(self) -> _F64_2 | None:
        """Joint accelerations, shape (N, J), or None."""
    @property
    def duration(self) -> float:
        """Duration of the motion, s."""
    @property
    def events(self) -> list[dict[str, Any]]:
        """Grasps and releases in time order."""
    @property
    def grasps(self) -> list[dict[str, Any]]:
        """The grasps used."""
    @property
    def placement(self) -> dict[str, Any]:
        """The placement chosen."""
    @property
    def object(self) -> dict[str, Any]:
        """The object's start and placed poses."""
    @property
    def key_poses(self) -> list[dict[str, Any]]:
        """The key poses in time order."""
    @property
    def rests(self) -> list[dict[str, Any]]:
        """Intermediate resting poses of a regrasp by placing."""
    @property
    def base(self) -> dict[str, Any] | None:
        """Where the robot stands: `{link, world_from_root}` (its root link and that link's pose
        in the world), or None in plans written before it was stated."""
    @property
    def arms(self) -> list[dict[str, Any]]:
        """Each arm's joints and gripper joints, and its tool frame (`tool`: `{link, parent,
        parent_from_tool}`, the frame of `link_from_object` and `world_from_tcp`)."""
    @property
    def stats(self) -> dict[str, Any]:
        """How the plan was found."""
    def __eq__(self, other: builtins.object, /) -> bool: ...

@final
class ValidationReport:
    """What `validate` found."""

    @property
    def ok(self) -> bool:
        """True when there is no problem."""
    @property
    def problems(self) -> list[str]:
        """Every problem, in time order."""
    @property
    def states_checked(self) -> int:
        """Interpolated states checked."""
    @property
    def duration(self) -> float:
        """Duration of the trajectory, s."""
    @property
    def stability_margin(self) -> float | None:
        """Stability margin of the final pose, m."""
    def to_dict(self) -> dict[str, Any]:
        """The report as a dict."""
    def __bool__(self) -> bool: ...

@final
class Robot:
    """A URDF (+ SRDF) robot model: FK, Jacobians, IK."""

    @staticmethod
    def load(
        urdf: _Path,
        srdf: _Path | None = None,
        *,
        package_dirs: Sequence[_Path] = ...,
        skip_unreadable_meshes: bool = False,
    ) -> Robot:
        """Reads a URDF and optionally its SRDF."""
    @property
    def name(self) -> str:
        """The robot's name."""
    @property
    def joint_names(self) -> list[str]:
        """Actuated joints, model order."""
    @property
    def link_names(self) -> list[str]:
        """Links, model order (root first)."""
    @property
    def lower_limits(self) -> _F64_1:
        """Lower joint limits, shape (J,)."""
    @property
    def upper_limits(self) -> _F64_1:
        """Upper joint limits, shape (J,)."""
    @property
    def velocity_limits(self) -> _F64_1:
        """Velocity limits, shape (J,)."""
    @property
    def groups(self) -> list[str]:
        """The SRDF's planning groups."""
    def zero_configuration(self) -> _F64_1:
        """Zero configuration clamped into the limits."""
    def state(self, name: str, q: _Vector | None = None) -> _F64_1:
        """A named SRDF group state applied over `q`."""
    def fk(self, q: _Vector, link: str | None = None) -> npt.NDArray[np.float64]:
        """A link's pose (4, 4), or every link's (L, 4, 4)."""
    def jacobian(
        self,
        q: _Vector,
        link: str,
        point: _Vector | None = None,
        joints: Sequence[str] | None = None,
    ) -> _F64_2:
        """The (6, n) Jacobian of a point fixed in a link."""
    def tcp_pose(self, q: _Vector, group: str) -> _F64_2:
        """A group's tip pose, 4x4."""
    def ik(
        self,
        pose: npt.ArrayLike,
        group: str,
        seed_q: _Vector | None = None,
        *,
        free_axis: _Vector | None = None,
        seed: int = 0,
        position_tolerance: float = 1e-4,
        orientation_tolerance: float = 1e-3,
    ) -> IkSolution:
        """Inverse kinematics of a group's tip."""

@final
class IkSolution:
    """The result of `Robot.ik`."""

    @property
    def success(self) -> bool:
        """True when both tolerances are met."""
    @property
    def positions(self) -> _F64_1:
        """Every joint of the model, shape (J,)."""
    @property
    def position_error(self) -> float:
        """TCP position error, m."""
    @property
    def orientation_error(self) -> float:
        """TCP orientation error, rad."""
    @property
    def attempts(self) -> int:
        """Attempts made."""
    def __bool__(self) -> bool: ...

def plan(
    scene: Scene,
    *,
    seed: int | None = None,
    strategy: _Strategy | None = None,
    time_budget: float | None = None,
    timings: bool = False,
    velocity_scaling: float | None = None,
    acceleration_scaling: float | None = None,
    sample_period: float | None = None,
) -> Plan:
    """Plans a pick-and-place motion (GIL released); raises NoPlanError."""

_State = str | _Vector | dict[str, float]

@final
class MotionWorld:
    """A robot and its obstacles, ready for motion queries (immutable)."""

    @staticmethod
    def load(
        path: _Path,
        *,
        obstacles: Sequence[dict[str, Any]] | None = None,
        cache_dir: _Path | None = None,
        use_cache: bool = True,
        package_dirs: Sequence[_Path] = (),
    ) -> MotionWorld:
        """The world of a scene file, with obstacles added."""
    @staticmethod
    def for_robot(
        urdf: _Path,
        srdf: _Path | None = None,
        *,
        obstacles: Sequence[dict[str, Any]] | None = None,
        cache_dir: _Path | None = None,
        use_cache: bool = True,
        package_dirs: Sequence[_Path] = (),
    ) -> MotionWorld:
        """The world of a robot alone, with obstacles."""
    def with_obstacles(self, obstacles: Sequence[dict[str, Any]]) -> MotionWorld:
        """A new world with obstacles added."""
    @property
    def joint_names(self) -> list[str]:
        """Every actuated joint, model order."""
    @property
    def start(self) -> _F64_1:
        """The start state (every joint)."""
    @property
    def obstacles(self) -> list[str]:
        """The obstacles' names, sorted."""
    @property
    def log(self) -> list[str]:
        """What loading did."""
    @property
    def warnings(self) -> list[str]:
        """What loading went on from."""

@final
class Motion:
    """A planned motion: the group's joints, path and timed trajectory."""

    def to_json(self) -> str:
        """The motion as JSON (`pickplace motion --out`)."""
    def to_dict(self) -> dict[str, Any]:
        """The motion as a dict."""
    @property
    def group(self) -> str:
        """The planning group."""
    @property
    def joint_names(self) -> list[str]:
        """The group's joints."""
    @property
    def times(self) -> _F64_1:
        """Sample times, (N,)."""
    @property
    def positions(self) -> _F64_2:
        """Joint positions, (N, J)."""
    @property
    def velocities(self) -> _F64_2:
        """Joint velocities, (N, J)."""
    @property
    def waypoints(self) -> _F64_2:
        """The path, (W, J)."""
    @property
    def duration(self) -> float:
        """Duration, s."""
    @property
    def stats(self) -> dict[str, Any]:
        """How it was found."""

def plan_motion(
    world: MotionWorld | _Path,
    goal: _State,
    start: _State | None = None,
    *,
    group: str | None = None,
    seed: int = 1,
    time_limit: float = 1.0,
    margin: float = 0.0,
    shortcut_attempts: int = 100,
    velocity_scaling: float | None = None,
    acceleration_scaling: float | None = None,
    sample_period: float = 0.04,
    blend_tolerance: float = 0.1,
    timings: bool = False,
) -> Motion:
    """A collision-free, timed motion of a group (GIL released); raises NoPlanError."""

def validate(scene: Scene, plan: Plan, *, plan_name: _Path = ...) -> ValidationReport:
    """Re-checks a plan against a scene (GIL released)."""

def clusters(
    mesh: _Path,
    *,
    mode: Literal["env", "finger"] = "env",
    h_max: float | None = None,
    scale: float = 1.0,
) -> dict[str, Any]:
    """Surface clusters of a mesh (`pickplace clusters --json`)."""

def placements(
    object: _Path,
    *,
    on: _Path | None = None,
    env_pose: npt.ArrayLike | None = None,
    target: _Vector | None = None,
    scale: float = 1.0,
    h_max: float = 0.001,
    max: int = 32,
) -> dict[str, Any]:
    """Stable placements (`pickplace placements --json`)."""

def grasps(
    mesh: _Path,
    robot: _Path,
    *,
    h_max: float | None = None,
    grid_step: float | None = None,
    approaches: int | None = None,
    clearance: float | None = None,
) -> dict[str, Any]:
    """Parallel-gripper grasps (`pickplace grasps --json`)."""

# The batch functions behind `pickplace.batch` and `pickplace.ray` (use those).
@final
class _BatchOptions:
    """A batch's options but its folder and threads (`_batch_options`)."""

def _batch_options(
    *,
    seed: int | None = None,
    strategy: _Strategy | None = None,
    time_budget: float | None = None,
    velocity_scaling: float | None = None,
    acceleration_scaling: float | None = None,
    sample_period: float | None = None,
    timings: bool = False,
    resume: bool = False,
    cache_dir: _Path | None = None,
    use_cache: bool = True,
    package_dirs: Sequence[_Path] = ...,
) -> _BatchOptions:
    """A batch's options: the strategy checked, the cache folder chosen."""

def _batch_plan_many(
    scenes: Sequence[_Path],
    out_dir: _Path,
    options: _BatchOptions,
    *,
    workers: int | None = None,
    progress: Any | None = None,
) -> list[str]:
    """Plans scenes in parallel; the summary lines (JSON)."""

def _batch_prepare(
    scenes: Sequence[_Path], out_dir: _Path, options: _BatchOptions
) -> list[pathlib.Path]:
    """Checks a batch's names and options, creates the folder; the plan files."""

def _batch_plan_one(
    scene: _Path,
    plan_path: _Path,
    options: _BatchOptions,
    *,
    display: str | None = None,
    threads: int | None = None,
) -> str:
    """One scene of a batch; its summary line (JSON)."""

def _batch_write_summary(path: _Path, lines: Sequence[str]) -> None:
    """Writes summary lines atomically."""
