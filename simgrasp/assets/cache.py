"""On-disk cache of convex decompositions: one checksummed ``.npz`` per (mesh, config).

The directory is ``platformdirs.user_cache_dir("simgrasp")/decompositions``, or
``$SIMGRASP_CACHE_DIR/decompositions`` when that variable is set. Entries are written to a
temporary file in the same directory and atomically renamed into place, so concurrent
builders of the same object never see a half-written entry; an entry that fails to parse or
whose checksum or format version does not match is deleted (with a warning) and rebuilt.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import tempfile
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import platformdirs
import trimesh

from simgrasp.errors import SimgraspError

log = logging.getLogger(__name__)

CACHE_ENV = "SIMGRASP_CACHE_DIR"
FORMAT_VERSION = 1


def cache_dir(kind: str = "decompositions") -> Path:
    """The directory holding the cache entries of ``kind`` (``decompositions``; the automatic
    handle labels' ``handle-labels``), created on demand; an error naming it when it cannot be
    a directory (``SIMGRASP_CACHE_DIR`` naming a file, say)."""
    variable = os.environ.get(CACHE_ENV)
    root = variable or platformdirs.user_cache_dir("simgrasp")
    path = Path(root) / kind
    try:
        path.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        where = f"{CACHE_ENV}={root}" if variable else f"the cache directory {root}"
        raise SimgraspError(
            f"{where}: {path} or a parent is not a directory; point {CACHE_ENV} at a directory"
        ) from None
    return path


def cache_key(mesh: trimesh.Trimesh, config_fields: dict[str, object]) -> str:
    """sha256 over the mesh's vertex and face bytes, the config fields and the format version."""
    digest = hashlib.sha256()
    digest.update(np.ascontiguousarray(mesh.vertices, dtype=np.float64).tobytes())
    digest.update(np.ascontiguousarray(mesh.faces, dtype=np.int64).tobytes())
    digest.update(json.dumps(config_fields, sort_keys=True).encode())
    digest.update(f"format={FORMAT_VERSION}".encode())
    return digest.hexdigest()


def entry_path(key: str) -> Path:
    return cache_dir() / f"{key}.npz"


def _payload_checksum(arrays: dict[str, np.ndarray]) -> str:
    digest = hashlib.sha256()
    for name in ("vertices", "faces", "vertex_counts", "face_counts"):
        digest.update(np.ascontiguousarray(arrays[name]).tobytes())
    return digest.hexdigest()


def save_hulls(path: Path, hulls: tuple[trimesh.Trimesh, ...]) -> None:
    """Write hulls atomically: temp file in ``path``'s directory, fsync, ``os.replace``."""
    arrays = {
        "vertices": np.concatenate([h.vertices for h in hulls]).astype(np.float64),
        "faces": np.concatenate([h.faces for h in hulls]).astype(np.int64),
        "vertex_counts": np.array([len(h.vertices) for h in hulls], dtype=np.int64),
        "face_counts": np.array([len(h.faces) for h in hulls], dtype=np.int64),
    }
    checksum = _payload_checksum(arrays)
    handle, tmp_name = tempfile.mkstemp(dir=path.parent, prefix=path.stem, suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") as tmp:
            header = {"format_version": np.array(FORMAT_VERSION), "checksum": np.array(checksum)}
            # dict[str, Any]: numpy's stub would match the arrays against savez's allow_pickle
            entries: dict[str, Any] = {**header, **arrays}
            np.savez(tmp, **entries)
            tmp.flush()
            os.fsync(tmp.fileno())
        os.replace(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise


def _read(path: Path) -> tuple[trimesh.Trimesh, ...]:
    with np.load(path, allow_pickle=False) as data:
        if int(data["format_version"]) != FORMAT_VERSION:
            raise SimgraspError(f"format version {int(data['format_version'])} != {FORMAT_VERSION}")
        arrays = {k: data[k] for k in ("vertices", "faces", "vertex_counts", "face_counts")}
        if str(data["checksum"]) != _payload_checksum(arrays):
            raise SimgraspError("checksum mismatch")
    vertex_ends = np.cumsum(arrays["vertex_counts"])
    face_ends = np.cumsum(arrays["face_counts"])
    if vertex_ends[-1] != len(arrays["vertices"]) or face_ends[-1] != len(arrays["faces"]):
        raise SimgraspError("hull counts do not match the stored arrays")
    vertices = np.split(arrays["vertices"], vertex_ends[:-1])
    faces = np.split(arrays["faces"], face_ends[:-1])
    return tuple(trimesh.Trimesh(v, f, process=False) for v, f in zip(vertices, faces, strict=True))


def load_hulls(path: Path) -> tuple[trimesh.Trimesh, ...] | None:
    """Read an entry; ``None`` if absent. A corrupt entry is logged, deleted and ``None``; a
    directory in its place (never written by simgrasp) is a ValueError naming it."""
    if not path.exists():
        return None
    if not path.is_file():
        raise SimgraspError(
            f"decomposition cache entry {path} is a directory, not a cache file; remove it"
        )
    try:
        return _read(path)
    except (OSError, EOFError, ValueError, KeyError, IndexError, zipfile.BadZipFile) as exc:
        log.warning("decomposition cache entry %s is corrupt (%s); rebuilding it", path, exc)
        path.unlink(missing_ok=True)
        return None
