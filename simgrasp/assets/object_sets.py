"""Named sets of objects (``generated``, ``families``, ``paper``, ``ycb``, ``all``) and their
expansion.

One meaning everywhere: ``all`` is every object with a handle label of the sets that came
first (the generated tools and the labeled YCB objects); ``ycb`` the labeled YCB objects;
``paper`` the paper's eight; ``families`` the procedural tool families
(:mod:`simgrasp.assets.families`), kept out of ``all`` so that the committed sweeps of ``all``
keep their objects.
"""

from __future__ import annotations

from collections.abc import Iterable

from simgrasp.assets.families import FAMILY_KINDS
from simgrasp.assets.generated import GENERATED_KINDS

PAPER_OBJECTS = (
    "001_chips_can",
    "014_lemon",
    "025_mug",
    "033_spatula",
    "030_fork",
    "035_power_drill",
    "044_flat_screwdriver",
    "048_hammer",
)
"""The YCB objects of the paper's Table I."""
LABELED_EXTRA = (
    "031_spoon",
    "032_knife",
    "043_phillips_screwdriver",
    "042_adjustable_wrench",
    "037_scissors",
    "019_pitcher_base",
    "011_banana",
)
"""YCB objects we labeled beyond the paper's."""
TRAINING_KINDS = ("strap_mug", "drill")
"""Generated kinds made for training the single-view classifier
(``scripts/train_candidate_classifier.py``), loadable by name (``gen_strap_mug_s3``,
``gen_drill_s1``) but kept out of the ``generated`` set, so the committed sweeps of that set
keep their objects."""
CHECK_KINDS = ("knife", "wrench")
"""Generated kinds made for checking the automatic handle labeler on long tools
(``scripts/generated_labels.py``), loadable by name (``gen_knife_s2``, ``gen_wrench_s0``) and
kept out of the ``generated`` set like :data:`TRAINING_KINDS`."""
GENERATED_OBJECTS = tuple(
    f"gen_{kind}" for kind in GENERATED_KINDS if kind not in TRAINING_KINDS + CHECK_KINDS
)
"""The procedurally generated tools (sizes of seed 0), the default without a YCB download."""

FAMILY_OBJECTS = tuple(f"gen_{kind}" for kind in FAMILY_KINDS)
"""The tool families' objects (sizes of seed 0, as ``generated``'s), one per kind."""

OBJECT_SETS: dict[str, tuple[str, ...]] = {
    "generated": GENERATED_OBJECTS,
    "families": FAMILY_OBJECTS,
    "paper": PAPER_OBJECTS,
    "ycb": PAPER_OBJECTS + LABELED_EXTRA,
    "all": GENERATED_OBJECTS + PAPER_OBJECTS + LABELED_EXTRA,
}


def expand_objects(names: Iterable[str]) -> list[str]:
    """Object names with the set names of :data:`OBJECT_SETS` expanded, first occurrence
    kept (other names pass through, checked when loaded)."""
    expanded = [obj for name in names for obj in OBJECT_SETS.get(name, (name,))]
    return list(dict.fromkeys(expanded))
