"""Automatic handle labels against the hand-made labels of the YCB objects.

For every YCB object of ``models/handles/ycb_handles.json`` (or those named): the automatic
label of its scanned mesh (``simgrasp label-handles`` with its default settings, or those given
as flags) against the label shipped with the package, drawn by hand as oriented boxes, on
20,000 points sampled on the mesh: intersection over union, the share of the shipped label
found (``recall``) and the share of the automatic label inside the shipped one
(``precision``). Objects shipped with no handle (a box, a can, a bottle, the clamp) or as
graspable everywhere (the chips can, the banana, the lemon) count as right when the automatic
label is empty; otherwise the row gives the share of their surface it labels. Neither the
labeler's settings nor its detector's were chosen on these labels
(``docs/results/handle-labels/README.md``, ``docs/results/generated-labels/README.md``).
Rows go to ``rows.jsonl`` as they finish (a rerun keeps those measured under the same
settings and shipped labels); ``ycb_auto_labels.md`` is the table. The YCB meshes come from
``SIMGRASP_YCB_DIR``; nothing derived from them but these figures is written.

    SIMGRASP_YCB_DIR=../shared/ycb python scripts/ycb_auto_labels.py
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from generated_labels import add_row, kept_rows, settings_key

from simgrasp.assets.registry import load_object
from simgrasp.autolabel.auto_label import auto_handle_label
from simgrasp.autolabel.config import AutoLabelConfig
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.errors import SimgraspError
from simgrasp.labels import load_label_file
from simgrasp.perception import sample_surface

SAMPLES = 20000
SHIPPED = Path(__file__).resolve().parents[1] / "models" / "handles" / "ycb_handles.json"


def measure_one(name: str, config: AutoLabelConfig) -> dict[str, object]:
    """The row of one YCB object (see the module doc)."""
    asset = load_object(name)
    shipped = asset.handle
    found = auto_handle_label(asset.mesh, asset.name, config)
    points, _ = sample_surface(asset.mesh, SAMPLES, np.random.default_rng(0))
    labeled = found.label.contains(points)
    row: dict[str, object] = {
        "object": asset.name,
        "shipped": "whole" if shipped.whole_object else "handle" if shipped.regions else "none",
        "parts": len(found.parts),
        "boxes": len(found.label.regions),
        "labeled_share": round(float(labeled.mean()), 3),
    }
    exact = shipped.contains(points)
    if shipped.regions and not shipped.whole_object and exact.any():
        both = int((labeled & exact).sum())
        row["iou"] = round(both / int((labeled | exact).sum()), 3)
        row["recall"] = round(both / int(exact.sum()), 3)
        row["precision"] = round(both / int(labeled.sum()), 3) if labeled.any() else None
    return row


def table(rows: list[dict]) -> str:
    """One line per object, then the handle objects' median IoU and the others' verdicts."""
    lines = [
        "| object | shipped label | automatic parts (boxes) | IoU | recall | precision "
        "| surface labeled |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        cells = [r.get(k) for k in ("iou", "recall", "precision")]
        shown = ["-" if c is None else f"{c:.2f}" for c in cells]
        lines.append(
            f"| {r['object']} | {r['shipped']} | {r['parts']} ({r['boxes']}) | {' | '.join(shown)} "
            f"| {r['labeled_share']:.2f} |"
        )
    handles = [r["iou"] for r in rows if r.get("iou") is not None]
    others = [r for r in rows if r["shipped"] != "handle"]
    empty = sum(r["boxes"] == 0 for r in others)
    if handles:
        lines.append(
            f"\nObjects with a handle: {len(handles)}, IoU median {np.median(handles):.2f}, "
            f"lowest {min(handles):.2f}."
        )
    if others:
        lines.append(f"Objects shipped without one: {len(others)}, {empty} get no label.")
    return "\n".join(lines) + "\n"


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    objects: tuple[str, ...] = ()
    """YCB objects to measure by their full names (``025_mug``; empty: every object of the
    shipped label file)."""
    out: Path = Path("docs/results/ycb-auto-labels")
    """Folder of ``rows.jsonl`` and ``ycb_auto_labels.md``."""
    label: AutoLabelConfig = field(default_factory=AutoLabelConfig)


def run(options: Options) -> str:
    """Measure every object not yet in ``rows.jsonl`` under these settings; the table."""
    shipped = load_label_file(SHIPPED)
    names = options.objects or tuple(sorted(shipped))
    unknown = [n for n in names if n not in shipped]
    if unknown:
        raise SimgraspError(f"no shipped YCB label for {unknown}; known: {', '.join(shipped)}")
    key = settings_key(options.label)
    labels_key = hashlib.sha256(SHIPPED.read_bytes()).hexdigest()[:16]
    options.out.mkdir(parents=True, exist_ok=True)
    done_file = options.out / "rows.jsonl"
    done = kept_rows(
        done_file, lambda r: r.get("settings") == key and r.get("labels") == labels_key
    )
    have = {r["object"] for r in done}
    for name in names:
        if name in have:
            continue
        row = measure_one(name, options.label)
        row.update(settings=key, labels=labels_key)
        done.append(row)
        add_row(done_file, row)
    text = table(sorted((r for r in done if r["object"] in names), key=lambda r: r["object"]))
    (options.out / "ycb_auto_labels.md").write_text(text)
    return text


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
