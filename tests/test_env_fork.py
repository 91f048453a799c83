"""``gymnasium.make_vec(..., vectorization_mode="async")`` with the default (fork) start method
after the parent has rendered: it used to hang forever, then failed at once
(a GL context must not cross a fork). Now the forked workers render depth with the GL-free ray
caster, which agrees with the parent's GL render to well under a millimeter but at silhouette
pixels, and the reset info says so (``render_backend``). Run in a fresh
process with a timeout so that a regression fails instead of hanging CI."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap

import pytest

TIMEOUT_S = 240

SCRIPT = textwrap.dedent(
    """
    import json
    import gymnasium, numpy as np, simgrasp
    from simgrasp.scenes.camera import CameraSpec
    from simgrasp.scenes.scene import SceneConfig
    from simgrasp.scenes.render import select_backend

    camera = CameraSpec("view0", pos=(0.3, -0.35, 0.4), lookat=(0.0, 0.0, 0.03), width=160,
                        height=120)
    small = dict(objects=("gen_hammer",), max_points=512, scene=SceneConfig(cameras=(camera,)))
    env = gymnasium.make("simgrasp/HandleGrasp-v0", **small)
    parent, parent_info = env.reset(seed=0)  # the parent renders: it holds a GL context now
    vector_env = gymnasium.make_vec(
        "simgrasp/HandleGrasp-v0", num_envs=2, vectorization_mode="async", **small
    )
    try:
        forked, info = vector_env.reset(seed=0)  # worker 0 resets with seed 0, as the parent
        step = vector_env.step(vector_env.action_space.sample())
    finally:
        vector_env.close(terminate=True)
        env.close()
    both = (parent["depth"][0] > 0) & (forked["depth"][0][0] > 0)
    diff = np.abs(parent["depth"][0] - forked["depth"][0][0])[both]
    seen = (parent["depth"][0] > 0) | (forked["depth"][0][0] > 0)
    print(json.dumps({
        "parent_backend": select_backend(),
        "parent_info_backend": parent_info["render_backend"],
        "worker_backends": [str(b) for b in info["render_backend"]],
        "pixels_both": int(both.sum()),
        "pixels_either": int(seen.sum()),
        "median_diff_m": float(np.median(diff)),
        "p99_diff_m": float(np.quantile(diff, 0.99)),
        "cloud_points": [int(v) for v in forked["valid"].sum(axis=1)],
        "rewards": [float(r) for r in step[1]],
    }))
    """
)


def run_isolated(script: str, timeout_s: float) -> tuple[int, str, str]:
    """Run ``script`` in a new session; on timeout kill the whole group (forked workers
    included, which a hang leaves behind) and fail."""
    process = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        out, err = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        pytest.fail(f"hung for {timeout_s} s")
    return process.returncode, out, err


def test_async_vector_env_after_a_parent_reset_renders_in_its_forked_workers() -> None:
    code, out, err = run_isolated(SCRIPT, TIMEOUT_S)
    assert code == 0, err[-3000:]
    result = json.loads(out.splitlines()[-1])
    assert result["pixels_both"] > 0.95 * result["pixels_either"] > 500, result
    assert result["median_diff_m"] < 5e-4, result  # the ray caster sees what GL saw
    assert result["p99_diff_m"] < 5e-3, result  # silhouette pixels aside
    assert min(result["cloud_points"]) > 100, result
    assert len(result["rewards"]) == 2, result
    # the reset info says which renderer made each cloud: the same seed differs at silhouettes
    assert result["parent_info_backend"] == result["parent_backend"] != "raycast", result
    assert result["worker_backends"] == ["raycast", "raycast"], result
