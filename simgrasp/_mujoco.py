"""MuJoCo, imported after its OpenGL platform is chosen.

MuJoCo reads ``MUJOCO_GL`` once, at its first import, so every simgrasp module imports it
from here (``from simgrasp._mujoco import mujoco``): the first such import chooses the platform
(:func:`simgrasp.gl_platform.configure_mujoco_gl`: ``SIMGRASP_RENDER_BACKEND`` or an existing
``MUJOCO_GL``, else EGL then OSMesa, probed in a subprocess), then imports mujoco. Importing a
stage package that does not need MuJoCo (``simgrasp.handles``, ``simgrasp.grippers``...) never
probes.
"""

from simgrasp.gl_platform import configure_mujoco_gl

configure_mujoco_gl()

import mujoco  # noqa: E402  (after MUJOCO_GL is chosen)

__all__ = ["mujoco"]
