"""Detection on the inputs the issue names: the default on a simulated single view (a
generated hammer through the kinect model, no data needed), a real osd-learn scene through
``detect --segment`` scored against our tab label (needs the real scenes), and the candidate
features of the single-view classifier on synthetic geometry."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from simgrasp.assets.real import default_real_dir
from simgrasp.assets.scene_labels import load_scene_labels
from simgrasp.cli import main
from simgrasp.errors import SimgraspError
from simgrasp.evaluation.sim_views import SimView, capture, score_view
from simgrasp.handles.core.detection import Candidate
from simgrasp.handles.presets import single_view_preset
from simgrasp.handles.single_view.candidate_features import (
    FEATURES,
    candidate_features,
    read_classifier,
)
from simgrasp.handles.single_view.detector import (
    FALLBACK_DETECTOR,
    SINGLE_VIEW_DETECTOR,
    _keep,
)
from simgrasp.labels import Box
from simgrasp.quadric.quadric import Quadric
from simgrasp.resources import model_path


def test_the_default_on_a_simulated_single_view_holds_the_hammer_by_its_handle() -> None:
    """One kinect view of the generated hammer from 0.6 m, 45 degrees up, with exact labels:
    the default detector (no preset) puts its top handle and nearly all candidates on the
    handle (measured 139 of 144 candidates, seed 0)."""
    view = SimView("gen_hammer", "upright", 0.6, 45.0, "kinect")
    row = score_view(view, "default", 0)
    assert row.top_on_handle
    assert row.on_handle >= 0.9 * row.candidates > 20


def test_the_default_keeps_a_thin_strap_seen_close_that_two_spacings_would_drop() -> None:
    """A flat-strap mug no classifier saw (seed 47), lying, seen by the stereo model from
    0.3 m as the real lying capture is: its strap is fitted 1-2 point spacings wide. The
    default keeps those fits (their axes near the surface) and holds the strap (measured:
    3 of 3 candidates on it); without narrow fits nothing passes, and the fallback ranks the
    body first (0 of 76; docs/results/real-detect/unseen-mugs-s30)."""
    view = SimView("gen_strap_mug_s47", "lying", 0.3, 90.0, "stereo")
    row = score_view(view, "default", 0)
    assert row.top_on_handle and row.on_handle == row.candidates > 0
    wide_only = replace(single_view_preset(), narrow_width_spacings=0.0)
    before = score_view(view, "default", 0, None, wide_only)
    assert not before.top_on_handle


def test_detect_takes_every_single_view_setting_as_a_flag(
    tmp_path, capsys: pytest.CaptureFixture[str]
) -> None:  # noqa: ANN001
    """``simgrasp detect`` on one kinect view of the generated hammer (camera frame, sensor at
    the origin): the default keeps classifier-passed candidates; a threshold of 1 keeps none,
    so the fallback detects; ``--single-view false`` runs the plain quadric detector; a
    threshold outside [0, 1] is one line naming the setting."""
    cloud = tmp_path / "hammer_view.npy"
    np.save(cloud, capture(SimView("gen_hammer", "upright", 0.6, 45.0, "kinect"), 0).points_cam)

    def detector(flags: list[str]) -> str:
        assert main(["detect", str(cloud), "--json", *flags]) == 0
        return str(json.loads(capsys.readouterr().out)["detector"])

    assert detector([]) == SINGLE_VIEW_DETECTOR
    assert detector(["--single-view-detector.classifier-threshold", "1"]) == FALLBACK_DETECTOR
    assert detector(["--single-view", "false"]) == "quadric"
    assert main(["detect", str(cloud), "--single-view-detector.classifier-threshold", "1.5"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and "single_view_detector.classifier_threshold" in error


@pytest.mark.real
def test_detect_segment_on_a_real_pot_scene_puts_the_top_handle_on_a_labeled_tab(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """learn36 through ``detect --segment`` with the committed pot settings
    (docs/results/real-pots/real_depth.toml): among the handles of the object whose segment
    (or part) is nearest the labeled tab (the pot), the top one lies in our tab label."""
    scene = default_real_dir() / "osd-learn" / "learn36.pcd"
    config = "docs/results/real-pots/real_depth.toml"
    assert main(["detect", str(scene), "--segment", "--config", config, "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    label = load_scene_labels()["learn36"].label
    tab_region = label.regions[0]
    assert isinstance(tab_region, Box)
    tab = tab_region.center
    objects = report["segmentation"]["objects"]
    nearest = min(objects, key=lambda o: float(np.linalg.norm(np.subtract(o["center"], tab))))
    on_pot = [h for h in report["handles"] if h["object"] == nearest["part_of"]]
    assert on_pot, "no handle on the pot"
    assert label.contains(np.array(on_pot[0]["center"])[None]).all()


@pytest.mark.real
def test_detect_segment_with_its_default_detector_holds_a_real_pot_by_its_tab(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """learn37 through ``detect --segment`` with the detector's defaults and the pots' rim
    joins (docs/results/real-pots, row ``detect default (single view)``: 5 of 5 seeds): every
    object is one view, the classifier keeps nothing on the pot's face-on tab and the
    fallback's plate test finds it; with ``--single-view false`` (the former default) the
    pot gets no handle on its tab (0 of 5)."""
    scene = default_real_dir() / "osd-learn" / "learn37.pcd"
    flags = ["--segment", "--segmentation.rim-band", "0.005", "--json"]
    label = load_scene_labels()["learn37"].label
    tab_region = label.regions[0]
    assert isinstance(tab_region, Box)

    def top_on_tab(extra: list[str]) -> tuple[bool, set[str]]:
        assert main(["detect", str(scene), *flags, *extra]) == 0
        report = json.loads(capsys.readouterr().out)
        tab = tab_region.center
        objects = report["segmentation"]["objects"]
        pot = min(objects, key=lambda o: float(np.linalg.norm(np.subtract(o["center"], tab))))
        on_pot = [h for h in report["handles"] if h["object"] == pot["part_of"]]
        on_tab = bool(on_pot) and bool(label.contains(np.array(on_pot[0]["center"])[None]).all())
        return on_tab, {h["detector"] for h in on_pot}

    on_tab, detectors = top_on_tab([])
    assert on_tab and detectors == {FALLBACK_DETECTOR}
    assert not top_on_tab(["--single-view", "false"])[0]


def _bar(width: float, axis_offset: float = 1.0) -> Candidate:
    """A cylinder of diameter ``width`` along x, its seen surface point 0.5 m - ``width`` / 2
    in front of the eye and its axis point ``axis_offset`` half widths behind that (1: on the
    cylinder's own axis)."""
    coefficients = [0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5, 0.25 - (width / 2) ** 2]
    surface = 0.5 - width / 2
    return Candidate(
        center=np.array([0.0, 0.0, surface]),
        quadric=Quadric(np.array(coefficients)),
        kind="real elliptic cylinder",
        axis=np.array([1.0, 0.0, 0.0]),
        width=width,
        handle_point=np.array([0.0, 0.0, surface + axis_offset * width / 2]),
    )


def _patch(half_width: float, step: float = 0.002) -> np.ndarray:
    x, y = np.meshgrid(np.arange(-0.05, 0.05, step), np.arange(-half_width, half_width, step))
    return np.column_stack([x.ravel(), y.ravel(), np.full(x.size, 0.5)])


def test_candidate_features_tell_a_slim_bar_from_a_wide_patch_and_the_model_reads() -> None:
    eye = np.zeros(3)
    bar, wide = (candidate_features((_bar(0.012),), _patch(h), eye, 0.002) for h in (0.006, 0.04))
    assert bar.shape == wide.shape == (1, len(FEATURES))
    slot = FEATURES.index("slot_max")
    assert bar[0, slot] == 0.0 and wide[0, slot] > 0.1
    assert bar[0, FEATURES.index("width_spacings")] == pytest.approx(6.0)
    model = read_classifier(model_path("handles", "candidate_classifier.json"))
    assert model.probability(bar)[0] > model.probability(wide)[0]


def test_an_ensemble_file_keeps_what_any_member_keeps(tmp_path) -> None:
    """An ensemble's probability is its members' largest, each moved by its logit shift
    (``scripts/train_candidate_classifier.py --combine``); a member over other features, or
    one without trees, is refused with a line naming the file."""
    shipped = json.loads(model_path("handles", "candidate_classifier.json").read_text())
    path = tmp_path / "ensemble.json"
    path.write_text(json.dumps({"members": [dict(shipped, shift=-2.0), dict(shipped, shift=1.0)]}))
    eye = np.zeros(3)
    rows = np.vstack(
        [candidate_features((_bar(0.012),), _patch(h), eye, 0.002) for h in (0.006, 0.04)]
    )
    alone = read_classifier(model_path("handles", "candidate_classifier.json")).probability(rows)
    raised = 1.0 / (1.0 + np.exp(-(np.log(alone / (1.0 - alone)) + 1.0)))
    np.testing.assert_allclose(read_classifier(path).probability(rows), raised, rtol=1e-9)
    path.write_text(json.dumps({"members": [dict(shipped, features=["width"])]}))
    with pytest.raises(SimgraspError, match="ensemble.json: its features"):
        read_classifier(path)
    path.write_text(json.dumps({"members": [{"features": list(FEATURES)}]}))
    with pytest.raises(SimgraspError, match="ensemble.json: not a candidate classifier file"):
        read_classifier(path)


def test_the_classifier_sees_a_narrow_fit_only_with_its_axis_near_its_surface() -> None:
    """``min_width_spacings`` drops unresolved fits before the classifier as it does before
    the standoff test (the default's 2 spacings: 4 mm in a 2 mm cloud), except fits at least
    ``narrow_width_spacings`` wide (1: 2 mm) whose axis lies within ``narrow_axis_offset``
    half widths of their seen surface (a thin strap at range, kept; a rim's unresolved fit,
    its axis 7 half widths off, dropped). The threshold at 0 keeps every other candidate."""
    settings = replace(single_view_preset(), classifier_threshold=0.0)
    cloud, eye = _patch(0.006), np.zeros(3)
    bars = (_bar(0.0015), _bar(0.003), _bar(0.003, axis_offset=7.0), _bar(0.012))
    assert _keep(bars, cloud, eye, 0.002, settings).tolist() == [False, True, False, True]
    two_spacings = replace(settings, narrow_width_spacings=0.0)
    assert _keep(bars, cloud, eye, 0.002, two_spacings).tolist() == [False, False, False, True]
    no_floor = replace(two_spacings, min_width_spacings=0.0)
    assert _keep(bars, cloud, eye, 0.002, no_floor).tolist() == [True] * 4


@pytest.mark.real
def test_the_learned_setting_holds_the_real_table_mug_by_its_handle(real_dir) -> None:  # noqa: ANN001
    """On the held-out GPD mug (docs/results/real-detect: 1.00, 5 of 5 seeds; the default
    0.24, 0 of 5), seed 0: a record of a measured figure, not a tuned one."""
    from simgrasp.evaluation.real_detect import score_cloud
    from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest

    (cloud,) = [c for c in read_manifest(None, real_dir) if c.name == "gpd_table_mug"]
    row = score_cloud(cloud, load_real_cloud(cloud), "learned", 0)
    assert row.top_on_handle and row.on_handle == row.candidates > 0
