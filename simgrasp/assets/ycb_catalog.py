"""The YCB object catalog: ids, names, published masses and which scans exist.

Masses are the measured masses published with the object set:
B. Calli, A. Walsman, A. Singh, S. Srinivasa, P. Abbeel, A. M. Dollar, "Benchmarking in
Manipulation Research: Using the Yale-CMU-Berkeley Object and Model Set", IEEE Robotics &
Automation Magazine 22(3):36-52, 2015, Table 1 (also on the object list at ycbbenchmarks.com).
Where Table 1 gives one mass for a multi-part set (cups, marbles, toy airplane, Lego Duplo,
colored wood blocks), the single parts have no published mass and ``mass_kg`` is ``None``.

Scans: the Berkeley meshes (``poisson``, ``tsdf``) and the Google scans (``google_16k``,
``google_64k``, ``google_512k``) are assumed for every object except ``001_chips_can``, which
has no Google scan (its ``poisson`` mesh is used instead). This was checked against the
shared 20-object download, not against the server for every object; a missing archive is
reported by ``simgrasp fetch-ycb`` as an HTTP error. The ids follow the official download
list (``objects.json``), which misspells the skillet as ``027-skillet``; the catalog uses
``027_skillet``, as the download file names do.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

from simgrasp.errors import SimgraspError

GOOGLE_SCANS = ("google_16k", "google_64k", "google_512k")
BERKELEY_SCANS = ("poisson", "tsdf")


@dataclass(frozen=True)
class YcbEntry:
    """One YCB object.

    Attributes:
        id: official id, e.g. ``"033_spatula"`` (the download's folder name).
        name: the id without its number, e.g. ``"spatula"``; lettered variants keep their
            letter, e.g. ``"cups_a"`` for ``"065-a_cups"``.
        mass_kg: published mass in kilograms, ``None`` if the set publishes none for it.
        scans: available mesh resolutions, e.g. ``("google_16k", ..., "poisson", "tsdf")``.
    """

    id: str
    name: str
    mass_kg: float | None
    scans: tuple[str, ...]

    @property
    def has_google_16k(self) -> bool:
        return "google_16k" in self.scans


def _entry(object_id: str, grams: float | None, google: bool = True) -> YcbEntry:
    number, _, rest = object_id.partition("_")
    _, _, letter = number.partition("-")
    name = f"{rest}_{letter}" if letter else rest
    scans = (GOOGLE_SCANS if google else ()) + BERKELEY_SCANS
    return YcbEntry(object_id, name, None if grams is None else grams / 1000.0, scans)


def _variants(number: str, name: str, letters: str) -> tuple[YcbEntry, ...]:
    return tuple(_entry(f"{number}-{letter}_{name}", None) for letter in letters)


# (id, grams) from Table 1 of Calli et al. 2015.
YCB_CATALOG: tuple[YcbEntry, ...] = (
    # food items
    _entry("001_chips_can", 205, google=False),
    _entry("002_master_chef_can", 414),
    _entry("003_cracker_box", 411),
    _entry("004_sugar_box", 514),
    _entry("005_tomato_soup_can", 349),
    _entry("006_mustard_bottle", 603),
    _entry("007_tuna_fish_can", 171),
    _entry("008_pudding_box", 187),
    _entry("009_gelatin_box", 97),
    _entry("010_potted_meat_can", 370),
    _entry("011_banana", 66),
    _entry("012_strawberry", 18),
    _entry("013_apple", 68),
    _entry("014_lemon", 29),
    _entry("015_peach", 33),
    _entry("016_pear", 49),
    _entry("017_orange", 47),
    _entry("018_plum", 25),
    # kitchen items
    _entry("019_pitcher_base", 178),
    _entry("021_bleach_cleanser", 1131),
    _entry("022_windex_bottle", 1022),
    _entry("023_wine_glass", 133),
    _entry("024_bowl", 147),
    _entry("025_mug", 118),
    _entry("026_sponge", 6.2),
    _entry("027_skillet", 950),
    _entry("028_skillet_lid", 652),
    _entry("029_plate", 279),
    _entry("030_fork", 34),
    _entry("031_spoon", 30),
    _entry("032_knife", 31),
    _entry("033_spatula", 51.5),
    # tool items
    _entry("035_power_drill", 895),
    _entry("036_wood_block", 729),
    _entry("037_scissors", 82),
    _entry("038_padlock", 208),
    _entry("039_key", 10.1),
    _entry("040_large_marker", 15.8),
    _entry("041_small_marker", 8.2),
    _entry("042_adjustable_wrench", 252),
    _entry("043_phillips_screwdriver", 97),
    _entry("044_flat_screwdriver", 98.4),
    _entry("046_plastic_bolt", 3.6),
    _entry("047_plastic_nut", 1.0),
    _entry("048_hammer", 665),
    _entry("049_small_clamp", 19.2),
    _entry("050_medium_clamp", 59),
    _entry("051_large_clamp", 125),
    _entry("052_extra_large_clamp", 202),
    # shape items
    _entry("053_mini_soccer_ball", 123),
    _entry("054_softball", 191),
    _entry("055_baseball", 148),
    _entry("056_tennis_ball", 58),
    _entry("057_racquetball", 41),
    _entry("058_golf_ball", 46),
    _entry("059_chain", 98),
    _entry("061_foam_brick", 28),
    _entry("062_dice", 5.2),
    *_variants("063", "marbles", "abcdef"),
    *_variants("065", "cups", "abcdefghij"),
    # task items
    *_variants("070", "colored_wood_blocks", "ab"),
    _entry("071_nine_hole_peg_test", 1435),
    *_variants("072", "toy_airplane", "abcdefghijk"),
    *_variants("073", "lego_duplo", "abcdefghijklm"),
    _entry("076_timer", 102),
    _entry("077_rubiks_cube", 94.5),
)

_BY_KEY: dict[str, YcbEntry] = {
    key: entry for entry in YCB_CATALOG for key in (entry.id.lower(), entry.name.lower())
}


def find_ycb_entry(name: str) -> YcbEntry:
    """The catalog entry for a full id (``"033_spatula"``) or a bare name (``"spatula"``).

    Case and surrounding whitespace are ignored; spaces count as underscores. Raises
    ``ValueError`` listing close matches when nothing matches.
    """
    key = name.strip().lower().replace(" ", "_")
    entry = _BY_KEY.get(key)
    if entry is not None:
        return entry
    variants = [e.id for e in YCB_CATALOG if e.name.startswith(f"{key}_")]
    close = difflib.get_close_matches(key, list(_BY_KEY), n=5, cutoff=0.6)
    ids = sorted(set(variants) | {_BY_KEY[c].id for c in close})
    hint = f"; did you mean {', '.join(ids)}?" if ids else "; see the YCB object list"
    raise SimgraspError(f"unknown YCB object {name!r}{hint}")
