"""``simgrasp sample-grasps OBJECT --n N --out FILE.npz``: antipodal grasps on an object's
mesh (as ACRONYM samples them), saved as a grasp set.

The grasps are in the object's mesh frame (``object_T_grasp``, ``width``; ``made_by``: the
object, count, seed and settings that drew them, as JSON text) and, unless
``--no-table``, clear of the table under the object's rest pose in the scene of ``--seed``
(the scene ``label-grasps --seed`` labels them in).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path

from simgrasp.assets.placement import DEFAULT_PLACEMENT, Placement
from simgrasp.cli.object_options import MeshObjectOptions
from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.config.checks import PositiveInt
from simgrasp.grippers.registry import DEFAULT_GRIPPER, gripper_names

EXAMPLES = ("simgrasp sample-grasps 048_hammer --n 2000 --out grasps.npz",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource, MeshObjectOptions):
    object: str = setting(positional=True, metavar="OBJECT")
    """YCB id (048_hammer or hammer), generated tool or mesh file (read with
    --scale/--units/--mass/...)."""
    n: PositiveInt
    """Number of grasps."""
    out: Path = setting(output="file", suffixes=(".npz",))
    """Output .npz file."""
    seed: int = setting(0, main=True)
    """Seed of the sampling and of the scene whose table the grasps clear (label them with
    the same --seed)."""
    gripper: str = setting(DEFAULT_GRIPPER, choices=gripper_names, main=True)
    """The gripper whose open jaws must fit."""
    placement: Placement = DEFAULT_PLACEMENT
    """Rest pose policy of the scene whose table the grasps clear."""
    no_table: bool = False
    """Sample all around the object (free space)."""


def run(options: Options) -> int:
    from simgrasp.api import sample_grasps
    from simgrasp.grasping.labeling.grasp_sets import write_grasp_set

    start = time.perf_counter()
    grasps = sample_grasps(
        options.object_name(options.object),
        options.n,
        seed=options.seed,
        gripper=options.gripper,
        placement=options.placement,
        table=not options.no_table,
        ycb_dir=options.ycb_dir,
    )
    made_by = {
        "command": "sample-grasps",
        "object": options.object_name(options.object),
        "n": options.n,
        "seed": options.seed,
        "gripper": options.gripper,
        "placement": options.placement,
        "table": not options.no_table,
    }
    write_grasp_set(options.out, grasps.object_T_tcp, grasps.width, made_by)
    seconds = time.perf_counter() - start
    found = len(grasps.width)
    short = f" (only {found} of {options.n} found)" if found < options.n else ""
    sys.stdout.write(f"{found} grasps{short} in {seconds:.1f} s -> {options.out}\n")
    return 0
