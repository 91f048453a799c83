"""``gymnasium.make_vec(..., vectorization_mode="async")`` with the default (fork) start method
after the parent has rendered: it used to hang forever (issue 14, item 1). A GL context must
not cross a fork, so the forked workers now fail at once with an error that says what to do.
Run in a fresh process with a timeout so that a regression fails instead of hanging CI."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap

import pytest

TIMEOUT_S = 240

SCRIPT = textwrap.dedent(
    """
    import gymnasium, simgrasp
    from simgrasp.scenes.camera import CameraSpec
    from simgrasp.scenes.scene import SceneConfig

    camera = CameraSpec("view0", pos=(0.3, -0.35, 0.4), lookat=(0.0, 0.0, 0.03), width=160,
                        height=120)
    small = dict(objects=("gen_hammer",), max_points=512, scene=SceneConfig(cameras=(camera,)))
    env = gymnasium.make("simgrasp/HandleGrasp-v0", **small)
    env.reset(seed=0)  # the parent renders: it holds a GL context now
    vector_env = gymnasium.make_vec(
        "simgrasp/HandleGrasp-v0", num_envs=2, vectorization_mode="async", **small
    )
    from simgrasp.scenes.render import select_backend

    print(select_backend())
    try:
        vector_env.reset(seed=0)
    except RuntimeError as exc:
        print("ERROR", exc)
    else:
        print("OK")
    finally:
        vector_env.close(terminate=True)
        env.close()
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


def test_async_vector_env_after_a_parent_reset_fails_at_once_saying_what_to_do() -> None:
    code, out, err = run_isolated(SCRIPT, TIMEOUT_S)
    assert code == 0, err[-3000:]
    backend, result = out.splitlines()[-2:]
    if backend == "raycast":  # no GL context was made: forked workers render as well
        assert result == "OK", out + err[-2000:]
        return
    assert result.startswith("ERROR"), out + err[-2000:]
    assert 'vector_kwargs={"context": "spawn"}' in result
