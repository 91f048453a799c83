"""Real scan files as they come: a cloud whose normals are partly zero or NaN (a scanner's export
gives the vertices no face uses a zero normal) is read with those normals estimated, a mesh file
(a scanner's reconstruction) is detected by its sampled surface or its vertices, and a cloud
whose size only millimetres explain names the fix in the caller's spelling; through the command
line and the Python API. Every file is made here."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh
from numpy.typing import ArrayLike

import simgrasp
from simgrasp.cli import main
from simgrasp.errors import SimgraspError
from simgrasp.perception.cloud_file import MeshReadConfig, is_mesh_file, read_object_cloud
from simgrasp.perception.cloud_io import ReadNote, read_cloud

from shapes import mug_like, mug_parts

HANDLE_X = 0.0405
"""The mug_like handle lies at x > this (m); its body within 4 cm of the z axis."""


def write_ply(path: Path, points: np.ndarray, normals: np.ndarray, faces=None) -> None:
    """A binary PLY as scanner software writes one: float vertices with normals, and faces
    (``vertex_indices`` lists) when given."""
    header = [
        "ply",
        "format binary_little_endian 1.0",
        f"element vertex {len(points)}",
        *(f"property float {name}" for name in ("x", "y", "z", "nx", "ny", "nz")),
    ]
    if faces is not None:
        header += [f"element face {len(faces)}", "property list uchar int vertex_indices"]
    body = np.hstack([points, normals]).astype("<f4").tobytes()
    if faces is not None:
        record = np.dtype([("n", "u1"), ("v", "<i4", (3,))])
        table = np.zeros(len(faces), dtype=record)
        table["n"], table["v"] = 3, faces
        body += table.tobytes()
    path.write_bytes(("\n".join([*header, "end_header"]) + "\n").encode() + body)


def on_handle(centers: ArrayLike) -> np.ndarray:
    return np.asarray(centers)[:, 0] > HANDLE_X


@pytest.fixture(scope="module")
def mug() -> tuple[np.ndarray, np.ndarray]:
    cloud = mug_like(seed=0, density=1.5e6)
    return cloud.points, cloud.normals


@pytest.fixture(scope="module")
def zero_normals_ply(tmp_path_factory, mug) -> tuple[Path, np.ndarray]:
    """The mug cloud as a PLY whose every third point has a zero normal; the true normals."""
    points, normals = mug
    given = normals.copy()
    given[::3] = 0.0
    path = tmp_path_factory.mktemp("real_files") / "mug_scan.ply"
    write_ply(path, points, given)
    return path, normals


@pytest.fixture(scope="module")
def mug_mesh(tmp_path_factory) -> Path:
    """A mug as one OBJ mesh: body, bottom and loop handle (:func:`shapes.mug_parts`)."""
    path = tmp_path_factory.mktemp("real_files") / "mug_scan.obj"
    trimesh.util.concatenate([mesh for mesh, _ in mug_parts()]).export(path)
    return path


def test_zero_normals_are_estimated_where_missing_with_a_note(zero_normals_ply) -> None:
    path, true_normals = zero_normals_ply
    with pytest.warns(ReadNote, match=r"mug_scan.ply: \d+ of \d+ normals are NaN, inf or zero"):
        points, normals = read_cloud(path)
    assert normals is not None
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)
    kept = np.arange(len(points)) % 3 != 0
    np.testing.assert_allclose(normals[kept], true_normals[kept], atol=1e-6)
    cosine = np.einsum("ij,ij->i", normals[~kept], true_normals[~kept])
    assert np.mean(cosine > 0.9) > 0.9, np.mean(cosine > 0.9)  # right plane, right side


def write_pcd(path: Path, points: np.ndarray, normals: np.ndarray) -> None:
    """An ASCII PCD with normals, as PCL writes one (NaN written as ``nan``)."""
    header = (
        "VERSION .7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\n"
        "TYPE F F F F F F\nCOUNT 1 1 1 1 1 1\n"
        f"WIDTH {len(points)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(points)}\n"
        "DATA ascii\n"
    )
    rows = "".join(" ".join(f"{v:.6g}" for v in row) + "\n" for row in np.hstack([points, normals]))
    path.write_text(header + rows)


def test_a_pcd_with_nan_normals_and_one_with_none_usable(tmp_path: Path) -> None:
    points = np.random.default_rng(0).uniform(-0.05, 0.05, (200, 3)) * [1, 1, 0]  # z = 0
    up = np.tile([0.0, 0.0, 1.0], (200, 1))
    some = up.copy()
    some[:50] = np.nan
    write_pcd(path := tmp_path / "plane.pcd", points, some)
    with pytest.warns(ReadNote, match="50 of 200 normals"):
        _, read = read_cloud(path)
    assert read is not None
    np.testing.assert_allclose(read, up, atol=1e-6)
    write_pcd(path, points, np.full((200, 3), np.nan))
    with pytest.warns(ReadNote, match="no normal in the file is usable: estimated"):
        assert read_cloud(path)[1] is None


def test_a_ply_with_zero_normals_is_detected_on_the_command_line(zero_normals_ply, capsys) -> None:
    path, _ = zero_normals_ply
    assert main(["detect", str(path), "--json"]) == 0
    captured = capsys.readouterr()
    report = json.loads(captured.out)
    assert [line for line in captured.err.splitlines() if "normals" in line] == [
        f"note: {report['input']['notes'][0]}"
    ]
    assert report["handles"] and on_handle([report["handles"][0]["center"]]).all()


def test_a_ply_with_zero_normals_is_detected_in_python(zero_normals_ply) -> None:
    path, _ = zero_normals_ply
    with pytest.warns(ReadNote):
        detection = simgrasp.detect_handles(path)
    assert detection.handles and on_handle(detection.handles[0].center[None]).all()
    assert on_handle(detection.candidate_centers).mean() > 0.7


def test_a_mesh_file_is_detected_on_the_command_line(mug_mesh, capsys) -> None:
    assert is_mesh_file(mug_mesh)
    assert main(["detect", str(mug_mesh), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["input"]["mesh"]["points"] == "auto"  # its 9 cm triangles: the surface
    assert report["handles"] and on_handle([report["handles"][0]["center"]]).all()


def test_a_mesh_file_is_detected_in_python_by_surface_or_vertices(mug_mesh) -> None:
    detection = simgrasp.detect_handles(mug_mesh, seed=1)
    assert detection.handles and on_handle(detection.handles[0].center[None]).all()
    surface, _ = read_object_cloud(mug_mesh, seed=1)
    loaded = trimesh.load(mug_mesh, force="mesh", process=False)
    assert isinstance(loaded, trimesh.Trimesh)
    assert abs(len(surface) - loaded.area / MeshReadConfig().spacing ** 2) < 1
    vertices, normals = read_object_cloud(mug_mesh, mesh=MeshReadConfig(points="vertices"))
    np.testing.assert_allclose(vertices, loaded.vertices)
    assert normals is None


def test_a_scanner_ply_with_faces_and_loose_zero_normal_vertices(tmp_path: Path) -> None:
    """A reconstruction (triangles of a few millimetres) whose vertices no face uses carry
    zero normals: read by its vertices (auto), those normals estimated; by its surface, they
    play no part."""
    coarse = trimesh.creation.box([0.1, 0.04, 0.03])
    vertices, faces = trimesh.remesh.subdivide_to_size(coarse.vertices, coarse.faces, 0.004)
    box = trimesh.Trimesh(vertices, faces)  # merged: one normal per corner of the surface
    loose = box.vertices[:4] + 1e-4  # near-duplicates no face uses, as VCG writes them
    points = np.vstack([box.vertices, loose])
    normals = np.vstack([box.vertex_normals, np.zeros((4, 3))])
    path = tmp_path / "scan.ply"
    write_ply(path, points, normals, faces=box.faces)
    assert is_mesh_file(path)
    with pytest.warns(ReadNote, match=f"4 of {len(points)} normals"):
        read, estimated = read_object_cloud(path)
    assert len(read) == len(points) and estimated is not None
    np.testing.assert_allclose(estimated[:-4], box.vertex_normals, atol=1e-6)
    cosine = np.einsum("ij,ij->i", estimated[-4:], box.vertex_normals[:4])
    assert (cosine > 0.5).all(), cosine  # a corner's estimate: one of its faces' planes
    sampled, _ = read_object_cloud(path, mesh=MeshReadConfig(points="surface"))
    assert abs(len(sampled) - box.area / MeshReadConfig().spacing ** 2) < 1


def test_a_millimetre_cloud_names_the_fix_in_the_callers_spelling(mug, tmp_path, capsys) -> None:
    points, _ = mug
    with pytest.raises(SimgraspError, match=r'is it in millimetres\? pass units="mm"'):
        simgrasp.detect_handles(points * 1000.0)
    detection = simgrasp.detect_handles(points * 1000.0, units="mm")
    assert detection.handles and on_handle(detection.handles[0].center[None]).all()
    path = tmp_path / "mug_mm.xyz"
    np.savetxt(path, points * 1000.0)
    with pytest.raises(SimgraspError, match=r'pass units="mm"'):
        simgrasp.detect_handles(path)
    assert main(["detect", str(path)]) == 2
    assert "pass --units mm" in capsys.readouterr().err


def test_a_millimetre_mesh_names_the_fix_in_the_callers_spelling(tmp_path, capsys) -> None:
    path = tmp_path / "big_mug.obj"
    trimesh.creation.box([80.0, 80.0, 95.0]).export(path)
    with pytest.raises(SimgraspError, match=r'name it ".*big_mug.obj\?units=mm"') as error:
        simgrasp.load_object(path)
    assert "--units" not in str(error.value)
    assert main(["object", "show", str(path), "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "pass --units mm (or --scale 0.001)" in err and "?units" not in err


def test_a_flat_mesh_says_one_line_and_no_warning(tmp_path, capsys) -> None:
    path = tmp_path / "flat.obj"
    trimesh.creation.box([0.1, 0.1, 0.0]).export(path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # trimesh's divide-by-zero warning would raise here
        with pytest.raises(SimgraspError, match="zero volume"):
            simgrasp.load_object(path)
    assert main(["object", "show", str(path), "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "zero volume" in err, err


def test_the_toolkinect_scans_are_read_as_given_and_their_labels_fit(real_dir: Path) -> None:
    """Each of the seven ToolKinect reconstructions (zero normals on the vertices no face
    uses) is read by its vertices with a note, and its hand label holds part of it."""
    from simgrasp.labels import load_label_file
    from simgrasp.resources import model_path

    labels = load_label_file(model_path("handles", "toolkinect_handles.json"))
    scans = sorted((real_dir / "toolkinect").glob("*_kinect.ply"))
    assert {scan.stem for scan in scans} == set(labels) and len(scans) == 7
    for scan in scans:
        with pytest.warns(ReadNote, match="normals are NaN, inf or zero length: estimated"):
            points, normals = read_object_cloud(scan)
        assert normals is not None and len(points) == len(normals)
        label = labels[scan.stem]
        inside = label.contains(points).mean()
        assert label.whole_object or 0.2 < inside < 0.95, (scan.stem, inside)


def test_detect_finds_the_hammer_scans_handle_as_given(real_dir: Path, capsys) -> None:
    """docs/results/real-tools, seed 0 of the hammer: read with its zero normals, the top
    handle on its labeled shaft."""
    from simgrasp.labels import load_label_file
    from simgrasp.resources import model_path

    label = load_label_file(model_path("handles", "toolkinect_handles.json"))["hammer_kinect"]
    assert main(["detect", str(real_dir / "toolkinect" / "hammer_kinect.ply"), "--json"]) == 0
    captured = capsys.readouterr()
    assert "note: " in captured.err and "2853 of 5465 normals" in captured.err
    report = json.loads(captured.out)
    assert report["handles"] and label.contains(np.array([report["handles"][0]["center"]])).all()


def test_a_cloud_too_large_for_meters_names_the_units_that_explain_it() -> None:
    """As for meshes, the hint names the first units (millimetres, then centimetres) that make
    the cloud an object: a 15 cm tool in centimetres would be 1.5 cm in millimetres."""
    from simgrasp.perception.units import cloud_in_meters

    tool_cm = np.array([[0.0, 0.0, 0.0], [12.0, 9.0, 0.0]])  # 15 units across
    with pytest.raises(SimgraspError, match=r'in centimetres\? pass units="cm"'):
        cloud_in_meters(tool_cm, "m", "tool")
    np.testing.assert_allclose(cloud_in_meters(tool_cm, "cm", "tool"), tool_cm / 100.0)
    with pytest.raises(SimgraspError, match=r'in millimetres\? pass units="mm"'):
        cloud_in_meters(tool_cm * 10.0, "m", "tool")
