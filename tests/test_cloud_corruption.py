"""Cut and corrupted cloud files are refused, never read with points that are not in them,
and ``simgrasp detect --json`` prints nothing but its JSON object."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import open3d as o3d
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from simgrasp.perception.cloud_io import read_cloud, write_cloud

from shapes import mug_like

# (suffix, writer): binary PLY / PCD and text / npy via write_cloud; ASCII PLY / PCD via Open3D.
VARIANTS = ["ply-binary", "ply-ascii", "pcd-binary", "pcd-ascii", "xyz", "npy"]


def cloud(seed: int, count: int, with_normals: bool) -> tuple[np.ndarray, np.ndarray | None]:
    rng = np.random.default_rng(seed)
    points = rng.uniform(-0.1, 0.1, (count, 3))
    if not with_normals:
        return points, None
    normals = rng.normal(size=(count, 3))
    return points, normals / np.linalg.norm(normals, axis=1, keepdims=True)


def write_variant(path_stem: Path, variant: str, points, normals) -> Path:
    suffix = "." + variant.split("-")[0]
    path = path_stem.with_suffix(suffix)
    if variant.endswith("-ascii"):
        pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
        if normals is not None:
            pc.normals = o3d.utility.Vector3dVector(normals)
        assert o3d.io.write_point_cloud(path, pc, write_ascii=True)
    else:
        write_cloud(path, points, normals)
    return path


def good_file(tmp_path: Path, variant: str, count: int = 50) -> tuple[Path, np.ndarray]:
    points, normals = cloud(0, count, with_normals=False)
    path = write_variant(tmp_path / "cloud", variant, points, normals)
    return path, read_cloud(path)[0]


@pytest.mark.parametrize("variant", ["ply-binary", "ply-ascii", "pcd-binary", "pcd-ascii"])
@pytest.mark.parametrize("keep", [0.5, 0.9, 0.999])
def test_a_cut_file_is_an_error_naming_it(tmp_path: Path, variant: str, keep: float) -> None:
    path, _ = good_file(tmp_path, variant)
    data = path.read_bytes()
    path.write_bytes(data[: int(len(data) * keep)])
    with pytest.raises(ValueError, match=rf"^{path}: ") as info:
        read_cloud(path)
    assert "\n" not in str(info.value)


def test_a_word_in_an_ascii_pcd_is_an_error(tmp_path: Path) -> None:
    path, _ = good_file(tmp_path, "pcd-ascii")
    lines = path.read_text().splitlines(keepends=True)
    lines[-3] = "0.01 oops 0.02\n"
    path.write_text("".join(lines))
    with pytest.raises(ValueError, match=rf"^{path}: .*not 3 numbers"):
        read_cloud(path)


@pytest.mark.parametrize("variant", ["ply-binary", "ply-ascii", "pcd-binary", "pcd-ascii"])
@pytest.mark.parametrize("declared", [40, 60])
def test_a_point_count_that_does_not_match_the_header_is_an_error(
    tmp_path: Path, variant: str, declared: int
) -> None:
    path, _ = good_file(tmp_path, variant)
    data = path.read_bytes()
    for key in (b"element vertex 50\n", b"WIDTH 50\n", b"POINTS 50\n"):
        data = data.replace(key, key.replace(b"50", str(declared).encode()))
    path.write_bytes(data)
    with pytest.raises(ValueError, match=rf"^{path}: "):
        read_cloud(path)


def run_detect(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "simgrasp", "detect", *args],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


def test_detect_json_prints_only_the_json_object(tmp_path: Path) -> None:
    """A broken compressed PCD is decoded by Open3D, which warns on stdout: the warning must go
    to stderr, and stdout stay empty on the error; on a good cloud stdout is one JSON object."""
    points, _ = cloud(0, 50, with_normals=False)
    broken = tmp_path / "broken.pcd"
    pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    assert o3d.io.write_point_cloud(broken, pc, compressed=True)
    data = bytearray(broken.read_bytes())
    body = data.index(b"binary_compressed\n") + len(b"binary_compressed\n") + 8
    data[body] = 0xFF  # an LZF back-reference before the start of the output
    broken.write_bytes(bytes(data))
    done = run_detect(str(broken), "--json")
    assert done.returncode == 2 and done.stdout == "", done.stdout
    assert f"{broken}: " in done.stderr
    good = tmp_path / "mug.npy"
    mug = mug_like(seed=0)
    np.save(good, np.hstack([mug.points, mug.normals]))
    done = run_detect(str(good), "--json")
    assert done.returncode == 0, done.stderr
    assert isinstance(json.loads(done.stdout), dict)
    assert done.stdout.count("\n") == 1


@st.composite
def damaged_files(draw):
    """A valid cloud file's bytes, then cut at a random length or one byte replaced."""
    variant = draw(st.sampled_from(VARIANTS))
    count = draw(st.integers(3, 40))
    with_normals = draw(st.booleans())
    seed = draw(st.integers(0, 2**16))
    cut = draw(st.booleans())
    fraction = draw(st.floats(0, 1, exclude_max=True))
    value = draw(st.integers(0, 255))
    return variant, count, with_normals, seed, cut, fraction, value


def rows(array: np.ndarray) -> set[tuple[float, ...]]:
    return {tuple(row) for row in array.tolist()}


@settings(
    max_examples=600, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(damaged_files())
def test_a_damaged_file_is_refused_or_read_with_only_its_own_points(tmp_path: Path, case) -> None:
    """Property: reading a cut or corrupted PLY / PCD / XYZ / NPY file either raises a
    ValueError naming the file, or returns only points the file holds.

    - Cut at any length: the result must be exactly the first m points of the intact file. Only
      a text ``.xyz`` file cut at a line end can succeed (m < N): a headerless list of lines cut
      between lines is indistinguishable from a shorter cloud. Every other format declares its
      point count (PLY, PCD) or size (NPY), and a text file cut inside a line has no final
      newline, so it is refused.
    - One byte replaced: the result must hold the intact file's points except at most one: the
      point whose bytes the change fell in now says something else, and it is what the file
      holds. Every header change that still parses must leave the layout as it was (counts
      and sizes are checked against the data, coordinates must be floats, so an ``F`` -> ``I``
      type or ``<f8`` -> ``<i8`` dtype is refused). An ``.xyz`` line turned into a comment
      drops that point, which is why one point may also be missing there; two lines merged
      by a lost newline change the column count, which is refused.
    """
    variant, count, with_normals, seed, cut, fraction, value = case
    points, normals = cloud(seed, count, with_normals)
    path = write_variant(tmp_path / f"c{seed}", variant, points, normals)
    intact, intact_normals = read_cloud(path)
    data = bytearray(path.read_bytes())
    position = int(fraction * len(data))
    if cut:
        path.write_bytes(bytes(data[:position]))
    else:
        if data[position] == value:
            return
        data[position] = value
        path.write_bytes(bytes(data))
    try:
        got, got_normals = read_cloud(path)
    except ValueError as exc:
        assert str(exc).startswith(f"{path}: "), exc
        return
    if cut:
        assert variant == "xyz", f"a cut {variant} file was read"
        np.testing.assert_array_equal(got, intact[: len(got)])
        return
    foreign = rows(got) - rows(intact)
    assert len(foreign) <= 1, f"{len(foreign)} points not in the {variant} file"
    assert len(got) == len(intact) or (variant == "xyz" and len(got) == len(intact) - 1)
    if got_normals is not None and intact_normals is not None and len(got) == len(intact):
        assert int((np.abs(got_normals - intact_normals) > 1e-9).any(axis=1).sum()) <= 1
