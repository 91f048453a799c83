"""The single-view default on generated mugs no classifier was trained on (simulation): flat
strap mugs (``gen_strap_mug``, the classifier saw seeds 0-9) and round-tube mugs
(``gen_mug``), each in five single views like the real mug captures and the training views
(upright kinect 0.78 and 0.6 m, upright stereo 0.78 m, lying stereo 0.3 m, lying kinect
0.6 m), from two azimuths (``--azimuths``), one sensor seed; scored in the mesh frame by
:func:`simgrasp.evaluation.sim_views.score_view`. Writes ``unseen_mugs.csv`` (one row per
view and setting) and ``unseen_mugs.md`` (per mug kind and view: pooled candidate accuracy
and views with the top handle on the handle) to ``--out``.

    python scripts/unseen_mugs.py --strap-seeds 70:90 --tube-seeds 25:30 --workers 2 \\
        --out out/unseen-mugs-s70

``--narrow-width-spacings 0`` scores the default of the runs before 4 December 2026 (no
narrow fits) beside today's (docs/results/real-detect/README.md); ``--classifier FILE`` adds
a column for the default with another trained classifier; ``--body-wall false`` scores the
default before 7 December 2026 (without the body-wall test), ``--also-body-wall true|false``
adds a column for the default with the test on or off; ``--azimuths 60,200`` views the mugs
from other sides.
"""

from __future__ import annotations

import csv
import itertools
import multiprocessing
from collections import defaultdict
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.config.fields import setting
from simgrasp.errors import SimgraspError
from simgrasp.evaluation.real_detect import RealDetectRow, pooled_score
from simgrasp.evaluation.sim_views import SimView, score_view
from simgrasp.handles import SingleViewConfig
from simgrasp.handles.presets import single_view_preset

VIEWS = (  # (pose, distance m, elevation deg, sensor)
    ("upright", 0.78, 32.0, "kinect"),
    ("upright", 0.78, 32.0, "stereo"),
    ("lying", 0.30, 90.0, "stereo"),
    ("lying", 0.60, 90.0, "kinect"),
    ("upright", 0.6, 40.0, "kinect"),
)
AZIMUTHS = (0.0, 120.0)
"""Default camera azimuths (degrees): the handle to the camera's right, and turned away by
120."""


def seed_range(text: str) -> tuple[int, ...]:
    """``START:STOP`` (stop excluded) as the seeds; a :class:`SimgraspError` on anything else."""
    start, _, stop = text.partition(":")
    try:
        return tuple(range(int(start), int(stop)))
    except ValueError:
        raise SimgraspError(f"seeds must be START:STOP, got {text!r}") from None


Job = tuple[str, SimView, SingleViewConfig]


def score(job: Job) -> tuple[str, SimView, RealDetectRow]:
    """One view scored with the job's settings (sensor seed 0)."""
    name, view, settings = job
    return name, view, score_view(view, "default", 0, None, settings)


def jobs(
    strap: tuple[int, ...],
    tube: tuple[int, ...],
    azimuths: tuple[float, ...],
    settings: dict[str, SingleViewConfig],
) -> list[Job]:
    """Every (setting name, view, settings) to score."""
    objects = [f"gen_strap_mug_s{s}" for s in strap] + [f"gen_mug_s{s}" for s in tube]
    return [
        (name, SimView(obj, pose, distance, elevation, sensor, azimuth_deg=azimuth), chosen)  # type: ignore[arg-type]
        for name, chosen in settings.items()
        for obj, (pose, distance, elevation, sensor), azimuth in itertools.product(
            objects, VIEWS, azimuths
        )
    ]


def table(scored: list[tuple[str, SimView, RealDetectRow]], names: list[str]) -> str:
    """Per mug kind and view (rows) and setting (columns): pooled accuracy (views with the
    top handle on the handle / views), and every view pooled."""
    groups: dict[tuple[str, str], list[RealDetectRow]] = defaultdict(list)
    for name, view, row in scored:
        kind = view.object.rsplit("_s", 1)[0]
        seen = f"{kind} {view.pose} {view.sensor} {view.distance:g} m"
        groups[(seen, name)].append(row)
        groups[("all views", name)].append(row)
    keys = sorted({seen for seen, _ in groups} - {"all views"}) + ["all views"]
    lines = ["| mug, view | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for seen in keys:
        cells = (pooled_score(groups[(seen, n)]) for n in names)
        text = [f"{accuracy:.3f} ({top}/{runs})" for accuracy, top, runs in cells]
        lines.append(f"| {seen} | " + " | ".join(text) + " |")
    return "\n".join(lines) + "\n"


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    strap_seeds: tuple[int, ...] = setting(
        tuple(range(70, 90)), parse=seed_range, metavar="START:STOP"
    )
    """Seeds of the flat-strap mugs (gen_strap_mug), START:STOP with STOP excluded."""
    tube_seeds: tuple[int, ...] = setting(
        tuple(range(25, 30)), parse=seed_range, metavar="START:STOP"
    )
    """Seeds of the round-tube mugs (gen_mug), START:STOP with STOP excluded."""
    narrow_width_spacings: float = 0.0
    """Also score the default with this narrow_width_spacings (0: before 4 December 2026)."""
    azimuths: tuple[float, ...] = AZIMUTHS
    """Camera azimuths (degrees): every view is rendered from each."""
    classifier: Path | None = None
    """Also score the default with this classifier file (train_candidate_classifier.py)."""
    body_wall: bool = True
    """The default's body-wall test (simgrasp.handles.single_view.body_wall): on since 7 December
    2026."""
    also_body_wall: bool | None = None
    """Also score the default with the body-wall test on (column "body wall") or off ("no body
    wall"); none: no such column."""
    workers: PositiveInt = 1
    """Worker processes scoring the views."""
    out: Path = Path("out/unseen-mugs")
    """Folder of unseen_mugs.csv and unseen_mugs.md."""


def run(options: Options) -> str:
    """Score every mug, view and setting; the table."""
    default = single_view_preset().with_body_wall(options.body_wall)
    settings = {
        "default": default,
        f"narrow {options.narrow_width_spacings:g}": replace(
            default, narrow_width_spacings=options.narrow_width_spacings
        ),
    }
    if options.classifier is not None:
        settings[options.classifier.name] = replace(
            default, classifier_file=str(options.classifier)
        )
    if options.also_body_wall is not None:
        name = "body wall" if options.also_body_wall else "no body wall"
        settings[name] = default.with_body_wall(options.also_body_wall)
    work = jobs(options.strap_seeds, options.tube_seeds, options.azimuths, settings)
    with multiprocessing.get_context("spawn").Pool(options.workers) as pool:
        scored = pool.map(score, work, chunksize=2)
    options.out.mkdir(parents=True, exist_ok=True)
    with (options.out / "unseen_mugs.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, ["setting", *(f.name for f in fields(RealDetectRow))])
        writer.writeheader()
        for name, _, row in scored:
            writer.writerow({"setting": name, **asdict(row)})
    text = table(scored, list(settings))
    (options.out / "unseen_mugs.md").write_text(text)
    return text


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
