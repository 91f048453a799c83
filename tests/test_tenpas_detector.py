"""The ten Pas & Platt style detector on generated clouds with known handles, on real YCB
meshes, and on degenerate input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from simgrasp.handles import TenPasConfig, detect
from simgrasp.handles.baselines.tenpas_detector import align_shells, detect_tenpas_handles
from simgrasp.handles.core.detection import TIMING_STEPS
from simgrasp.labels import ycb_handle_label

from shapes import hammer_like

TILTED_AXIS = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])


def _cylinder_cloud(radius: float, count: int = 20000) -> np.ndarray:
    """Surface points of a closed 30 cm cylinder of ``radius`` (m) along ``TILTED_AXIS``,
    centered at (0.1, 0.2, 0.3)."""
    mesh = trimesh.creation.cylinder(radius=radius, height=0.3)
    rotation = trimesh.geometry.align_vectors([0, 0, 1], TILTED_AXIS)
    mesh.apply_transform(rotation)
    mesh.apply_translation([0.1, 0.2, 0.3])
    points, _ = trimesh.sample.sample_surface(mesh, count, seed=4)
    return points


def _mug_cloud(density: float = 4e6) -> tuple[np.ndarray, np.ndarray]:
    """A 4 cm-radius open mug body with a bottom and a torus handle (major radius 2.8 cm,
    minor 7 mm, in the x-z plane, only its part beyond x = 4.6 cm); returns the points and
    whether each lies on the handle."""
    wall = trimesh.creation.annulus(r_min=0.037, r_max=0.040, height=0.09)
    wall.apply_translation([0, 0, 0.045])
    bottom = trimesh.creation.cylinder(radius=0.037, height=0.005)
    bottom.apply_translation([0, 0, 0.0025])
    torus = trimesh.creation.torus(major_radius=0.028, minor_radius=0.007)
    torus.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    torus.apply_translation([0.040, 0, 0.045])
    points, on_handle = [], []
    for i, (mesh, is_handle) in enumerate([(wall, False), (bottom, False), (torus, True)]):
        sampled, _ = trimesh.sample.sample_surface(mesh, int(mesh.area * density), seed=i)
        if is_handle:
            sampled = sampled[sampled[:, 0] > 0.046]
        points.append(sampled)
        on_handle.append(np.full(len(sampled), is_handle))
    return np.concatenate(points), np.concatenate(on_handle)


def _on_part(points: np.ndarray, flags: np.ndarray, query: np.ndarray) -> np.ndarray:
    """Whether the cloud point nearest each query point is flagged."""
    _, index = cKDTree(points).query(query)
    return flags[index]


def _angle_degrees(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.degrees(np.arccos(np.clip(abs(a @ b), 0.0, 1.0))))


def test_thin_cylinder_is_one_handle_along_its_axis() -> None:
    points = _cylinder_cloud(0.015)
    detection = detect_tenpas_handles(points, seed=0)
    assert detection.detector == "tenpas"
    assert len(detection.handles) == 1
    handle = detection.handles[0]
    assert _angle_degrees(handle.axis, TILTED_AXIS) < 3.0
    assert handle.width == pytest.approx(0.03, rel=0.2)
    assert 0 < handle.score <= 1
    assert handle.support >= 10
    # the handle center lies on the true axis line
    offset = handle.center - np.array([0.1, 0.2, 0.3])
    assert np.linalg.norm(offset - (offset @ TILTED_AXIS) * TILTED_AXIS) < 0.003
    assert {c.kind for c in detection.candidates} == {"cylinder_shell"}
    widths = np.array([c.width for c in detection.candidates])
    assert np.median(widths) == pytest.approx(0.03, rel=0.1)


def test_wide_cylinder_is_not_a_handle() -> None:
    detection = detect_tenpas_handles(_cylinder_cloud(0.10), seed=0)
    assert detection.neighborhoods > 50
    assert detection.handles == ()


def test_mug_handle_is_found_on_the_torus() -> None:
    points, on_handle = _mug_cloud()
    detection = detect_tenpas_handles(points, seed=1)
    on_torus = _on_part(points, on_handle, np.stack([h.center for h in detection.handles]))
    assert on_torus.any(), "no handle on the torus"
    handle = detection.handles[int(np.argmax(on_torus))]
    assert handle.width == pytest.approx(0.014, rel=0.2)
    # the torus handle's long side is vertical (z) at x = 6.8 cm
    assert _angle_degrees(handle.axis, np.array([0, 0, 1.0])) < 15.0
    # every other handle is the 8 cm body, which the default 8.5 cm gripper can span
    for other, torus in zip(detection.handles, on_torus, strict=True):
        if not torus:
            assert other.width == pytest.approx(0.08, rel=0.05)


def test_mug_handle_is_the_best_handle_for_a_narrower_gripper() -> None:
    points, on_handle = _mug_cloud()
    detection = detect_tenpas_handles(points, config=TenPasConfig(gripper_max_opening=0.06))
    assert detection.handles
    assert _on_part(points, on_handle, detection.handles[0].center[None])[0]
    assert _on_part(points, on_handle, detection.candidate_centers).mean() >= 0.8


def test_hammer_handle_is_found_on_the_handle_part() -> None:
    cloud = hammer_like()
    detection = detect_tenpas_handles(cloud.points, seed=2)
    assert detection.handles
    best = detection.handles[0]
    assert cloud.handle_share(best.center[None]) == 1.0
    assert cloud.handle_share(detection.candidate_centers) >= 0.9
    assert _angle_degrees(best.axis, np.array([1.0, 0, 0])) < 3.0
    assert best.width == pytest.approx(0.03, rel=0.2)


def test_single_view_half_of_the_hammer_still_gives_its_handle_axis() -> None:
    cloud = hammer_like()
    camera = np.array([0.0, 0.0, 0.5])
    visible = np.einsum("ni,ni->n", cloud.normals, camera - cloud.points) > 0
    detection = detect_tenpas_handles(cloud.points[visible], seed=0)
    assert detection.handles
    best = detection.handles[0]
    assert _angle_degrees(best.axis, np.array([1.0, 0, 0])) < 3.0
    assert best.width == pytest.approx(0.03, rel=0.2)
    assert np.hypot(best.center[1], best.center[2]) < 0.003  # on the true axis (y = z = 0)


def _ycb_cloud(ycb_dir: str, object_id: str) -> np.ndarray:
    """20k points sampled on the YCB mesh, in its own (label) frame, meters."""
    mesh = trimesh.load(Path(ycb_dir) / object_id / "google_16k" / "textured.obj", force="mesh")
    points_object, _ = trimesh.sample.sample_surface(mesh, 20000, seed=0)
    return points_object


@pytest.mark.parametrize(
    ("object_id", "handle_width"), [("033_spatula", 0.02), ("048_hammer", 0.034)]
)
def test_ycb_handle_and_most_candidates_lie_in_the_label(
    object_id: str, handle_width: float, ycb_dir: str
) -> None:
    label = ycb_handle_label(object_id)
    assert label.regions, f"no shipped handle label for {object_id}"
    detection = detect_tenpas_handles(_ycb_cloud(ycb_dir, object_id), seed=0)
    assert detection.handles, f"no handle on {object_id}"
    best = detection.handles[0]
    assert label.contains(best.center[None])[0]
    assert best.width == pytest.approx(handle_width, rel=0.25)
    inside = label.contains(detection.candidate_centers)
    assert len(inside) >= 10
    assert inside.mean() >= 0.7, f"{inside.mean():.2f} of the candidates in the handle label"


def test_alignment_chains_only_parallel_close_similar_shells() -> None:
    config = TenPasConfig()  # 20 deg, 6 mm off-line, radius ratio 0.5, 4 cm gap, 3 shells
    along_z = np.tile([0.0, 0.0, 1.0], (6, 1))
    radii = np.full(6, 0.01)
    two_groups = np.array(
        [[0, 0, 0], [0, 0, 0.01], [0, 0, 0.02], [0, 0, 0.2], [0, 0, 0.21], [0, 0, 0.22]]
    )
    handles = align_shells(two_groups, along_z, radii, config)
    assert sorted(h.support for h in handles) == [3, 3]
    assert {round(h.center[2], 3) for h in handles} == {0.01, 0.21}
    assert all(h.width == pytest.approx(0.02) and h.score == pytest.approx(0.5) for h in handles)
    crossed = along_z.copy()
    crossed[1] = [1.0, 0, 0]  # one perpendicular shell leaves only two in the first group
    assert [h.support for h in align_shells(two_groups, crossed, radii, config)] == [3]
    offset = two_groups.copy()
    offset[1] = [0.01, 0, 0.01]  # 1 cm off the others' axis line
    assert [h.support for h in align_shells(offset, along_z, radii, config)] == [3]
    thicker = radii.copy()
    thicker[1] = 0.03  # three times the radius of its neighbors
    assert [h.support for h in align_shells(two_groups, along_z, thicker, config)] == [3]


def test_same_seed_same_result_and_seed_matters() -> None:
    cloud = hammer_like().points
    a, b = detect_tenpas_handles(cloud, seed=5), detect_tenpas_handles(cloud, seed=5)
    assert np.array_equal(a.neighborhood_centers, b.neighborhood_centers)
    assert np.array_equal(a.candidate_centers, b.candidate_centers)
    assert [h.to_json() for h in a.handles] == [h.to_json() for h in b.handles]
    c = detect_tenpas_handles(cloud, seed=6)
    assert not np.array_equal(a.neighborhood_centers, c.neighborhood_centers)


def test_result_moves_with_the_cloud() -> None:
    cloud = hammer_like().points
    shift = np.array([3.0, -2.0, 1.0])
    original = detect_tenpas_handles(cloud, seed=3)
    moved = detect_tenpas_handles(cloud + shift, seed=3)
    assert np.allclose(moved.handles[0].center - shift, original.handles[0].center, atol=2e-3)
    assert np.allclose(moved.handles[0].width, original.handles[0].width, rtol=0.02)


def test_dispatcher_runs_tenpas_and_reports_every_timing_step() -> None:
    detection = detect(hammer_like().points, seed=0, detector="tenpas")
    assert detection.detector == "tenpas"
    assert set(detection.timings_s) == set(TIMING_STEPS)
    assert all(t >= 0 for t in detection.timings_s.values())
    assert detection.to_json()["detector"] == "tenpas"
    with pytest.raises(ValueError, match="QuadricDetectorConfig"):
        detect(hammer_like().points, config=TenPasConfig(), detector="quadric")


def test_nan_empty_and_misshaped_clouds_give_clear_errors() -> None:
    cloud = hammer_like().points.copy()
    cloud[5] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        detect_tenpas_handles(cloud)
    with pytest.raises(ValueError, match="empty"):
        detect_tenpas_handles(np.zeros((0, 3)))
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        detect_tenpas_handles(np.zeros((10, 2)))


def test_tiny_planar_and_line_clouds_give_empty_detections() -> None:
    rng = np.random.default_rng(0)
    tiny = detect_tenpas_handles(rng.normal(size=(5, 3)) * 0.01)
    assert tiny.handles == () and tiny.candidates == ()
    plane = np.column_stack([rng.uniform(-0.1, 0.1, (5000, 2)), np.zeros(5000)])
    flat = detect_tenpas_handles(plane)
    assert flat.neighborhoods > 0
    assert flat.handles == () and flat.candidates == ()
    line = np.outer(np.linspace(0, 0.2, 500), [1.0, 0.0, 0.0])
    assert detect_tenpas_handles(line).handles == ()


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("gripper_max_opening", 0.0, "gripper_max_opening"),
        ("neighborhood_radius", -0.01, "neighborhood_radius"),
        ("finger_clearance", float("nan"), "finger_clearance"),
        ("shell_gap", -0.001, "shell_gap"),
        ("min_radius", 0.05, "min_radius"),
        ("max_shell_fraction", 1.0, "max_shell_fraction"),
        ("align_angle", 2.0, "align_angle"),
        ("min_points", 5, "min_points"),
        ("min_shells", 0, "min_shells"),
        ("neighborhoods", 0, "neighborhoods"),
        ("kind_rtol", 1.5, "kind_rtol"),
        ("voxel_size", "3 mm", "voxel_size"),
    ],
)
def test_config_rejects_bad_values_by_name(field: str, value: object, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        TenPasConfig(**{field: value})  # type: ignore[arg-type]  # a bad value on purpose
