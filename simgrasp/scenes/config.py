"""Scene layout settings (meters): table, parked gripper, cameras and how the object rests.

Free of MuJoCo imports, so settings trees and command lines can use it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

from simgrasp.assets.placement import DEFAULT_PLACEMENT, Placement
from simgrasp.config import setting
from simgrasp.config.checks import Checked, NonNegative, Positive, Range
from simgrasp.scenes.camera_spec import CameraSpec
from simgrasp.scenes.clutter_sets import DEFAULT_CLUTTER_SET, MAX_CLUTTER, check_clutter
from simgrasp.scenes.views import MAX_VIEWS


@dataclass(frozen=True)
class SceneConfig(Checked):
    """Scene layout (meters, seconds).

    Attributes:
        table_top_z: height of the table's top face (world z).
        table_half_size: half extents of the table box (x, y, thickness/2).
        table_friction: sliding friction of the table top.
        park_height: TCP height of the parked gripper above the table top.
        cameras: explicit cameras; empty means ``num_views`` default tabletop viewpoints
            (640x480, 58 deg vertical FoV) looking at the object.
        num_views: number of default viewpoints (1..4) when ``cameras`` is empty.
        random_yaw: rotate the object's rest pose by a seeded random yaw about world z.
        placement: ``"stable"``, a rest pose drawn among all stable poses by the probability
            of landing in it from a random drop, or ``"upright"``, only among the poses that
            stand the object on its own base (+z up), as a person places a mug.
        clutter: distractor objects (0..19) drawn by the seed, dropped around the object and
            settled by the simulator before the cameras look (:mod:`simgrasp.scenes.clutter`).
        clutter_objects: what distractors are drawn from: ``all`` (every object we have but
            the target: the generated tools, and the YCB objects when ``$SIMGRASP_YCB_DIR``
            is set), ``generated``, ``ycb`` or a comma list of object names.
    """

    table_top_z: float = 0.0
    table_half_size: tuple[Positive, Positive, Positive] = (0.5, 0.5, 0.025)
    table_friction: NonNegative = 0.6
    park_height: Annotated[float, Range(gt=0.3)] = 1.2
    cameras: tuple[CameraSpec, ...] = ()
    num_views: int = setting(1, flag="--views", choices=tuple(range(1, MAX_VIEWS + 1)))
    random_yaw: bool = True
    placement: Placement = setting(DEFAULT_PLACEMENT, flag="--placement", main=True)
    clutter: int = setting(0, flag="--clutter", choices=tuple(range(MAX_CLUTTER + 1)))
    clutter_objects: str = setting(
        DEFAULT_CLUTTER_SET, flag="--clutter-objects", metavar="all|generated|ycb|NAMES"
    )

    def _check(self) -> None:
        check_clutter(self.clutter, self.clutter_objects)
