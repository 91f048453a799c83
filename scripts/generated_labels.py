"""Automatic handle labels against the exact labels of generated objects.

For every generated kind and seed asked for: the automatic label of the object's mesh
(``simgrasp label-handles`` with its default settings, or those given as flags) against
the exact label its builder wrote, on 20,000 points sampled on the surface: intersection over
union, the share of the handle's surface labeled (``recall``), and per part that is not the
handle (a knife's blade and bolster, a hammer's head) the share of its surface within
``--near`` (5 mm, the trials' on-handle margin) of labeled surface, i.e. where a grasp on that
part would count as on the handle. This is the place to choose labeler settings outside the
ACRONYM files (``docs/results/handle-labels/README.md``). Rows go to ``rows.jsonl`` as they
finish (a rerun keeps those measured under the same settings on the same meshes and labels);
``generated_labels.md`` is the table.

    python scripts/generated_labels.py --kinds knife --seeds 20 --out docs/results/generated-labels

Labeler settings are flags (``--label.cross-section.min-ratio 0.6``), as in ``label-handles``.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.assets.auto_handles import LABELER_VERSION
from simgrasp.assets.generated import ALL_GENERATED_KINDS, generate_parts, generate_tool
from simgrasp.assets.object import ObjectAsset
from simgrasp.autolabel.auto_label import auto_handle_label
from simgrasp.autolabel.config import AutoLabelConfig
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, NonNegativeInt, Positive, PositiveInt
from simgrasp.config.tree import flatten
from simgrasp.errors import SimgraspError
from simgrasp.perception import sample_surface

SAMPLES = 20000


def settings_key(config: AutoLabelConfig) -> str:
    """The labeler's settings and version a row was measured under."""
    given = {"label": flatten(config), "labeler_version": LABELER_VERSION}
    return hashlib.sha256(json.dumps(given, sort_keys=True).encode()).hexdigest()[:16]


def mesh_key(asset: ObjectAsset) -> str:
    """A hash of a generated object's mesh and exact label: a row measured on another build
    is stale."""
    label = json.dumps(asset.handle.to_json(), sort_keys=True).encode()
    mesh = asset.mesh.vertices.tobytes() + asset.mesh.faces.tobytes()
    return hashlib.sha256(mesh + label).hexdigest()[:16]


def measure_one(kind: str, seed: int, config: AutoLabelConfig, near: float) -> dict[str, object]:
    """The row of one generated object (see the module doc)."""
    asset = generate_tool(kind, seed)
    found = auto_handle_label(asset.mesh, asset.name, config)
    points, _ = sample_surface(asset.mesh, SAMPLES, np.random.default_rng(seed))
    labeled, exact = found.label.contains(points), asset.handle.contains(points)
    union = int((labeled | exact).sum())
    near_part, near_exact = {}, {}
    for part in generate_parts(kind, seed).parts:
        on_part = ~exact & (part.mesh.nearest.signed_distance(points) > -1e-4)
        if part.is_handle or not on_part.any():
            continue
        near_part[part.name] = _near_share(points, labeled, on_part, near)
        near_exact[part.name] = _near_share(points, exact, on_part, near)
    return {
        "object": asset.name,
        "kind": kind,
        "seed": seed,
        "parts": len(found.parts),
        "boxes": len(found.label.regions),
        "iou": round(float((labeled & exact).sum() / union), 3) if union else None,
        "recall": round(float((labeled & exact).sum() / exact.sum()), 3) if exact.any() else None,
        "near": near_part,
        "near_exact": near_exact,
        "mesh": mesh_key(asset),
    }


def kept_rows(path: Path, keep: Callable[[dict], bool]) -> list[dict]:
    """The rows of a ``rows.jsonl`` file (none when it is missing) that ``keep`` accepts; the
    file is rewritten with those only, so a killed run loses no kept row. A line that is not
    JSON is one clear error."""
    try:
        rows = [json.loads(line) for line in path.read_text().splitlines() if line]
    except FileNotFoundError:
        rows = []
    except json.JSONDecodeError as error:
        message = f"{path}: not a rows file ({error}); remove it to start again"
        raise SimgraspError(message) from None
    rows = [r for r in rows if keep(r)]
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    return rows


