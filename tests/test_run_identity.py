"""runs.identity: ``file_digest``, the SHA-256 a run records of its input files, read once per
unchanged file and never stale after an edit; ``claim_entries``, the values each named
setting's rows were made with."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import pytest

from simgrasp.errors import SimgraspError
from simgrasp.runs.identity import claim_entries, file_digest


def test_the_digest_is_the_files_sha256_and_follows_an_edit_of_the_same_size(
    tmp_path: Path,
) -> None:
    path = tmp_path / "grasps.h5"
    path.write_bytes(b"first")
    assert file_digest(path) == hashlib.sha256(b"first").hexdigest()
    assert file_digest(str(path)) == file_digest(path)
    stat = path.stat()
    path.write_bytes(b"other")  # same size; a later modification time
    os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1_000_000))
    assert file_digest(path) == hashlib.sha256(b"other").hexdigest()


def test_entries_are_compared_only_where_rows_of_them_remain(tmp_path: Path) -> None:
    """A held entry that changed is refused naming it and the value; one whose rows are gone
    takes the new values; a new entry joins; entries not claimed again are kept."""
    path = tmp_path / "settings.json"
    claim = {"what": "detector setting", "hint": "use another --out"}
    claim_entries(path, {"a": {"x": 1}, "b": {"x": 2}}, set(), **claim)
    with pytest.raises(SimgraspError, match=r"'a' made with other values \(a.x: 1 -> 3\)"):
        claim_entries(path, {"a": {"x": 3}}, {"a", "b"}, **claim)
    claim_entries(path, {"a": {"x": 3}, "c": {"x": 4}}, {"b"}, **claim)
    assert json.loads(path.read_text()) == {"a": {"x": 3}, "b": {"x": 2}, "c": {"x": 4}}
    path.write_text("[1]")
    with pytest.raises(SimgraspError, match="is not a table of detector settings"):
        claim_entries(path, {"a": {"x": 3}}, set(), **claim)
