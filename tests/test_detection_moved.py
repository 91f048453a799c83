"""A detection moved into another frame: every position, direction and quadric moves with it,
and moving it back gives the same detection (``Detection.moved``, which scoring against an
object-frame label uses)."""

from __future__ import annotations

import numpy as np

from simgrasp.evaluation.sim_views import SimView, capture
from simgrasp.handles import detect
from simgrasp.handles.detector_config import DetectorConfig
from simgrasp.transforms import pose7_to_matrix


def _moved(points: np.ndarray, a_T_b: np.ndarray) -> np.ndarray:
    return points @ a_T_b[:3, :3].T + a_T_b[:3, 3]


def test_a_detection_moved_there_and_back_is_unchanged() -> None:
    """The rendered hammer's kinect view (single-view detector): moved by a turn and back, its
    candidates (centers, handle points, axes, quadrics up to scale), neighborhood centers,
    worked cloud and handles (centers, traces) are the same; moved once, the top handle's
    center is the moved center and the candidates still lie on their moved quadrics."""
    shot = capture(SimView("gen_hammer", "upright", 0.6, 45.0, "kinect"), 0)
    found = detect(shot.points_cam, None, DetectorConfig().chosen(), 0, viewpoint=np.zeros(3))
    assert found.candidates and found.handles and found.points is not None
    a_T_b = pose7_to_matrix(np.array([0.1, 0.2, 0.3, 0.8, 0.2, -0.5, 0.26]))
    moved = found.moved(a_T_b)
    back = moved.moved(np.linalg.inv(a_T_b).astype(np.float64))
    for before, after in zip(found.candidates, back.candidates, strict=True):
        assert np.allclose(before.center, after.center)
        assert np.allclose(before.handle_point, after.handle_point)
        assert np.allclose(before.axis, after.axis)
        scale = before.quadric.coefficients / np.abs(before.quadric.coefficients).max()
        again = after.quadric.coefficients / np.abs(after.quadric.coefficients).max()
        assert np.allclose(scale, again, atol=1e-6)
    assert np.allclose(back.neighborhood_centers, found.neighborhood_centers)
    assert back.points is not None and np.allclose(back.points, found.points)
    assert np.allclose(back.handles[0].trace, found.handles[0].trace)
    assert np.allclose(moved.handles[0].center, _moved(found.handles[0].center[None], a_T_b)[0])
    on_moved = [float(c.quadric.evaluate(c.center)) for c in moved.candidates]
    on_found = [float(c.quadric.evaluate(c.center)) for c in found.candidates]
    assert np.allclose(on_moved, on_found, atol=1e-9)
