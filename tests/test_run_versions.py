"""``OUT/versions.json``: the library versions a run's records were written under, one entry
per distinct set, so a figure that stops reproducing can be traced to a library."""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np

from simgrasp.runs.out_dir import claim_out_dir
from simgrasp.runs.versions import VERSIONS_FILE, library_versions


def test_a_claimed_folder_records_the_versions_once(tmp_path: Path) -> None:
    for _ in range(2):  # a resumed run under the same versions adds nothing
        with claim_out_dir(tmp_path, ["simgrasp", "evaluate"]):
            pass
    sets = json.loads((tmp_path / VERSIONS_FILE).read_text(encoding="utf-8"))
    assert len(sets) == 1
    assert sets[0]["mujoco"] == mujoco.__version__
    assert sets[0]["numpy"] == np.__version__


def test_another_set_is_added_after_the_earlier_ones(tmp_path: Path) -> None:
    older = {**library_versions(), "mujoco": "0.0.1"}
    (tmp_path / VERSIONS_FILE).write_text(json.dumps([older]), encoding="utf-8")
    with claim_out_dir(tmp_path, ["simgrasp", "evaluate"]):
        pass
    sets = json.loads((tmp_path / VERSIONS_FILE).read_text(encoding="utf-8"))
    assert sets == [older, library_versions()]
