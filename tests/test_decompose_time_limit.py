"""A CoACD run that never ends is stopped and redone on CoACD's remeshed manifold.

CoACD's triangulation loops forever on the generated kettle of seed 106 (overlapping closed
parts, no remeshing): these tests run that real mesh.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

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


def _processes_naming(text: str) -> list[int]:
    """PIDs whose command line contains ``text`` (Linux ``/proc``)."""
    found = []
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            if text.encode() in cmdline.read_bytes():
                found.append(int(cmdline.parent.name))
        except OSError:  # the process ended while we looked
            continue
    return found


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc (Linux)")
def test_an_interrupted_decomposition_leaves_no_coacd_running(tmp_path: Path) -> None:
    """Ctrl-C (SIGINT) during a decomposition: the run stops with KeyboardInterrupt and leaves
    no CoACD child behind. The child process installs Python's own SIGINT handler first: a
    test run started where SIGINT is ignored (a background job of a non-interactive shell) would
    otherwise pass that on, and the interrupt would never arrive."""
    script = (
        "import signal\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "from simgrasp.assets.generated import generate_tool\n"
        "from simgrasp.assets.decompose import run_coacd\n"
        "from simgrasp.assets.model import default_decomposition\n"
        "asset = generate_tool('kettle', 106)\n"
        "print('decomposing', flush=True)\n"
        "run_coacd(asset.mesh, default_decomposition(asset), asset.name)\n"
    )
    parent = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "TMPDIR": str(tmp_path)},
    )
    assert parent.stdout is not None and parent.stdout.readline() == "decomposing\n"
    deadline = time.monotonic() + 30
    while not _processes_naming(str(tmp_path)) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _processes_naming(str(tmp_path)), "CoACD's child process never started"
    parent.send_signal(signal.SIGINT)
    _, errors = parent.communicate(timeout=30)
    assert "KeyboardInterrupt" in errors
    assert _processes_naming(str(tmp_path)) == []
