"""``simgrasp detect CLOUD``: handles in a point cloud file, as a table or JSON.

Every threshold of the detectors is a flag (``--detector.quadric.shell-test false``,
``--single-view-detector.classifier-threshold 0.6``), or set it from a file (``--config
detect.toml``); ``--print-config`` lists them all.

Detector defaults: the quadric detector's plain defaults (one pass), the same as
``detect-eval``'s, whose committed tables (docs/results/detect-eval) they produced; a cloud
that the data show to be one camera's view from the viewpoint goes to the single-view
detector instead (``--single-view``, docs/results/real-detect). ``trial``
and ``evaluate`` add a fine pass for the fused clouds of rendered depth views
(``--detector.quadric.fine-half-size 0.012``, the preset ``two_scales``), on which
thin handles (a lying mug's strap) are seen from two sides; give that flag here to detect on a
cloud file as ``trial`` does. The defaults stay apart so that both commands' committed
results stay as they are.
"""

from __future__ import annotations

import json
import sys
import warnings
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from simgrasp.config import setting
from simgrasp.config.checks import Checked
from simgrasp.errors import SimgraspError
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.core.detection import Detection
from simgrasp.handles.detector_config import DetectorConfig
from simgrasp.handles.presets import single_view_preset
from simgrasp.handles.single_view.detector import SingleViewConfig
from simgrasp.perception.cloud_file import MeshReadConfig, is_mesh_file
from simgrasp.perception.depth_image import DEPTH_IMAGE_FORMATS, DepthImageConfig
from simgrasp.perception.segmentation.segment_config import SegmentConfig
from simgrasp.perception.units import Units

EXAMPLES = (
    "simgrasp detect mug.ply --units mm --json",
    "simgrasp detect view.pcd --viewpoint 0 0 0 --detector tenpas",
)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    cloud: Path = setting(positional=True, metavar="CLOUD")
    """Point cloud file: .ply, .pcd, .xyz or .npy (in --units; normals it leaves out, NaN or
    zero, are estimated, said in a note); a mesh file, .obj .stl .off .glb .gltf or a .ply with
    faces (a scanner's reconstruction: read by its vertices; a model's large triangles: by its
    surface, sampled by the seed; --mesh.points); or a depth image .png / .tif (one sensor
    frame: --depth.intrinsics, --depth.scale; the whole scene with --segment, else its valid
    pixels as the object, with a note when they hold a table)."""
    units: Units = setting("m", main=True)
    """Units of the file's coordinates and of --viewpoint (results are in meters)."""
    json: bool = setting(False, main=True)
    """Print one JSON object instead of a table."""
    seed: int = setting(0, main=True)
    """Seed of the neighborhood sampling (and of the points drawn over a mesh's surface)."""
    detector: DetectorConfig = field(default_factory=DetectorConfig)
    gripper_width: float | None = None
    """Maximum gripper opening (m); sets the chosen detector's gripper_max_opening."""
    viewpoint: tuple[float, float, float] | None = setting(None, metavar=("X", "Y", "Z"), main=True)
    """Camera position for a single-view cloud (m, the cloud's frame): normals are turned
    toward it."""
    single_view: bool = True
    """A cloud measured to be one camera's view from the viewpoint (--viewpoint, with
    --segment the file's VIEWPOINT, else the origin: a sensor's own frame;
    `simgrasp.handles.single_view.view_kind`) is detected with the
    single-view detector (the preset `learned`: the shipped candidate classifier;
    quadric detector only); false: the quadric settings below on every cloud."""
    single_view_detector: SingleViewConfig = setting(
        default_factory=single_view_preset, exclude=("fallback",)
    )
    """Where the classifier keeps nothing, the fallback is
    the preset `real_depth` (not a flag)."""
    plot: Path | None = setting(None, metavar="OUT.png", output="plot", main=True)
    """Write a picture of the detection."""
    segment: bool = setting(False, main=True)
    """CLOUD is a whole scene: segment it (as `simgrasp segment`) and detect on each object;
    normals face the file's VIEWPOINT unless --viewpoint is given."""
    object: str = setting("all", metavar="K|all")
    """With --segment: only the object with label K, with its side parts (the label of a side
    part, a pot's tab, stands for its object)."""
    segmentation: SegmentConfig = field(default_factory=SegmentConfig)
    depth: DepthImageConfig = field(default_factory=DepthImageConfig)
    mesh: MeshReadConfig = field(default_factory=MeshReadConfig)


