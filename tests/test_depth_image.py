"""Depth images (one sensor frame: a 16-bit PNG of millimetres) as scene and object input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from test_render import build_scene

from simgrasp.cli import main
from simgrasp.perception.camera import depth_to_points_cam
from simgrasp.perception.depth_image import DepthImageConfig, read_depth_image, returned_points
from simgrasp.perception.scene_cloud import read_scene
from simgrasp.scenes.render import DepthFrame, SceneRenderer


@pytest.fixture(scope="module")
def frame() -> DepthFrame:
    """The shared test scene (a box and clutter on a table) seen by one camera, ray cast."""
    model, data = build_scene()
    with SceneRenderer(model, backend="raycast") as renderer:
        return renderer.depth(data, "view0")


def _png(path: Path, depth_m: np.ndarray) -> Path:
    """``depth_m`` written as a sensor writes it: uint16 millimetres, 0 for no return."""
    Image.fromarray(np.round(depth_m * 1000).astype(np.uint16)).save(path)
    return path


def _intrinsics(frame: DepthFrame) -> list[str]:
    k = frame.intrinsics
    return [str(v) for v in (k.fx, k.fy, k.cx, k.cy)]


def _intrinsic_values(frame: DepthFrame) -> tuple[float, float, float, float]:
    """fx, fy, cx, cy (px) as the command line reads them from :func:`_intrinsics`."""
    fx, fy, cx, cy = map(float, _intrinsics(frame))
    return fx, fy, cx, cy


def test_a_png_frame_back_projects_as_the_renderer_camera_does(frame, tmp_path):
    png = _png(tmp_path / "depth.png", frame.depth)
    k = frame.intrinsics
    config = DepthImageConfig(intrinsics=(k.fx, k.fy, k.cx, k.cy))
    grid = read_depth_image(png, config)
    assert grid.shape == (k.height, k.width, 3)
    quantized = np.round(frame.depth * 1000) / 1000
    expected, pixels = depth_to_points_cam(quantized, k)
    flat = grid.reshape(-1, 3)
    assert np.array_equal(np.flatnonzero(np.isfinite(flat).all(axis=1)), pixels)  # NaN: none
    assert np.allclose(flat[pixels], expected, atol=1e-6)
    assert np.array_equal(returned_points(grid), flat[pixels])
    scene = read_scene(png, config)  # the organized scene cloud, the sensor at the origin
    assert (scene.width, scene.height) == (k.width, k.height)
    assert scene.organized and np.allclose(scene.viewpoint, 0.0)
    assert np.array_equal(scene.grid(), grid, equal_nan=True)


def test_segment_reads_a_png_frame_as_its_organized_cloud(frame, tmp_path, capsys):
    png = _png(tmp_path / "depth.png", frame.depth)
    grid = read_scene(png, DepthImageConfig(intrinsics=_intrinsic_values(frame)))
    np.save(tmp_path / "cloud.npy", grid.grid())
    args = ["--labels"]
    assert main(["segment", str(png), "--depth.intrinsics", *_intrinsics(frame), *args,
                 str(tmp_path / "png.npy")]) == 0  # fmt: skip
    assert main(["segment", str(tmp_path / "cloud.npy"), *args, str(tmp_path / "npy.npy")]) == 0
    from_png, from_npy = np.load(tmp_path / "png.npy"), np.load(tmp_path / "npy.npy")
    assert np.array_equal(from_png, from_npy)
    assert from_png.max() >= 3  # the table (1) and at least the box and the clutter
    capsys.readouterr()
    import simgrasp

    depth = simgrasp.DepthImageConfig(intrinsics=_intrinsic_values(frame))
    assert np.array_equal(simgrasp.segment_scene(png, depth=depth).labels, from_png)
    assert np.array_equal(simgrasp.segment_scene(grid.grid()).labels, from_png)


def test_detect_takes_a_cut_object_frame_and_records_how_to_read_it(frame, tmp_path, capsys):
    box = frame.geom_ids == 1  # the object box: the table is geom 0
    depth = np.where(box, frame.depth, 0.0)
    png = _png(tmp_path / "box.png", depth)
    assert main(["detect", str(png), "--depth.intrinsics", *_intrinsics(frame), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["input"]["depth"]["intrinsics"] == [float(v) for v in _intrinsics(frame)]
    assert report["neighborhoods"] > 0
    (tmp_path / "d.json").write_text(json.dumps(report))
    assert main(["view", str(tmp_path / "d.json"), "--export", str(tmp_path / "p.html")]) == 0
    assert (tmp_path / "p.html").stat().st_size > 10_000
    assert "holds a table" not in capsys.readouterr().err  # a cut object: no note


def test_detect_notes_a_whole_scene_given_without_segment(frame, tmp_path, capsys):
    """The whole frame, table and all, is detected as one object as asked, with one note on
    stderr that --segment cuts its objects; the JSON on stdout stays one object."""
    png = _png(tmp_path / "scene.png", frame.depth)
    assert main(["detect", str(png), "--depth.intrinsics", *_intrinsics(frame), "--json"]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out)["input"]["path"] == str(png.resolve())
    notes = [line for line in err.splitlines() if "holds a table" in line]
    assert len(notes) == 1 and "pass --segment" in notes[0] and str(png) in notes[0], err


@pytest.mark.parametrize("case", ["no_intrinsics", "colour", "not_an_image", "scale", "units"])
def test_a_bad_depth_image_is_one_line(case, frame, tmp_path, capsys):
    png = _png(tmp_path / "depth.png", frame.depth)
    command, expected = ["segment", str(png), "--depth.intrinsics", *_intrinsics(frame)], ""
    if case == "no_intrinsics":
        command, expected = ["segment", str(png)], "needs its camera's intrinsics"
    elif case == "colour":
        Image.new("RGB", (8, 6)).save(png)
        expected = "has one channel"
    elif case == "not_an_image":
        png.write_bytes(b"not a png")
        expected = "not a readable depth image"
    elif case == "scale":
        command += ["--depth.scale", "1"]  # millimetres read as meters
        expected = "is the scale right"
    else:
        command = ["detect", *command[1:], "--units", "mm"]
        expected = "units are set by --depth.scale"
    assert main(command) == 2
    err = capsys.readouterr().err
    assert expected in err and len(err.strip().splitlines()) == 1, err


def _image_manifest(tmp_path: Path, frame: DepthFrame, extra: str) -> Path:
    """A one-entry ``detect-eval --real`` manifest of the frame as a PNG, its label a box
    around the object box's points."""
    png = _png(tmp_path / "depth.png", frame.depth)
    points_cam, pixels = depth_to_points_cam(np.round(frame.depth * 1000) / 1000, frame.intrinsics)
    box = points_cam[frame.geom_ids.ravel()[pixels] == 1]
    region = {"type": "box", "center": box.mean(axis=0).tolist(), "half_extents": [0.02] * 3}
    labels = {"objects": {"box": {"whole_object": False, "regions": [region]}}}
    (tmp_path / "labels.json").write_text(json.dumps(labels))
    manifest = tmp_path / "manifest.toml"
    manifest.write_text(
        f'[[cloud]]\nname = "box"\ndataset = "rendered"\nsplit = "tune"\npath = "{png}"\n'
        f'labels = "labels.json"\nviewpoint = [0.0, 0.0, 0.0]\n{extra}'
    )
    return manifest


