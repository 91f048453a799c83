"""The settings tree of one full-chain trial: scene, detector, planner, trial.

Free of MuJoCo imports: the command line generates its flags from these fields, and a sweep's
trial identity is the object, the seed and how a trial's :class:`ChainConfig` differs from the
default one (:mod:`simgrasp.evaluation.trial_log`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, Any, Literal

from simgrasp.config import build, setting
from simgrasp.config.checks import Checked, Range
from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grasping.proposers import DEFAULT_PROPOSER, proposer_names
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers.registry import DEFAULT_GRIPPER, gripper_names
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.detector_config import DetectorConfig
from simgrasp.handles.presets import chain_quadric
from simgrasp.perception.segmentation.segment_config import SegmentConfig
from simgrasp.perception.sensors.settings import SensorSettings
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.views import CHAIN_VIEWS

NoiseSigma = Annotated[float, Range(ge=0, lt=1)]
"""The paper's multiplicative noise sigma on a cloud, in [0, 1)."""
Perception = Literal["auto", "segment", "mask"]
PERCEPTIONS: tuple[Perception, ...] = ("auto", "segment", "mask")


@dataclass(frozen=True)
class ChainDetectorConfig(DetectorConfig):
    """The grasp proposer: a handle detector, or a baseline planner that ignores handles.

    The quadric detector's chain default is the preset ``two_scales`` (the
    defaults plus a fine Taubin pass for thin handles seen in fused depth views: a lying
    mug's strap); ``detect`` and ``detect-eval`` keep the plain defaults (one pass). They
    differ on purpose and say so in their ``--help``: each default produced its command's
    committed results (docs/results/chain, docs/results/detect-eval), which one shared
    default would change."""

    kind: str = setting(  # type: ignore[assignment]
        DEFAULT_PROPOSER, flag="--detector", choices=proposer_names, main=True
    )
    """The grasp proposer (:mod:`simgrasp.grasping.proposers`): quadric: quadric fits with the
    paper's criteria; tenpas: ten Pas & Platt 2013's shells; centroid: top-down grasps at the
    cloud centroid; random: random antipodal point pairs."""
    quadric: QuadricDetectorConfig = field(default_factory=chain_quadric)


def _chain_scene() -> SceneConfig:
    return SceneConfig(num_views=CHAIN_VIEWS)


@dataclass(frozen=True)
class ChainConfig(Checked):
    """What one full-chain trial uses (render -> detect -> plan -> execute -> score)."""

    detector: ChainDetectorConfig = setting(
        default_factory=ChainDetectorConfig,
        exclude=("quadric.gripper_max_opening", "tenpas.gripper_max_opening"),
    )
    """The detectors' gripper opening is the chain gripper's."""
    gripper: str = setting(DEFAULT_GRIPPER, choices=gripper_names, main=True)
    """The parallel-jaw gripper that executes the grasp."""
    noise: NoiseSigma = 0.0
    """The paper's multiplicative noise sigma on the observed cloud about its centroid
    (Table II's model), so detection and grasp sweeps share one noise axis."""
    sensor: SensorSettings = field(default_factory=SensorSettings)
    perception: Perception = setting("auto", flag="--perception")
    """How the target's cloud is cut from the views (:mod:`simgrasp.scenes.perceive`): segment
    (our scene segmenter, the segments mostly on the target's pixels; the other segments
    are obstacles), mask (the renderer's segmentation: ground truth); auto: segment in
    clutter, mask otherwise."""
    segment: SegmentConfig = field(default_factory=SegmentConfig.simulated)
    """The scene segmenter of ``perception`` segment (:meth:`SegmentConfig.simulated`: the
    rendered table is exactly flat)."""
    scene: SceneConfig = field(default_factory=_chain_scene)
    planner: PlannerConfig = field(default_factory=PlannerConfig)
    trial: TrialConfig = field(default_factory=TrialConfig)

    @classmethod
    def of(cls, **settings: Any) -> ChainConfig:
        """The default config with dotted settings changed, keyword-friendly:
        ``ChainConfig.of(detector__kind="tenpas", scene__placement="upright")``."""
        return build(cls, {key.replace("__", "."): value for key, value in settings.items()})

    @property
    def perception_mode(self) -> Literal["segment", "mask"]:
        """``perception`` with auto resolved: segment in clutter, mask without."""
        if self.perception != "auto":
            return self.perception
        return "segment" if self.scene.clutter else "mask"
