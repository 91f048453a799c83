"""How many default tabletop cameras look at the object, and how many the grasp chain fuses.

Free of mujoco imports so that command-line parsers can use it.
"""

from __future__ import annotations

from typing import Final

from simgrasp.errors import SimgraspError

MAX_VIEWS: Final = 4
"""Default viewpoints are spread evenly in azimuth around the object; at most this many."""
CHAIN_VIEWS: Final = 4
"""Cameras of the full chain (render -> detect -> plan -> execute). Four views around the table
see a thin handle from both sides: the YCB mug's strap, standing upright, is found in 10 of 10
scenes with four views and in 5 of 10 with two, where often only one face and an edge are seen."""
VIEWS_BEFORE_RECORDED: Final = 2
"""Cameras of the chain that wrote sweep records without a ``views`` field."""


def check_views(views: int) -> int:
    """``views`` if it is a whole number of default viewpoints in 1..MAX_VIEWS, else a
    ValueError."""
    if isinstance(views, bool) or not isinstance(views, int) or not 1 <= views <= MAX_VIEWS:
        raise SimgraspError(f"the number of camera views must be 1..{MAX_VIEWS}, got {views!r}")
    return views
