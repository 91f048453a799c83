"""scenes stage: MuJoCo scenes, cameras and rendering (grippers: simgrasp.grippers)."""

from simgrasp.gl_platform import configure_mujoco_gl

configure_mujoco_gl()
