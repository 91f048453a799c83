"""The YCB loader on the real download (SIMGRASP_YCB_DIR) and on broken copies in tmp_path."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from simgrasp.assets.mesh_check import MeshError
from simgrasp.assets.ycb import (
    available_ycb_objects,
    load_ycb_object,
    resolve_ycb_root,
    ycb_mesh_path,
)
from simgrasp.assets.ycb_catalog import find_ycb_entry

# The 20 objects of the shared test download.
SHARED_OBJECTS = [
    "001_chips_can",
    "003_cracker_box",
    "005_tomato_soup_can",
    "006_mustard_bottle",
    "011_banana",
    "014_lemon",
    "019_pitcher_base",
    "022_windex_bottle",
    "025_mug",
    "030_fork",
    "031_spoon",
    "032_knife",
    "033_spatula",
    "035_power_drill",
    "037_scissors",
    "042_adjustable_wrench",
    "043_phillips_screwdriver",
    "044_flat_screwdriver",
    "048_hammer",
    "050_medium_clamp",
]


def test_available_objects(ycb_dir: str) -> None:
    assert available_ycb_objects(ycb_dir) == SHARED_OBJECTS


@pytest.mark.parametrize("object_id", SHARED_OBJECTS)
def test_every_object_loads_in_meters(object_id: str, ycb_dir: str) -> None:
    asset = load_ycb_object(object_id, ycb_dir=ycb_dir)
    assert asset.name == object_id
    assert asset.source == "ycb"
    assert asset.mass == find_ycb_entry(object_id).mass_kg
    extents = asset.mesh.extents
    # Hand-held household objects: largest side 5-35 cm, smallest side at least 1 cm.
    assert 0.05 < extents.max() < 0.35, extents
    assert extents.min() > 0.01, extents
    # Resting near z = 0 in the scan frame.
    assert abs(asset.mesh.bounds[0, 2]) < 0.01
    assert len(asset.mesh.faces) > 10_000
    assert np.isfinite(asset.mesh.vertices).all()
    assert asset.mesh_file is not None and asset.mesh_file.is_file()
    assert asset.handle.object_name == object_id


def test_google_scan_with_jpg_texture_and_trailing_space_mtl(ycb_dir: str) -> None:
    mtl = Path(ycb_dir) / "025_mug" / "google_16k" / "textured.mtl"
    assert "texture_map.jpg \n" in mtl.read_text()  # the quirk this test is about
    asset = load_ycb_object("mug", ycb_dir=ycb_dir)
    assert asset.mesh_file == Path(ycb_dir) / "025_mug" / "google_16k" / "textured.obj"
    assert asset.texture_file == Path(ycb_dir) / "025_mug" / "google_16k" / "texture_map.jpg"
    assert asset.mass == pytest.approx(0.118)


def test_chips_can_falls_back_to_poisson(ycb_dir: str) -> None:
    asset = load_ycb_object("chips_can", ycb_dir=ycb_dir)
    assert asset.mesh_file == Path(ycb_dir) / "001_chips_can" / "poisson" / "nontextured.stl"
    assert asset.texture_file is None
    assert asset.mass == pytest.approx(0.205)
    assert asset.mesh.extents[2] == pytest.approx(0.245, abs=0.01)


def test_root_from_environment(ycb_dir: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SIMGRASP_YCB_DIR", ycb_dir)
    assert resolve_ycb_root() == Path(ycb_dir)
    assert load_ycb_object("hammer").mass == pytest.approx(0.665)


def test_no_root_tells_user_what_to_do(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("SIMGRASP_YCB_DIR", raising=False)
    with pytest.raises(FileNotFoundError, match=r"SIMGRASP_YCB_DIR.*simgrasp fetch-ycb"):
        resolve_ycb_root()


def test_root_that_does_not_exist(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"YCB folder .*nowhere does not exist"):
        resolve_ycb_root(tmp_path / "nowhere")


def test_object_not_downloaded(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"'048_hammer' is not in .*fetch-ycb"):
        load_ycb_object("hammer", ycb_dir=tmp_path)


def test_unknown_object_name(ycb_dir: str) -> None:
    with pytest.raises(ValueError, match=r"did you mean 048_hammer"):
        load_ycb_object("hamer", ycb_dir=ycb_dir)


def test_part_without_published_mass_needs_explicit_mass(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"'065-a_cups' has no published mass"):
        load_ycb_object("065-a_cups", ycb_dir=tmp_path)


def test_object_folder_without_mesh(tmp_path: Path) -> None:
    (tmp_path / "025_mug" / "google_16k").mkdir(parents=True)
    with pytest.raises(FileNotFoundError, match=r"'025_mug' .* has no mesh file"):
        ycb_mesh_path(tmp_path, "025_mug")


def test_png_texture_and_missing_mtl(ycb_dir: str, tmp_path: Path) -> None:
    scan = tmp_path / "025_mug" / "google_16k"
    scan.mkdir(parents=True)
    shutil.copy(Path(ycb_dir) / "025_mug" / "google_16k" / "textured.obj", scan)
    (scan / "texture_map.png").write_bytes(b"not decoded")
    mesh_path, texture_path = ycb_mesh_path(tmp_path, "025_mug")
    assert mesh_path == scan / "textured.obj"
    assert texture_path == scan / "texture_map.png"


def test_millimetre_copy_is_rejected_naming_object_and_file(ycb_dir: str, tmp_path: Path) -> None:
    source = Path(ycb_dir) / "030_fork" / "google_16k" / "textured.obj"
    lines = []
    for line in source.read_text().splitlines():
        if line.startswith("v "):
            x, y, z = (float(t) * 1000.0 for t in line.split()[1:4])
            line = f"v {x} {y} {z}"
        lines.append(line)
    scan = tmp_path / "030_fork" / "google_16k"
    scan.mkdir(parents=True)
    (scan / "textured.obj").write_text("\n".join(lines))
    with pytest.raises(MeshError, match=r"'030_fork'.*textured\.obj.*millimetres"):
        load_ycb_object("fork", ycb_dir=tmp_path)
