"""How a scene places its object on the table: the names of the rest-pose policies.

Kept free of heavy imports so that command-line parsers can list the choices.
"""

from __future__ import annotations

from typing import Literal

Placement = Literal["stable", "upright"]
PLACEMENTS: tuple[str, ...] = ("stable", "upright")
"""``"stable"``: a stable pose drawn by the probability of landing in it from a random drop;
``"upright"``: only among the stable poses that stand the object on its own base."""
