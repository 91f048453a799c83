"""Which objects a cluttered scene draws its distractors from (``SceneConfig.clutter_objects``).

Free of MuJoCo imports, so settings trees and command lines can use it. A set is ``generated``
(the procedurally generated tools), ``ycb`` (every YCB object in the YCB folder,
``$SIMGRASP_YCB_DIR``), ``all`` (both; only the generated ones when no YCB folder is set) or a
comma-separated list of object names. The target itself is never its own distractor.
"""

from __future__ import annotations

import os
import re

from simgrasp.errors import SimgraspError

MAX_CLUTTER = 19
"""Most distractors a scene holds (a scene of 20 objects). From 13 on, the ring around the
target fills: a few drop spots are the clipped fallback of ``_free_spot`` (overlapping a
neighbour) and an object or two may fall off the table (left out); N <= 12 scenes are as
when the cap was 12."""
CLUTTER_SETS = ("all", "generated", "ycb")
DEFAULT_CLUTTER_SET = "all"

_GENERATED_UNSIZED = re.compile(r"^gen_[a-z]+$")


def check_clutter(count: int, objects: str) -> None:
    """A ValueError naming the setting unless ``count`` is 0..MAX_CLUTTER and ``objects`` a set
    name or a list of names."""
    if isinstance(count, bool) or not isinstance(count, int) or not 0 <= count <= MAX_CLUTTER:
        raise SimgraspError(f"clutter must be a whole number 0..{MAX_CLUTTER}, got {count!r}")
    if not isinstance(objects, str) or not [n for n in objects.split(",") if n.strip()]:
        raise SimgraspError(
            f"clutter_objects must be {', '.join(CLUTTER_SETS)} or a comma list of object "
            f"names, got {objects!r}"
        )


def canonical_name(name: str) -> str:
    """The asset name an object name loads as (``gen_hammer`` is ``gen_hammer_s0``)."""
    name = name.strip()
    return f"{name}_s0" if _GENERATED_UNSIZED.match(name) else name


def distractor_pool(objects: str, target: str, ycb_dir: str | None = None) -> tuple[str, ...]:
    """The object names distractors are drawn from, in a fixed order, without ``target``
    (an asset name); a ValueError when nothing is left."""
    from simgrasp.assets.object_sets import GENERATED_OBJECTS

    if objects in CLUTTER_SETS:
        names: list[str] = []
        if objects in ("all", "generated"):
            names += GENERATED_OBJECTS
        if objects in ("all", "ycb"):
            names += _ycb_objects(ycb_dir, required=objects == "ycb")
    else:
        names = [n.strip() for n in objects.split(",") if n.strip()]
    pool = tuple(dict.fromkeys(n for n in names if canonical_name(n) != canonical_name(target)))
    if not pool:
        raise SimgraspError(
            f"clutter_objects {objects!r} holds no object other than the target {target!r}"
        )
    return pool


def _ycb_objects(ycb_dir: str | None, required: bool) -> list[str]:
    """The YCB objects of ``ycb_dir`` (or ``$SIMGRASP_YCB_DIR``); none when no folder is set,
    unless ``required`` (then its error)."""
    from simgrasp.assets.ycb import YCB_DIR_ENV, available_ycb_objects, resolve_ycb_root

    if not required and not (ycb_dir or os.environ.get(YCB_DIR_ENV)):
        return []
    return available_ycb_objects(resolve_ycb_root(ycb_dir))
