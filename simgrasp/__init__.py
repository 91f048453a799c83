"""simgrasp: simulation-in-the-loop grasp evaluation around quadric-based handle detection.

Sub-packages, one per stage: ``assets`` (objects and handle labels), ``sim`` (MuJoCo scenes,
grippers and grasp trials), ``perception`` (clouds and normals), ``quadric`` (quadric maths and
fitting), ``handles`` (handle detection), ``envs`` (gymnasium), ``evaluation`` (sweeps).
"""

__version__ = "0.1.0"
