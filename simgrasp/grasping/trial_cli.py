"""``simgrasp trial``: run one grasp trial on an object in MuJoCo and report the outcome."""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.cli_args import add_placement_argument, add_views_argument

RENDER_SIZE = (640, 480)
FRAME_SECONDS = 1.0
"""How long each key frame is shown in an mp4."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "object",
        help="YCB id (025_mug or mug) or generated tool: gen_hammer (= gen_hammer_s0), or "
        "gen_hammer_s3 for the sizes drawn from seed 3",
    )
    parser.add_argument("--gripper", choices=("builtin", "robotiq_2f85"), default="builtin")
    parser.add_argument(
        "--grasp",
        nargs=7,
        type=float,
        metavar=("X", "Y", "Z", "QW", "QX", "QY", "QZ"),
        help="TCP pose (TCP between the pads, +z approach, +y jaw direction); without it the "
        "full chain runs: render the scene, detect handles, plan and execute the best grasp",
    )
    parser.add_argument(
        "--detector",
        choices=("quadric", "tenpas", "centroid", "random"),
        default="quadric",
        help="grasp proposer for the full chain (without --grasp)",
    )
    parser.add_argument(
        "--noise", type=float, default=0.0, help="multiplicative cloud noise sigma (full chain)"
    )
    parser.add_argument(
        "--grasp-frame",
        choices=("world", "object"),
        default="world",
        help="frame of --grasp: world, or the object's mesh frame (placed at its scene pose)",
    )
    parser.add_argument(
        "--width", type=float, default=None, help="jaw opening before closing (m; default max)"
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=0,
        help="seed of the scene (rest pose and yaw) and of the chain (noise, detection, "
        "planning), as in an evaluate record: the same object and seed rerun that trial",
    )
    add_placement_argument(parser)
    add_views_argument(parser)
    parser.add_argument("--ycb-dir", default=None, help="YCB root (default $SIMGRASP_YCB_DIR)")
    parser.add_argument("--json", action="store_true", help="print the trial record as JSON")
    parser.add_argument(
        "--render",
        type=Path,
        default=None,
        help="write key frames (pre-grasp, closed, lifted, perturbed): .png grid or .mp4",
    )


def run(args: argparse.Namespace) -> int:
    if args.width is not None and args.grasp is None:
        raise ValueError("--width needs --grasp (the full chain plans its own jaw opening)")
    if args.render is not None:
        _check_render_target(args.render)
    frames: list[np.ndarray] = []
    recorder = _FrameRecorder(frames) if args.render is not None else None
    trial = _manual_trial if args.grasp is not None else _chain_trial
    record = trial(args, recorder)
    if args.render is not None:
        record["render"] = _write_frames(frames, args.render)
    if args.json:
        print(json.dumps(record))
    else:
        _print_summary(record)
    return 0


def _manual_trial(args: argparse.Namespace, recorder: _FrameRecorder | None) -> dict[str, Any]:
    """Execute the grasp given with ``--grasp``."""
    from simgrasp.assets.model import build_object_model
    from simgrasp.assets.registry import load_object
    from simgrasp.grasping.grasp import Grasp, matrix_from_pose7
    from simgrasp.grasping.trial import run_trial
    from simgrasp.scenes.gripper import make_gripper
    from simgrasp.scenes.scene import SceneConfig, build_scene

    gripper = make_gripper(args.gripper)
    object_model = build_object_model(load_object(args.object, args.ycb_dir))
    scene = build_scene(object_model, gripper, SceneConfig(placement=args.placement), args.seed)
    width = gripper.max_opening if args.width is None else args.width
    if not 0 < width <= gripper.max_opening:
        raise ValueError(
            f"--width must be in (0, {gripper.max_opening}] m for gripper {gripper.name!r}, "
            f"got {width}"
        )
    pose = matrix_from_pose7(args.grasp, "--grasp")
    if args.grasp_frame == "object":
        grasp = Grasp.from_object_frame(pose, scene.world_T_object, width, source="cli")
    else:
        grasp = Grasp(pose, width, source="cli")
    return run_trial(scene, grasp, on_phase=recorder).to_json()


def _chain_trial(args: argparse.Namespace, recorder: _FrameRecorder | None) -> dict[str, Any]:
    """Render, detect, plan and execute (see :mod:`simgrasp.grasping.chain`)."""
    from simgrasp.assets.model import build_object_model
    from simgrasp.assets.registry import load_object
    from simgrasp.grasping.chain import ChainConfig, run_chain

    config = (
        ChainConfig(detector=args.detector, gripper=args.gripper, noise=args.noise)
        .with_placement(args.placement)
        .with_views(args.views)
    )
    object_model = build_object_model(load_object(args.object, args.ycb_dir))
    return run_chain(object_model, config, args.seed, on_phase=recorder).to_json()


def _check_render_target(path: Path) -> None:
    suffix = path.suffix.lower()
    if suffix not in (".png", ".mp4"):
        raise ValueError(f"--render must end in .png or .mp4, got {path}")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise ValueError(
            f"--render {path}: writing mp4 needs the ffmpeg encoder, which is not installed; "
            "use a .png path for a grid of the key frames"
        )
    from simgrasp.evaluation.out_dir import check_output_file

    check_output_file(path, "--render")


class _FrameRecorder:
    """Phase callback that renders one RGB picture per key moment of a trial, with the
    process's kept renderer (:mod:`simgrasp.scenes.kept_renderer`; the full chain has already
    rendered its depth views with it)."""

    def __init__(self, frames: list[np.ndarray]) -> None:
        self.frames = frames
        self._camera: Any = None

    def __call__(self, _phase: str, scene: Any) -> None:
        from simgrasp.scenes.kept_renderer import kept_renderer

        if self._camera is None:
            import mujoco

            self._camera = mujoco.MjvCamera()
            self._camera.type = mujoco.mjtCamera.mjCAMERA_FREE
            self._camera.distance = 0.9
            self._camera.azimuth = 135.0
            self._camera.elevation = -25.0
            self._camera.lookat[:] = scene.world_T_object[:3, 3] + np.array([0.0, 0.0, 0.12])
        self.frames.append(kept_renderer(scene).rgb(scene.data, self._camera, *RENDER_SIZE))


def _write_frames(frames: list[np.ndarray], path: Path) -> str | None:
    """Write the key frames to ``path``; None, and nothing written, when the chain found no
    grasp to execute (so no key frame was taken)."""
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


def _write_mp4(frames: list[np.ndarray], path: Path) -> None:
    height, width = frames[0].shape[:2]
    command = [
        "ffmpeg", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
        "-s", f"{width}x{height}", "-r", str(1.0 / FRAME_SECONDS), "-i", "-",
        "-pix_fmt", "yuv420p", "-vf", "fps=25", str(path),
    ]  # fmt: skip
    stream = b"".join(np.ascontiguousarray(f).tobytes() for f in frames)
    done = subprocess.run(command, input=stream, capture_output=True, check=False)
    if done.returncode != 0:
        raise ValueError(f"ffmpeg could not write {path}: {done.stderr.decode().strip()}")


def _print_summary(record: dict[str, Any]) -> None:
    """A few lines for a person: the chain's detection (full chain only) and, when a grasp
    was executed, how it went."""
    outcome = {True: "success", False: f"failed ({record['failure']})", None: "sim unstable"}
    lines = [
        f"object       {record['object']}  (gripper {record['gripper']}, seed {record['seed']})",
        f"outcome      {outcome[record['success']]}",
    ]
    if "handles" in record:
        lines.append(
            f"detection    {record['handles']} handle(s) from {record['candidates']} "
            f"candidates on {record['cloud_points']} cloud points; "
            f"{record['grasp_candidates']} collision-free grasp(s)"
        )
    if record["failure"] != "no_grasp":
        handle_share = f"share of contacts {record['handle_fraction']:.2f}"
        lines += [
            f"on handle    {record['on_handle']}  ({handle_share})",
            f"lift height  {record['lift_height']:.3f} m",
            f"sim time     {record['sim_time']:.2f} s in {record['timings_s']['total']:.2f} s wall",
        ]
    if "render" in record:
        lines.append(f"frames       {record['render'] or 'none: no grasp was executed'}")
    sys.stdout.write("\n".join(lines) + "\n")
