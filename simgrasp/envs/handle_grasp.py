"""``simgrasp/HandleGrasp-v0``: one grasp per episode on an object resting on the table.

Episode: :meth:`HandleGraspEnv.reset` picks an object and an episode seed, builds the chain's
scene (the object in a seeded stable pose and yaw, :func:`simgrasp.scenes.scene.build_scene`)
and observes it as the chain does (:func:`simgrasp.scenes.observe.observe`), so the cloud is
exactly the one :func:`simgrasp.grasping.trials.chain.run_chain` would plan on with that seed.
:meth:`HandleGraspEnv.step` executes the action as a grasp trial
(:func:`simgrasp.grasping.trials.trial.run_trial`) and ends the episode.

Observation: see :mod:`simgrasp.envs.observation`. Action: see :mod:`simgrasp.envs.action`
(``[x, y, z, qw, qx, qy, qz, width]``, world frame, meters).

Processes: a GL context made before ``fork`` hangs the child, so asynchronous vector envs must
start their workers with ``spawn`` or ``forkserver``
(``vector_kwargs={"context": "spawn"}``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from typing import Annotated, Any, Literal

import gymnasium
import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import ObjectModel, model_for
from simgrasp.assets.object_sets import GENERATED_OBJECTS
from simgrasp.config import setting
from simgrasp.config.checks import Checked, MinLength, PositiveInt
from simgrasp.envs.action import action_space, grasp_from_action
from simgrasp.envs.object_names import check_object_names
from simgrasp.envs.observation import (
    Observation,
    camera_layout,
    make_observation,
    observation_space,
)
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import NoiseSigma
from simgrasp.grasping.trials.result import TrialResult
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers import DEFAULT_GRIPPER, gripper_names, make_gripper
from simgrasp.perception.sensors.settings import SensorSettings
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.kept_renderer import RendererKeeper
from simgrasp.scenes.observe import observe
from simgrasp.scenes.render import select_backend
from simgrasp.scenes.scene import Scene, build_scene
from simgrasp.scenes.views import CHAIN_VIEWS, MAX_VIEWS
from simgrasp.seeding import rng_for

RewardKind = Literal["on_handle", "lift"]
EPISODE_SEEDS = 2**31
"""Episode seeds are drawn from [0, EPISODE_SEEDS)."""
RESET_OPTIONS = ("object", "episode_seed")
RENDER_SIZE = (640, 480)
"""(width, height) of ``rgb_array`` pictures (pixels; fits MuJoCo's default framebuffer)."""


@dataclass(frozen=True)
class HandleGraspConfig(Checked):
    """What an episode uses; every field is also a ``gymnasium.make(..., **kwargs)`` keyword.

    Attributes:
        objects: object names an episode draws from (YCB ids or names read from ``ycb_dir``,
            generated tools ``gen_<kind>[_s<N>]``, ``gen_<kind>`` being ``gen_<kind>_s0``);
            default: the generated tools. The env refuses an unknown name when it is made;
            models are built on first use.
        gripper: a registered gripper name (:func:`simgrasp.grippers.gripper_names`).
        noise: multiplicative noise sigma on the cloud, as ``ChainConfig.noise``.
        sensor: the depth sensor each view passes through (``ChainConfig.sensor``); the
            observation's ``depth`` is what it returns.
        num_views: default scene cameras (1..4, default the chain's 4); replaces
            ``scene.num_views``. Explicit ``scene.cameras`` take precedence (V = their
            number; they must share one size).
        max_points: N, the cloud size of the observation (zero-padded; larger clouds are
            subsampled with the episode seed).
        reward: ``"on_handle"``: 1.0 when the trial succeeds holding the labeled handle;
            ``"lift"``: 1.0 for any successful lift. Otherwise 0.0.
        ycb_dir: the YCB download (default ``$SIMGRASP_YCB_DIR``).
        scene: table, parking and camera layout (defaults: the chain's scene).
        trial: the grasp trial's parameters.
    """

    objects: Annotated[tuple[str, ...], MinLength(1)] = GENERATED_OBJECTS
    gripper: str = setting(DEFAULT_GRIPPER, choices=gripper_names)
    noise: NoiseSigma = 0.0
    sensor: SensorSettings = field(default_factory=SensorSettings)
    num_views: int = setting(CHAIN_VIEWS, choices=tuple(range(1, MAX_VIEWS + 1)))
    max_points: PositiveInt = 8192
    reward: RewardKind = "on_handle"
    ycb_dir: str | None = None
    scene: SceneConfig = field(default_factory=SceneConfig)
    trial: TrialConfig = field(default_factory=TrialConfig)

    def __post_init__(self) -> None:
        objects = (self.objects,) if isinstance(self.objects, str) else tuple(self.objects)
        object.__setattr__(self, "objects", objects)
        super().__post_init__()

    @property
    def scene_config(self) -> SceneConfig:
        """The scene every episode is built with (``scene`` with ``num_views``)."""
        return replace(self.scene, num_views=self.num_views)


def trial_reward(result: TrialResult, reward: RewardKind) -> float:
    """1.0 for a successful trial (on the handle, for ``"on_handle"``), else 0.0; a diverged
    simulation (``success`` None) scores 0.0."""
    lifted = result.success is True
    return float(lifted if reward == "lift" else lifted and result.on_handle)


@dataclass(frozen=True)
class _Episode:
    scene: Scene
    observation: Observation
    episode_seed: int
    terminated: bool = False


class HandleGraspEnv(gymnasium.Env[Observation, NDArray[np.float64]]):
    """Grasp an object resting on a table, once per episode (see the module docstring).

    ``reset(seed=s)`` seeds ``np_random``; every reset draws an object index and an episode
    seed from it (both, always), and ``options={"object": name, "episode_seed": k}`` overrides
    either, e.g. to reproduce ``run_chain(model_for(name), config, seed=k)``. The episode seed
    fixes the rest pose, the cloud noise and the cloud subsample; the reset info holds it.

    ``step(action)`` executes the grasp ``[x, y, z, qw, qx, qy, qz, width]``: the TCP pose
    ``world_T_tcp`` (world frame, meters; README convention: TCP midway between the pads, +z
    the approach, +y the jaw direction; the quaternion is normalized) and the jaw opening
    before closing (meters, clipped into [``MIN_OPENING``, the gripper's max opening]); a
    non-finite action or a (nearly) zero quaternion raises ``ValueError``. It runs the trial
    and returns ``reward`` (see :func:`trial_reward`), ``terminated=True``, ``truncated=False``
    and as ``info`` the trial record (``TrialResult.to_json()``: ``object``, ``grasp``,
    ``success``, ``failure``, ``on_handle`` ...) without its wall-clock ``timings_s`` (so that
    identical steps give identical infos), plus ``episode_seed``. The observation does not
    change within an episode. Stepping again needs a reset.

    ``render_mode="rgb_array"``: :meth:`render` returns a (480, 640, 3) uint8 picture from a
    free camera looking at the object (needs a GL render backend, EGL or OSMesa).

    Object models are built once per env and reused; :meth:`close` frees the GL renderer.
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 1}

    def __init__(
        self,
        config: HandleGraspConfig | None = None,
        render_mode: str | None = None,
        **overrides: Any,
    ) -> None:
        """``overrides`` replace fields of ``config`` (default :class:`HandleGraspConfig`)."""
        names = {f.name for f in fields(HandleGraspConfig)}
        unknown = sorted(set(overrides) - names)
        if unknown:
            raise TypeError(f"unknown HandleGraspEnv option(s) {unknown}; options: {sorted(names)}")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise SimgraspError(f"unsupported render_mode {render_mode!r}; use None or 'rgb_array'")
        self.config = replace(config or HandleGraspConfig(), **overrides)
        check_object_names(self.config.objects)
        self.render_mode = render_mode
        self._gripper = make_gripper(self.config.gripper)
        self.observation_space = observation_space(  # type: ignore[assignment]
            camera_layout(self.config.scene_config), self.config.max_points
        )
        self.action_space = action_space(  # type: ignore[assignment]
            self._gripper.max_opening, self.config.scene_config
        )
        self._models: dict[str, ObjectModel] = {}
        self._episode: _Episode | None = None
        self._failed_reset: str | None = None
        """Why the last reset() failed (it ended the episode before it), for step()."""
        self._renderers = RendererKeeper()

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Observation, dict[str, Any]]:
        """Start an episode; info: ``object`` (the model's name), ``episode_seed``,
        ``cloud_points`` (the cloud's size before subsampling) and ``render_backend`` (the
        depth renderer: GL, or ``raycast`` in a worker forked after its parent rendered, whose
        silhouette pixels differ, so the same seed gives another cloud). A reset that fails
        (an unknown object, say) has ended the previous episode: ``step`` then raises, naming
        it."""
        super().reset(seed=seed)
        self._end_episode()
        try:
            self._failed_reset = None
            return self._new_episode(options or {})
        except Exception as exc:
            self._failed_reset = f"{type(exc).__name__}: {exc}"
            raise

    def _new_episode(self, options: dict[str, Any]) -> tuple[Observation, dict[str, Any]]:
        object_name, episode_seed = self._draw_episode(options)
        scene = build_scene(
            self._object_model(object_name), self._gripper, self.config.scene_config, episode_seed
        )
        renderer = self._renderers.renderer_for(scene)
        seen = observe(scene, renderer, self.config.noise, episode_seed, self.config.sensor)
        cloud = seen.cloud
        observation = make_observation(
            seen.frames,
            scene.object_body,
            cloud,
            self.config.max_points,
            rng_for(episode_seed, "env", "subsample"),
        )
        self._episode = _Episode(scene, observation, episode_seed)
        info = {
            "object": scene.object_name,
            "episode_seed": episode_seed,
            "cloud_points": len(cloud),
            "render_backend": select_backend(),
        }
        return _copied(observation), info

    def step(
        self, action: NDArray[np.float64]
    ) -> tuple[Observation, float, bool, bool, dict[str, Any]]:
        """Execute the grasp ``action`` and end the episode (see the class docstring)."""
        episode = self._episode
        if episode is None and self._failed_reset is not None:
            raise RuntimeError(
                f"HandleGraspEnv.step(): the last reset() failed ({self._failed_reset}); "
                "call reset() again"
            )
        if episode is None:
            raise RuntimeError("HandleGraspEnv.step() called before reset()")
        if episode.terminated:
            raise RuntimeError(
                "the episode has terminated (one grasp per episode); call reset() before step()"
            )
        grasp = grasp_from_action(action, self._gripper.max_opening)
        result = run_trial(episode.scene, grasp, self.config.trial)
        self._episode = replace(episode, terminated=True)
        info = result.to_json()
        del info["timings_s"]
        info["episode_seed"] = episode.episode_seed
        reward = trial_reward(result, self.config.reward)
        return _copied(episode.observation), reward, True, False, info

    def render(self) -> NDArray[np.uint8] | None:
        """The scene's current state seen from a free camera aimed at the object's center of
        mass, (480, 640, 3) uint8; None without ``render_mode``."""
        if self.render_mode is None:
            return None
        if self._episode is None:
            raise RuntimeError("HandleGraspEnv.render() called before reset()")
        scene = self._episode.scene
        width, height = RENDER_SIZE
        renderer = self._renderers.renderer_for(scene)  # the one that rendered its views
        return renderer.rgb(scene.data, _object_camera(scene), width, height)

    def close(self) -> None:
        """Free the GL renderer (idempotent)."""
        self._end_episode()
        self._renderers.close()
        super().close()

    def _draw_episode(self, options: dict[str, Any]) -> tuple[str, int]:
        unknown = sorted(set(options) - set(RESET_OPTIONS))
        if unknown:
            raise SimgraspError(
                f"unknown reset option(s) {unknown}; options: {list(RESET_OPTIONS)}"
            )
        index = int(self.np_random.integers(len(self.config.objects)))
        episode_seed = int(self.np_random.integers(EPISODE_SEEDS))
        object_name = str(options.get("object", self.config.objects[index]))
        episode_seed = options.get("episode_seed", episode_seed)
        if not isinstance(episode_seed, int | np.integer) or episode_seed < 0:
            raise SimgraspError(
                f"episode_seed must be a non-negative integer, got {episode_seed!r}"
            )
        return object_name, int(episode_seed)

    def _object_model(self, name: str) -> ObjectModel:
        if name not in self._models:
            self._models[name] = model_for(name, self.config.ycb_dir)
        return self._models[name]

    def _end_episode(self) -> None:
        """Forget the episode (its renderer stays kept for the next scene built alike)."""
        self._episode = None


def _object_camera(scene: Scene) -> mujoco.MjvCamera:
    """A free camera 0.8 m from the object's center of mass, looking down at 30 degrees."""
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    camera.lookat[:] = scene.data.xipos[scene.object_body]
    camera.distance = 0.8
    camera.azimuth = 135.0
    camera.elevation = -30.0
    return camera


def _copied(observation: Observation) -> Observation:
    """A fresh copy (callers keep what they get; the env keeps its own)."""
    return {key: value.copy() for key, value in observation.items()}