def run(options: Options) -> int:
    from simgrasp.stdout_guard import stdout_to_stderr

    if options.cloud.is_dir():
        raise SimgraspError(f"{options.cloud}: is a folder, not a point-cloud file")
    if options.segment:
        return _run_segmented(options)
    if options.object != "all":
        raise SimgraspError("--object needs --segment")

    with stdout_to_stderr():  # library warnings must not mix with the output (--json)
        detection, notes = _detect(options)
    if options.json:
        record = {**_input_record(options), "notes": notes}
        json.dump({**detection.to_json(), "input": record}, sys.stdout)
        sys.stdout.write("\n")
        return 0
    print(
        f"{detection.detector}: {detection.neighborhoods} neighborhoods, "
        f"{len(detection.candidates)} candidates, {len(detection.handles)} handles"
    )
    for i, handle in enumerate(detection.handles):
        center = ", ".join(f"{v:+.4f}" for v in handle.center)
        axis = ", ".join(f"{v:+.3f}" for v in handle.axis)
        print(
            f"  handle {i}: center [{center}] m, axis [{axis}], width {handle.width * 100:.1f} cm,"
            f" score {handle.score:.2f}, support {handle.support}"
        )
    steps = ", ".join(f"{k} {v * 1000:.0f} ms" for k, v in detection.timings_s.items())
    print(f"  timings: {steps}")
    if options.plot:
        print(f"  plot written to {options.plot}")
    return 0


def _run_segmented(options: Options) -> int:
    """``--segment``: detect on each object of the scene (``simgrasp.handles.scene_detect``)."""
    from simgrasp.handles.scene_detect import detect_in_scene, parse_object_choice
    from simgrasp.stdout_guard import stdout_to_stderr

    if options.plot:
        raise SimgraspError(
            "--plot is not available with --segment (use `simgrasp segment --plot`)"
        )
    with stdout_to_stderr():
        result = detect_in_scene(
            options.cloud,
            _detector_config(options),
            options.seed,
            detector=options.detector.kind,
            viewpoint=options.viewpoint,
            single_view=_single_view(options),
            only_object=parse_object_choice(options.object),
            segment_config=options.segmentation,
            depth=options.depth,
        )
    report = {**result.to_json(), "input": _input_record(options)}
    if options.json:
        json.dump(report, sys.stdout)
        sys.stdout.write("\n")
        return 0
    kind = options.detector.kind
    print(f"{kind}: {len(result.detections)} objects, {len(report['handles'])} handles")
    for handle in report["handles"]:
        center = ", ".join(f"{v:+.4f}" for v in handle["center"])
        print(f"  object {handle['object']}: center [{center}] m, score {handle['score']:.2f}")
    return 0


def _input_record(options: Options) -> dict[str, Any]:
    """What made the detection, and what ``simgrasp view`` needs to draw it over its input:
    the cloud's resolved path and SHA-256 (a file replaced since is not drawn under it), its
    units, the seed, and with ``--segment`` the segmentation settings."""
    from simgrasp.runs.identity import file_digest

    record: dict[str, Any] = {
        "path": str(options.cloud.resolve()),
        "sha256": file_digest(options.cloud),
        "units": options.units,
        "seed": options.seed,
    }
    if options.segment:
        record["segmentation"] = asdict(options.segmentation)
    if options.cloud.suffix.lower() in DEPTH_IMAGE_FORMATS:
        record["depth"] = asdict(options.depth)
    if not options.segment and is_mesh_file(options.cloud):
        record["mesh"] = asdict(options.mesh)
    return record


