"""``scripts/family_detection.py``: the scenes it plans and the table of its rows."""

from __future__ import annotations

from types import ModuleType

import pytest
from script_modules import SCRIPTS, load_script

from simgrasp.errors import SimgraspError


@pytest.fixture(scope="module")
def script() -> ModuleType:
    with pytest.MonkeyPatch.context() as patch:
        patch.syspath_prepend(str(SCRIPTS))  # its sibling import of generated_labels
        return load_script("family_detection")


def test_vessels_are_also_stood_upright_and_bad_names_refused(script: ModuleType) -> None:
    options = script.Options(kinds=("cup", "spoon"), seeds=(7,), upright_kinds=("cup",))
    assert script._plan(options) == [
        ("cup", 7, "stable"),
        ("cup", 7, "upright"),
        ("spoon", 7, "stable"),
    ]
    with pytest.raises(SimgraspError, match="teapot"):
        script._plan(script.Options(kinds=("teapot",)))
    with pytest.raises(SimgraspError, match="sideways"):
        script._plan(script.Options(kinds=("cup",), placements=("sideways",)))


def test_table_pools_candidates_and_counts_top_handles(script: ModuleType) -> None:
    def row(view: object, sensor: str, on: int, top: bool) -> dict[str, object]:
        named = {"kind": "cup", "placement": "stable", "sensor": sensor, "view": view}
        return {**named, "candidates": 10, "on_handle": on, "top_on_handle": top}

    rows = [row(0, "ideal", 10, True), row(1, "ideal", 0, False), row("fused", "ideal", 5, True)]
    rows.append(row("fused", "kinect", 2, False))
    text = script.table(rows)
    cup = next(line for line in text.splitlines() if line.startswith("| cup"))
    assert cup == "| cup | stable | 0.50 (1/2) | 0.50 (1/1) | — (0/0) | 0.20 (0/1) |"
