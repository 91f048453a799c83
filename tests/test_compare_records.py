"""``scripts/compare_records.py``: a rerun's records against committed ones, past a field the
newer run adds and last-bit float differences."""

from __future__ import annotations

import gzip
import json
from pathlib import Path
from types import ModuleType

import pytest
from script_modules import load_script


@pytest.fixture(scope="module")
def script() -> ModuleType:
    return load_script("compare_records")


def _trial(seed: int, lift: float, **extra: object) -> dict[str, object]:
    return {"object": "025_mug", "seed": seed, "success": True, "lift_height": lift, **extra}


def _write(folder: Path, rows: list[dict[str, object]], gz: bool = False) -> Path:
    folder.mkdir()
    text = "".join(json.dumps(row) + "\n" for row in rows)
    if gz:
        (folder / "trials.jsonl.gz").write_bytes(gzip.compress(text.encode()))
    else:
        (folder / "trials.jsonl").write_text(text)
    return folder


def test_a_new_field_is_named_and_ignored_and_floats_rounded(
    script: ModuleType, tmp_path: Path
) -> None:
    committed = _write(tmp_path / "a", [_trial(0, 0.2), _trial(1, 0.1)], gz=True)
    rerun = _write(
        tmp_path / "b",
        [_trial(0, 0.2 + 1e-15, source="shipped"), _trial(1, 0.1, source="shipped")],
    )
    why = script.compare(committed, rerun, "trials.jsonl")
    assert why is not None and "fields only in the second: source" in why
    ignoring = script.Canon(frozenset({"source"}))
    assert "1 only in the first" in script.compare(committed, rerun, "trials.jsonl", ignoring)
    rounded = script.Canon(frozenset({"source"}), digits=6)
    assert script.compare(committed, rerun, "trials.jsonl", rounded) is None


def test_an_outcome_that_changed_still_differs_when_rounded(
    script: ModuleType, tmp_path: Path
) -> None:
    committed = _write(tmp_path / "a", [_trial(0, 0.2)])
    rerun = _write(tmp_path / "b", [{**_trial(0, 0.2), "success": False}])
    why = script.compare(committed, rerun, "trials.jsonl", script.Canon(digits=3))
    assert why == "1 against 1 records; 1 only in the first, 1 in the second"
