"""Scene clouds: reading keeps every point in order, segmentation against real labels, and
bad scenes give one clear line (or an empty result), never a traceback."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from simgrasp.assets.real import default_real_dir
from simgrasp.cli import main
from simgrasp.evaluation.segment_eval import part_ious, score_scene
from simgrasp.perception._arrays import import_open3d
from simgrasp.perception.scene_cloud import read_scene, scene_from_array
from simgrasp.perception.segmentation.organized_segments import _closed_cuts
from simgrasp.perception.segmentation.segment import segment_scene
from simgrasp.perception.segmentation.segment_config import FIRST_OBJECT, SegmentConfig
from simgrasp.perception.segmentation.segment_fragments import absorb_fragments
from simgrasp.perception.segmentation.segment_objects import LabelPixels, label_pixels
from simgrasp.perception.segmentation.segment_parts import part_parents, table_edge_claims
from simgrasp.perception.segmentation.segment_scale import pixel_footprint, pixel_scale, scaled

OSD = default_real_dir() / "osd-learn"
needs_osd = pytest.mark.real  # skipped without the scenes (tests/data_needs.py)
FOCAL, WIDTH, HEIGHT = 525.0, 640, 480


def _rays() -> np.ndarray:
    """(H, W, 3) pinhole ray directions (z = 1), OpenCV axes."""
    cols, rows = np.meshgrid(np.arange(WIDTH), np.arange(HEIGHT))
    return np.stack(
        [(cols - 319.5) / FOCAL, (rows - 239.5) / FOCAL, np.ones((HEIGHT, WIDTH))], axis=2
    )


def tabletop(sphere_radii: tuple[float, ...] = (0.05, 0.04)) -> np.ndarray:
    """An organized (H, W, 3) scene (m): a 0.8 m square table 0.6 m under the camera, seen
    40 degrees down, with spheres of the given radii resting on it 0.15 m apart; NaN where
    a ray hits nothing."""
    rays = _rays()
    up = np.array([0.0, -np.cos(np.radians(50)), -np.sin(np.radians(50))])  # table normal
    center = np.array([0.0, 0.0, -0.6 / up[2]])  # where the optical axis meets the table
    depth = -0.6 / (rays @ up)
    on_table = (np.abs(depth[..., None] * rays - center) < 0.4).all(axis=2) & (depth > 0)
    depth = np.where(on_table, depth, np.inf)
    squared = (rays * rays).sum(axis=2)
    for k, radius in enumerate(sphere_radii):
        middle = center + [0.15 * (k - (len(sphere_radii) - 1) / 2), 0.0, 0.0] + radius * up
        b = rays @ middle
        disc = b * b - squared * (middle @ middle - radius * radius)
        t = (b - np.sqrt(np.maximum(disc, 0.0))) / squared
        depth = np.where((disc > 0) & (t < depth), t, depth)
    points = depth[..., None] * rays
    points[~np.isfinite(depth)] = np.nan
    return points


def _object_pixels(labels: np.ndarray) -> LabelPixels:
    """The object pixels (labels >= 2) of a label image grouped by label, as the segmenter
    hands them to its side-part step."""
    flat = labels.reshape(-1)
    index = np.flatnonzero(flat >= FIRST_OBJECT)
    return label_pixels(flat[index], index, int(flat.max()) + 1)


def _save_npy(tmp_path: Path, points: np.ndarray, name: str = "scene.npy") -> Path:
    path = tmp_path / name
    np.save(path, points)
    return path


def test_synthetic_tabletop_gives_two_objects_nearest_first(tmp_path: Path) -> None:
    grid = tabletop()
    scene = read_scene(_save_npy(tmp_path, grid))
    assert scene.organized and (scene.width, scene.height) == (WIDTH, HEIGHT)
    result = segment_scene(scene)
    assert result.labels.dtype == np.int32 and result.labels.shape == (WIDTH * HEIGHT,)
    assert (result.labels[~scene.valid] == 0).all()
    assert [obj.label for obj in result.objects] == [2, 3]
    distances = [np.linalg.norm(obj.center) for obj in result.objects]
    assert distances == sorted(distances)
    diameters = sorted(float(obj.extent.max()) for obj in result.objects)
    assert diameters == pytest.approx([0.08, 0.10], abs=0.01)
    assert result.plane[3] == pytest.approx(0.6, abs=0.005)  # camera 0.6 m above the table


def test_binned_normals_find_the_same_objects(tmp_path: Path) -> None:
    scene = read_scene(_save_npy(tmp_path, tabletop()))
    config = SegmentConfig(normal_bin_px=2, normal_window_px=3, normal_step_px=1, concave_step_px=2)
    full, binned = segment_scene(scene), segment_scene(scene, config)
    assert len(binned.objects) == 2
    for a, b in zip(full.objects, binned.objects, strict=True):
        assert abs(a.points - b.points) < 0.02 * a.points


def test_the_pixel_footprint_sets_the_scale_of_the_pixel_settings(tmp_path: Path) -> None:
    """A pixel of the tabletop covers about its median range / focal length (less off the
    optical axis, where neighbouring rays are closer in angle); a frame twice as fine
    as the reference runs at scale 2 (blocks, reaches x 2, counts x 4), one under 1.5 times
    as fine or coarser as given, and a reference of 0 turns it off."""
    scene = read_scene(_save_npy(tmp_path, tabletop()))
    ranges = np.linalg.norm(scene.points[scene.valid], axis=1)
    footprint = pixel_footprint(scene, scene.valid)
    assert footprint == pytest.approx(np.median(ranges) / FOCAL, rel=0.1)
    assert [pixel_scale(f, 0.0014) for f in (0.0007, 0.00094, 0.00093, 0.002)] == [2, 1, 2, 1]
    assert pixel_scale(0.0007, 0.0) == pixel_scale(float("nan"), 0.0014) == 1
    config = SegmentConfig()
    assert scaled(config, 1) is config
    double = scaled(config, 2)
    assert (double.normal_bin_px, double.attach_radius_px) == (2, 2 * config.attach_radius_px)
    assert double.min_object_points == 4 * config.min_object_points
    assert double.normal_window_px == config.normal_window_px  # in blocks: twice the pixels
    assert segment_scene(scene).pixel_scale == 1  # 1.3 mm a pixel here


@needs_osd
def test_osd_learn_runs_at_the_scale_its_settings_were_chosen_at() -> None:
    """osd-learn's pixels cover 1.3 - 1.6 mm: scale 1, the labels those without scaling."""
    scene = read_scene(OSD / "learn10.pcd")
    result = segment_scene(scene)
    assert result.pixel_scale == 1
    unscaled = segment_scene(scene, SegmentConfig(reference_footprint=0.0))
    assert np.array_equal(result.labels, unscaled.labels)


