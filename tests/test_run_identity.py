"""runs.identity.file_digest: the SHA-256 a run records of its input files, read once per
unchanged file and never stale after an edit."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from simgrasp.runs.identity import file_digest


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
