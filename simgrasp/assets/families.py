"""The procedural tool families: kinds of generated object, each drawn by seed with an exact
handle label, grouped in the families the documentation pictures
(``docs/concepts/families.md``). Loadable as ``gen_<kind>`` / ``gen_<kind>_s<N>`` like the
older generated kinds, and gathered in the ``families`` object set
(:mod:`simgrasp.assets.object_sets`); the ``generated`` set keeps its seven objects."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from simgrasp.assets.family_kitchen import frying_pan, ladle, saucepan, spoon
from simgrasp.assets.family_tools import brush, chef_knife, pliers, scissors, table_knife
from simgrasp.assets.family_vessels import cup, jug, kettle
from simgrasp.assets.generated_shapes import Built

Builder = Callable[[np.random.Generator], Built]

FAMILIES: dict[str, tuple[str, ...]] = {
    "spoons and ladles": ("spoon", "ladle"),
    "pans": ("frying_pan", "saucepan"),
    "loop handles": ("cup", "jug", "kettle"),
    "two grips": ("scissors", "pliers"),
    "knives": ("chef_knife", "table_knife"),
    "brushes": ("brush",),
}
"""Family -> its kinds (``gen_<kind>``)."""

FAMILY_BUILDERS: dict[str, Builder] = {
    "spoon": spoon,
    "ladle": ladle,
    "frying_pan": frying_pan,
    "saucepan": saucepan,
    "cup": cup,
    "jug": jug,
    "kettle": kettle,
    "scissors": scissors,
    "pliers": pliers,
    "chef_knife": chef_knife,
    "table_knife": table_knife,
    "brush": brush,
}
"""Kind -> builder (sizes drawn from the generator; parts, label regions, whole-object)."""

FAMILY_KINDS: tuple[str, ...] = tuple(FAMILY_BUILDERS)
