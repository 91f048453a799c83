"""``simgrasp view PATH``: an interactive 3D view of a ``label-grasps`` output folder, served
on localhost (``--port``) or written as one self-contained HTML file (``--export``) that opens
offline: plotly.js is inlined, no request leaves the page.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.errors import SimgraspError


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    path: Path = setting(positional=True, metavar="PATH")
    """A label-grasps output folder (run.json, labels.jsonl)."""
    port: int = 8000
    """Port of the local server (bound to 127.0.0.1 only)."""
    export: Path | None = None
    """Write the page to this .html file instead of serving it."""


def run(options: Options) -> int:
    from simgrasp.viewer.grasp_page import grasp_page, is_label_dir

    if not is_label_dir(options.path):
        raise SimgraspError(
            f"{options.path}: not a label-grasps output folder (run.json and labels.jsonl)"
        )
    if options.export is not None:
        options.export.parent.mkdir(parents=True, exist_ok=True)
        options.export.write_text(grasp_page(options.path, options.ycb_dir))
        print(f"{options.export} ({options.export.stat().st_size / 1e6:.1f} MB)")
        return 0
    from simgrasp.viewer.server import serve

    serve(lambda: grasp_page(options.path, options.ycb_dir), options.port)
    return 0
