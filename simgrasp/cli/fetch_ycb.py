"""``simgrasp fetch-ycb``: download YCB objects from the official site into a local folder.

Interrupted downloads resume when run again; ``--kind berkeley`` fetches the Berkeley meshes,
``--base-url`` points at a mirror.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import cast

from simgrasp.assets.fetch import (
    SCAN_DIR,
    YCB_BASE_URL,
    ArchiveKind,
    FetchError,
    ServerUnreachable,
    check_base_url,
    fetch_object,
    resolve_object_ids,
)
from simgrasp.assets.ycb import YCB_DIR_ENV
from simgrasp.config import setting
from simgrasp.config.checks import Checked, Positive
from simgrasp.errors import SimgraspError

EXAMPLES = ("simgrasp fetch-ycb --objects 025_mug,048_hammer --dest ~/ycb",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    objects: str
    """Comma-separated YCB ids or names (025_mug,hammer), or all."""
    dest: str | None = setting(None, main=True)
    """Folder to put the objects in (default: $SIMGRASP_YCB_DIR)."""
    kind: str = setting("google_16k", choices=tuple(sorted(SCAN_DIR)))
    """google_16k: textured 16k-face scans; berkeley: Poisson/TSDF meshes."""
    base_url: str = YCB_BASE_URL
    """Site to download from (default: the official YCB mirror)."""
    timeout: Positive = 30.0
    """Network timeout (s)."""
    no_progress: bool = False
    """No progress bars."""

    def _check(self) -> None:
        check_base_url(self.base_url)


def run(options: Options) -> int:
    dest_text = options.dest or os.environ.get(YCB_DIR_ENV)
    if not dest_text:
        raise SimgraspError(f"give --dest DIR (or set {YCB_DIR_ENV})")
    dest = Path(dest_text).expanduser()
    kind = cast(ArchiveKind, options.kind)
    object_ids = resolve_object_ids(options.objects, kind)
    _check_dest(dest, "--dest" if options.dest else f"${YCB_DIR_ENV}")
    failed: list[str] = []
    for index, object_id in enumerate(object_ids):
        try:
            result = fetch_object(
                object_id,
                dest,
                kind,
                base_url=options.base_url,
                timeout=options.timeout,
                progress=not options.no_progress,
            )
        except ServerUnreachable as exc:
            print(f"simgrasp fetch-ycb: error: {exc}", file=sys.stderr)
            skipped = len(object_ids) - index - 1
            if skipped:
                print(f"simgrasp fetch-ycb: stopped; {skipped} more not tried", file=sys.stderr)
            return 1
        except FetchError as exc:  # its message names the object
            failed.append(object_id)
            print(f"simgrasp fetch-ycb: error: {exc}", file=sys.stderr)
            continue
        except OSError as exc:  # disk full, permissions, ...
            failed.append(object_id)
            print(f"simgrasp fetch-ycb: error: {object_id}: {exc}", file=sys.stderr)
            continue
        print(f"{object_id}: {result.status} ({result.path})")
    if failed:
        print(
            f"simgrasp fetch-ycb: {len(failed)} of {len(object_ids)} objects failed: "
            f"{', '.join(failed)}",
            file=sys.stderr,
        )
        return 1
    return 0


def _check_dest(dest: Path, option: str) -> None:
    """Refuse a destination that is a file (or lies inside one) or that cannot be written,
    before any download: a one-line error naming ``option`` and ``dest``."""
    from simgrasp.runs.out_dir import check_out_dir

    if dest.exists() and not dest.is_dir():
        raise SimgraspError(f"{option} {dest}: is a file, not a folder")
    check_out_dir(dest, option)
