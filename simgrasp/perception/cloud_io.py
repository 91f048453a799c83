"""Read and write point clouds: ``.ply`` and ``.pcd`` (Open3D), ``.xyz`` (text), ``.npy``.

``.xyz`` is whitespace-separated text, one point per line: ``x y z`` or ``x y z nx ny nz``
(``#`` starts a comment). ``.npy`` holds an (N, 3) or (N, 6) float array, same columns.

Policy for bad data: reading refuses (``ValueError`` naming the file) an unknown extension, a
missing or unreadable file, a wrong column count, an empty cloud, and any non-finite value,
reporting how many points have NaN or inf: silently dropping points would change what a
detector sees. The one exception is the PCD format's own mark of a pixel with no return: a
``.pcd`` point whose x, y and z are all NaN (as PCL writes the empty pixels of an organized
cloud, cropped or not) is no point and is left out, as a depth image's zero pixels are.
Normals are rescaled to unit length. Normals that are NaN, inf or zero (scanner exports give
the vertices no face uses a zero normal) are estimated from their neighbours
(:mod:`simgrasp.perception.normal_fill`), or, when none is usable, left to the detector to
estimate; a :class:`ReadNote` warning says so in one line. A cut or corrupted file
is refused rather than read with points that are not in it: ``.ply`` and ``.pcd`` by the
strict readers of :mod:`simgrasp.perception.cloud_formats` (point counts must match the
header, every value must parse), ``.npy`` when its size does not match its header or it is
not a little-endian float32 / float64 array (as ``np.save`` writes one), and text (``.xyz``,
ASCII PLY / PCD) whose last line has no newline (it may have been cut inside a number).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.perception._arrays import import_open3d, to_open3d
from simgrasp.perception.cloud_formats import read_pcd, read_ply
from simgrasp.perception.normal_fill import fill_missing_normals, missing_normals

FORMATS = (".ply", ".pcd", ".xyz", ".npy")

Cloud = tuple[NDArray[np.float64], NDArray[np.float64] | None]


class ReadNote(UserWarning):
    """What reading a file changed, in one line: its normals partly or wholly estimated."""


def _format(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise SimgraspError(
            f"{path}: unknown point-cloud extension {suffix!r}; use one of {', '.join(FORMATS)}"
        )
    return suffix


def read_cloud(path: str | Path) -> Cloud:
    """Read a cloud file; returns (N, 3) points and (N, 3) unit normals or None (meters). A
    PCD's points with no return (x, y and z all NaN) are left out; normals the file left out
    (NaN, inf or zero) are estimated, with a :class:`ReadNote` warning saying how many."""
    path = Path(path)
    suffix = _format(path)
    if not path.is_file():
        raise SimgraspError(f"{path}: no such point-cloud file")
    if suffix in (".ply", ".pcd"):
        points, normals = _read_structured(path, suffix)
        if suffix == ".pcd":
            points, normals = _returns_only(points, normals)
    else:
        points, normals = _split_columns(path, _read_table(path, suffix))
    return _checked(path, points, normals, fill=True)


def _returns_only(points: NDArray[np.float64], normals: NDArray[np.float64] | None) -> Cloud:
    """``points`` (N, 3) and their ``normals`` without the points whose three coordinates are
    all NaN: a PCD's pixels with no return."""
    returned = ~np.isnan(points).all(axis=1)
    if returned.all():
        return points, normals
    return points[returned], None if normals is None else normals[returned]


def write_cloud(path: str | Path, points: ArrayLike, normals: ArrayLike | None = None) -> None:
    """Write (N, 3) points (and optional (N, 3) normals) to ``path``; format by extension.

    ``.ply`` and ``.pcd`` are written in binary by Open3D as float32 (about 1e-8 m error for
    clouds within a meter of the origin), ``.xyz`` as text with full float64 precision,
    ``.npy`` as an (N, 3) or (N, 6) float64 array.
    """
    path = Path(path)
    suffix = _format(path)
    pts, nrm = _checked(path, np.asarray(points, dtype=np.float64), normals)
    if suffix in (".ply", ".pcd"):
        o3d = import_open3d()
        if not o3d.io.write_point_cloud(str(path), to_open3d(pts, nrm)):
            raise SimgraspError(f"{path}: Open3D could not write the point cloud")
        return
    table = pts if nrm is None else np.hstack([pts, nrm])
    if suffix == ".npy":
        np.save(path, table)
    else:
        np.savetxt(path, table, fmt="%.17g")


NORMAL_NAMES = {".ply": ("nx", "ny", "nz"), ".pcd": ("normal_x", "normal_y", "normal_z")}
NPY_DTYPES = ("<f4", "<f8")