def test_unorganized_ply_keeps_order_and_clusters(tmp_path: Path) -> None:
    points = tabletop().reshape(-1, 3)
    keep = np.isfinite(points).all(axis=1)
    o3d = import_open3d()
    path = tmp_path / "scene.ply"
    o3d.t.io.write_point_cloud(str(path), o3d.t.geometry.PointCloud(points[keep]))
    scene = read_scene(path)
    assert not scene.organized
    np.testing.assert_allclose(scene.points, points[keep], atol=1e-6)
    result = segment_scene(scene)
    assert len(result.objects) == 2


def test_part_ious_scores_each_part_by_its_best_object() -> None:
    truth = np.array([0, 1, 20, 20, 20, 20, 30, 30, 31])
    predicted = np.array([0, 1, 2, 2, 2, 3, 3, 3, 0])
    np.testing.assert_allclose(part_ious(truth, predicted), [0.75, 2 / 3, 0.0])


@needs_osd
def test_read_scene_keeps_the_organized_grid_and_viewpoint() -> None:
    scene = read_scene(OSD / "learn0.pcd")
    assert (scene.width, scene.height) == (640, 480) and len(scene.points) == 307200
    np.testing.assert_array_equal(scene.viewpoint, [0.0, 0.0, 0.0])
    assert scene.labels is not None
    assert (scene.labels[~scene.valid] == 0).all() and (scene.labels[scene.valid] > 0).all()
    grid = scene.grid()
    rows, cols = np.nonzero(np.isfinite(grid[..., 2]))
    u = grid[rows, cols, 0] / grid[rows, cols, 2] * FOCAL + 319.5  # pixel column from x / z
    np.testing.assert_allclose(u, cols, atol=0.6)


@needs_osd
@pytest.mark.parametrize("name", ["learn17", "learn30", "learn43"])
def test_osd_scene_matches_its_labels(name: str) -> None:
    scene = read_scene(OSD / f"{name}.pcd")
    result = segment_scene(scene)
    assert scene.labels is not None
    ious = part_ious(scene.labels, result.labels)
    assert ious.min() >= 0.8, ious
    table = scene.labels[(result.labels == 1)]
    assert np.mean((table >= 1) & (table < 10)) > 0.99


