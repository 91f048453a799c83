"""The front door: one call each to load an object, detect handles and run a grasp trial.

These are the functions ``import simgrasp`` exposes (``simgrasp.detect_handles`` etc.); each
takes plain arrays or names and one settings object, and imports MuJoCo only when it needs
it. Units are meters; frames are named as in the README (``world_T_tcp``, ``points``).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike

from simgrasp.errors import SimgraspError

if TYPE_CHECKING:
    from simgrasp.assets.model import ObjectModel
    from simgrasp.assets.object import ObjectAsset
    from simgrasp.assets.placement import Placement
    from simgrasp.grasping.labeling.grasp_sets import GraspSet
    from simgrasp.grasping.trials.chain import ChainResult
    from simgrasp.grasping.trials.chain_config import ChainConfig
    from simgrasp.grasping.trials.result import TrialResult
    from simgrasp.handles.config import QuadricDetectorConfig
    from simgrasp.handles.detection import Detection
    from simgrasp.handles.detector_config import DetectorConfig
    from simgrasp.handles.tenpas_config import TenPasConfig
    from simgrasp.perception.depth_image import DepthImageConfig
    from simgrasp.perception.segmentation.segment import Segmentation
    from simgrasp.perception.segmentation.segment_config import SegmentConfig


def load_object(
    name_or_path: str | os.PathLike[str], *, ycb_dir: str | os.PathLike[str] | None = None
) -> ObjectAsset:
    """The object ``name_or_path`` names: a generated tool (``"gen_hammer"``), a YCB id
    (``"025_mug"``, read from ``ycb_dir`` or ``$SIMGRASP_YCB_DIR``), a name from an
    ``objects.toml`` catalog, or a mesh file with optional settings
    (``"mug.obj?units=mm&mass=0.3&handles=handles.json"``), with its mesh (object frame,
    meters), mass (kg) and handle label."""
    from simgrasp.assets.registry import load_object as lookup

    return lookup(os.fspath(name_or_path), ycb_dir)


def detect_handles(
    points: ArrayLike,
    normals: ArrayLike | None = None,
    *,
    config: DetectorConfig | QuadricDetectorConfig | TenPasConfig | None = None,
    seed: int = 0,
    viewpoint: ArrayLike | None = None,
    single_view: bool = True,
) -> Detection:
    """Handles in one object's cloud: ``points`` (N, 3) in meters, any frame; ``normals``
    (N, 3) pointing out of the object, estimated when omitted (toward ``viewpoint``, the
    camera position in the cloud's frame, for a single view). ``config`` picks the detector
    (a :class:`DetectorConfig`, or one detector's own settings); the default is the one
    ``simgrasp detect`` runs: with ``single_view``, a cloud the data show to be one camera's
    view from ``viewpoint`` (none given: from the origin, a sensor's own frame) goes to the
    single-view detector (:meth:`~simgrasp.handles.single_view.SingleViewConfig.learned`).
    Results are in the cloud's frame."""
    from simgrasp.handles import detect
    from simgrasp.handles.config import QuadricDetectorConfig
    from simgrasp.handles.detector_config import DetectorConfig
    from simgrasp.handles.single_view import SingleViewConfig

    chosen = config if config is not None else DetectorConfig()
    if isinstance(chosen, DetectorConfig):
        kind, settings = chosen.kind, chosen.chosen()
    else:
        kind = "quadric" if isinstance(chosen, QuadricDetectorConfig) else "tenpas"
        settings = chosen
    chosen_view = SingleViewConfig.learned() if single_view else None
    return detect(
        points,
        normals,
        settings,
        seed,
        detector=kind,
        viewpoint=viewpoint,
        single_view=chosen_view,
    )


def _object_model(obj: object, ycb_dir: str | os.PathLike[str] | None) -> ObjectModel:
    from simgrasp.assets.model import ObjectModel, build_object_model, model_for
    from simgrasp.assets.object import ObjectAsset

    if isinstance(obj, ObjectModel):
        return obj
    if isinstance(obj, ObjectAsset):
        return build_object_model(obj)
    if isinstance(obj, str | os.PathLike):
        return model_for(os.fspath(obj), None if ycb_dir is None else os.fspath(ycb_dir))
    raise SimgraspError(
        f"object must be a name, a path, an ObjectAsset or an ObjectModel, got {type(obj)}"
    )


def _grasp_pose7(grasp: ArrayLike) -> np.ndarray:
    """A ``[x, y, z, qw, qx, qy, qz]`` pose from a 7-vector or a (4, 4) transform."""
    from simgrasp.transforms import matrix_to_pose7

    array = np.asarray(grasp, dtype=float)
    if array.shape == (4, 4):
        return matrix_to_pose7(array)
    if array.shape == (7,):
        return array
    raise SimgraspError(f"grasp must be a (4, 4) transform or a 7-vector, got shape {array.shape}")


def run_trial(
    obj: str | os.PathLike[str] | ObjectAsset | ObjectModel,
    *,
    seed: int = 0,
    grasp: ArrayLike | None = None,
    grasp_frame: Literal["world", "object"] = "world",
    width: float | None = None,
    config: ChainConfig | None = None,
    ycb_dir: str | os.PathLike[str] | None = None,
) -> ChainResult | TrialResult:
    """One grasp trial of ``obj`` on the table scene of ``seed`` (rest pose, yaw, noise).

    Without ``grasp`` the full chain runs (render, detect, plan, execute, score) and a
    :class:`ChainResult` comes back; with it, ``grasp`` (the TCP pose ``world_T_tcp`` or, with
    ``grasp_frame="object"``, ``object_T_tcp``: a (4, 4) transform or ``[x, y, z, qw, qx, qy,
    qz]``; +z the approach, +y the jaw axis) is executed with the jaws opened to ``width`` (m,
    default the gripper's maximum) and a :class:`TrialResult` comes back. Both have
    ``success``, ``on_handle`` and ``to_json()`` (the record ``simgrasp trial --json`` prints).
    """
    from simgrasp.grasping.trials.chain_config import ChainConfig

    config = config if config is not None else ChainConfig()
    model = _object_model(obj, ycb_dir)
    if grasp is None:
        if width is not None:
            raise SimgraspError("width needs a grasp (the full chain plans its own jaw opening)")
        from simgrasp.grasping.trials.chain import run_chain

        return run_chain(model, config, seed)
    from simgrasp.grasping.trials.given_grasp import trial_of_grasp
    from simgrasp.grippers import make_gripper

    return trial_of_grasp(
        model,
        make_gripper(config.gripper),
        _grasp_pose7(grasp),
        frame=grasp_frame,
        width=width,
        scene_config=config.scene,
        trial_config=config.trial,
        seed=seed,
    )


def sample_grasps(
    obj: str | os.PathLike[str] | ObjectAsset | ObjectModel,
    count: int,
    *,
    seed: int = 0,
    gripper: str = "builtin",
    placement: Placement = "stable",
    table: bool = True,
    ycb_dir: str | os.PathLike[str] | None = None,
) -> GraspSet:
    """``count`` antipodal grasps on ``obj``'s mesh, as ACRONYM samples them (``object_T_tcp``
    in the mesh frame, meters, and the jaw openings) for ``gripper``; unless ``table`` is
    False, clear of the table under the rest pose (``placement``) of the scene of ``seed``,
    the scene :func:`simgrasp.label_grasps` labels them in with the same seed. Fewer than
    ``count`` when the sampler runs out of rounds."""
    from simgrasp.grasping.labeling.grasp_sets import GraspSet
    from simgrasp.grasping.planning.antipodal import Table, sample_antipodal
    from simgrasp.grippers import make_gripper
    from simgrasp.scenes.config import SceneConfig
    from simgrasp.scenes.scene import build_scene

    hand = make_gripper(gripper)
    model = _object_model(obj, ycb_dir)
    clear_of = None
    if table:
        scene = build_scene(model, hand, SceneConfig(placement=placement), seed)
        clear_of = Table(scene.world_T_object, scene.config.table_top_z)
    poses, widths = sample_antipodal(
        model.asset.mesh, hand.planning_geometry(), count, seed, table=clear_of
    )
    return GraspSet.from_arrays(poses, widths)


def segment_scene(
    scene: str | os.PathLike[str] | ArrayLike,
    config: SegmentConfig | None = None,
    *,
    depth: DepthImageConfig | None = None,
    viewpoint: ArrayLike | None = None,
) -> Segmentation:
    """The table plane and the objects on it, as ``simgrasp segment`` finds them: ``scene`` is
    a scene file (``.pcd``, ``.ply``, ``.npy``, or a depth image ``.png`` / ``.tif`` read
    through ``depth``'s intrinsics and scale) or an array of points in meters, (H, W, 3) for
    an organized cloud (NaN where the sensor returned nothing) or (N, 3), with the sensor at
    ``viewpoint`` (default: the origin, a sensor's own frame). ``.labels`` holds one label per
    point in the input's order: 0 invalid, 1 table, 2.. objects nearest the sensor first."""
    from simgrasp.perception.scene_cloud import read_scene, scene_from_array
    from simgrasp.perception.segmentation.segment import segment_scene as segment

    if isinstance(scene, str | os.PathLike):
        cloud = read_scene(os.fspath(scene), depth)
    else:
        points = np.asarray(scene, dtype=np.float64)
        eye = None if viewpoint is None else np.asarray(viewpoint, dtype=np.float64)
        cloud = scene_from_array(points, eye)
    return segment(cloud, config)
