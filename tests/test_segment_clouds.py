"""``simgrasp segment --clouds DIR``: each whole object of a scene as a cloud file with normals."""

from __future__ import annotations

import numpy as np
from test_depth_image import frame as frame  # the module's rendered frame fixture

from simgrasp.cli import main
from simgrasp.perception.camera import depth_to_points_cam
from simgrasp.perception.cloud_io import read_cloud
from simgrasp.perception.scene_cloud import scene_from_array
from simgrasp.perception.segmentation.segment import segment_scene


def test_each_object_is_written_with_normals_toward_the_sensor(frame, tmp_path, capsys):
    points_cam, pixels = depth_to_points_cam(frame.depth, frame.intrinsics)
    grid = np.full((frame.intrinsics.height * frame.intrinsics.width, 3), np.nan)
    grid[pixels] = points_cam
    np.save(tmp_path / "scene.npy", grid.reshape(frame.depth.shape + (3,)))
    out = tmp_path / "objects"
    out.mkdir()
    (out / "object_99.ply").write_bytes(b"left by an earlier run")
    assert main(["segment", str(tmp_path / "scene.npy"), "--clouds", str(out)]) == 0
    capsys.readouterr()
    scene = scene_from_array(grid.reshape(frame.depth.shape + (3,)).astype(np.float32))
    segmentation = segment_scene(scene)
    labels = segmentation.whole_objects()
    assert len(labels) >= 2  # the box and the clutter at least
    assert sorted(p.name for p in out.iterdir()) == sorted(f"object_{k}.ply" for k in labels)
    for label in labels:
        points, normals = read_cloud(out / f"object_{label}.ply")
        expected = scene.points[segmentation.object_mask(label)]
        assert points.shape == expected.shape and np.allclose(points, expected, atol=1e-6)
        assert normals is not None
        toward = np.einsum("ij,ij->i", normals, -points)  # the sensor is at the origin
        assert (toward > 0).all()
