"""How the default detector's real-cloud figures hold when the capture is made worse.

Issue 26's real-mug goal is checked on captures we do not have: other sensors, distances and
densities. This script takes the clouds of the real-data manifest
(``models/handles/real_detect.toml``: the two held-out mugs, the five tune knives) and
degrades each one as another capture might, from a seed: fewer points, range noise,
holes, a wrong viewpoint
(:mod:`simgrasp.evaluation.capture_degradations`). Then ``detect``'s default runs on it
(:func:`simgrasp.evaluation.real_detect.score_cloud`), once per seed. The simulated views
posed like each real mug capture (:data:`~simgrasp.evaluation.sim_views.REAL_CAPTURE_VIEWS`)
are degraded and scored alike, so the table says whether simulation predicts where the real
captures break. For each cloud or view and degradation it reports the candidate accuracy
pooled over the seeds and in how many seeds the top handle is on the labeled handle. Nothing
is tuned on these runs. Rows go to ``rows.jsonl`` as they finish, so a rerun keeps them.
``robustness.md`` is the table.

    SIMGRASP_REAL_DIR=../shared/real python scripts/real_robustness.py \\
        --out docs/results/real-detect/body-wall/robustness

``--body-wall false`` scores the default before 7 December 2026, without the body-wall test
(``docs/results/real-detect/robustness``; an output folder holds one setting's rows:
``run.json`` says which).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.evaluation.capture_degradations import DEGRADATIONS, degraded
from simgrasp.evaluation.real_detect import (
    RealDetectRow,
    pooled_score,
    score_cloud,
    setting_record,
)
from simgrasp.evaluation.real_manifest import RealCloud, load_real_cloud, read_manifest
from simgrasp.evaluation.sim_views import REAL_CAPTURE_VIEWS, SimView, score_view
from simgrasp.handles import SingleViewConfig
from simgrasp.handles.presets import single_view_preset
from simgrasp.runs.identity import claim_identity
from simgrasp.seeding import rng_for


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    manifest: Path | None = None
    """Real-data manifest (default: the shipped models/handles/real_detect.toml)."""
    real_dir: Path | None = None
    """Real data root (default: $SIMGRASP_REAL_DIR, else ../shared/real)."""
    seeds: PositiveInt = 5
    """Seeds 0 .. seeds - 1: each draws its degradation and seeds its detection."""
    out: Path = Path("docs/results/real-detect/robustness")
    """Folder of rows.jsonl and robustness.md."""
    sim: bool = True
    """Also degrade and score the simulated views posed like the real mug captures (needs
    $SIMGRASP_YCB_DIR for the YCB mug)."""
    body_wall: bool = True
    """The default's body-wall test (:mod:`simgrasp.handles.single_view.body_wall`): on, as
    ``detect`` runs it since 7 December 2026; false scores the default before that day."""

    def single_view(self) -> SingleViewConfig | None:
        """The single-view settings to score (None: ``detect``'s default)."""
        if self.body_wall:
            return None
        return single_view_preset().with_body_wall(False)


def measure(
    cloud: RealCloud,
    points: NDArray[np.float64],
    kind: str,
    seed: int,
    single_view: SingleViewConfig | None,
) -> dict[str, Any]:
    """One row: the default detector (``single_view`` as ``score_cloud`` takes it) on
    ``cloud`` degraded by ``kind`` from ``seed``."""
    rng = rng_for(seed, "real_robustness", kind, cloud.name)
    worse, viewpoint = degraded(points, cloud.viewpoint, kind, rng)
    row = score_cloud(replace(cloud, viewpoint=viewpoint), worse, "default", seed, single_view)
    return {**asdict(row), "degradation": kind}


def measure_view(
    view: SimView, real: str, kind: str, seed: int, single_view: SingleViewConfig | None
) -> dict[str, Any]:
    """One row: the default detector on simulated ``view`` (posed like real cloud ``real``)
    degraded by ``kind`` from ``seed``."""
    row = score_view(view, "default", seed, None, single_view, degradation=kind)
    return {**asdict(row), "split": f"sim of {real}", "degradation": kind}


def identity(options: Options) -> dict[str, Any]:
    """What the rows depend on besides the clouds and seeds: the manifest and every value of
    the default they score (with its classifier's SHA-256), so that a rerun after the
    default changed refuses the folder instead of keeping old rows under new settings."""
    return {
        "manifest": str(options.manifest or "shipped"),
        "default": setting_record("default", options.single_view()),
    }


def run(options: Options) -> str:
    """Measure every (cloud, degradation, seed) not yet in ``rows.jsonl``; the table. A cloud
    whose rows are all there is not read again."""
    clouds = read_manifest(options.manifest, options.real_dir)
    settings = options.single_view()
    claim_identity(options.out / "run.json", identity(options), what="rows of another setting")
    rows_file = options.out / "rows.jsonl"
    rows = [json.loads(line) for line in rows_file.open()] if rows_file.is_file() else []
    done = {(r["cloud"], r["degradation"], r["seed"]) for r in rows}
    names = []
    with rows_file.open("a") as log:
        for cloud in clouds:
            views = REAL_CAPTURE_VIEWS.get(cloud.name, ()) if options.sim else ()
            names += [cloud.name, *(view.name for view in views)]
            missing = {
                (kind, seed)
                for kind in DEGRADATIONS
                for seed in range(options.seeds)
                if (cloud.name, kind, seed) not in done
            }
            points = load_real_cloud(cloud) if missing else None
            for kind in DEGRADATIONS:
                for seed in range(options.seeds):
                    if points is not None and (kind, seed) in missing:
                        rows.append(measure(cloud, points, kind, seed, settings))
                        log.write(json.dumps(rows[-1]) + "\n")
                    for view in views:
                        if (view.name, kind, seed) not in done:
                            rows.append(measure_view(view, cloud.name, kind, seed, settings))
                            log.write(json.dumps(rows[-1]) + "\n")
                    log.flush()
    text = table(rows, names, options.seeds)
    (options.out / "robustness.md").write_text(text)
    return text


def table(rows: list[dict[str, Any]], names: list[str], seeds: int) -> str:
    """Per cloud (split in brackets) and degradation: candidate accuracy pooled over the seeds
    (:func:`~simgrasp.evaluation.real_detect.pooled_score`; "-" where no run kept a
    candidate) and the seeds whose top handle is on the handle."""
    head = "| cloud | " + " | ".join(DEGRADATIONS) + " |\n"
    head += "|---|" + "---|" * len(DEGRADATIONS) + "\n"
    lines = []
    for name in names:
        mine = [r for r in rows if r["cloud"] == name and r["seed"] < seeds]
        cells = []
        for kind in DEGRADATIONS:
            these = [detect_row(r) for r in mine if r["degradation"] == kind]
            accuracy, tops, runs = pooled_score(these)
            found = any(r.candidates for r in these)
            cells.append(f"{accuracy:.2f}, {tops} of {runs}" if found else f"-, {tops} of {runs}")
        split = mine[0]["split"] if mine else "?"
        lines.append(f"| {name} ({split}) | " + " | ".join(cells) + " |")
    legend = (
        "Each cell: candidate accuracy pooled over the seeds, and the seeds whose top handle "
        "lies on the labeled handle.\n\n"
    )
    return legend + head + "\n".join(lines) + "\n"


def detect_row(row: dict[str, Any]) -> RealDetectRow:
    """A ``rows.jsonl`` row as the :class:`~simgrasp.evaluation.real_detect.RealDetectRow` it
    was written from (its ``degradation`` left out)."""
    return RealDetectRow(**{f.name: row[f.name] for f in fields(RealDetectRow)})


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
