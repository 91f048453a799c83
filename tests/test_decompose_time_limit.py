"""A CoACD run that never ends is stopped and redone on CoACD's remeshed manifold.

CoACD's triangulation loops forever on the generated kettle of seed 106 (overlapping closed
parts, no remeshing): these tests run that real mesh.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from simgrasp.assets import decompose
from simgrasp.assets.decompose import DecompositionConfig, remeshed, run_coacd
from simgrasp.assets.generated import generate_tool
from simgrasp.assets.model import default_decomposition

HANGING = "kettle", 106


@pytest.mark.slow
def test_a_run_that_never_ends_is_redone_on_the_remeshed_manifold(
    capsys: pytest.CaptureFixture[str],
) -> None:
    asset = generate_tool(*HANGING)
    config = replace(default_decomposition(asset), time_limit=40.0)
    calls = decompose.coacd_calls()
    hulls = run_coacd(asset.mesh, config, asset.name)
    assert decompose.coacd_calls() == calls + 2  # the stopped run, then the remeshed one
    assert "CoACD did not finish in 40 s; redoing it on its remeshed manifold" in (
        capsys.readouterr().err
    )
    assert 1 <= len(hulls) <= config.max_convex_hull
    assert all(hull.is_convex and hull.volume > 0 for hull in hulls)
    hulls_bounds = np.array([hull.bounds for hull in hulls])
    low, high = hulls_bounds[:, 0].min(axis=0), hulls_bounds[:, 1].max(axis=0)
    # The whole kettle (body, spout, handle) is covered, thickened by the remeshing's voxels.
    assert np.allclose(low, asset.mesh.bounds[0], atol=0.006)
    assert np.allclose(high, asset.mesh.bounds[1], atol=0.006)


def test_remeshed_settings_turn_remeshing_on_and_keep_the_rest() -> None:
    config = DecompositionConfig(preprocess_mode="off", threshold=0.2, seed=3)
    again = remeshed(config)
    assert again.preprocess_mode == "on" and again.preprocess_resolution == 50
    assert replace(again, preprocess_mode="off", preprocess_resolution=25) == config
    assert remeshed(replace(config, preprocess_resolution=80)).preprocess_resolution == 80


def test_the_time_limit_is_not_a_coacd_parameter_nor_in_the_cache_key() -> None:
    assert "time_limit" not in DecompositionConfig().coacd_params()
    assert (
        DecompositionConfig(time_limit=1.0).coacd_params() == DecompositionConfig().coacd_params()
    )


@pytest.mark.parametrize("seconds", [0.0, -1.0, float("nan")])
def test_a_bad_time_limit_is_refused_in_one_line(seconds: float) -> None:
    with pytest.raises(ValueError, match=r"^DecompositionConfig.time_limit must be positive"):
        DecompositionConfig(time_limit=seconds)