def test_closing_the_cuts_bridges_a_one_pixel_gap_and_the_outline() -> None:
    """A cut band three pixels wide (a concave cut spans its step + 1 pixels) with a
    one-pixel gap, ending a pixel short of the candidates' outline, splits them once closed
    (``cut_close_px`` 1); a gap of three pixels stays open."""
    kept = np.zeros((20, 30), dtype=bool)
    kept[2:18, 2:28] = True
    cut = np.zeros_like(kept)
    cut[3:18, 13:16] = True  # from a pixel below the top edge (row 2) to the bottom one (17)
    cut[9] = False  # a one-pixel gap
    closed = _closed_cuts(cut, kept, 1)
    assert ndimage.label(kept & ~cut)[1] == 1
    assert ndimage.label(kept & ~closed)[1] == 2
    assert not (closed & ~kept).any() and closed[cut].all()
    cut[8:11] = False  # a three-pixel gap
    assert ndimage.label(kept & ~_closed_cuts(cut, kept, 1))[1] == 1


@needs_osd
def test_a_box_lying_across_another_is_two_objects() -> None:
    """learn25: a cereal box lies across another; their concave crease is traced with
    one-pixel gaps and ends a pixel short of the outline, so the traced cuts leave the two
    boxes one segment. Closing the cuts' gaps (``cut_close_px``) separates them."""
    scene = read_scene(OSD / "learn25.pcd")
    assert scene.labels is not None
    traced = part_ious(scene.labels, segment_scene(scene, SegmentConfig(cut_close_px=0)).labels)
    closed = part_ious(scene.labels, segment_scene(scene, SegmentConfig(cut_close_px=1)).labels)
    assert traced.max() < 0.6, traced
    assert closed.min() > 0.9, closed


