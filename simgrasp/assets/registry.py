"""Look objects up by name: generated tools (``gen_<kind>``) or YCB objects (id or bare name)."""

from __future__ import annotations

import os
import re

from simgrasp.assets.generated import GENERATED_KINDS, generate_tool
from simgrasp.assets.object import ObjectAsset

__all__ = ["GENERATED_KINDS", "default_objects", "load_object"]

_GENERATED = re.compile(r"^gen_(?P<kind>[a-z]+)(?:_s(?P<seed>\d+))?$")


def load_object(
    name: str, ycb_dir: str | os.PathLike[str] | None = None, *, seed: int = 0
) -> ObjectAsset:
    """Load ``gen_<kind>`` (sizes drawn from ``seed``), ``gen_<kind>_s<N>`` (seed N), or a
    YCB object (``"025_mug"`` or ``"mug"``) from ``ycb_dir`` / ``$SIMGRASP_YCB_DIR``."""
    match = _GENERATED.match(name)
    if match:
        kind = match["kind"]
        if kind not in GENERATED_KINDS:
            raise ValueError(
                f"unknown generated object {name!r}; generated objects are "
                f"{', '.join(default_objects())}"
            )
        return generate_tool(kind, int(match["seed"]) if match["seed"] else seed)
    if name.startswith("gen_"):
        raise ValueError(
            f"bad generated object name {name!r}: expected gen_<kind> or gen_<kind>_s<seed> "
            f"with kind one of {', '.join(GENERATED_KINDS)}"
        )
    from simgrasp.assets.ycb import load_ycb_object
    from simgrasp.assets.ycb_catalog import find_ycb_entry

    try:
        find_ycb_entry(name)
    except ValueError as exc:
        raise ValueError(
            f"{exc}; generated objects are {', '.join(default_objects())} "
            "(add _s<seed> to pick sizes)"
        ) from None
    return load_ycb_object(name, ycb_dir)


def default_objects() -> list[str]:
    """The generated tools, the objects used when no YCB download is present."""
    return [f"gen_{kind}" for kind in GENERATED_KINDS]
