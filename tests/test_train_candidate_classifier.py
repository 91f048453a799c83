"""``scripts/train_candidate_classifier.py``'s training rows: a view's candidates, also with
the view made worse first (``--degradations``), and the option's bad values."""

from __future__ import annotations

from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
from script_modules import load_script

from simgrasp.errors import SimgraspError
from simgrasp.evaluation.sim_views import SimView
from simgrasp.handles.single_view.candidate_features import FEATURES


@pytest.fixture(scope="module")
def script() -> ModuleType:
    return load_script("train_candidate_classifier")


def test_a_degraded_copy_of_a_view_gives_rows_of_its_own(script: ModuleType) -> None:
    """The generated hammer seen by the kinect model: rows of every feature, some on the
    handle; with a quarter of its points fewer candidates, the same ones from the same seed."""
    view = SimView("gen_hammer", "upright", 0.6, 45.0, "kinect")
    x, y = script.view_rows(view, 0)
    quarter_x, quarter_y = script.view_rows(view, 0, "quarter")
    assert x.shape[1] == quarter_x.shape[1] == len(FEATURES)
    assert y.any() and 0 < len(quarter_y) < len(y)
    again_x, _ = script.view_rows(view, 0, "quarter")
    np.testing.assert_array_equal(again_x, quarter_x)


def test_an_unknown_degradation_is_refused_in_one_line(script: ModuleType, tmp_path: Path) -> None:
    with pytest.raises(SimgraspError, match="--degradations: unknown blur; choose from half"):
        script.Options(degradations=("half", "blur"), out=tmp_path / "model.json")


def test_every_view_is_trained_on_as_captured_and_degraded(script: ModuleType) -> None:
    """Each object, view, azimuth and seed once as captured and once per degradation."""
    views = script.training_views(["gen_hammer"], [0.0, 120.0], 2, ("half", "holes"))
    assert len(views) == len(script.VIEWS) * 2 * 2 * 3
    assert [kind for _, _, kind in views[:3]] == ["as captured", "half", "holes"]
    assert len({(view.name, seed, kind) for view, seed, kind in views}) == len(views)


def test_a_kept_view_is_read_back_not_rendered_again(script: ModuleType, tmp_path: Path) -> None:
    """``--cache``: a view's rows are written once, then read from the file (here changed, so
    that a second render would show)."""
    view = SimView("gen_hammer", "upright", 0.6, 45.0, "kinect")
    x, y = script.cached_rows(view, 0, "as captured", tmp_path)
    (kept,) = tmp_path.glob("*.npz")
    np.testing.assert_array_equal(np.load(kept)["x"], x)
    np.savez(kept, x=x[:1], y=y[:1])
    again_x, again_y = script.cached_rows(view, 0, "as captured", tmp_path)
    assert len(again_x) == len(again_y) == 1


def test_family_objects_are_seen_from_an_azimuth_drawn_from_the_seed(script: ModuleType) -> None:
    """A family object's views of one seed share one drawn azimuth; the others keep theirs."""
    views = script.training_views(
        ["gen_spoon_s0", "gen_hammer"], [0.0], 2, (), script.VIEWS, frozenset({"gen_spoon_s0"})
    )
    turns: dict[tuple[str, int], set[float]] = {(v.object, seed): set() for v, seed, _ in views}
    for view, seed, _ in views:
        turns[view.object, seed].add(view.azimuth_deg)
    assert turns["gen_hammer", 0] == turns["gen_hammer", 1] == {0.0}
    spoon = [turns["gen_spoon_s0", seed] for seed in (0, 1)]
    assert all(len(t) == 1 for t in spoon) and spoon[0] != spoon[1]
    assert spoon[0] == {script.drawn_azimuth("gen_spoon_s0", 0)}


def test_trained_family_seeds_are_kept_apart_from_scored_ones(
    script: ModuleType, tmp_path: Path
) -> None:
    with pytest.raises(SimgraspError, match="--eval-seeds: family seeds below 5"):
        script.Options(evaluate=(tmp_path / "m.json",), eval_seeds=(4, 5))
    with pytest.raises(SimgraspError, match="family_seeds: 6 is not in"):
        script.Options(family_seeds=6, out=tmp_path / "m.json")
