"""Strict readers of the PLY and PCD point-cloud formats: every point the header declares is in
the file, every value parses, and nothing else is read as a point.

Open3D's readers fill a cut file's missing points with zeros (or leftover memory) and read a
word as 0; these refuse such a file with a ``ValueError`` naming it and saying what is wrong.
Supported: PLY ``ascii``, ``binary_little_endian`` and ``binary_big_endian`` with a ``vertex``
element of scalar properties ``x y z`` (and ``nx ny nz``; other properties are ignored, other
elements skipped), and PCD ``ascii`` and ``binary`` with fields ``x y z`` (and ``normal_x
normal_y normal_z``). A PCD ``binary_compressed`` body is checked against its declared sizes and
decoded by Open3D (LZF has no checksum: a corrupted compressed body is not always detected).

Text data must end with a newline after its last point: without one the last line may have been
cut inside a number, which would read as a different point.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError

Table = dict[str, NDArray[np.float64]]
"""Columns by property / field name."""

PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}  # fmt: skip
PLY_FORMATS = {"ascii": "", "binary_little_endian": "<", "binary_big_endian": ">"}
PCD_TYPES = {"F": "f", "I": "i", "U": "u"}


def _header(path: Path, data: bytes, last_key: bytes) -> tuple[list[list[str]], int]:
    """The header's lines (as word lists) up to and including the line starting with
    ``last_key``, and the offset of the body after it."""
    end = data.find(b"\n" + last_key)
    stop = data.find(b"\n", end + 1) if end >= 0 else -1
    if stop < 0:
        raise SimgraspError(f"{path}: no complete header (no {last_key.decode()} line)")
    try:
        text = data[:stop].decode("ascii")
    except UnicodeDecodeError:
        raise SimgraspError(f"{path}: the header is not ASCII text") from None
    lines = [line.split() for line in text.splitlines()]
    return [words for words in lines if words and not words[0].startswith("#")], stop + 1


def _text_rows(
    path: Path, body: bytes, start: int, count: int, columns: int, last: bool
) -> NDArray:
    """``count`` rows of ``columns`` numbers from the text ``body``, skipping ``start`` lines;
    each row must end with a newline, and no text may follow them when they are ``last``."""
    lines = body.split(b"\n")
    if last and b"".join(lines[start + count :]).strip():
        raise SimgraspError(f"{path}: text follows its {count} points: the point count is wrong")
    if len(lines) < start + count + 1:  # the last piece is what follows the last newline
        held = max(0, min(count, len(lines) - 1 - start))
        raise SimgraspError(
            f"{path}: holds {held} complete point lines of the {count} its header declares "
            "(the file is cut, or its last line has no newline)"
        )
    rows = lines[start : start + count]
    if count == 0:
        return np.zeros((0, columns))
    try:
        table = np.loadtxt(
            [r.decode("ascii") for r in rows], dtype=np.float64, comments=None, ndmin=2
        )
    except (ValueError, UnicodeDecodeError) as exc:
        raise SimgraspError(f"{path}: a point line is not {columns} numbers ({exc})") from None
    if table.shape != (count, columns):
        raise SimgraspError(
            f"{path}: point lines hold {table.shape[1]} values, the header declares {columns}"
        )
    return table


def _binary_rows(path: Path, data: bytes, offset: int, dtype: np.dtype, count: int, last: bool):
    """``count`` records of ``dtype`` at ``offset``; the data must hold them all, and nothing
    after them when they are the file's ``last`` element."""
    need = count * dtype.itemsize
    held = len(data) - offset
    if held < need:
        raise SimgraspError(
            f"{path}: its header declares {count} points ({need} bytes) but the file holds "
            f"{held} bytes of them: the file is cut"
        )
    if last and held > need:
        raise SimgraspError(
            f"{path}: {held - need} bytes follow its {count} points: the header's point count "
            "does not match the data"
        )
    return np.frombuffer(data, dtype=dtype, count=count, offset=offset)


def _check_float_coordinates(path: Path, dtype: np.dtype, normals: tuple[str, ...]) -> None:
    """Coordinates and normals must be stored as floats (an integer type there is a damaged
    header far more often than a real file)."""
    for name in ("x", "y", "z", *normals):
        if name in (dtype.names or ()) and dtype[name].kind != "f":
            raise SimgraspError(f"{path}: {name} is stored as {dtype[name]}, not as a float")


