"""Pictures of a trial's key moments (pre-grasp, closed, lifted, perturbed): recorded by a
phase callback with the process's kept renderer, written as a PNG grid or an mp4."""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.errors import SimgraspError
from simgrasp.scenes.kept_renderer import RendererKeeper

RENDER_SIZE = (640, 480)
"""(width, height) of each key frame (pixels)."""
FRAME_SECONDS = 1.0
"""How long each key frame is shown in an mp4."""


def check_frames_target(path: Path) -> None:
    """Fail before any work when key frames cannot be written to ``path`` (.png or .mp4)."""
    suffix = path.suffix.lower()
    if suffix not in (".png", ".mp4"):
        raise SimgraspError(f"--render must end in .png or .mp4, got {path}")


class FrameRecorder:
    """Phase callback that renders one RGB picture per key moment of a trial, with the
    renderer ``renderers`` keeps for the trial's scene (give it the session's: the full chain
    has already rendered its depth views with it), from a free camera ``distance`` (m) away.

    By default the camera looks down 25 degrees at a point 12 cm above where the object is at
    the first key moment (its rest pose on the table). ``aim_world`` (a world point, m) and
    ``view_world`` (the camera's viewing direction, world frame) set both instead, e.g. across
    a grasp's jaws at its TCP."""

    def __init__(
        self,
        renderers: RendererKeeper,
        distance: float = 0.9,
        aim_world: NDArray[np.float64] | None = None,
        view_world: NDArray[np.float64] | None = None,
    ) -> None:
        self.frames: list[np.ndarray] = []
        self.renderers = renderers
        self.distance = distance
        self.aim_world = aim_world
        self.view_world = view_world
        self._camera: mujoco.MjvCamera | None = None

    def __call__(self, _phase: str, scene: Any) -> None:
        if self._camera is None:
            self._camera = self._placed(scene)
        self.frames.append(
            self.renderers.renderer_for(scene).rgb(scene.data, self._camera, *RENDER_SIZE)
        )

    def _placed(self, scene: Any) -> mujoco.MjvCamera:
        camera = mujoco.MjvCamera()
        camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        camera.distance = self.distance
        camera.azimuth, camera.elevation = 135.0, -25.0
        if self.view_world is not None:
            view = np.asarray(self.view_world, dtype=float)
            view = view / np.linalg.norm(view)
            camera.azimuth = float(np.degrees(np.arctan2(view[1], view[0])))
            camera.elevation = float(np.degrees(np.arcsin(np.clip(view[2], -1.0, 1.0))))
        aim = scene.object_pose()[:3, 3] + [0.0, 0.0, 0.12]
        camera.lookat[:] = aim if self.aim_world is None else self.aim_world
        return camera


def write_frames(frames: list[np.ndarray], path: Path) -> str | None:
    """Write the key frames to ``path``; None, and nothing written, when no key frame was
    taken (the chain found no grasp to execute)."""
    if not frames:
        return None
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix.lower() == ".mp4":
        _write_mp4(frames, path)
        return str(path)
    from PIL import Image

    height, width = frames[0].shape[:2]
    columns = 2 if len(frames) > 1 else 1
    rows = (len(frames) + columns - 1) // columns
    grid = np.full((rows * height, columns * width, 3), 255, dtype=np.uint8)
    for k, frame in enumerate(frames):
        r, c = divmod(k, columns)
        grid[r * height : (r + 1) * height, c * width : (c + 1) * width] = frame
    Image.fromarray(grid).save(path)
    return str(path)


def ffmpeg_binary() -> str:
    """The ffmpeg executable shipped in the imageio-ffmpeg wheel (no system ffmpeg needed)."""
    import imageio_ffmpeg

    return str(imageio_ffmpeg.get_ffmpeg_exe())


def _write_mp4(frames: list[np.ndarray], path: Path) -> None:
    height, width = frames[0].shape[:2]
    command = [
        ffmpeg_binary(), "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
        "-s", f"{width}x{height}", "-r", str(1.0 / FRAME_SECONDS), "-i", "-",
        "-pix_fmt", "yuv420p", "-vf", "fps=25", str(path),
    ]  # fmt: skip
    stream = b"".join(np.ascontiguousarray(f).tobytes() for f in frames)
    done = subprocess.run(command, input=stream, capture_output=True, check=False)
    if done.returncode != 0:
        raise SimgraspError(f"ffmpeg could not write {path}: {done.stderr.decode().strip()}")
