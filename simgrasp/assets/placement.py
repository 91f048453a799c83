"""How a scene places its object on the table: the names of the rest-pose policies.

Kept free of heavy imports so that command-line parsers can list the choices.
"""

from __future__ import annotations

from typing import Final, Literal, cast

from simgrasp.errors import SimgraspError

Placement = Literal["stable", "upright"]
PLACEMENTS: tuple[str, ...] = ("stable", "upright")
"""``"stable"``: a stable pose drawn by the probability of landing in it from a random drop;
``"upright"``: only among the stable poses that stand the object on its own base."""
DEFAULT_PLACEMENT: Final[Placement] = "stable"
"""Also what a sweep record written before placements existed was placed by."""


def check_placement(placement: str) -> Placement:
    """``placement`` if it names a policy, else a ValueError listing them."""
    if placement not in PLACEMENTS:
        raise SimgraspError(f"placement must be one of {', '.join(PLACEMENTS)}, got {placement!r}")
    return cast(Placement, placement)
