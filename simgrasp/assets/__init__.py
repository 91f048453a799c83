"""assets stage."""

from simgrasp.gl_platform import configure_mujoco_gl

configure_mujoco_gl()
