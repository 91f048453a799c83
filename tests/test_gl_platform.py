"""The GL platform is chosen where MuJoCo is first imported (simgrasp._mujoco), never when a
stage package is imported."""

from __future__ import annotations

import os
import subprocess
import sys

PROBE_COUNTER = """
import sys
spawned = []
sys.addaudithook(lambda event, args: spawned.append(args) if event == "subprocess.Popen" else None)
{imports}
import os
print(len(spawned), "mujoco" in sys.modules, os.environ.get("MUJOCO_GL", ""))
"""


def _run(imports: str) -> list[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    env.pop("SIMGRASP_RENDER_BACKEND", None)
    code = PROBE_COUNTER.format(imports=imports)
    result = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return result.stdout.split()


def test_importing_the_stage_packages_starts_no_probe() -> None:
    packages = ("assets", "scenes", "grasping", "envs", "handles", "grippers", "evaluation")
    out = _run("\n".join(f"import simgrasp.{p}" for p in packages))
    assert out == ["0", "False"]


def test_the_first_mujoco_import_chooses_the_platform() -> None:
    """Through simgrasp._mujoco, MuJoCo is imported after a probe chose a platform (or none
    worked: rendering then falls back to ray casting)."""
    spawned, imported, *platform = _run("from simgrasp._mujoco import mujoco")
    assert int(spawned) >= 1 and imported == "True"
    assert platform in ([], ["egl"], ["osmesa"])


def test_a_failed_probe_says_why() -> None:
    """The ray-casting fallback's warning names the probe's failure: a timeout (a loaded
    machine), or the probe's exit code and last line (a missing platform)."""
    from simgrasp.gl_platform import gl_problem

    assert gl_problem("egl", timeout_s=0.001) == "the probe timed out after 0.001 s"
    problem = gl_problem("no_such_platform")
    assert problem is not None and problem.startswith("the probe exited with code 1: ")
    assert "no_such_platform" in problem


WORKER_ENVIRONMENT = """
import warnings
from simgrasp.scenes.render import select_backend, worker_environment
print(worker_environment()["SIMGRASP_RENDER_BACKEND"])
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    print(select_backend(), len(caught))
"""


def test_workers_are_given_ray_casting_without_a_warning_until_something_renders() -> None:
    """Without a headless GL platform (glfw), the workers a run starts are told to ray cast;
    the fallback's warning comes only when this process itself renders (a label run's workers
    never do)."""
    env = {k: v for k, v in os.environ.items() if k != "SIMGRASP_RENDER_BACKEND"}
    env["MUJOCO_GL"] = "glfw"
    result = subprocess.run(
        [sys.executable, "-W", "error", "-c", WORKER_ENVIRONMENT],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    assert result.stdout.split() == ["raycast", "raycast", "1"]
