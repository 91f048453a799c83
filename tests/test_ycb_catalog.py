"""The YCB catalog: coverage of the local download, published masses, name lookup."""

from __future__ import annotations

from pathlib import Path

import pytest

from simgrasp.assets.ycb_catalog import YCB_CATALOG, find_ycb_entry


def test_ids_and_names_are_unique() -> None:
    ids = [e.id for e in YCB_CATALOG]
    names = [e.name for e in YCB_CATALOG]
    assert len(set(ids)) == len(ids)
    assert len(set(names)) == len(names)
    assert not set(ids) & set(names)


def test_catalog_covers_every_local_object(ycb_dir: str) -> None:
    local = {d.name for d in Path(ycb_dir).iterdir() if d.is_dir()}
    assert len(local) >= 20
    assert local <= {e.id for e in YCB_CATALOG}


@pytest.mark.parametrize(
    ("object_id", "grams"),
    [
        ("001_chips_can", 205),
        ("025_mug", 118),
        ("035_power_drill", 895),
        ("048_hammer", 665),
        ("033_spatula", 51.5),
        ("044_flat_screwdriver", 98.4),
    ],
)
def test_published_masses(object_id: str, grams: float) -> None:
    assert find_ycb_entry(object_id).mass_kg == pytest.approx(grams / 1000.0)


def test_masses_are_plausible_kilograms() -> None:
    masses = [e.mass_kg for e in YCB_CATALOG if e.mass_kg is not None]
    assert len(masses) >= 60
    assert all(0.0005 <= m <= 2.0 for m in masses)


def test_chips_can_has_no_google_scan_but_berkeley_meshes() -> None:
    chips = find_ycb_entry("001_chips_can")
    assert not chips.has_google_16k
    assert "poisson" in chips.scans
    without_google = [e.id for e in YCB_CATALOG if not e.has_google_16k]
    assert without_google == ["001_chips_can"]


@pytest.mark.parametrize("query", ["033_spatula", "spatula", "  Spatula ", "033_SPATULA"])
def test_lookup_by_id_or_bare_name(query: str) -> None:
    assert find_ycb_entry(query).id == "033_spatula"


def test_lettered_variants_have_their_own_names() -> None:
    assert find_ycb_entry("065-c_cups").name == "cups_c"
    assert find_ycb_entry("cups_c").id == "065-c_cups"
    assert find_ycb_entry("cups_c").mass_kg is None


def test_unknown_name_lists_close_matches() -> None:
    with pytest.raises(ValueError, match=r"unknown YCB object 'spatla'; did you mean 033_spatula"):
        find_ycb_entry("spatla")
    with pytest.raises(ValueError, match=r"065-a_cups.*065-j_cups"):
        find_ycb_entry("cups")
    with pytest.raises(ValueError, match=r"unknown YCB object 'zzzz'; see the YCB object list"):
        find_ycb_entry("zzzz")
