"""The automatic handle label of a mesh object that comes with none, cached on disk.

A mesh object (:mod:`simgrasp.assets.mesh_object`) given no ``handles`` file gets the label
``simgrasp label-handles`` would write for it
(:func:`simgrasp.autolabel.auto_label.auto_handle_label` with its default settings), so
``trial``, ``evaluate``, ``label-grasps`` and the env score ``on_handle`` on any mesh; records
say where the label came from
(:attr:`simgrasp.assets.object.ObjectAsset.handle_source`). Scanning and detecting take a few
seconds a mesh, so the label is kept in the cache directory's ``handle-labels`` folder, one
JSON file per (mesh, settings), written atomically (concurrent workers never read half a
file; a file that does not parse is rebuilt).
"""

from __future__ import annotations

import logging
import os
import sys
import tempfile
from pathlib import Path

import trimesh

from simgrasp.assets.cache import cache_dir, cache_key
from simgrasp.config.tree import flatten
from simgrasp.errors import SimgraspError
from simgrasp.labels import HandleLabel, load_label_file, write_label_file

log = logging.getLogger(__name__)

LABELER_VERSION = 7
"""Part of every entry's key with the labeler's settings: raised whenever
:func:`simgrasp.autolabel.auto_label.auto_handle_label` finds other labels with the same
settings (2: bodies of revolution; 3: a long tool's thin sections left out; 4: the k-means
pieces' seeding and fallback; 5: k-means started from the slabs, no random draw; 6: a long
tool's heads left out; 7: a part on a blade is told by a thicker run 3 cm long, not by the
tool's median slab), so no stale label is read."""


def automatic_handle_label(mesh: trimesh.Trimesh, name: str) -> HandleLabel:
    """The automatic handle label of ``mesh`` (its frame, m) for object ``name``, from the
    cache when it holds one for this mesh and the labeler's settings."""
    from simgrasp.autolabel.auto_label import auto_handle_label
    from simgrasp.autolabel.config import AutoLabelConfig

    config = AutoLabelConfig()
    fields = {**flatten(config), "labeler_version": LABELER_VERSION}
    path = cache_dir("handle-labels") / f"{cache_key(mesh, fields)}.json"
    cached = _read(path)
    if cached is None:
        print(
            f"note: object {name} has no handle file: finding its handle automatically (once: "
            f"kept in {path.parent})",
            file=sys.stderr,
        )
        cached = auto_handle_label(mesh, "label", config).label
        _write(path, cached)
    return HandleLabel(name, cached.regions, cached.whole_object)


def _read(path: Path) -> HandleLabel | None:
    """The cached label at ``path``; None when absent or unreadable (then removed)."""
    if not path.is_file():
        return None
    try:
        return load_label_file(path)["label"]
    except (SimgraspError, KeyError, TypeError, ValueError) as exc:
        log.warning("handle label cache entry %s is unreadable (%s); rebuilding it", path, exc)
        path.unlink(missing_ok=True)
        return None


def _write(path: Path, label: HandleLabel) -> None:
    """Write ``label`` to ``path`` atomically (temporary file in the same folder, renamed)."""
    handle, tmp_name = tempfile.mkstemp(dir=path.parent, prefix=path.stem, suffix=".tmp")
    os.close(handle)
    try:
        write_label_file(Path(tmp_name), {"label": label}, "automatic (simgrasp label-handles)")
        os.replace(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
