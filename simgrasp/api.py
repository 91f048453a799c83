"""The front door: one call each to load an object, detect handles and run a grasp trial.

These are the functions ``import simgrasp`` exposes (``simgrasp.detect_handles`` etc.); each
takes plain arrays or names and one settings object, and imports MuJoCo only when it needs
it. Units are meters; frames are named as in the README (``world_T_tcp``, ``points``).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Literal, get_args

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError

if TYPE_CHECKING:
    from simgrasp.assets.model import ObjectModel
    from simgrasp.assets.object import ObjectAsset
    from simgrasp.assets.placement import Placement
    from simgrasp.grasping.labeling.grasp_sets import GraspSet
    from simgrasp.grasping.session import Session
    from simgrasp.grasping.trials.chain import ChainResult
    from simgrasp.grasping.trials.chain_config import ChainConfig
    from simgrasp.grasping.trials.result import TrialResult
    from simgrasp.handles.baselines.tenpas_config import TenPasConfig
    from simgrasp.handles.core.config import QuadricDetectorConfig
    from simgrasp.handles.core.detection import Detection
    from simgrasp.handles.detector_config import DetectorConfig
    from simgrasp.perception.cloud_file import MeshReadConfig
    from simgrasp.perception.depth_image import DepthImageConfig
    from simgrasp.perception.segmentation.segment import Segmentation
    from simgrasp.perception.segmentation.segment_config import SegmentConfig
    from simgrasp.perception.units import Units


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
    points: ArrayLike | str | os.PathLike[str],
    normals: ArrayLike | None = None,
    *,
    config: DetectorConfig | QuadricDetectorConfig | TenPasConfig | None = None,
    seed: int = 0,
    viewpoint: ArrayLike | None = None,
    single_view: bool = True,
    units: Units = "m",
    mesh: MeshReadConfig | None = None,
) -> Detection:
    """Handles in one object's cloud: ``points`` (N, 3) in ``units``, any frame, or a file
    ``simgrasp detect`` reads (a cloud, whose normals it leaves out are estimated with a
    :class:`~simgrasp.perception.cloud_io.ReadNote` warning; a mesh, read as ``mesh`` says:
    a scan's by its vertices, a model's by its surface sampled by ``seed``); ``normals``
    (N, 3) pointing out of the object, estimated when omitted (toward ``viewpoint``, the
    camera position in the cloud's frame and units, for a single view). A cloud whose size
    only other units explain is refused, naming the ``units`` to pass. ``config`` picks the
    detector (a :class:`DetectorConfig`, or one detector's own settings); the default is the
    one ``simgrasp detect`` runs: with ``single_view``, a cloud the data show to be one
    camera's view from ``viewpoint`` (none given: from the origin, a sensor's own frame) goes
    to the single-view detector (the preset ``learned``, :mod:`simgrasp.handles.presets`).
    Results are in the cloud's frame, in meters."""
    from simgrasp.handles import detect
    from simgrasp.handles.baselines.tenpas_config import TenPasConfig
    from simgrasp.handles.core.config import QuadricDetectorConfig
    from simgrasp.handles.detector_config import DetectorConfig
    from simgrasp.handles.presets import single_view_preset

    points, normals, viewpoint = _cloud_in_meters(points, normals, viewpoint, units, mesh, seed)

    chosen = config if config is not None else DetectorConfig()
    _check_type(chosen, "config", DetectorConfig, QuadricDetectorConfig, TenPasConfig)
    if isinstance(chosen, DetectorConfig):
        kind, settings = chosen.kind, chosen.chosen()
    else:
        kind = "quadric" if isinstance(chosen, QuadricDetectorConfig) else "tenpas"
        settings = chosen
    chosen_view = single_view_preset() if single_view else None
    return detect(
        points,
        normals,
        settings,
        seed,
        detector=kind,
        viewpoint=viewpoint,
        single_view=chosen_view,
    )


def _cloud_in_meters(
    points: ArrayLike | str | os.PathLike[str],
    normals: ArrayLike | None,
    viewpoint: ArrayLike | None,
    units: Units,
    mesh: MeshReadConfig | None,
    seed: int,
) -> tuple[NDArray[np.float64], ArrayLike | None, ArrayLike | None]:
    """:func:`detect_handles`' points (read from the file they name), normals and viewpoint,
    in meters."""
    from simgrasp.perception._arrays import as_points
    from simgrasp.perception.cloud_file import read_object_cloud
    from simgrasp.perception.units import UNIT_SCALE, cloud_in_meters

    if isinstance(points, str | os.PathLike):
        if normals is not None:
            raise SimgraspError("normals come from the file when points is a file; pass neither")
        path_points, normals = read_object_cloud(Path(points), units, mesh=mesh, seed=seed)
    else:
        path_points = cloud_in_meters(as_points(points), units, "points")
    if viewpoint is not None and units != "m":
        viewpoint = np.asarray(viewpoint, dtype=np.float64) * UNIT_SCALE[units]
    return path_points, normals, viewpoint


def _check_type(value: object, name: str, *kinds: type) -> None:
    """A :class:`SimgraspError` naming argument ``name`` unless ``value`` is one of ``kinds``."""
    if not isinstance(value, kinds):
        names = [kind.__name__ for kind in kinds]
        wanted = f"{', '.join(names[:-1])} or {names[-1]}" if len(names) > 1 else names[0]
        raise SimgraspError(f"{name} must be a {wanted}, got {type(value).__name__}")


def _object_model(
    obj: object, ycb_dir: str | os.PathLike[str] | None, session: Session | None = None
) -> ObjectModel:
    """The model of ``obj``; a name or path is looked up in ``session``'s models when given
    one (and ``ycb_dir`` is not), else built."""
    from simgrasp.assets.model import ObjectModel, build_object_model, model_for
    from simgrasp.assets.object import ObjectAsset

    if isinstance(obj, ObjectModel):
        return obj
    if isinstance(obj, ObjectAsset):
        return build_object_model(obj)
    if isinstance(obj, str | os.PathLike):
        if session is not None and ycb_dir is None:
            return session.model(os.fspath(obj))
        return model_for(os.fspath(obj), None if ycb_dir is None else os.fspath(ycb_dir))
    raise SimgraspError(
        f"obj must be a name, a path, an ObjectAsset or an ObjectModel, got {type(obj).__name__}"
    )


def _grasp_pose7(grasp: ArrayLike) -> NDArray[np.float64]:
    """A ``[x, y, z, qw, qx, qy, qz]`` pose from a rigid (4, 4) transform or a 7-vector with a
    unit quaternion, refused (naming ``grasp``) as label-grasps refuses its rows otherwise."""
    from simgrasp.grasping.labeling.grasp_sets import pose_problem, rigid_problem
    from simgrasp.perception._arrays import float_array
    from simgrasp.transforms import matrix_to_pose7

    array = float_array(grasp, "grasp", "a (4, 4) transform or a 7-vector [x y z qw qx qy qz]")
    if array.shape == (4, 4):
        if (problem := rigid_problem(array)) is not None:
            raise SimgraspError(f"grasp: {problem}")
        return matrix_to_pose7(array)
    if array.shape != (7,):
        raise SimgraspError(
            f"grasp must be a (4, 4) transform or a 7-vector, got shape {array.shape}"
        )
    if (problem := pose_problem(array)) is not None:
        raise SimgraspError(f"grasp: {problem}")
    return array


def _jaw_width(width: object, max_opening: float) -> float:
    """``width`` (m) checked to be a number in (0, ``max_opening``]."""
    if isinstance(width, bool) or not isinstance(width, int | float | np.integer | np.floating):
        raise SimgraspError(f"width must be a number (m), got {type(width).__name__}")
    opening = float(width)
    if not 0 < opening <= max_opening:
        raise SimgraspError(f"width must be in (0, {max_opening:g}] m, got {opening:g}")
    return opening


def run_trial(
    obj: str | os.PathLike[str] | ObjectAsset | ObjectModel,
    *,
    seed: int = 0,
    grasp: ArrayLike | None = None,
    grasp_frame: Literal["world", "object"] = "world",
    width: float | None = None,
    config: ChainConfig | None = None,
    ycb_dir: str | os.PathLike[str] | None = None,
    session: Session | None = None,
) -> ChainResult | TrialResult:
    """One grasp trial of ``obj`` on the table scene of ``seed`` (rest pose, yaw, noise).

    Without ``grasp`` the full chain runs (render, detect, plan, execute, score) and a
    :class:`ChainResult` comes back; with it, ``grasp`` (the TCP pose ``world_T_tcp`` or, with
    ``grasp_frame="object"``, ``object_T_tcp``: a (4, 4) transform or ``[x, y, z, qw, qx, qy,
    qz]``; +z the approach, +y the jaw axis) is executed with the jaws opened to ``width`` (m,
    default the gripper's maximum) and a :class:`TrialResult` comes back. Both have
    ``success``, ``on_handle`` and ``to_json()`` (the record ``simgrasp trial --json`` prints).
    Trials run one after another share a :class:`~simgrasp.grasping.session.Session`'s
    renderer and object models when given one (``with simgrasp.Session() as session``);
    without it each call makes its own.
    """
    from simgrasp.grasping.trials.chain_config import ChainConfig
    from simgrasp.grasping.trials.given_grasp import GraspFrame

    config = config if config is not None else ChainConfig()
    _check_type(config, "config", ChainConfig)
    if grasp_frame not in get_args(GraspFrame):
        frames = ", ".join(get_args(GraspFrame))
        raise SimgraspError(f"grasp_frame: {grasp_frame!r} is not one of {frames}")
    if grasp is None:
        if width is not None:
            raise SimgraspError("width needs a grasp (the full chain plans its own jaw opening)")
        if grasp_frame != "world":
            raise SimgraspError("grasp_frame needs a grasp (the full chain plans its own grasp)")
        from simgrasp.grasping.trials.chain import run_chain

        return run_chain(_object_model(obj, ycb_dir, session), config, seed, session=session)
    from simgrasp.grasping.trials.given_grasp import trial_of_grasp
    from simgrasp.grippers import make_gripper

    pose7 = _grasp_pose7(grasp)
    hand = make_gripper(config.gripper)
    opening = None if width is None else _jaw_width(width, hand.max_opening)
    return trial_of_grasp(
        _object_model(obj, ycb_dir, session),
        hand,
        pose7,
        frame=grasp_frame,
        width=opening,
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
    from simgrasp.grasping.planning.antipodal import Table, grasp_count, sample_antipodal
    from simgrasp.grippers import make_gripper
    from simgrasp.scenes.config import SceneConfig
    from simgrasp.scenes.scene import build_scene

    grasp_count(count)
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
    point in the input's order: 0 invalid, 1 table, 2.. objects nearest the sensor first.
    ``depth`` is for a depth image file and ``viewpoint`` for an array: a file's sensor
    position is its own (a PCD's ``VIEWPOINT``, else the origin)."""
    from simgrasp.perception._arrays import float_array
    from simgrasp.perception.depth_image import DepthImageConfig
    from simgrasp.perception.scene_cloud import read_scene, scene_from_array
    from simgrasp.perception.segmentation.segment import segment_scene as segment
    from simgrasp.perception.segmentation.segment_config import SegmentConfig

    if config is not None:
        _check_type(config, "config", SegmentConfig)
    if isinstance(scene, str | os.PathLike):
        if viewpoint is not None:
            raise SimgraspError(
                "viewpoint is for an array scene; a file's viewpoint is its own (load the "
                "file into an array to give another)"
            )
        if depth is not None:
            _check_type(depth, "depth", DepthImageConfig)
        return segment(read_scene(os.fspath(scene), depth), config)
    if depth is not None:
        raise SimgraspError("depth is for a depth image file, not an array scene")
    points = float_array(scene, "scene", "a scene file path or an (N, 3) or (H, W, 3) array")
    return segment(scene_from_array(points, _viewpoint(viewpoint)), config)


def _viewpoint(viewpoint: ArrayLike | None) -> NDArray[np.float64] | None:
    """The sensor position ``viewpoint`` checked to be 3 finite coordinates (m), or None."""
    from simgrasp.perception._arrays import float_array

    if viewpoint is None:
        return None
    eye = float_array(viewpoint, "viewpoint", "3 coordinates (m)")
    if eye.shape != (3,) or not np.all(np.isfinite(eye)):
        raise SimgraspError(f"viewpoint must be 3 finite coordinates (m), got {eye.tolist()}")
    return eye
