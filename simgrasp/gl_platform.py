"""Choose mujoco's OpenGL platform (``MUJOCO_GL``) before mujoco is first imported.

MuJoCo reads ``MUJOCO_GL`` once, at its first import, so the choice must happen before any
simgrasp module imports mujoco: they all import it through :mod:`simgrasp._mujoco`, which
calls :func:`configure_mujoco_gl` first. This module itself never imports mujoco (the probe
runs in a subprocess). See :mod:`simgrasp.scenes.render` for how backends are used.
"""

from __future__ import annotations

import os
import subprocess
import sys

from simgrasp.errors import SimgraspError

BACKENDS: tuple[str, ...] = ("egl", "osmesa", "raycast")
GL_BACKENDS: tuple[str, ...] = ("egl", "osmesa")
FORCE_ENV = "SIMGRASP_RENDER_BACKEND"
PROBE_TIMEOUT_S = 30.0

_PROBE_SCRIPT = """
import mujoco
model = mujoco.MjModel.from_xml_string(
    '<mujoco><worldbody><geom type="box" size="0.5 0.5 0.1" pos="0 0 -1"/>'
    '<camera name="c" pos="0 0 0"/></worldbody></mujoco>')
data = mujoco.MjData(model)
mujoco.mj_forward(model, data)
with mujoco.Renderer(model, 8, 8) as renderer:
    renderer.update_scene(data, "c")
    renderer.enable_depth_rendering()
    depth = renderer.render()
assert abs(float(depth[4, 4]) - 0.9) < 1e-3, depth[4, 4]
print("ok")
"""


def forced_backend() -> str | None:
    forced = os.environ.get(FORCE_ENV, "").strip().lower()
    if not forced:
        return None
    if forced not in BACKENDS:
        raise SimgraspError(
            f"{FORCE_ENV}={forced!r} is not a render backend; use one of {BACKENDS}"
        )
    return forced


def probe_gl(platform: str, timeout_s: float = PROBE_TIMEOUT_S) -> bool:
    """True if a fresh process with ``MUJOCO_GL=platform`` renders a correct depth pixel."""
    return gl_problem(platform, timeout_s) is None


def gl_problem(platform: str, timeout_s: float = PROBE_TIMEOUT_S) -> str | None:
    """Why a fresh process with ``MUJOCO_GL=platform`` does not render a correct depth pixel
    (it timed out, or its exit code and last line of output), or None when it does."""
    env = dict(os.environ, MUJOCO_GL=platform, PYOPENGL_PLATFORM=platform)
    try:
        result = subprocess.run(
            [sys.executable, "-c", _PROBE_SCRIPT],
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout_s,
            check=False,
        )
    except subprocess.TimeoutExpired:
        return f"the probe timed out after {timeout_s:g} s"
    if result.returncode == 0 and result.stdout.strip() == "ok":
        return None
    last = (result.stderr.strip() or result.stdout.strip() or "no output").splitlines()[-1]
    return f"the probe exited with code {result.returncode}: {last[:200]}"


def configure_mujoco_gl() -> None:
    """Set ``MUJOCO_GL`` before mujoco's first import (see the module docstring); a bad
    ``SIMGRASP_RENDER_BACKEND`` is an error even when the platform is already chosen."""
    forced = forced_backend()
    if "mujoco" in sys.modules or os.environ.get("MUJOCO_GL"):
        return
    if forced == "raycast":
        return
    candidates = (forced,) if forced else GL_BACKENDS
    for platform in candidates:
        if forced or probe_gl(platform):
            os.environ["MUJOCO_GL"] = platform
            return