def test_a_manifest_entry_may_be_a_depth_image(frame, tmp_path):
    from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest

    k = frame.intrinsics
    manifest = _image_manifest(tmp_path, frame, f"intrinsics = [{', '.join(_intrinsics(frame))}]\n")
    (cloud,) = read_manifest(manifest)
    assert cloud.depth.intrinsics == (k.fx, k.fy, k.cx, k.cy)
    points = load_real_cloud(cloud)
    expected, _ = depth_to_points_cam(np.round(frame.depth * 1000) / 1000, k)
    assert points.shape == expected.shape and np.allclose(points, expected, atol=1e-6)


@pytest.mark.parametrize(
    ("extra", "problem"),
    [
        ("intrinsics = [1.0, 2.0]\n", "'intrinsics' must be numbers of shape (4,)"),
        ("intrinsics = [0.0, 500.0, 320.0, 240.0]\n", "focal lengths must be positive"),
        ("depth_scale = -1\n", "'depth_scale' must be a positive number"),
        ('units = "mm"\n', "a depth image's units are its 'depth_scale'"),
    ],
)
def test_bad_depth_image_entries_are_one_line(frame, tmp_path, capsys, extra, problem):
    manifest = _image_manifest(tmp_path, frame, extra)
    assert main(["detect-eval", "--real", str(manifest), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "cloud box" in err and problem in err and len(err.strip().splitlines()) == 1, err


def test_depth_image_keys_on_a_cloud_file_are_one_line(tmp_path):
    from simgrasp.errors import SimgraspError
    from simgrasp.evaluation.real_manifest import read_manifest

    (tmp_path / "labels.json").write_text(json.dumps({"objects": {"c": {"regions": []}}}))
    manifest = tmp_path / "m.toml"
    manifest.write_text(
        '[[cloud]]\nname = "c"\ndataset = "d"\nsplit = "tune"\npath = "c.pcd"\n'
        'labels = "labels.json"\nviewpoint = [0.0, 0.0, 0.0]\ndepth_scale = 0.001\n'
    )
    with pytest.raises(SimgraspError, match="'depth_scale' is for a depth image"):
        read_manifest(manifest, tmp_path)
