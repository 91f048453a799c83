"""What an output directory was recorded with (``run.json``, ``defaults.json``): written by
the first run, compared by every later one, so a resume never mixes records of two
configurations."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from simgrasp.errors import SimgraspError

SHOWN_CHANGES = 3
"""Changed settings named one by one in a refusal before the rest are counted."""


def claim_identity(
    path: Path,
    current: dict[str, Any],
    *,
    what: str,
    hint: str = "use another --out",
    shared_only: bool = False,
    indent: int = 2,
) -> None:
    """Write ``current`` (JSON) to ``path``, or refuse (naming the directory, up to
    :data:`SHOWN_CHANGES` changed keys with both values, and ``hint``) a directory whose file
    differs: ``what`` says what it holds instead (e.g. ``"labels of another run"``). With
    ``shared_only`` only keys both have are compared (a setting added since starts at its
    default, so it changes no earlier record)."""
    path = Path(path)
    current = json.loads(json.dumps(current))  # as it reads back (tuples as lists)
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(current, indent=indent) + "\n", encoding="utf-8")
        return
    try:
        earlier = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as error:
        raise SimgraspError(f"{path} is not JSON ({error})") from error
    if not isinstance(earlier, dict):
        raise SimgraspError(f"{path} is not a table of settings")
    keys = [k for k in current if k in earlier] if shared_only else sorted({*current, *earlier})
    changed = [k for k in keys if earlier.get(k) != current.get(k)]
    if changed:
        shown = ", ".join(
            f"{k}: {earlier.get(k)!r:.60} -> {current.get(k)!r:.60}"
            for k in changed[:SHOWN_CHANGES]
        )
        more = f" and {len(changed) - SHOWN_CHANGES} more" if len(changed) > SHOWN_CHANGES else ""
        raise SimgraspError(f"{path.parent} holds {what} ({shown}{more}); {hint}")
