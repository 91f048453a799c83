"""simgrasp: simulation-in-the-loop grasp evaluation around quadric-based handle detection.

The front door (lazy: ``import simgrasp`` imports neither MuJoCo nor Open3D)::

    import simgrasp
    detection = simgrasp.detect_handles(points)              # (N, 3) meters -> handles
    result = simgrasp.run_trial("gen_hammer", seed=0)       # render, detect, plan, execute
    labels = simgrasp.label_grasps("gen_hammer", object_T_grasp)   # in memory, arrays out

Sub-packages, one per stage: ``assets`` (objects and handle labels), ``scenes`` (MuJoCo scenes,
cameras, rendering), ``perception`` (clouds, normals, sensor models, segmentation), ``quadric``
(quadric maths and fitting), ``handles`` (handle detection), ``grasping`` (planning, trials,
labeling), ``grippers``, ``envs`` (gymnasium), ``evaluation`` (sweeps and reports), ``plots``,
``config`` (the settings machinery), ``cli``.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

import gymnasium

__version__ = "0.1.0"

_EXPORTS = {
    "load_object": "simgrasp.api",
    "detect_handles": "simgrasp.api",
    "run_trial": "simgrasp.api",
    "sample_grasps": "simgrasp.api",
    "segment_scene": "simgrasp.api",
    "label_grasps": "simgrasp.grasping.labeling.labeling",
    "LabelResult": "simgrasp.grasping.labeling.labeling",
    "GraspSet": "simgrasp.grasping.labeling.grasp_sets",
    "ChainConfig": "simgrasp.grasping.trials.chain_config",
    "DetectorConfig": "simgrasp.handles.detector_config",
    "QuadricDetectorConfig": "simgrasp.handles.core.config",
    "TenPasConfig": "simgrasp.handles.baselines.tenpas_config",
    "TrialConfig": "simgrasp.grasping.trials.trial_config",
    "SceneConfig": "simgrasp.scenes.config",
    "PlannerConfig": "simgrasp.grasping.planning.planner_config",
    "SensorSettings": "simgrasp.perception.sensors.settings",
    "LabelConfig": "simgrasp.grasping.labeling.labeling",
    "SimgraspError": "simgrasp.errors",
    "Session": "simgrasp.grasping.session",
    "SegmentConfig": "simgrasp.perception.segmentation.segment_config",
    "DepthImageConfig": "simgrasp.perception.depth_image",
    "Detection": "simgrasp.handles.core.detection",
    "Handle": "simgrasp.handles.core.detection",
    "TrialResult": "simgrasp.grasping.trials.result",
    "ChainResult": "simgrasp.grasping.trials.chain",
    "Segmentation": "simgrasp.perception.segmentation.segment",
}
"""Public name -> the module that defines it (imported on first use)."""

__all__ = [
    "ChainConfig",
    "ChainResult",
    "DepthImageConfig",
    "Detection",
    "DetectorConfig",
    "GraspSet",
    "Handle",
    "LabelConfig",
    "LabelResult",
    "PlannerConfig",
    "QuadricDetectorConfig",
    "SceneConfig",
    "SegmentConfig",
    "Segmentation",
    "SensorSettings",
    "Session",
    "SimgraspError",
    "TenPasConfig",
    "TrialConfig",
    "TrialResult",
    "detect_handles",
    "label_grasps",
    "load_object",
    "run_trial",
    "sample_grasps",
    "segment_scene",
]

if TYPE_CHECKING:
    from simgrasp.api import detect_handles, load_object, run_trial, sample_grasps, segment_scene
    from simgrasp.errors import SimgraspError
    from simgrasp.grasping.labeling.grasp_sets import GraspSet
    from simgrasp.grasping.labeling.labeling import LabelConfig, LabelResult, label_grasps
    from simgrasp.grasping.planning.planner_config import PlannerConfig
    from simgrasp.grasping.session import Session
    from simgrasp.grasping.trials.chain import ChainResult
    from simgrasp.grasping.trials.chain_config import ChainConfig
    from simgrasp.grasping.trials.result import TrialResult
    from simgrasp.grasping.trials.trial_config import TrialConfig
    from simgrasp.handles.baselines.tenpas_config import TenPasConfig
    from simgrasp.handles.core.config import QuadricDetectorConfig
    from simgrasp.handles.core.detection import Detection, Handle
    from simgrasp.handles.detector_config import DetectorConfig
    from simgrasp.perception.depth_image import DepthImageConfig
    from simgrasp.perception.segmentation.segment import Segmentation
    from simgrasp.perception.segmentation.segment_config import SegmentConfig
    from simgrasp.perception.sensors.settings import SensorSettings
    from simgrasp.scenes.config import SceneConfig


def __getattr__(name: str) -> Any:
    """Import a front-door name's module on first access (PEP 562)."""
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'simgrasp' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*__all__, "__version__"])


# The entry point is a string so that `import simgrasp` stays light (no mujoco).
gymnasium.register(
    id="simgrasp/HandleGrasp-v0",
    entry_point="simgrasp.envs.handle_grasp:HandleGraspEnv",
)
