"""``simgrasp scenes export``: cluttered scenes as organized, labeled PCD files.

Each seed's scene (the target with ``--clutter`` distractors, :mod:`simgrasp.scenes.clutter`)
is seen by every camera through ``--sensor``; each view is written as
``OUT/<object>_s<seed>_<camera>.pcd`` (a mesh file object: its file's stem) in osd-learn's
layout: organized 640 x 480, binary, fields ``label x y z rgba``, meters in the camera's
OpenCV frame (``VIEWPOINT`` at the origin), NaN where the sensor returned nothing. Labels are
exact: 0 invalid, 1 the table, 20 the target, 30, 40, ... the distractors in body order
(``simgrasp segment`` reads the files).

One export at a time holds ``--out``; its ``run.json`` records the settings the views were made
with (:mod:`simgrasp.evaluation.scene_export`). A rerun with other settings is refused; one with the
same settings skips the seeds whose views are all there, so a killed export resumes and more
``--seeds`` add the missing ones.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Literal

import numpy as np

from simgrasp.cli import invocation
from simgrasp.cli.object_options import MeshObjectOptions
from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.perception.sensors.settings import SensorSettings

TARGET_LABEL, FIRST_DISTRACTOR_LABEL, TABLE_LABEL = 20, 30, 1


EXAMPLES = ("simgrasp scenes export --clutter 5 --seeds 10 --sensor kinect --out out/scenes",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource, MeshObjectOptions):
    action: Literal["export"] = setting(positional=True, metavar="ACTION")
    """export: write the scenes' views as labeled PCD files."""
    object: str = setting("gen_hammer", main=True)
    """The target object (YCB id, generated tool or mesh file, read with
    --scale/--units/--mass/...)."""
    seeds: int = setting(3, main=True)
    """Scenes of seeds 0..N-1."""
    out: Path = setting(output="dir")
    """Output directory."""
    chain: ChainConfig = setting(default_factory=ChainConfig, flatten=True)


def run(options: Options) -> int:
    """Export the views of seeds ``0..--seeds-1`` into ``--out``, holding it for the run and
    skipping the seeds a run of the same settings finished there (module docstring)."""
    from simgrasp.assets.mesh_object import file_stem
    from simgrasp.assets.model import model_for
    from simgrasp.evaluation.scene_export import (
        camera_names,
        claim_export_dir,
        export_identity,
        finished_seeds,
        refuse_other_command,
        spans,
    )
    from simgrasp.grippers import make_gripper
    from simgrasp.runs.out_dir import claim_out_dir
    from simgrasp.scenes.kept_renderer import RendererKeeper
    from simgrasp.scenes.scene import build_scene

    if options.seeds < 1:
        raise SimgraspError(f"--seeds must be >= 1, got {options.seeds}")
    name, out, chain = options.object_name(options.object), options.out, options.chain
    model, gripper = model_for(name, options.ycb_dir), make_gripper("builtin")
    identity = export_identity(name, model.asset.name, chain.scene, chain.sensor)
    stem, cameras = file_stem(name), camera_names(chain.scene)
    with (
        claim_out_dir(out, invocation(), partial(refuse_other_command, out)),
        RendererKeeper() as renderers,
    ):
        claim_export_dir(out, identity)
        done = finished_seeds(out, stem, options.seeds, cameras)
        if done:
            print(f"skipped seeds {spans(done)}: their views are already in {out}")
        for seed in sorted(set(range(options.seeds)) - set(done)):
            scene = build_scene(model, gripper, chain.scene, seed)
            _export_views(scene, chain.sensor, out, stem, renderers.renderer_for(scene))
    return 0


def _export_views(scene, sensor: SensorSettings, out: Path, stem: str, renderer) -> None:  # noqa: ANN001
    """Write every camera's view of ``scene`` (a Scene; ``renderer`` a SceneRenderer for it:
    lazy imports) through ``sensor`` as ``OUT/<stem>_s<seed>_<camera>.pcd`` and print each
    path."""
    from simgrasp.evaluation.scene_export import view_path
    from simgrasp.scenes.observe import observe

    for frame in observe(scene, renderer, 0.0, scene.seed, sensor).frames:
        rgb = renderer.rgb(scene.data, frame.camera_name, *frame.depth.shape[::-1])
        path = view_path(out, stem, scene.seed, frame.camera_name)
        _write_pcd(path, frame, _labels(scene, frame), rgb)
        print(path)


def _labels(scene, frame) -> np.ndarray:  # noqa: ANN001 (Scene, DepthFrame: lazy imports)
    """(H, W) uint32 osd-learn labels of ``frame``'s pixels."""
    labels = np.zeros(frame.depth.shape, dtype=np.uint32)
    labels[frame.geom_ids == scene.table_geom] = TABLE_LABEL
    labels[frame.body_ids == scene.object_body] = TARGET_LABEL
    for index, distractor in enumerate(scene.distractors):
        body = scene.model.body(distractor.body).id
        labels[frame.body_ids == body] = FIRST_DISTRACTOR_LABEL + 10 * index
    labels[~(frame.depth > 0)] = 0
    return labels


def _write_pcd(path: Path, frame, labels: np.ndarray, rgb: np.ndarray) -> None:  # noqa: ANN001
    """One organized binary PCD: ``label x y z rgba`` in the camera's OpenCV frame (m)."""
    from simgrasp.evaluation.scene_export import write_whole
    from simgrasp.perception.camera import depth_to_points_cam

    height, width = frame.depth.shape
    points_cam, pixels = depth_to_points_cam(frame.depth, frame.intrinsics)
    xyz = np.full((height * width, 3), np.nan, dtype=np.float32)
    xyz[pixels] = points_cam
    color = rgb.reshape(-1, 3).astype(np.uint32)
    rows = np.zeros(
        height * width,
        dtype=[("label", "<u4"), ("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgba", "<u4")],
    )
    rows["label"], rows["x"], rows["y"], rows["z"] = labels.reshape(-1), *xyz.T
    rows["rgba"] = (255 << 24) | (color[:, 0] << 16) | (color[:, 1] << 8) | color[:, 2]
    header = (
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
        "FIELDS label x y z rgba\nSIZE 4 4 4 4 4\nTYPE U F F F U\nCOUNT 1 1 1 1 1\n"
        f"WIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\n"
        f"POINTS {height * width}\nDATA binary\n"
    )
    write_whole(path, header.encode("ascii") + rows.tobytes())
