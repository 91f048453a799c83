"""``simgrasp view PATH``: an interactive 3D view of what simgrasp wrote (the kinds of PATH:
:mod:`simgrasp.viewer.kinds`), served on localhost (``--port``) or written as one
self-contained HTML file (``--export``) that opens offline: plotly.js is inlined, no request
leaves the page.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from simgrasp.cli.options import YcbSource
from simgrasp.config import setting

EXAMPLES = ("simgrasp view out/eval --export eval.html",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    path: Path = setting(positional=True, metavar="PATH")
    """A label-grasps output folder (run.json, labels.jsonl), a trial record (trial
    --record --json > t.json), a detection (detect --json > d.json, drawn over the input cloud
    it records) or an evaluate or demo output folder (trials.jsonl, report.md)."""
    port: int = setting(8000, main=True)
    """Port of the local server (bound to 127.0.0.1 only)."""
    export: Path | None = setting(None, output="file", suffixes=(".html", ".htm"), main=True)
    """Write the page to this .html file instead of serving it."""


def run(options: Options) -> int:
    from simgrasp.viewer.kinds import kind_of

    page = kind_of(options.path).page(options.path, options.ycb_dir)  # bad input fails here
    if options.export is not None:
        options.export.parent.mkdir(parents=True, exist_ok=True)
        options.export.write_text(page)
        print(f"{options.export} ({options.export.stat().st_size / 1e6:.1f} MB)")
        return 0
    from simgrasp.viewer.server import serve

    serve(lambda: page, options.port)
    return 0
