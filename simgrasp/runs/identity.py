"""What an output directory was recorded with (``run.json``, ``defaults.json``): written by
the first run, compared by every later one, so a resume never mixes records of two
configurations."""

from __future__ import annotations

import functools
import hashlib
import json
from pathlib import Path
from typing import Any

from simgrasp.errors import SimgraspError


def file_digest(path: str | Path) -> str:
    """SHA-256 of a file's bytes (hex): how a run records which input file it was made from.
    A file unchanged since it was last hashed in this process (same size and modification
    time) is not read again: a command checks its output folder's identity before it runs
    and records it when it starts."""
    resolved = Path(path).resolve()
    stat = resolved.stat()
    return _digest_of(resolved, stat.st_size, stat.st_mtime_ns)


@functools.lru_cache(maxsize=256)
def _digest_of(path: Path, size: int, mtime_ns: int) -> str:
    """SHA-256 of ``path``'s bytes; ``size`` and ``mtime_ns`` key the cache."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def object_file_digests(name: str) -> dict[str, str]:
    """SHA-256 of the files object ``name`` is read from, which can change under its name:
    ``mesh_sha256`` for a mesh file object or a catalog name
    (:func:`~simgrasp.assets.registry.mesh_file_of`), ``handles_sha256`` for a handle label file
    given for it (:func:`~simgrasp.assets.registry.handles_file_of`); neither for a YCB object
    or a generated tool with its shipped or automatic label. A named file that is not there is
    one line naming it."""
    from simgrasp.assets.registry import handles_file_of, mesh_file_of
    from simgrasp.errors import DataNotFoundError

    digests = {}
    if (mesh := mesh_file_of(name)) is not None:
        if not mesh.is_file():
            raise DataNotFoundError(f"object mesh {mesh} does not exist")
        digests["mesh_sha256"] = file_digest(mesh)
    if (handles := handles_file_of(name)) is not None:
        if not handles.is_file():
            raise DataNotFoundError(f"handle label file {handles} does not exist")
        digests["handles_sha256"] = file_digest(handles)
    return digests


SHOWN_CHANGES = 3
"""Changed settings named one by one in a refusal before the rest are counted."""


def claim_identity(
    path: Path,
    current: dict[str, Any],
    *,
    what: str,
    hint: str = "use another --out",
    shared_only: bool = False,
    ignore: tuple[str, ...] = (),
    indent: int = 2,
) -> None:
    """Write ``current`` (JSON) to ``path``, or refuse (naming the directory, up to
    :data:`SHOWN_CHANGES` changed settings with both values, nested tables by their dotted
    keys, and ``hint``) a directory whose file differs: ``what`` says what it holds instead
    (e.g. ``"labels of another run"``). With ``shared_only`` only keys both have are compared
    (a setting added since starts at its default, so it changes no earlier record). Keys in
    ``ignore`` are recorded, not compared: when only they differ the file takes the new
    values (a label run extended to more of the same grasps)."""
    path = Path(path)
    current = json.loads(json.dumps(current))  # as it reads back (tuples as lists)
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(current, indent=indent) + "\n", encoding="utf-8")
        return
    earlier = _read_table(path, "settings")
    keys = [k for k in current if k in earlier] if shared_only else sorted({*current, *earlier})
    changed = _changes(earlier, current, [k for k in keys if k not in ignore])
    if changed:
        raise SimgraspError(f"{path.parent} holds {what} ({_shown(changed)}); {hint}")
    if any(earlier.get(k) != current.get(k) for k in ignore):
        path.write_text(json.dumps({**earlier, **current}, indent=indent) + "\n", encoding="utf-8")


def _read_table(path: Path, what: str) -> dict[str, Any]:
    """The JSON object in ``path``; one line naming the file when it is no JSON or no table
    (of ``what``)."""
    try:
        table = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as error:
        raise SimgraspError(f"{path} is not JSON ({error})") from error
    if not isinstance(table, dict):
        raise SimgraspError(f"{path} is not a table of {what}")
    return table


def _shown(changed: list[tuple[str, Any, Any]]) -> str:
    """Up to :data:`SHOWN_CHANGES` changed values with both values, and how many more."""
    shown = ", ".join(f"{k}: {a!r:.60} -> {b!r:.60}" for k, a, b in changed[:SHOWN_CHANGES])
    more = f" and {len(changed) - SHOWN_CHANGES} more" if len(changed) > SHOWN_CHANGES else ""
    return shown + more


def _changes(
    earlier: dict[str, Any], current: dict[str, Any], keys: list[str], prefix: str = ""
) -> list[tuple[str, Any, Any]]:
    """(dotted key, earlier value, current value) of each setting that differs among
    ``keys``, nested tables compared key by key (a missing value is None)."""
    changed: list[tuple[str, Any, Any]] = []
    for key in keys:
        before, after = earlier.get(key), current.get(key)
        if isinstance(before, dict) and isinstance(after, dict):
            inner = sorted({*before, *after})
            changed += _changes(before, after, inner, f"{prefix}{key}.")
        elif before != after:
            changed.append((f"{prefix}{key}", before, after))
    return changed


def claim_entries(
    path: Path, current: dict[str, Any], held: set[str], *, what: str, hint: str
) -> None:
    """Record ``current``'s named entries (e.g. each detector setting's values, by its name) in
    the JSON table at ``path``, or refuse (naming the entry and up to :data:`SHOWN_CHANGES`
    changed values, and ``hint``) when the entry it holds for a name in ``held`` (the names
    the folder still has rows of) differs: those rows were made with the recorded values.
    ``what`` says what the entries are (``"detector setting"``). Entries of names not in
    ``current`` are kept as they were."""
    path = Path(path)
    current = json.loads(json.dumps(current))  # as it reads back (tuples as lists)
    earlier = _read_table(path, f"{what}s") if path.exists() else {}
    for name in sorted(set(current) & set(earlier) & held):
        changed = _changes({name: earlier[name]}, {name: current[name]}, [name])
        if changed:
            raise SimgraspError(
                f"{path.parent} holds rows of {what} {name!r} made with other values "
                f"({_shown(changed)}); {hint}"
            )
    merged = {**earlier, **current}
    if merged != earlier:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(merged, indent=2, sort_keys=True) + "\n", encoding="utf-8")
