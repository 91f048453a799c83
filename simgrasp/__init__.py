"""simgrasp: simulation-in-the-loop grasp evaluation around quadric-based handle detection.

Sub-packages, one per stage: ``assets`` (objects and handle labels), ``scenes`` (MuJoCo scenes,
grippers, cameras), ``perception`` (clouds and normals), ``quadric`` (quadric maths and
fitting), ``handles`` (handle detection), ``grasping`` (grasps and trials), ``envs``
(gymnasium), ``evaluation`` (sweeps and reports).
"""

import gymnasium

__version__ = "0.1.0"

# The entry point is a string so that `import simgrasp` stays light (no mujoco).
gymnasium.register(
    id="simgrasp/HandleGrasp-v0",
    entry_point="simgrasp.envs.handle_grasp:HandleGraspEnv",
)