def add_row(path: Path, row: dict) -> None:
    """Append ``row`` to a ``rows.jsonl`` file as soon as it is measured, and print it."""
    with path.open("a") as handle:
        handle.write(json.dumps(row) + "\n")
    print(json.dumps(row), flush=True)


def _near_share(
    points: NDArray[np.float64], labeled: NDArray[np.bool_], on_part: NDArray[np.bool_], near: float
) -> float:
    """The share of a part's sampled ``points`` within ``near`` (m) of a labeled point."""
    if not labeled.any():
        return 0.0
    distance = cKDTree(points[labeled]).query(points[on_part])[0]
    return round(float((distance <= near).mean()), 3)


def _mean_column(rows: list[dict], field: str, part: str) -> tuple[float, float]:
    """Mean and largest ``row[field][part]`` over the rows that have the part."""
    values = [r[field][part] for r in rows if part in r[field]]
    return float(np.mean(values)), float(max(values))


def table(rows: list[dict]) -> str:
    """Per kind: objects, median and lowest IoU, mean recall, and per other part the mean and
    largest share of its surface near the label."""
    lines = [
        "| kind | objects | IoU median (lowest) | handle labeled | other parts' surface near the "
        "label: mean (largest; the exact label's mean) | objects with >1 part |",
        "|---|---|---|---|---|---|",
    ]
    for kind in dict.fromkeys(r["kind"] for r in rows):
        chosen = [r for r in rows if r["kind"] == kind]
        ious = [r["iou"] for r in chosen if r["iou"] is not None]
        recalls = [r["recall"] for r in chosen if r["recall"] is not None]
        names = sorted({n for r in chosen for n in r["near"]})
        near = ", ".join(
            "{} {:.3f} ({:.3f}; exact label {:.3f})".format(
                n, *_mean_column(chosen, "near", n), _mean_column(chosen, "near_exact", n)[0]
            )
            for n in names
        )
        iou = f"{np.median(ious):.2f} ({min(ious):.2f})" if ious else "-"
        recall = f"{np.mean(recalls):.3f}" if recalls else "-"
        multi = sum(r["parts"] > 1 for r in chosen)
        lines.append(f"| {kind} | {len(chosen)} | {iou} | {recall} | {near or '-'} | {multi} |")
    return "\n".join(lines) + "\n"


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    kinds: tuple[str, ...] = ("knife",)
    """Generated kinds to measure."""
    seeds: PositiveInt = 20
    """N seeds of each kind, from ``first_seed`` ..."""
    first_seed: NonNegativeInt = 0
    """... to ``first_seed`` + N - 1 (a tune set and a held-out set of seeds apart)."""
    near: Positive = 0.005
    """Margin (m) around the labeled surface counted as on the label."""
    out: Path = Path("docs/results/generated-labels")
    """Folder of ``rows.jsonl`` and ``generated_labels.md``."""
    label: AutoLabelConfig = field(default_factory=AutoLabelConfig)


def run(options: Options) -> str:
    """Measure every (kind, seed) not yet in ``rows.jsonl`` under these settings; the table."""
    unknown = [k for k in options.kinds if k not in ALL_GENERATED_KINDS]
    if unknown:
        raise SimgraspError(f"unknown kinds {unknown}; known: {', '.join(ALL_GENERATED_KINDS)}")
    key = settings_key(options.label)
    options.out.mkdir(parents=True, exist_ok=True)
    done_file = options.out / "rows.jsonl"
    done = kept_rows(
        done_file,
        lambda r: (
            r.get("settings") == key
            and r.get("near_margin") == options.near
            and r.get("kind") in ALL_GENERATED_KINDS
            and r.get("mesh") == mesh_key(generate_tool(r["kind"], r["seed"]))
        ),
    )
    have = {(r["kind"], r["seed"]) for r in done}
    for kind in options.kinds:
        for seed in range(options.first_seed, options.first_seed + options.seeds):
            if (kind, seed) in have:
                continue
            row = measure_one(kind, seed, options.label, options.near)
            row.update(settings=key, near_margin=options.near)
            done.append(row)
            add_row(done_file, row)
    seeds = range(options.first_seed, options.first_seed + options.seeds)
    wanted = [r for r in done if r["kind"] in options.kinds and r["seed"] in seeds]
    text = table(wanted)
    (options.out / "generated_labels.md").write_text(text)
    return text


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
