"""`simgrasp object show|export`: a picture with hulls and handle, a standalone MJCF."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest
from PIL import Image

from simgrasp.cli import main


def test_show_renders_object_hulls_and_red_handle(tmp_path: Path) -> None:
    # a fresh process: MuJoCo picks its GL platform (EGL here) when first imported
    out = tmp_path / "hammer.png"
    command = [sys.executable, "-m", "simgrasp", "object", "show", "gen_hammer", "--seed", "2"]
    env = {k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}
    done = subprocess.run(
        [*command, "--out", str(out), "--size", "96"], env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    assert "gen_hammer_s2" in done.stdout
    image = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert image.shape == (96, 192, 3)
    left, right = image[:, :96], image[:, 96:]
    for panel in (left, right):
        assert (panel.sum(axis=2) > 60).mean() > 0.01, "the object is not visible"
        red = (panel[..., 0] > 1.5 * panel[..., 1]) & (panel[..., 0] > 80)
        assert red.mean() > 0.002, "the handle label is not drawn"
    assert not np.array_equal(left, right), "hull view should differ from the visual view"


def test_export_writes_a_loadable_standalone_mjcf(tmp_path: Path) -> None:
    out = tmp_path / "export"
    assert main(["object", "export", "gen_mug_s1", "--out", str(out)]) == 0
    xml = out / "gen_mug_s1.xml"
    assert "meshdir" not in xml.read_text()
    model = mujoco.MjModel.from_xml_path(str(xml))
    assert model.body("gen_mug_s1").mass[0] > 0.1
    assert model.nmesh == len(list(out.glob("*.stl")))
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, 200)
    assert np.all(np.isfinite(data.qpos))


def test_export_ycb_object_with_texture(tmp_path: Path, ycb_dir: str) -> None:
    out = tmp_path / "spatula"
    assert main(["object", "export", "033_spatula", "--ycb-dir", ycb_dir, "--out", str(out)]) == 0
    model = mujoco.MjModel.from_xml_path(str(out / "033_spatula.xml"))
    assert model.ntex == 1 and model.nmeshtexcoord > 0
    assert (out / "033_spatula_texture.png").is_file()


def test_unknown_object_is_a_clear_error(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    assert main(["object", "show", "gen_teapot", "--out", str(tmp_path / "x.png")]) == 2
    assert "gen_teapot" in capsys.readouterr().err
    assert main(["object", "show", "gen_mug", "--out", str(tmp_path / "x.jpg")]) == 2
    assert ".png" in capsys.readouterr().err
