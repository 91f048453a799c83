"""Mesh checks on bad meshes written into tmp_path, and on a real open YCB scan."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from simgrasp.assets.mesh_check import (
    MeshError,
    load_mesh_file,
    mass_properties_solid,
    mesh_report,
    validate_mesh,
)


def _write_box(path: Path, scale: float = 1.0) -> Path:
    box = trimesh.creation.box(extents=(0.1, 0.05, 0.02))
    box.apply_scale(scale)
    box.export(path)
    return path


def test_good_box_loads_watertight_with_own_volume(tmp_path: Path) -> None:
    mesh = load_mesh_file(_write_box(tmp_path / "box.obj"), "box")
    report = mesh_report(mesh, "box", tmp_path / "box.obj")
    assert report.watertight
    assert report.volume_from == "mesh"
    assert report.warnings == ()
    np.testing.assert_allclose(sorted(report.extents), [0.02, 0.05, 0.1], atol=1e-9)
    solid, _ = mass_properties_solid(mesh)
    assert solid.volume == pytest.approx(0.1 * 0.05 * 0.02)


def test_inside_out_box_is_turned_outward(tmp_path: Path) -> None:
    box = trimesh.creation.box(extents=(0.1, 0.05, 0.02))
    box.invert()
    assert box.volume < 0
    box.export(tmp_path / "inverted.obj")
    mesh = load_mesh_file(tmp_path / "inverted.obj", "box")
    assert mesh.volume == pytest.approx(0.1 * 0.05 * 0.02)
    # Outward faces: each face normal points away from the box center.
    assert np.all(np.einsum("ij,ij->i", mesh.face_normals, mesh.triangles_center) > 0)


def test_missing_file_names_object_and_file(tmp_path: Path) -> None:
    path = tmp_path / "nope" / "textured.obj"
    with pytest.raises(MeshError, match=r"'mugx'.*nope/textured\.obj.*does not exist"):
        load_mesh_file(path, "mugx")


@pytest.mark.parametrize(
    ("filename", "content"),
    [
        ("empty.obj", ""),
        ("vertices_only.obj", "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\n"),
        ("empty.stl", "solid x\nendsolid x\n"),
    ],
)
def test_empty_mesh_rejected(tmp_path: Path, filename: str, content: str) -> None:
    path = tmp_path / filename
    path.write_text(content)
    with pytest.raises(MeshError, match=rf"'thing'.*{filename}.*empty \(no faces\)"):
        load_mesh_file(path, "thing")


def test_unreadable_file_rejected(tmp_path: Path) -> None:
    path = tmp_path / "mesh.ply"
    path.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 99\n\x00\x01garbage")
    with pytest.raises(MeshError, match=r"'thing'.*mesh\.ply.*cannot read mesh"):
        load_mesh_file(path, "thing")


def test_nan_vertices_rejected(tmp_path: Path) -> None:
    path = tmp_path / "nan.obj"
    path.write_text("v 0 0 0\nv nan 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 2 3\nf 1 3 4\n")
    with pytest.raises(MeshError, match=r"'thing'.*nan\.obj.*1 of 4 vertices are NaN"):
        load_mesh_file(path, "thing")


def test_millimetre_units_rejected_with_advice(tmp_path: Path) -> None:
    path = _write_box(tmp_path / "mm.stl", scale=1000.0)
    with pytest.raises(MeshError, match=r"'thing'.*mm\.stl.*millimetres; scale by 0\.001"):
        load_mesh_file(path, "thing")


def test_tiny_mesh_rejected(tmp_path: Path) -> None:
    path = _write_box(tmp_path / "tiny.stl", scale=0.001)
    with pytest.raises(MeshError, match=r"implausibly small"):
        load_mesh_file(path, "thing")


def test_validate_mesh_rejects_in_memory_nan_without_file() -> None:
    mesh = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    vertices = mesh.vertices.copy()
    vertices[0, 2] = np.inf
    bad = trimesh.Trimesh(vertices, mesh.faces, process=False)
    with pytest.raises(MeshError, match=r"^object 'cube': 1 of 8 vertices"):
        validate_mesh(bad, "cube")


def test_non_manifold_mesh_loads_and_is_reported(tmp_path: Path) -> None:
    # A closed box plus a fin: a third triangle on one of the box's edges.
    box = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    edge = box.edges_unique[0]
    fin_tip = box.vertices[edge].mean(axis=0) + np.array([0.0, 0.0, 0.3])
    vertices = np.vstack([box.vertices, fin_tip])
    faces = np.vstack([box.faces, [edge[0], edge[1], len(box.vertices)]])
    path = tmp_path / "fin.ply"
    trimesh.Trimesh(vertices, faces, process=False).export(path)

    mesh = load_mesh_file(path, "fin")
    report = mesh_report(mesh, "fin", path)
    assert report.non_manifold_edges == 1
    assert report.boundary_edges == 2  # the fin's two free edges
    assert not report.watertight
    assert report.volume_from == "convex_hull"
    assert any("non-manifold" in w for w in report.warnings)
    solid, _ = mass_properties_solid(mesh)
    assert solid.is_volume
    assert solid.volume > 0.1**3  # the hull includes the fin


def test_open_mesh_uses_hull_for_mass_properties() -> None:
    box = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-2], process=False)
    report = mesh_report(open_box, "open")
    assert report.boundary_edges == 4
    assert report.volume_from == "convex_hull"
    solid, source = mass_properties_solid(open_box)
    assert source == "convex_hull"
    assert solid.volume == pytest.approx(1e-3)


def test_chips_can_scan_is_imperfect_but_loads(ycb_dir: str) -> None:
    path = Path(ycb_dir) / "001_chips_can" / "poisson" / "nontextured.stl"
    mesh = load_mesh_file(path, "001_chips_can")
    report = mesh_report(mesh, "001_chips_can", path)
    assert not report.watertight
    assert report.volume_from == "convex_hull"
    solid, _ = mass_properties_solid(mesh)
    # A can of about 7.5 cm diameter and 25 cm height: ~1.1 l.
    assert 0.8e-3 < solid.volume < 1.4e-3
    # The scan is wound inside out; loading turns it outward (else a renderer culling back
    # faces shows the far inner wall and the camera cloud's normals point into the can).
    assert mesh.volume > 0.8e-3