@needs_osd
def test_detect_segment_on_a_real_pot_scene(capsys: pytest.CaptureFixture[str]) -> None:
    path = str(OSD / "learn40.pcd")
    assert main(["detect", path, "--segment", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    objects = {obj["label"]: obj for obj in report["segmentation"]["objects"]}
    assert report["handles"] and report["viewpoint"] == [0.0, 0.0, 0.0]
    for handle in report["handles"]:
        obj = objects[handle["object"]]
        low = np.subtract(obj["center"], obj["extent"]) - 0.02
        high = np.add(obj["center"], obj["extent"]) + 0.02
        assert (low <= handle["center"]).all() and (handle["center"] <= high).all()
    whole = {obj["label"] for obj in objects.values() if obj["part_of"] == obj["label"]}
    assert {h["object"] for h in report["handles"]} <= whole  # parts go with their object
    first = report["handles"][0]["object"]
    assert main(["detect", path, "--segment", "--object", str(first), "--json"]) == 0
    only = json.loads(capsys.readouterr().out)
    assert {h["object"] for h in only["handles"]} == {first}


def _pixel_grid(labels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(H, W, 3) float32 points of a flat grid 1 m from the sensor, 2 mm a pixel, the pixels
    of label 4 pushed 20 cm back (touching the others in the image only), and each pixel's
    row index."""
    height, width = labels.shape
    cols, rows = np.meshgrid(np.arange(width), np.arange(height))
    points = np.stack([cols * 0.002, rows * 0.002, np.ones(labels.shape)], axis=2)
    points[labels == 4, 2] += 0.2
    return points.astype(np.float32), rows


def test_thin_small_segments_touching_a_larger_one_are_its_parts() -> None:
    """A 40 x 40 px object (2), a thin tab touching it (3), a thin tab 20 cm behind it in
    depth (4: touching in the image only), a tall small segment touching it (5), and a thin
    tab touching only tab 3 (6: a part of a part is a part of the whole)."""
    labels = np.zeros((60, 80), dtype=np.int32)
    labels[10:50, 10:50] = 2
    labels[20:30, 50:58] = 3
    labels[20:30, 2:10] = 4
    labels[50:58, 20:30] = 5
    labels[30:34, 50:58] = 6
    points, rows = _pixel_grid(labels)
    height = np.where(labels == 2, rows * 0.002, 0.05).astype(np.float32)
    height[labels == 5] = 0.05 + rows[labels == 5] * 0.004  # 3 cm tall
    grouped = _object_pixels(labels)
    parents = part_parents(labels, points, height, SegmentConfig(), grouped)
    np.testing.assert_array_equal(parents, [0, 1, 2, 2, 4, 5, 2])
    off = part_parents(labels, points, height, SegmentConfig(part_min_contact=0), grouped)
    np.testing.assert_array_equal(off, np.arange(7))


def test_fragments_join_the_segment_they_touch_within_reach() -> None:
    """A 40 x 40 px segment (2), a 10 x 8 px fragment touching it (3), a fragment touching
    it in the image only, 20 cm behind (4), and a fragment touching only fragment 3 (5):
    the first pass gives 3 to 2, the second 5; 4 keeps its id. With no pass, none moves."""
    raw = np.zeros((60, 80), dtype=np.int32)
    raw[10:50, 10:50] = 2
    raw[20:30, 50:58] = 3
    raw[20:30, 2:10] = 4
    raw[20:30, 58:64] = 5
    flat_points = _pixel_grid(raw)[0].reshape(-1, 3)
    for passes, expected in ((2, [2, 2, 4, 2]), (1, [2, 2, 4, 5]), (0, [2, 3, 4, 5])):
        joined = raw.reshape(-1).copy()
        absorb_fragments(joined, flat_points, raw.shape, SegmentConfig(fragment_passes=passes))
        joined = joined.reshape(raw.shape)
        assert [joined[15, 15], joined[25, 52], joined[25, 5], joined[25, 60]] == expected
    assert (joined == raw).all()


def test_a_side_part_claims_the_raised_table_pixels_at_its_edge() -> None:
    """Table pixels (1) within 3 px of part 3 are claimed when more than 2 mm above the
    table and within 1 cm in 3-D; the object itself (2) claims none."""
    labels = np.ones((20, 40), dtype=np.int32)
    labels[:, :10] = 2
    labels[5:15, 10:20] = 3
    cols, rows = np.meshgrid(np.arange(40), np.arange(20))
    points = np.stack([cols * 0.002, rows * 0.002, np.ones((20, 40))], axis=2).astype(np.float32)
    height = np.where(labels == 1, 0.004, 0.01).astype(np.float32)
    height[:, 21] = 0.001  # table level: stays table
    points[15:, 10:20, 2] += 0.05  # 5 cm behind in depth: stays table
    parents = np.array([0, 1, 2, 2], dtype=np.int32)
    claims = table_edge_claims(
        labels, points, height, parents, SegmentConfig(), _object_pixels(labels)
    )
    assert claims is not None
    row_span, col_span, window = claims
    claimed = labels.copy()
    claimed[row_span, col_span] = window
    gained = (claimed == 3) & (labels == 1)
    expected = np.zeros_like(gained)
    expected[2:18, 20:23] = True
    expected[2:5, 10:20] = True
    expected[:, 21] = False
    expected[15:, 10:20] = False
    np.testing.assert_array_equal(gained, expected)
    assert (claimed[labels != 1] == labels[labels != 1]).all()


@needs_osd
def test_a_real_pots_side_tab_is_a_part_of_the_pot() -> None:
    """learn33: the pot's visible side tab is cut off at the crease with its wall; it keeps
    its own label (OSD's parts) but names the pot as its whole and claims the table pixels of
    its edge, and `detect --segment` is handed the pot with the tab."""
    from simgrasp.assets.real import read_labeled_scene
    from simgrasp.evaluation.real_pots import labeled_scenes, segmented_pot

    label = labeled_scenes()["learn33"]
    scene = read_labeled_scene(OSD / "learn33.pcd")
    result = segment_scene(scene.cloud)
    tab = label.label.contains(scene.points) & (scene.labels // 10 == label.object_id)
    ids, counts = np.unique(result.labels[tab], return_counts=True)
    tab_segment = int(ids[np.argmax(counts)])
    pot = result.objects[tab_segment - 2].part_of
    assert pot != tab_segment and pot in result.whole_objects()
    assert result.object_mask(pot)[tab].mean() > 0.6
    plain = segment_scene(scene.cloud, SegmentConfig(part_min_contact=0))
    changed = plain.labels != result.labels  # only table pixels at the tab's edge change
    assert changed.any() and (plain.labels[changed] == 1).all()
    assert set(result.labels[changed].tolist()) == {tab_segment}
    assert all(obj.part_of == obj.label for obj in plain.objects)
    points, _ = segmented_pot(scene, label)
    assert label.label.contains(points).sum() > 0.6 * tab.sum()


@needs_osd
def test_side_parts_on_a_real_scene_lie_on_the_object_of_their_whole() -> None:
    """learn36: the pot's tab and its inner floor pieces are side parts, each on the same
    ground-truth object as the segment it is a part of (scored as segment_osd.py does)."""
    score = score_scene(OSD / "learn36.pcd", "grid")
    assert score.side_parts >= 3 and score.side_parts_right == score.side_parts
    assert score_scene(OSD / "learn36.pcd", "dbscan").side_parts == 0


def _one_error_line(capsys: pytest.CaptureFixture[str], argv: list[str], words: str) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith(f"simgrasp {argv[0]}: error:"), err
    assert words in err, err


def test_bad_scenes_give_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    grid = tabletop()
    blob = np.random.default_rng(0).normal(size=(HEIGHT, WIDTH, 3)) * 0.1 + [0, 0, 1.0]
    rays = _rays() / np.linalg.norm(_rays(), axis=2, keepdims=True)
    ahead = rays[..., 2] * 0.5  # a ball of radius 0.3 m, 0.5 m ahead, fills the view
    with np.errstate(invalid="ignore"):  # the corner rays miss it: NaN pixels
        ball = (ahead - np.sqrt(ahead**2 - 0.25 + 0.09))[..., None] * rays
    o3d = import_open3d()
    whole = tmp_path / "whole.pcd"
    finite = grid.reshape(-1, 3)[np.isfinite(grid.reshape(-1, 3)).all(axis=1)]
    o3d.t.io.write_point_cloud(str(whole), o3d.t.geometry.PointCloud(finite), compressed=True)
    (tmp_path / "cut.pcd").write_bytes(whole.read_bytes()[: whole.stat().st_size // 2])
    cases = {
        "no table plane (the best plane holds": _save_npy(tmp_path, blob, "blob.npy"),
        "no table plane (the best plane is curved": _save_npy(tmp_path, ball, "ball.npy"),
        "no valid point": _save_npy(tmp_path, np.full_like(grid, np.nan), "nan.npy"),
        "millimetres": _save_npy(tmp_path, grid * 1000.0, "mm.npy"),
        "no such scene-cloud file": tmp_path / "missing.pcd",
        "truncated": tmp_path / "cut.pcd",
    }
    for words, path in cases.items():
        _one_error_line(capsys, ["segment", str(path)], words)
        _one_error_line(capsys, ["detect", str(path), "--segment"], words)


def test_a_wall_filling_the_view_is_an_empty_result(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    wall = _rays() * 0.5  # a plane 0.5 m ahead fills every pixel: it is the table
    path = _save_npy(tmp_path, wall)
    labels = tmp_path / "labels.npy"
    assert main(["segment", str(path), "--json", "--labels", str(labels)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["objects"] == [] and report["table"]["points"] == WIDTH * HEIGHT
    assert set(report) == {"table", "objects", "timings_s", "pixel_scale", "settings"}
    assert report["settings"]["seed"] == 0  # what made it: the segmentation settings
    assert (np.load(labels) == 1).all()
    assert main(["detect", str(path), "--segment", "--json", "--seed", "4"]) == 0
    detection = json.loads(capsys.readouterr().out)
    assert detection["handles"] == [] and detection["input"]["seed"] == 4


def test_scene_from_array_refuses_a_wrong_shape() -> None:
    with pytest.raises(ValueError, match="expected"):
        scene_from_array(np.zeros((10, 2)))


@pytest.mark.parametrize("kind", ["ascii", "binary"])
def test_a_cut_uncompressed_scene_is_refused(
    kind: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A scene PCD cut in half is an error naming the file, not read with made-up points (the
    strict readers of cloud_formats, as for detect's clouds)."""
    o3d = import_open3d()
    finite = tabletop().reshape(-1, 3)
    finite = finite[np.isfinite(finite).all(axis=1)]
    whole = tmp_path / "whole.pcd"
    cloud = o3d.t.geometry.PointCloud(finite.astype(np.float32))
    o3d.t.io.write_point_cloud(str(whole), cloud, write_ascii=kind == "ascii")
    cut = tmp_path / "cut.pcd"
    cut.write_bytes(whole.read_bytes()[: whole.stat().st_size // 2])
    _one_error_line(capsys, ["segment", str(cut)], "cut.pcd")
    assert len(read_scene(whole).points) == len(finite)
