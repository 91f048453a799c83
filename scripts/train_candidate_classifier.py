"""Train the single-view candidate classifier (``models/handles/candidate_classifier.json``)
on simulated views with exact handle labels: the procedural tool families, generated mugs and
tools and the labeled YCB objects, upright and lying, near and far, through the ideal, kinect and
stereo sensor models (:mod:`simgrasp.evaluation.sim_views`), as captured and made worse
(:mod:`simgrasp.evaluation.capture_degradations`). No real cloud is used. Each candidate of
:func:`~simgrasp.handles.single_view.detector.single_view_candidates` is a row of
:func:`~simgrasp.handles.single_view.candidate_features.candidate_features`, labeled by whether
its center lies in the object's handle label; boosted trees (scikit-learn) are fitted
with every view weighted alike and written as JSON. Needs scikit-learn and ``SIMGRASP_YCB_DIR``.

    python scripts/train_candidate_classifier.py --family-seeds 5 --seeds 1 --cache out/rows \
        --workers 2 --out out/families.json

Family objects ``gen_<kind>_s0`` .. ``s<N-1>`` (``--family-seeds N``) are trained on; seeds from
:data:`FIRST_UNTRAINED_SEED` on never are (tune and held-out seeds,
docs/results/data-engine). ``--evaluate A.json B.json`` scores models instead of training: the
default detector with each on the views of the untrained family seeds ``--eval-seeds``.
``--cache DIR`` keeps every view's rows, so a rerun renders nothing it rendered before.
``--first-objects`` trains on the 13 objects of the first classifier, ``--with-drills`` adds ten
generated drills; ``--leave-one-out`` prints, per object, how a model trained on the others does
on its views (``--ensemble-leave-one-out``: with and without the drills and the two as one
ensemble); ``--combine A.json:0.7 B.json:0.6 --out E.json`` writes an ensemble that keeps a
candidate where any of its models keeps it (tried models: docs/results/real-detect).
"""

from __future__ import annotations

import functools
import hashlib
import itertools
import json
import multiprocessing
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import numpy as np

from simgrasp.assets.families import FAMILY_KINDS
from simgrasp.config import Checked, setting
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import MinLength, NonNegativeInt, Positive, PositiveInt, Range
from simgrasp.errors import SimgraspError
from simgrasp.evaluation.capture_degradations import DEGRADATIONS, degraded
from simgrasp.evaluation.sim_views import Pose, SimCapture, SimView, capture
from simgrasp.handles.single_view.candidate_features import FEATURES, candidate_features
from simgrasp.handles.single_view.detector import SingleViewConfig, single_view_candidates
from simgrasp.seeding import rng_for

OBJECTS = (
    "gen_hammer",
    "gen_mug",
    "gen_spatula",
    "gen_screwdriver",
    "gen_pan",
    "025_mug",
    "033_spatula",
    "048_hammer",
    "030_fork",
    "044_flat_screwdriver",
    "035_power_drill",
    "019_pitcher_base",
    "037_scissors",
)
"""The first classifier's objects; the flat-strap mugs of seeds 0-9 are added
(``--strap-mugs 10``)."""
YCB_TOOLS = ("031_spoon", "032_knife", "042_adjustable_wrench", "043_phillips_screwdriver")
"""The other labeled YCB objects with a handle, added with ``--family-seeds``."""
FIRST_UNTRAINED_SEED = 5
"""Family seeds from here on are never trained on: 5-6 tune, 100-102 held out."""
DRILLS = tuple(f"gen_drill_s{seed}" for seed in range(10))
"""Generated pistol-grip drills, added with ``--with-drills`` (a model tried and not shipped:
docs/results/real-detect)."""
VIEWS: tuple[tuple[Pose, float, float, str], ...] = (
    ("upright", 0.6, 32.0, "kinect"),
    ("upright", 0.8, 45.0, "kinect"),
    ("upright", 0.5, 60.0, "stereo"),
    ("upright", 0.8, 32.0, "stereo"),
    ("lying", 0.6, 90.0, "kinect"),
    ("lying", 0.35, 70.0, "stereo"),
)
"""(pose, distance m, elevation deg, sensor) of every view; the kinect sees nothing nearer
0.5 m."""
IDEAL_VIEWS: tuple[tuple[Pose, float, float, str], ...] = (
    ("upright", 0.6, 45.0, "ideal"),
    ("lying", 0.45, 70.0, "ideal"),
)
"""Views through the ideal sensor, added with ``--family-seeds``."""
TOP_VIEWS: tuple[tuple[Pose, float, float, str], ...] = (
    ("upright", 0.85, 90.0, "stereo"),
    ("upright", 0.7, 90.0, "kinect"),
)
"""Views from straight above the object's own pose (a flat tool lying flat, as a camera over a
workbench sees it), added with ``--top-views``."""


