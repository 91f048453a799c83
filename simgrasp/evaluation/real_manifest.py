"""The real-data detection manifest: which real clouds ``detect-eval --real`` scores, and how.

A TOML file of ``[[cloud]]`` tables, each::

    name = "gpd_table_mug"              # unique, also the default label key
    path = "handles/gpd_table_mug.pcd"  # relative to the real data dir, or absolute
    dataset = "gpd"                     # rows are summarized per data set
    split = "holdout"                   # "tune" (settings may be chosen on it) or "holdout"
    units = "m"                         # the file's (and viewpoint's, crop's) units: m, mm or cm
    viewpoint = [0.0, 0.0, 0.0]         # sensor position in the cloud's frame
    labels = "real_handles.json"        # handle label file, relative to the manifest's folder
    label_key = "gpd_table_mug"         # optional: the entry in the label file (default name)
    cut = "table"                       # optional: "none" (default) or "table"
    crop = [[x0, y0, z0], [x1, y1, z1]] # optional: keep points inside this box first
    intrinsics = [fx, fy, cx, cy]       # a depth image (.png, .tif) only: pixels
    depth_scale = 0.001                 # a depth image only: meters per stored unit

A depth image (one sensor frame, :mod:`simgrasp.perception.depth_image`) is read through its
``intrinsics`` (or a GraspNet ``meta.mat`` beside it) at ``depth_scale``; its points, viewpoint
and crop are in meters.

``cut = "table"`` keeps the points above the scene's dominant plane (the table of
:func:`simgrasp.perception.segmentation.segment.fit_table_plane`) in its largest connected
cluster: the object a user's segmenter would hand over. Labels are regions
(:mod:`simgrasp.labels`) in the cloud's frame, in meters. The shipped manifest is
``models/handles/real_detect.toml``.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.assets.real import default_real_dir
from simgrasp.config.checks import SettingError
from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.labels import HandleLabel, load_label_file
from simgrasp.perception.depth_image import DEPTH_IMAGE_FORMATS, DepthImageConfig
from simgrasp.perception.units import UNIT_SCALE, Units, cloud_in_meters
from simgrasp.resources import model_path, models_dir

REAL_MANIFEST = ("handles", "real_detect.toml")
Split = Literal["tune", "holdout"]
_KEYS = {"name", "path", "dataset", "split", "units", "viewpoint", "labels", "label_key", "cut"}
_KEYS |= {"crop", "intrinsics", "depth_scale"}
MIN_LABELED_POINTS = 20
"""A label must hold at least this many of its cloud's points: fewer means it lies outside
the cloud (a wrong frame or units)."""


@dataclass(frozen=True)
class RealCloud:
    """One manifest entry, resolved: paths absolute, viewpoint and crop in meters."""

    name: str
    path: Path
    dataset: str
    split: Split
    units: Units
    viewpoint: NDArray[np.float64]
    label: HandleLabel
    cut: Literal["none", "table"] = "none"
    crop: NDArray[np.float64] | None = None
    """(2, 3) lower and upper corner (m), or None."""
    depth: DepthImageConfig = DepthImageConfig()
    """How a depth image entry becomes points (unused for a cloud file)."""


def _entry_error(manifest: Path, index: int, entry: dict[str, Any], problem: str) -> SimgraspError:
    name = entry.get("name", f"#{index + 1}")
    return SimgraspError(f"{manifest}: cloud {name}: {problem}")


def _field(manifest: Path, index: int, entry: dict[str, Any], key: str, kind: type) -> Any:
    if key not in entry:
        raise _entry_error(manifest, index, entry, f"missing '{key}'")
    if not isinstance(entry[key], kind):
        raise _entry_error(manifest, index, entry, f"'{key}' must be a {kind.__name__}")
    return entry[key]


def _vector(manifest: Path, index: int, entry: dict[str, Any], key: str, shape: tuple[int, ...]):  # noqa: ANN202
    try:
        value = np.asarray(entry[key], dtype=float)
    except (TypeError, ValueError):
        value = np.zeros(0)
    if value.shape != shape or not np.all(np.isfinite(value)):
        raise _entry_error(manifest, index, entry, f"'{key}' must be numbers of shape {shape}")
    return value


def _resolve(path: str, root: Path) -> Path:
    candidate = Path(path).expanduser()
    return candidate if candidate.is_absolute() else root / candidate


def _entry(manifest: Path, index: int, entry: dict[str, Any], real_dir: Path) -> RealCloud:
    """One ``[[cloud]]`` table as a :class:`RealCloud`; each problem is one line naming it."""
    unknown = sorted(set(entry) - _KEYS)
    if unknown:
        raise _entry_error(manifest, index, entry, f"unknown key(s) {', '.join(unknown)}")
    name = _field(manifest, index, entry, "name", str)
    units = entry.get("units", "m")
    if units not in UNIT_SCALE:
        raise _entry_error(
            manifest, index, entry, f"units must be one of {', '.join(UNIT_SCALE)}, got {units!r}"
        )
    split = _field(manifest, index, entry, "split", str)
    if split not in ("tune", "holdout"):
        raise _entry_error(manifest, index, entry, f"split must be tune or holdout, got {split!r}")
    cut = entry.get("cut", "none")
    if cut not in ("none", "table"):
        raise _entry_error(manifest, index, entry, f"cut must be none or table, got {cut!r}")
    scale = UNIT_SCALE[units]
    crop = _vector(manifest, index, entry, "crop", (2, 3)) * scale if "crop" in entry else None
    path = _resolve(_field(manifest, index, entry, "path", str), real_dir)
    label_file = _resolve(_field(manifest, index, entry, "labels", str), manifest.parent)
    key = entry.get("label_key", name)
    labels = load_label_file(label_file)
    if key not in labels:
        raise _entry_error(manifest, index, entry, f"label file {label_file} has no entry {key!r}")
    viewpoint = _vector(manifest, index, entry, "viewpoint", (3,)) * scale
    dataset = _field(manifest, index, entry, "dataset", str)
    depth = _depth(manifest, index, entry, path)
    return RealCloud(name, path, dataset, split, units, viewpoint, labels[key], cut, crop, depth)


def _depth(manifest: Path, index: int, entry: dict[str, Any], path: Path) -> DepthImageConfig:
    """The depth image settings of an entry; refused on a cloud file, or with units other than
    meters (a depth image's scale says its units)."""
    image = path.suffix.lower() in DEPTH_IMAGE_FORMATS
    given = sorted({"intrinsics", "depth_scale"} & set(entry))
    if given and not image:
        problem = f"'{given[0]}' is for a depth image (.png, .tif)"
        raise _entry_error(manifest, index, entry, problem)
    if image and entry.get("units", "m") != "m":
        raise _entry_error(manifest, index, entry, "a depth image's units are its 'depth_scale'")
    intrinsics = entry.get("intrinsics")
    scale = entry.get("depth_scale", DepthImageConfig.scale)
    if isinstance(scale, bool) or not isinstance(scale, int | float) or not scale > 0:
        raise _entry_error(manifest, index, entry, "'depth_scale' must be a positive number")
    if intrinsics is None:
        return DepthImageConfig(scale=float(scale))
    fx, fy, cx, cy = _vector(manifest, index, entry, "intrinsics", (4,))
    try:
        return DepthImageConfig(intrinsics=(fx, fy, cx, cy), scale=float(scale))
    except SettingError as exc:
        raise _entry_error(manifest, index, entry, f"'intrinsics' {exc.detail}") from None


def shipped_if_absent(path: Path) -> Path:
    """``path``, or where it names a file the package ships (``models/handles/real_detect.toml``
    as the README writes it) and is not there, as from an installed wheel, the shipped file."""
    if path.exists() or path.is_absolute() or path.parts[:1] != ("models",):
        return path
    shipped = models_dir().joinpath(*path.parts[1:])
    return shipped if shipped.is_file() else path


def read_manifest(path: Path | None = None, real_dir: Path | None = None) -> list[RealCloud]:
    """The clouds of manifest ``path`` (default: the shipped one); cloud paths are relative to
    ``real_dir`` (default ``$SIMGRASP_REAL_DIR``, else ``../shared/real``). Files are not
    read here: :func:`load_real_cloud` checks each when it is scored."""
    path = shipped_if_absent(Path(path)) if path is not None else model_path(*REAL_MANIFEST)
    real_dir = Path(real_dir) if real_dir is not None else default_real_dir()
    try:
        data = tomllib.loads(path.read_text())
    except FileNotFoundError as exc:
        raise DataNotFoundError(f"{path}: no such manifest file") from exc
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise SimgraspError(f"{path}: cannot read the manifest: {exc}") from exc
    entries = data.get("cloud")
    if not isinstance(entries, list) or not entries:
        raise SimgraspError(f"{path}: the manifest lists no [[cloud]] tables")
    clouds = [_entry(path, i, e, real_dir) for i, e in enumerate(entries)]
    names = [c.name for c in clouds]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise SimgraspError(f"{path}: cloud name(s) listed twice: {', '.join(repeated)}")
    return clouds


def require_file(cloud: RealCloud) -> None:
    """One line naming the cloud when its file is not there."""
    if not cloud.path.is_file():
        raise DataNotFoundError(
            f"cloud {cloud.name}: no file {cloud.path}; point --real-dir or $SIMGRASP_REAL_DIR "
            "at the real data folder"
        )


def load_real_cloud(cloud: RealCloud) -> NDArray[np.float64]:
    """The cloud's points to detect on (m, the cloud's frame): read, converted from its units,
    cropped and cut as the manifest says; one line naming the cloud when the file is missing,
    the units are wrong or its label lies outside it."""
    from simgrasp.perception.cloud_io import read_cloud
    from simgrasp.perception.depth_image import read_depth_image, returned_points

    require_file(cloud)
    if cloud.path.suffix.lower() in DEPTH_IMAGE_FORMATS:
        points = returned_points(read_depth_image(cloud.path, cloud.depth))
    else:
        points, _ = read_cloud(cloud.path)
        points = cloud_in_meters(points, cloud.units, f"cloud {cloud.name} ({cloud.path})")
    if cloud.crop is not None:
        points = points[np.all((points >= cloud.crop[0]) & (points <= cloud.crop[1]), axis=1)]
    if cloud.cut == "table":
        points = object_above_table(points, cloud.viewpoint, cloud.name)
    inside = int(cloud.label.contains(points).sum())
    if cloud.label.regions and inside < MIN_LABELED_POINTS:
        raise SimgraspError(
            f"cloud {cloud.name}: its handle label holds {inside} of its {len(points)} points "
            f"(fewer than {MIN_LABELED_POINTS}): the label lies outside the cloud (wrong frame "
            "or units?)"
        )
    return points


def object_above_table(
    points: NDArray[np.float64], viewpoint: NDArray[np.float64], name: str
) -> NDArray[np.float64]:
    """The largest connected cluster (1 cm) of the points above the dominant plane (m)."""
    from simgrasp.perception._arrays import to_open3d
    from simgrasp.perception.scene_cloud import scene_from_array
    from simgrasp.perception.segmentation.segment import fit_table_plane
    from simgrasp.perception.segmentation.segment_config import SegmentConfig

    config = SegmentConfig()
    scene = scene_from_array(points.astype(np.float32), viewpoint, source=f"cloud {name}")
    valid = np.ones(len(points), dtype=bool)
    plane = fit_table_plane(scene.points, valid, scene, config)
    height = points @ plane[:3] + plane[3]
    above = points[(height > config.table_distance) & (height < config.max_object_height)]
    if len(above) == 0:
        raise SimgraspError(f"cloud {name}: nothing above its table plane")
    clusters = np.asarray(to_open3d(above).cluster_dbscan(eps=0.01, min_points=10))
    if not (clusters >= 0).any():
        raise SimgraspError(f"cloud {name}: no cluster of points above its table plane")
    return above[clusters == np.bincount(clusters[clusters >= 0]).argmax()]
