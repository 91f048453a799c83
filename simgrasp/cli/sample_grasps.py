"""``simgrasp sample-grasps OBJECT --n N --out FILE.npz``: antipodal grasps on an object's
mesh (as ACRONYM samples them), saved as a grasp set.

The grasps are in the object's mesh frame (``object_T_grasp``, ``width``) and, unless
``--no-table``, clear of the table under the object's rest pose in the scene of ``--seed``
(the scene ``label-grasps --seed`` labels them in).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path

from simgrasp.assets.placement import DEFAULT_PLACEMENT, Placement
from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.config.checks import PositiveInt
from simgrasp.errors import SimgraspError
from simgrasp.grippers.registry import DEFAULT_GRIPPER, gripper_names


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    object: str = setting(positional=True, metavar="OBJECT")
    """YCB id (048_hammer or hammer) or generated tool."""
    n: PositiveInt
    """Number of grasps."""
    out: Path
    """Output .npz file."""
    seed: int = 0
    """Seed of the sampling and of the scene whose table the grasps clear (label them with
    the same --seed)."""
    gripper: str = setting(DEFAULT_GRIPPER, choices=gripper_names)
    """The gripper whose open jaws must fit."""
    placement: Placement = DEFAULT_PLACEMENT
    """Rest pose policy of the scene whose table the grasps clear."""
    no_table: bool = False
    """Sample all around the object (free space)."""


def run(options: Options) -> int:
    from simgrasp.assets.model import model_for
    from simgrasp.grasping.labeling.grasp_sets import write_grasp_set
    from simgrasp.grasping.planning.antipodal import Table, sample_antipodal
    from simgrasp.grippers import make_gripper
    from simgrasp.scenes.config import SceneConfig
    from simgrasp.scenes.scene import build_scene

    if options.out.suffix.lower() != ".npz":
        raise SimgraspError(f"--out must end in .npz, got {options.out}")
    gripper = make_gripper(options.gripper)
    model = model_for(options.object, options.ycb_dir)
    table = None
    if not options.no_table:
        scene_config = SceneConfig(placement=options.placement)
        scene = build_scene(model, gripper, scene_config, options.seed)
        table = Table(scene.world_T_object, scene.config.table_top_z)
    start = time.perf_counter()
    poses, widths = sample_antipodal(
        model.asset.mesh, gripper.planning_geometry(), options.n, options.seed, table=table
    )
    write_grasp_set(options.out, poses, widths)
    seconds = time.perf_counter() - start
    short = f" (only {len(poses)} of {options.n} found)" if len(poses) < options.n else ""
    sys.stdout.write(f"{len(poses)} grasps{short} in {seconds:.1f} s -> {options.out}\n")
    return 0