def _read_structured(path: Path, suffix: str) -> Cloud:
    """Points (and normals, when the file has all three components) of a PLY or PCD file."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise SimgraspError(f"{path}: cannot read the point cloud ({exc.strerror})") from None
    table = read_ply(path, data) if suffix == ".ply" else read_pcd(path, data)
    missing = [axis for axis in "xyz" if axis not in table]
    if missing:
        raise SimgraspError(f"{path}: the cloud has no {', '.join(missing)} coordinates")
    points = np.column_stack([table[axis] for axis in "xyz"])
    names = NORMAL_NAMES[suffix]
    normals = np.column_stack([table[n] for n in names]) if set(names) <= set(table) else None
    return points, normals


def _read_table(path: Path, suffix: str) -> NDArray[np.float64]:
    try:
        table = _read_npy(path) if suffix == ".npy" else _read_text(path)
    except (ValueError, OSError, EOFError) as exc:
        raise SimgraspError(f"{path}: not a readable {suffix} point cloud ({exc})") from exc
    return np.asarray(table, dtype=np.float64)


def _read_text(path: Path) -> NDArray[np.float64]:
    """The numbers of a text cloud; its last line must end with a newline (or be a comment)."""
    text = path.read_bytes()
    tail = text[text.rfind(b"\n") + 1 :].strip()
    if tail and not tail.startswith(b"#"):
        raise SimgraspError("the last line has no newline: the file may be cut inside a number")
    with warnings.catch_warnings():  # an empty file is reported later, not warned
        warnings.simplefilter("ignore", UserWarning)
        return np.loadtxt(path, dtype=np.float64, comments="#", ndmin=2)


def _read_npy(path: Path) -> NDArray[np.float64]:
    """An ``.npy`` array whose file size matches its header exactly, of a float dtype."""
    npy = np.lib.format
    with path.open("rb") as handle:
        try:
            version = npy.read_magic(handle)
            reader = npy.read_array_header_1_0 if version == (1, 0) else npy.read_array_header_2_0
            shape, _, dtype = reader(handle)
        except Exception as exc:  # numpy parses the header with Python's tokenizer
            raise SimgraspError(f"bad .npy header: {exc}") from None
        data_size = int(np.prod(shape)) * dtype.itemsize
        body = path.stat().st_size - handle.tell()
    if dtype.str not in NPY_DTYPES:
        raise SimgraspError(f"expected a little-endian float32 or float64 array, got {dtype.str}")
    if body != data_size:
        raise SimgraspError(f"its header declares {shape} ({data_size} bytes), it holds {body}")
    return np.load(path, allow_pickle=False)


def _split_columns(path: Path, table: NDArray[np.float64]) -> Cloud:
    if table.size == 0:
        raise SimgraspError(f"{path}: the point cloud is empty")
    if table.ndim != 2 or table.shape[1] not in (3, 6):
        raise SimgraspError(
            f"{path}: expected N x 3 (points) or N x 6 (points, normals), got shape {table.shape}"
        )
    return table[:, :3], (table[:, 3:] if table.shape[1] == 6 else None)


def _checked(
    path: Path, points: NDArray[np.float64], normals: ArrayLike | None, fill: bool = False
) -> Cloud:
    """``points`` and unit ``normals`` or None, checked; with ``fill`` (reading) the missing
    normals are estimated (:mod:`simgrasp.perception.normal_fill`) with a :class:`ReadNote`
    saying how many, else (writing) refused."""
    if points.ndim != 2 or points.shape[1] != 3:
        raise SimgraspError(f"{path}: points must be N x 3, got shape {points.shape}")
    if len(points) == 0:
        raise SimgraspError(f"{path}: the point cloud is empty")
    bad = ~np.isfinite(points).all(axis=1)
    if bad.any():
        raise SimgraspError(
            f"{path}: {int(bad.sum())} of {len(points)} points have NaN or inf coordinates; "
            "remove them first"
        )
    if normals is None:
        return points, None
    nrm = np.asarray(normals, dtype=np.float64)
    if nrm.shape != points.shape:
        raise SimgraspError(
            f"{path}: normals shape {nrm.shape} does not match points {points.shape}"
        )
    bad = missing_normals(nrm)
    if not bad.any():
        return points, nrm / np.linalg.norm(nrm, axis=1)[:, None]
    if not fill:
        raise SimgraspError(
            f"{path}: {int(bad.sum())} of {len(points)} normals are NaN, inf or zero length"
        )
    if bad.all():
        warnings.warn(f"{path}: no normal in the file is usable: estimated", ReadNote, 2)
        return points, None
    warnings.warn(
        f"{path}: {int(bad.sum())} of {len(points)} normals are NaN, inf or zero length: "
        "estimated from their neighbours",
        ReadNote,
        2,
    )
    return points, fill_missing_normals(points, nrm)
