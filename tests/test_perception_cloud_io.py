"""Cloud files: round trips for every format, clear errors naming the file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from simgrasp.perception import read_cloud, write_cloud
from simgrasp.seeding import rng_for

FORMATS = [".ply", ".pcd", ".xyz", ".npy"]


def _cloud() -> tuple[np.ndarray, np.ndarray]:
    rng = rng_for(0, "cloud_io")
    points = rng.uniform(-0.2, 0.2, size=(500, 3))
    normals = rng.normal(size=(500, 3))
    return points, normals / np.linalg.norm(normals, axis=1, keepdims=True)


@pytest.mark.parametrize("suffix", FORMATS)
@pytest.mark.parametrize("with_normals", [True, False])
def test_round_trip(tmp_path: Path, suffix: str, with_normals: bool) -> None:
    points, normals = _cloud()
    path = tmp_path / f"cloud{suffix}"
    write_cloud(path, points, normals if with_normals else None)
    read_points, read_normals = read_cloud(path)
    atol = 1e-7 if suffix in (".ply", ".pcd") else 1e-15  # Open3D stores float32
    np.testing.assert_allclose(read_points, points, rtol=0, atol=atol)
    if with_normals:
        assert read_normals is not None
        np.testing.assert_allclose(read_normals, normals, rtol=0, atol=atol)
    else:
        assert read_normals is None


def test_text_with_comments_and_unnormalised_normals(tmp_path: Path) -> None:
    path = tmp_path / "c.xyz"
    path.write_text("# x y z nx ny nz\n0 0 0 0 0 2\n1 2 3 3 0 0\n")
    points, normals = read_cloud(path)
    np.testing.assert_array_equal(points, [[0, 0, 0], [1, 2, 3]])
    np.testing.assert_array_equal(normals, [[0, 0, 1], [1, 0, 0]])


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("c.obj", "v 0 0 0\n", "unknown point-cloud extension"),
        ("c.xyz", "1 2\n3 4\n", "N x 3"),
        ("c.xyz", "1 2 3\nnan 2 3\n4 5 inf\n", "2 of 3 points have NaN or inf"),
        ("c.xyz", "# nothing\n", "empty"),
        ("c.xyz", "1 2 three\n", "not a readable"),
        ("c.ply", "not a ply\n", "not a PLY file"),
        ("c.npy", "garbage", "not a readable"),
    ],
)
def test_bad_files_name_the_file(tmp_path: Path, name: str, content: str, message: str) -> None:
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(ValueError, match=message) as info:
        read_cloud(path)
    assert str(path) in str(info.value)


def test_bad_npy_shape_and_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "c.npy"
    np.save(path, np.zeros((4, 4)))
    with pytest.raises(ValueError, match=r"got shape \(4, 4\)"):
        read_cloud(path)
    with pytest.raises(ValueError, match="no such point-cloud file"):
        read_cloud(tmp_path / "missing.ply")


def test_write_refuses_bad_arrays(tmp_path: Path) -> None:
    points, normals = _cloud()
    with pytest.raises(ValueError, match="NaN"):
        write_cloud(tmp_path / "c.ply", np.vstack([points, [np.nan, 0, 0]]))
    with pytest.raises(ValueError, match="does not match"):
        write_cloud(tmp_path / "c.npy", points, normals[:10])
    with pytest.raises(ValueError, match="unknown"):
        write_cloud(tmp_path / "c.txt", points)


def _ascii_pcd(rows: list[str], fields: str = "x y z", width: int = 2) -> str:
    """An organized ASCII PCD of ``rows`` (one point each), ``width`` points a row."""
    count = len(fields.split())
    return (
        f"VERSION 0.7\nFIELDS {fields}\nSIZE {' '.join(['4'] * count)}\n"
        f"TYPE {' '.join(['F'] * count)}\nCOUNT {' '.join(['1'] * count)}\nWIDTH {width}\n"
        f"HEIGHT {len(rows) // width}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(rows)}\n"
        "DATA ascii\n" + "".join(row + "\n" for row in rows)
    )


def test_a_pcd_pixel_with_no_return_is_left_out(tmp_path: Path) -> None:
    """An organized PCD as PCL writes it, its empty pixels all NaN: the other points are read,
    their normals with them; a point with only some coordinates NaN is still refused."""
    path = tmp_path / "view.pcd"
    rows = ["0 0 1 0 0 -1", "nan nan nan nan nan nan", "0.1 0 1 0 0 -1", "0 0.1 1 1 0 0"]
    path.write_text(_ascii_pcd(rows, "x y z normal_x normal_y normal_z"))
    points, normals = read_cloud(path)
    np.testing.assert_allclose(
        points, [[0.0, 0.0, 1.0], [0.1, 0.0, 1.0], [0.0, 0.1, 1.0]], atol=1e-7
    )
    np.testing.assert_array_equal(normals, [[0, 0, -1], [0, 0, -1], [1, 0, 0]])
    path.write_text(_ascii_pcd(["0 0 1", "nan 0 1", "0.1 0 1", "nan nan nan"]))
    with pytest.raises(ValueError, match="1 of 3 points have NaN or inf"):
        read_cloud(path)
    path.write_text(_ascii_pcd(["nan nan nan", "nan nan nan"]))
    with pytest.raises(ValueError, match="the point cloud is empty"):
        read_cloud(path)
