"""``simgrasp fetch-ycb``: download YCB objects from the official site into a local folder."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from simgrasp.assets.fetch import (
    SCAN_DIR,
    YCB_BASE_URL,
    FetchError,
    ServerUnreachable,
    fetch_object,
    resolve_object_ids,
)
from simgrasp.assets.ycb import YCB_DIR_ENV


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--objects",
        required=True,
        help="comma-separated YCB ids or names (025_mug,hammer), or 'all'",
    )
    parser.add_argument(
        "--dest",
        default=os.environ.get(YCB_DIR_ENV),
        help=f"folder to put the objects in (default: ${YCB_DIR_ENV})",
    )
    parser.add_argument(
        "--kind",
        choices=sorted(SCAN_DIR),
        default="google_16k",
        help="google_16k: textured 16k-face scans; berkeley: Poisson/TSDF meshes",
    )
    parser.add_argument(
        "--base-url",
        default=YCB_BASE_URL,
        help="site to download from (default: the official YCB mirror)",
    )
    parser.add_argument("--timeout", type=float, default=30.0, help="network timeout, seconds")
    parser.add_argument("--no-progress", action="store_true", help="no progress bars")


def run(args: argparse.Namespace) -> int:
    if not args.dest:
        raise ValueError(f"give --dest DIR (or set {YCB_DIR_ENV})")
    if not args.timeout > 0:
        raise ValueError(f"--timeout must be positive, got {args.timeout}")
    dest = Path(args.dest).expanduser()
    object_ids = resolve_object_ids(args.objects, args.kind)
    failed: list[str] = []
    for index, object_id in enumerate(object_ids):
        try:
            result = fetch_object(
                object_id,
                dest,
                args.kind,
                base_url=args.base_url,
                timeout=args.timeout,
                progress=not args.no_progress,
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