@functools.lru_cache(maxsize=1)
def _rendered(view: SimView, seed: int) -> SimCapture:
    """``view`` rendered with ``seed``, kept for its degraded copies: :func:`run` hands a
    worker each view's copies together, one after another."""
    return capture(view, seed)


def view_rows(
    view: SimView, seed: int, degradation: str = "as captured", grid_rolls: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """Features and on-handle labels of one rendered view's candidates, the view made worse by
    ``degradation`` first (:func:`~simgrasp.evaluation.capture_degradations.degraded`, drawn
    from ``seed``)."""
    shot = _rendered(view, seed)
    rng = rng_for(seed, "train_candidate_classifier", degradation, view.name)
    points, eye = degraded(np.asarray(shot.points_cam, np.float64), np.zeros(3), degradation, rng)
    if len(points) < 50:
        return np.zeros((0, len(FEATURES))), np.zeros(0, dtype=bool)
    config = SingleViewConfig(grid_rolls=grid_rolls)
    raw, cloud, spacing = single_view_candidates(points, config, seed, eye)
    if not raw.candidates:
        return np.zeros((0, len(FEATURES))), np.zeros(0, dtype=bool)
    features = candidate_features(raw.candidates, cloud, eye, spacing, config.standoff)
    centers = np.stack([c.center for c in raw.candidates])
    in_mesh = centers @ shot.object_T_cam[:3, :3].T + shot.object_T_cam[:3, 3]
    return features, shot.label.contains(in_mesh)


def cached_rows(
    view: SimView, seed: int, degradation: str, cache: Path | None, grid_rolls: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`view_rows`, kept in ``cache`` (a folder, None: not kept) as one ``.npz`` per
    view, seed and degradation, named by them and the features and candidate settings."""
    if cache is None:
        return view_rows(view, seed, degradation, grid_rolls)
    given = [repr(view), seed, degradation, FEATURES, repr(SingleViewConfig(grid_rolls=grid_rolls))]
    key = hashlib.sha256(json.dumps(given).encode()).hexdigest()[:20]
    path = cache / f"{key}.npz"
    if path.exists():
        with np.load(path) as kept:
            return kept["x"], kept["y"]
    x, y = view_rows(view, seed, degradation, grid_rolls)
    np.savez(cache / f"{key}.part.npz", x=x, y=y)
    (cache / f"{key}.part.npz").replace(path)  # whole or absent if killed
    return x, y


def weights(y: np.ndarray, views: np.ndarray, view_weight: np.ndarray | None = None) -> np.ndarray:
    """Sample weights giving every view the same total weight (or ``view_weight[v]`` (V,)
    times it), split evenly between its on-handle and off-handle candidates (a mug's few
    strap candidates count as much as its body's many, and a dense view as much as a sparse
    one)."""
    w = np.zeros(len(y))
    for v in np.unique(views):
        scale = 1.0 if view_weight is None else float(view_weight[v])
        for side in (True, False):
            rows = (views == v) & (y == side)
            if rows.any():
                w[rows] = scale / rows.sum()
    return w * len(y) / w.sum()


def boosted(  # noqa: ANN201
    x: np.ndarray, y: np.ndarray, views: np.ndarray, view_weight: np.ndarray | None = None
):
    """The fitted scikit-learn model: 60 boosted trees of depth 3, zero initial guess, the
    samples weighted by :func:`weights`."""
    from sklearn.ensemble import GradientBoostingClassifier

    model = GradientBoostingClassifier(
        n_estimators=60, max_depth=3, learning_rate=0.2, init="zero", random_state=0
    )
    return model.fit(x, y, sample_weight=weights(y, views, view_weight))


def view_scores(
    p: np.ndarray, y: np.ndarray, views: np.ndarray, threshold: float = 0.6
) -> tuple[float, float]:
    """Over the views with a candidate on the handle: the mean share of kept candidates
    (p >= ``threshold``) on the handle (0 for a view keeping none), and the share of views
    keeping one on the handle."""
    shares, hits = [], []
    for v in np.unique(views[y]):
        kept = (views == v) & (p >= threshold)
        shares.append(float(y[kept].mean()) if kept.any() else 0.0)
        hits.append(bool(y[kept].any()))
    return float(np.mean(shares)), float(np.mean(hits))


def leave_one_out(x: np.ndarray, y: np.ndarray, views: np.ndarray, objects: np.ndarray) -> None:
    """Print, per training object, the :func:`view_scores` of a model trained on the others."""
    for name in dict.fromkeys(objects):
        held = objects == name
        model = boosted(x[~held], y[~held], views[~held])
        share, hit = view_scores(model.predict_proba(x[held])[:, 1], y[held], views[held])
        print(f"held out {name}: kept on handle {share:.3f}, views with one {hit:.3f}", flush=True)


def ensemble_leave_one_out(
    x: np.ndarray, y: np.ndarray, views: np.ndarray, objects: np.ndarray
) -> None:
    """Print, per training object, the :func:`view_scores` of three models trained on the
    others: without the generated drills at 0.7 (the shipped model's threshold), with them
    at 0.6, and the two as one :class:`~simgrasp.handles.single_view.candidate_features.MaxEnsemble`
    (a candidate kept where either keeps it)."""
    drills = np.char.startswith(objects.astype(str), "gen_drill")
    for name in dict.fromkeys(objects):
        held = objects == name
        base = boosted(x[~held & ~drills], y[~held & ~drills], views[~held & ~drills])
        with_drills = boosted(x[~held], y[~held], views[~held])
        p_base = base.predict_proba(x[held])[:, 1]
        p_drills = with_drills.predict_proba(x[held])[:, 1]
        either = (p_base >= 0.7) | (p_drills >= 0.6)
        cells = [
            view_scores(p, y[held], views[held], t)
            for p, t in ((p_base, 0.7), (p_drills, 0.6), (either.astype(float), 0.5))
        ]
        text = ", ".join(f"{share:.3f} / {hit:.3f}" for share, hit in cells)
        print(f"held out {name}: without drills, with drills, either: {text}", flush=True)


def combined(members: list[str], threshold: float) -> dict:
    """The ensemble JSON of the models ``FILE:THRESHOLD`` in ``members``, each shifted so that
    its own threshold becomes ``threshold`` (the one the settings apply)."""

    def logit(p: float) -> float:
        return float(np.log(p / (1.0 - p)))

    models = []
    for member in members:
        path, _, own = member.rpartition(":")
        model = json.loads(Path(path).read_text())
        model["shift"] = logit(threshold) - logit(float(own))
        models.append(model)
    return {"members": models, "threshold": threshold}


def fit(
    x: np.ndarray, y: np.ndarray, views: np.ndarray, view_weight: np.ndarray | None = None
) -> dict:
    """:func:`boosted` as the JSON that
    :class:`~simgrasp.handles.single_view.candidate_features.TreeClassifier` reads."""
    model = boosted(x, y, views, view_weight)
    trees = []
    for (estimator,) in model.estimators_:
        t = estimator.tree_
        trees.append(
            {
                "feature": t.feature.tolist(),
                "threshold": t.threshold.tolist(),
                "left": t.children_left.tolist(),
                "right": t.children_right.tolist(),
                "value": t.value[:, 0, 0].tolist(),
            }
        )
    print(f"weighted training accuracy {model.score(x, y, weights(y, views, view_weight)):.3f}")
    return {"features": list(FEATURES), "learning_rate": model.learning_rate, "trees": trees}


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    seeds: PositiveInt = 2
    """Seeds 0 .. seeds - 1 of every view."""
    azimuths: Annotated[tuple[float, ...], MinLength(1)] = (0.0,)
    """Camera azimuths (degrees): every view is rendered from each."""
    workers: PositiveInt = 1
    """Processes rendering the views."""
    first_objects: bool = False
    """Train on the first classifier's 13 objects (no gen_strap_mug)."""
    with_drills: bool = False
    """Add the generated drills."""
    strap_mugs: NonNegativeInt = 10
    """Train on the flat-strap mugs of seeds 0..N-1 (the shipped model: 10)."""
    degradations: tuple[str, ...] = setting((), many=True, metavar="KIND")
    """Also train on every view made worse by each of these (``half``, ``quarter``,
    ``noise1mm``, ``noise2mm``, ``holes``, ``viewpoint10cm``; drawn from the view's seed), each
    copy weighted as a view of its own."""
    strap_family_weight: Positive | None = None
    """The strap mugs' views together weigh as many objects' views as this (default: each strap
    mug as one object)."""
    leave_one_out: bool = False
    """Print each object's figures under a model trained without it; write nothing."""
    ensemble_leave_one_out: bool = False
    """With --with-drills: print each object's figures under the models trained without it with
    and without the drills, and under the two as one ensemble; write nothing."""
    combine: tuple[str, ...] = setting((), many=True, metavar="FILE:THRESHOLD")
    """Write the ensemble of these trained models (a candidate kept where any keeps it at its
    own threshold) for the settings' --threshold; train nothing."""
    threshold: Annotated[float, Range(gt=0, lt=1)] = 0.7
    """With --combine: the threshold the ensemble's settings apply."""
    family_seeds: Annotated[int, Range(ge=0, le=FIRST_UNTRAINED_SEED)] = 0
    """Also train on every family kind's ``gen_<kind>_s0`` .. ``s<N-1>``, seen from an azimuth
    drawn from the seed, the other labeled YCB tools (:data:`YCB_TOOLS`) and, for every
    object, the ideal sensor's views (:data:`IDEAL_VIEWS`)."""
    grid_rolls: PositiveInt = 1
    """Candidates of each view pooled over this many turned voxel grids
    (``SingleViewConfig.grid_rolls``), as the detector that reads the model will pool them."""
    top_views: bool = False
    """Also train on (and with --evaluate, score) the views from straight above
    (:data:`TOP_VIEWS`)."""
    cache: Path | None = None
    """Folder keeping every view's rows (a rerun renders nothing it rendered before)."""
    evaluate: tuple[Path, ...] = setting((), many=True, metavar="FILE")
    """Score these models on the views of the family seeds --eval-seeds; train nothing."""
    eval_seeds: tuple[int, ...] = (5, 6)
    """With --evaluate: the family seeds (never trained on) whose views are scored."""
    out: Path | None = None
    """The JSON file written: the model, or with --combine the ensemble."""

    def _check(self) -> None:
        """The combinations the command line refuses."""
        if self.combine and self.out is None:
            raise SimgraspError("--combine needs --out")
        if self.out is None and not (
            self.leave_one_out or self.ensemble_leave_one_out or self.evaluate
        ):
            raise SimgraspError(
                "--out is required unless --leave-one-out, --ensemble-leave-one-out or --evaluate"
            )
        unknown = sorted(set(self.degradations) - set(DEGRADATIONS[1:]))
        if unknown:
            raise SimgraspError(
                f"--degradations: unknown {', '.join(unknown)}; "
                f"choose from {', '.join(DEGRADATIONS[1:])}"
            )
        if self.ensemble_leave_one_out and not self.with_drills:
            raise SimgraspError("--ensemble-leave-one-out needs --with-drills")
        if any(seed < FIRST_UNTRAINED_SEED for seed in self.eval_seeds):
            raise SimgraspError(
                f"--eval-seeds: family seeds below {FIRST_UNTRAINED_SEED} are trained on"
            )


def drawn_azimuth(obj: str, seed: int) -> float:
    """The azimuth (whole degrees) a family object is seen from in its views of ``seed``."""
    return float(rng_for(seed, "train_azimuth", obj).integers(360))


def training_views(
    objects: list[str],
    azimuths: list[float],
    seeds: int,
    degradations: tuple[str, ...],
    views: tuple[tuple[Pose, float, float, str], ...] = VIEWS,
    turned: frozenset[str] = frozenset(),
) -> list[tuple[SimView, int, str]]:
    """Every (view, seed, degradation) trained on: each object in each of ``views`` from each
    azimuth (the ``turned`` objects: from :func:`drawn_azimuth`) and seed, as captured and made
    worse by each of ``degradations``."""
    kinds = ["as captured", *degradations]
    return [
        (SimView(obj, pose, distance, elevation, sensor, azimuth_deg=azimuth), seed, kind)
        for obj, (pose, distance, elevation, sensor), seed in itertools.product(
            objects, views, range(seeds)
        )
        for azimuth in ([drawn_azimuth(obj, seed)] if obj in turned else azimuths)
        for kind in kinds
    ]


def scored_view(view: SimView, model: Path) -> tuple[int, int, bool]:
    """Candidates, candidates on the handle and whether the top handle is on it, when the
    default detector (``simgrasp detect``) runs with the classifier ``model`` on ``view``."""
    from simgrasp.evaluation.sim_views import score_view
    from simgrasp.handles.presets import single_view_preset

    single = single_view_preset(classifier_file=str(model))
    row = score_view(view, "default", 0, single_view=single)
    return row.candidates, row.on_handle, row.top_on_handle


def evaluate(options: Options) -> None:
    """Print, per model, sensor and family kind, pooled accuracy and top handles on the
    views of the family seeds ``--eval-seeds`` (every view of :data:`VIEWS` and
    :data:`IDEAL_VIEWS`, and with ``--top-views`` :data:`TOP_VIEWS`, from
    :func:`drawn_azimuth`)."""
    names = [f"gen_{kind}_s{seed}" for kind in FAMILY_KINDS for seed in options.eval_seeds]
    seen = VIEWS + IDEAL_VIEWS + (TOP_VIEWS if options.top_views else ())
    views = [v for v, _, _ in training_views(names, [], 1, (), seen, frozenset(names))]
    with multiprocessing.get_context("spawn").Pool(options.workers) as pool:
        scored = [pool.starmap(scored_view, [(v, m) for v in views]) for m in options.evaluate]
    for model, rows in zip(options.evaluate, scored, strict=True):
        cells: dict[tuple[str, str], list[tuple[int, int, bool]]] = {}
        for view, row in zip(views, rows, strict=True):
            kind = view.object.rsplit("_s", 1)[0]
            for key in ((view.sensor, kind), (view.sensor, "all"), ("all", "all")):
                cells.setdefault(key, []).append(row)
        for (sensor, kind), got in sorted(cells.items()):
            candidates, on_handle = sum(r[0] for r in got), sum(r[1] for r in got)
            accuracy = on_handle / candidates if candidates else float("nan")
            tops = sum(r[2] for r in got)
            print(f"{model} {sensor} {kind}: accuracy {accuracy:.3f}, tops {tops}/{len(got)}")


def training_set(
    options: Options, strap_mugs: int
) -> tuple[list[str], tuple[tuple[Pose, float, float, str], ...], list[tuple[SimView, int, str]]]:
    """The objects, the views of each and every (view, seed, degradation) trained on."""
    objects = [*OBJECTS, *(f"gen_strap_mug_s{seed}" for seed in range(strap_mugs))]
    objects += list(DRILLS) if options.with_drills else []
    seen = VIEWS
    families = [f"gen_{k}_s{s}" for k in FAMILY_KINDS for s in range(options.family_seeds)]
    if options.family_seeds:
        objects += [*YCB_TOOLS, *families]
        seen = VIEWS + IDEAL_VIEWS
    seen += TOP_VIEWS if options.top_views else ()
    jobs = training_views(
        objects,
        list(options.azimuths),
        options.seeds,
        options.degradations,
        seen,
        frozenset(families),
    )
    return objects, seen, jobs


def rendered_rows(
    options: Options, jobs: list[tuple[SimView, int, str]]
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Every job's features and labels (rendered by ``--workers`` processes, or read from
    ``--cache``), each job's counts printed."""
    if options.cache is not None:
        options.cache.mkdir(parents=True, exist_ok=True)
    with multiprocessing.get_context("spawn").Pool(options.workers) as pool:
        copies = 1 + len(options.degradations)  # a view's copies in one chunk: one render
        cached = [(*job, options.cache, options.grid_rolls) for job in jobs]
        results = pool.starmap(cached_rows, cached, chunksize=4 * copies)
    for (sim, seed, kind), (_, on_handle) in zip(jobs, results, strict=True):
        print(
            f"{sim.name} seed {seed} {kind}: {len(on_handle)} candidates, "
            f"{on_handle.sum()} on handle"
        )
    return [x for x, _ in results], [y for _, y in results]


def run(options: Options) -> None:
    """Write the ensemble (``--combine``), print the leave-one-out figures, or train and write
    the model."""
    if options.combine:
        assert options.out is not None  # _check: --combine needs --out
        options.out.write_text(
            json.dumps(combined(list(options.combine), options.threshold)) + "\n"
        )
        print(f"wrote {options.out}")
        return
    if options.evaluate:
        evaluate(options)
        return
    strap_mugs = 0 if options.first_objects else options.strap_mugs
    objects, seen, jobs = training_set(options, strap_mugs)
    rows, labels = rendered_rows(options, jobs)
    x, y = np.concatenate(rows), np.concatenate(labels)
    views = np.concatenate([np.full(len(label), i) for i, label in enumerate(labels)])
    if options.leave_one_out or options.ensemble_leave_one_out:
        objects_of_rows = np.concatenate(
            [
                np.full(len(label), sim.object)
                for (sim, _, _), label in zip(jobs, labels, strict=True)
            ]
        )
        check = ensemble_leave_one_out if options.ensemble_leave_one_out else leave_one_out
        check(x, y, views, objects_of_rows)
        return
    view_weight = None
    if options.strap_family_weight is not None and strap_mugs:
        strap = [sim.object.startswith("gen_strap_mug") for sim, _, _ in jobs]
        view_weight = np.where(strap, options.strap_family_weight / strap_mugs, 1.0)
    model = fit(x, y, views, view_weight)
    model["trained_on"] = {
        "objects": objects,
        "views": [list(v) for v in seen],
        "azimuths_deg": list(options.azimuths),
        "seeds": options.seeds,
        "family_seeds": options.family_seeds,
        "degradations": list(options.degradations),
        "candidates": int(len(y)),
        "on_handle": int(y.sum()),
    }
    if view_weight is not None:
        model["trained_on"]["strap_family_weight"] = options.strap_family_weight
    assert options.out is not None  # _check: --out unless a leave-one-out run (returned above)
    options.out.write_text(json.dumps(model) + "\n")
    print(f"{len(y)} candidates ({y.sum()} on handle); wrote {options.out}")


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
