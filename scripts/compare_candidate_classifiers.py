"""Compare candidate classifiers as ``detect``'s single-view default would use them, on the
TUNE data only (never the holdout mugs): the Mech-Mind knives of the real manifest (5 seeds),
simulated views (the mug views of ``sim_views.md``, the generated hammer, mug and spatula at
0.6 m, and mug views from azimuths no training set holds; 3 seeds) and the osd-learn pots
through the segmentation with rim joins and through their labels (5 seeds). A cell is the
pooled candidate accuracy and (runs with the top handle on a labeled handle / runs).

    python scripts/train_candidate_classifier.py --seeds 2 --azimuths 0,90,180,270 \\
        --workers 2 --out /tmp/wide.json
    python scripts/compare_candidate_classifiers.py models/handles/candidate_classifier.json \\
        /tmp/wide.json

Needs ``SIMGRASP_REAL_DIR`` and ``SIMGRASP_YCB_DIR``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path
from typing import Annotated

from simgrasp.config import Checked, setting
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Fraction, MinLength, NonNegative
from simgrasp.evaluation.real_detect import RealDetectRow, score_cloud
from simgrasp.evaluation.real_manifest import RealCloud, load_real_cloud, read_manifest
from simgrasp.evaluation.real_pots import POT_SEGMENTATION, PotResult, evaluate_real_pots
from simgrasp.evaluation.sim_views import SimView, score_view
from simgrasp.handles import QuadricDetectorConfig, SingleViewConfig
from simgrasp.handles.presets import single_view_preset

SIM_VIEWS = (
    SimView(pose="upright", distance=0.78, elevation_deg=32.0, sensor="kinect"),
    SimView(pose="upright", distance=0.78, elevation_deg=32.0, sensor="stereo"),
    SimView(pose="lying", distance=0.30, elevation_deg=90.0, sensor="stereo"),
    SimView(pose="lying", distance=0.60, elevation_deg=90.0, sensor="kinect"),
    *(
        SimView(tool, "upright", 0.6, 45.0, sensor)
        for tool in ("gen_hammer", "gen_mug", "gen_spatula")
        for sensor in ("kinect", "stereo")
    ),
    *(
        view
        for azimuth in (45.0, 135.0, 225.0)
        for view in (
            SimView("025_mug", "upright", 0.6, 40.0, "kinect", azimuth_deg=azimuth),
            SimView("gen_mug", "lying", 0.4, 60.0, "stereo", azimuth_deg=azimuth),
        )
    ),
)


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    models: Annotated[tuple[Path, ...], MinLength(1)] = setting(positional=True, many=True)
    """Classifier JSON files, a column each."""
    threshold: Fraction | None = None
    """Classifier threshold (default: the learned setting's)."""
    min_width_spacings: NonNegative | None = None
    """Narrowest fit kept, in measured point spacings (default: the learned setting's)."""
    narrow_width_spacings: NonNegative | None = None
    """Narrowest fit kept when its axis is near its surface, in spacings (default: the learned
    setting's)."""
    body_wall: bool = True
    """The default's body-wall test (:mod:`simgrasp.handles.single_view.body_wall`): on since 7
    December 2026; false scores the default before that day."""


def cell(rows: list[RealDetectRow] | list[PotResult]) -> str:
    candidates = sum(r.candidates for r in rows)
    accuracy = sum(r.on_handle for r in rows) / candidates if candidates else 0.0
    return f"{accuracy:.2f} ({sum(r.top_on_handle for r in rows)}/{len(rows)})"


def _real_cell(cloud: RealCloud, settings: SingleViewConfig) -> str:
    """One real tune cloud, loaded once, over 5 seeds."""
    points = load_real_cloud(cloud)
    return cell([score_cloud(cloud, points, "default", s, settings) for s in range(5)])


def _sim_cell(view: SimView, settings: SingleViewConfig) -> str:
    """One simulated view over 3 seeds."""
    return cell([score_view(view, "default", s, None, settings) for s in range(3)])


def _pots_cell(cut: str, settings: SingleViewConfig) -> str:
    """The osd-learn pots cut by ``cut`` (``segment`` or ``labels``) over 5 seeds."""
    return cell(
        evaluate_real_pots(
            QuadricDetectorConfig(),
            range(5),
            cut=cut,
            segment_config=POT_SEGMENTATION,
            single_view=settings,
        )
    )


def rows_for(settings: SingleViewConfig) -> Iterator[tuple[str, Callable[[], str]]]:
    """(row name, a function giving its cell) for every tune item."""
    for cloud in read_manifest(None, None):
        if cloud.split == "tune":
            yield f"real {cloud.name}", partial(_real_cell, cloud, settings)
    for view in SIM_VIEWS:
        yield f"sim {view.name}", partial(_sim_cell, view, settings)
    for cut in ("segment", "labels"):
        yield f"osd-learn pots, {cut} cut", partial(_pots_cell, cut, settings)


def run(options: Options) -> None:
    """Print the table: a row per tune item, a column per model."""
    settings = single_view_preset().with_body_wall(options.body_wall)
    if options.threshold is not None:
        settings = replace(settings, classifier_threshold=options.threshold)
    if options.min_width_spacings is not None:
        settings = replace(settings, min_width_spacings=options.min_width_spacings)
    if options.narrow_width_spacings is not None:
        settings = replace(settings, narrow_width_spacings=options.narrow_width_spacings)
    models = options.models
    columns = [list(rows_for(replace(settings, classifier_file=str(path)))) for path in models]
    print("| tune item | " + " | ".join(p.name for p in models) + " |")
    print("|---" * (len(models) + 1) + "|")
    for i, (name, _) in enumerate(columns[0]):
        print(f"| {name} | " + " | ".join(column[i][1]() for column in columns) + " |")


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
