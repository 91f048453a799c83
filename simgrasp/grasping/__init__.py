"""grasping stage: grasp poses from handles, grasp trials in MuJoCo and their scoring."""

from simgrasp.gl_platform import configure_mujoco_gl

configure_mujoco_gl()