def _detector_config(options: Options) -> QuadricDetectorConfig | TenPasConfig:
    """The chosen detector's settings, with --gripper-width applied."""
    config = options.detector.chosen()
    if options.gripper_width is None:
        return config
    if not options.gripper_width > 0:
        raise SimgraspError(f"--gripper-width must be positive, got {options.gripper_width}")
    return replace(config, gripper_max_opening=options.gripper_width)


def _single_view(options: Options) -> SingleViewConfig | None:
    """The single-view detector's settings (``--single-view-detector.*``), None with
    ``--single-view false``."""
    return options.single_view_detector if options.single_view else None


def _may_be_a_view_elsewhere(options: Options, points: Any, detection: Detection) -> bool:
    """Whether the quadric detector ran on a cloud, given no viewpoint, that may be one
    camera's view from elsewhere than the origin (`view_kind.one_view_from_somewhere`)."""
    from simgrasp.handles.single_view.view_kind import one_view_from_somewhere

    if not options.single_view or options.viewpoint is not None:
        return False
    if detection.detector != "quadric":  # the plain quadric detector, not tenpas nor one view
        return False
    return one_view_from_somewhere(points, options.single_view_detector.view_test)


def _note_a_scene(cloud: Path, points: Any) -> None:
    """Say on stderr when the cloud holds a table (``scene_detect.table_in``): detection ran
    on the whole scene, table and all, where ``--segment`` would cut its objects."""
    from simgrasp.handles.scene_detect import table_in

    table = table_in(points)
    if table is not None:
        print(
            f"note: {cloud} holds a table ({table[0]:.0%} of its points on a plane "
            f"{table[1]:.2f} m across): it was detected as one object; pass --segment to "
            "detect on each object of the scene",
            file=sys.stderr,
        )


def _read(options: Options) -> tuple[Any, Any, list[str]]:
    """The cloud's points (m) and normals or None, and the notes reading made (normals
    estimated), each printed on stderr as a line ``note: ...``."""
    from simgrasp.perception.cloud_file import read_object_cloud
    from simgrasp.perception.cloud_io import ReadNote

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ReadNote)
        points, normals = read_object_cloud(
            options.cloud, options.units, options.depth, options.mesh, options.seed
        )
    notes = [str(w.message) for w in caught if issubclass(w.category, ReadNote)]
    for note in notes:
        print(f"note: {note}", file=sys.stderr)
    for other in (w for w in caught if not issubclass(w.category, ReadNote)):
        warnings.warn_explicit(other.message, other.category, other.filename, other.lineno)
    return points, normals, notes


def _detect(options: Options) -> tuple[Detection, list[str]]:
    from simgrasp.handles import detect
    from simgrasp.perception.units import UNIT_SCALE

    config = _detector_config(options)
    points, normals, notes = _read(options)
    scale = UNIT_SCALE[options.units]
    viewpoint = None if options.viewpoint is None else [v * scale for v in options.viewpoint]
    kind = options.detector.kind
    detection = detect(
        points,
        normals,
        config,
        options.seed,
        detector=kind,
        viewpoint=viewpoint,
        single_view=_single_view(options),
    )
    _note_a_scene(options.cloud, points)
    if _may_be_a_view_elsewhere(options, points, detection):
        print(
            f"note: {options.cloud} is not one view from the origin, but it holds one surface "
            "per ray from some direction: if it is one camera's view in another frame, give the "
            "camera's position with --viewpoint X Y Z for the single-view detector",
            file=sys.stderr,
        )
    if options.plot:
        from simgrasp.plots.detection import plot_detection

        plot_detection(detection, options.plot, title=f"{options.cloud} ({detection.detector})")
    return detection, notes
