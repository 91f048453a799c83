"""simgrasp: simulation-in-the-loop grasp evaluation around quadric-based handle detection.

Sub-packages, one per stage: ``assets`` (objects and handle labels), ``scenes`` (MuJoCo scenes,
grippers, cameras), ``perception`` (clouds and normals), ``quadric`` (quadric maths and
fitting), ``handles`` (handle detection), ``grasping`` (grasps and trials), ``envs``
(gymnasium), ``evaluation`` (sweeps and reports).
"""

__version__ = "0.1.0"