def _ply_elements(path: Path, lines: list[list[str]]) -> list[tuple[str, int, list[list[str]]]]:
    """(name, count, property lines) per element, in file order."""
    elements: list[tuple[str, int, list[list[str]]]] = []
    for words in lines[2:-1]:
        if words[0] == "element" and len(words) == 3 and words[2].isdigit():
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements and len(words) in (3, 5):
            elements[-1][2].append(words[1:])
        elif words[0] not in ("comment", "obj_info"):
            raise SimgraspError(f"{path}: bad PLY header line {' '.join(words)!r}")
    return elements


def _ply_dtype(path: Path, name: str, properties: list[list[str]], endian: str) -> np.dtype:
    """The record type of an element of scalar properties."""
    fields = []
    for prop in properties:
        if len(prop) != 2 or prop[0] not in PLY_TYPES:
            raise SimgraspError(
                f"{path}: PLY element {name!r} has a property {' '.join(prop)!r} that is not "
                "a scalar of a known type (list properties are read only after the vertices)"
            )
        fields.append((prop[1], endian + PLY_TYPES[prop[0]]))
    try:
        return np.dtype(fields)
    except ValueError as exc:
        raise SimgraspError(f"{path}: bad PLY element {name!r} ({exc})") from None


def read_ply(path: Path, data: bytes) -> Table:
    """The vertex columns of a PLY file's bytes."""
    if not data.startswith(b"ply"):
        raise SimgraspError(f"{path}: not a PLY file (it does not start with 'ply')")
    lines, offset = _header(path, data, b"end_header")
    form = lines[1] if len(lines) > 1 else []
    if len(form) != 3 or form[0] != "format" or form[1] not in PLY_FORMATS:
        raise SimgraspError(f"{path}: unknown PLY format line {' '.join(form)!r}")
    elements = _ply_elements(path, lines)
    names = [name for name, _, _ in elements]
    if "vertex" not in names:
        raise SimgraspError(f"{path}: the PLY file has no vertex element")
    index = names.index("vertex")
    _, count, properties = elements[index]
    endian = PLY_FORMATS[form[1]]
    dtype = _ply_dtype(path, "vertex", properties, endian or "<")
    _check_float_coordinates(path, dtype, ("nx", "ny", "nz"))
    last = index == len(elements) - 1
    fields = dtype.names or ()
    if not endian:
        skip = sum(n for _, n, _ in elements[:index])
        rows = _text_rows(path, data[offset:], skip, count, len(fields), last)
        return {name: rows[:, k] for k, name in enumerate(fields)}
    for name, n, props in elements[:index]:
        offset += n * _ply_dtype(path, name, props, endian).itemsize
    records = _binary_rows(path, data, offset, dtype, count, last)
    return {name: records[name].astype(np.float64) for name in fields}


def _pcd_fields(path: Path, header: dict[str, list[str]]) -> tuple[list[str], np.dtype]:
    """The field names and the binary record type of a PCD header."""
    names = header.get("FIELDS", [])
    sizes, types = header.get("SIZE", []), header.get("TYPE", [])
    counts = header.get("COUNT", ["1"] * len(names))
    if not names or not len(names) == len(sizes) == len(types) == len(counts):
        raise SimgraspError(f"{path}: PCD FIELDS, SIZE, TYPE and COUNT do not match")
    fields = []
    for k, (name, size, kind, count) in enumerate(zip(names, sizes, types, counts, strict=True)):
        if kind not in PCD_TYPES or size not in ("1", "2", "4", "8") or not count.isdigit():
            raise SimgraspError(f"{path}: bad PCD field {name!r} (SIZE {size}, TYPE {kind})")
        code = "<" + PCD_TYPES[kind] + size
        unique = name if name != "_" else f"_pad{k}"
        fields.append((unique, code, (int(count),)) if count != "1" else (unique, code))
    try:
        return [f[0] for f in fields], np.dtype(fields)
    except (ValueError, TypeError) as exc:
        raise SimgraspError(f"{path}: bad PCD fields ({exc})") from None


def _pcd_count(path: Path, header: dict[str, list[str]]) -> int:
    """The number of points (``POINTS``, which must equal ``WIDTH * HEIGHT``)."""
    try:
        width, height = int(header["WIDTH"][0]), int(header["HEIGHT"][0])
        points = int(header.get("POINTS", [width * height])[0])
    except (KeyError, IndexError, ValueError):
        raise SimgraspError(f"{path}: PCD header without valid WIDTH, HEIGHT and POINTS") from None
    if points != width * height or points < 0:
        raise SimgraspError(f"{path}: PCD POINTS {points} is not WIDTH x HEIGHT {width}x{height}")
    return points


def pcd_header(path: Path, data: bytes) -> dict[str, list[str]]:
    """A PCD file's header entries (``FIELDS``, ``WIDTH``, ``VIEWPOINT`` ... ``DATA``)."""
    return _pcd_header_and_offset(path, data)[0]


def _pcd_header_and_offset(path: Path, data: bytes) -> tuple[dict[str, list[str]], int]:
    lines, offset = _header(path, data, b"DATA")
    return {words[0]: words[1:] for words in lines}, offset


def read_pcd(path: Path, data: bytes) -> Table:
    """The field columns of a PCD file's bytes (a field with COUNT > 1 is left out)."""
    header, offset = _pcd_header_and_offset(path, data)
    names, dtype = _pcd_fields(path, header)
    _check_float_coordinates(path, dtype, ("normal_x", "normal_y", "normal_z"))
    count = _pcd_count(path, header)
    kind = (header.get("DATA") or [""])[0]
    scalars = [n for n in names if dtype[n].shape == ()]
    if kind == "ascii":
        width = sum(int(np.prod(dtype[n].shape)) for n in names)
        rows = _text_rows(path, data[offset:], 0, count, width, last=True)
        columns = np.cumsum([0, *(int(np.prod(dtype[n].shape)) for n in names)])
        return {n: rows[:, columns[k]] for k, n in enumerate(names) if n in scalars}
    if kind == "binary":
        records = _binary_rows(path, data, offset, dtype, count, last=True)
        return {n: records[n].astype(np.float64) for n in scalars}
    if kind == "binary_compressed":
        return _read_compressed_pcd(path, data, offset, count, dtype)
    raise SimgraspError(f"{path}: unknown PCD DATA kind {kind!r}")


def check_compressed_pcd(path: Path, data: bytes) -> None:
    """Refuse a ``binary_compressed`` PCD whose body does not hold the header's points (cut,
    padded or corrupt sizes), without decoding it."""
    header, offset = _pcd_header_and_offset(path, data)
    _, dtype = _pcd_fields(path, header)
    _check_compressed_sizes(path, data, offset, _pcd_count(path, header), dtype)


def _check_compressed_sizes(
    path: Path, data: bytes, offset: int, count: int, dtype: np.dtype
) -> None:
    sizes = (
        np.frombuffer(data, dtype="<u4", count=2, offset=offset)
        if len(data) >= offset + 8
        else None
    )
    if sizes is None or int(sizes[1]) != count * dtype.itemsize:
        raise SimgraspError(f"{path}: the compressed PCD body does not hold {count} points")
    if len(data) - offset - 8 < int(sizes[0]):  # trailing bytes (PCL's padding) are allowed
        raise SimgraspError(
            f"{path}: the compressed PCD body is {len(data) - offset - 8} bytes, its header "
            f"says {int(sizes[0])}: the file is truncated"
        )


def _read_compressed_pcd(path: Path, data: bytes, offset: int, count: int, dtype: np.dtype):
    """A ``binary_compressed`` body: sizes checked here, decoded by Open3D."""
    from simgrasp.perception._arrays import import_open3d

    _check_compressed_sizes(path, data, offset, count, dtype)
    cloud = import_open3d().io.read_point_cloud(str(path), format="pcd")
    if len(cloud.points) != count:
        raise SimgraspError(f"{path}: the compressed PCD body could not be decoded")
    table = {a: np.asarray(cloud.points)[:, k] for k, a in enumerate("xyz")}
    if cloud.has_normals():
        table |= {f"normal_{a}": np.asarray(cloud.normals)[:, k] for k, a in enumerate("xyz")}
    return table


def ply_face_count(path: Path, data: bytes) -> int:
    """How many faces a PLY file's header declares (0 for a point cloud): a file with faces is
    a mesh, a scanner's reconstruction."""
    if not data.startswith(b"ply"):
        raise SimgraspError(f"{path}: not a PLY file (it does not start with 'ply')")
    lines, _ = _header(path, data, b"end_header")
    return sum(count for name, count, _ in _ply_elements(path, lines) if name == "face")
