"""Automatic handle labels (``simgrasp label-handles``) on generated objects with exact labels,
their file round trip, bad input, and one ACRONYM mug whose handle grasps are known."""

from __future__ import annotations

import functools
import json
from dataclasses import replace
from pathlib import Path
from typing import cast

import numpy as np
import pytest
import trimesh
from data_needs import require_data

from simgrasp.assets.generated import generate_tool
from simgrasp.autolabel.auto_label import auto_handle_label
from simgrasp.autolabel.config import AutoLabelConfig
from simgrasp.autolabel.cross_section import CrossSectionConfig
from simgrasp.autolabel.label_surface import piece_boxes
from simgrasp.autolabel.revolution import RevolutionConfig
from simgrasp.autolabel.virtual_scan import ScanConfig
from simgrasp.cli import main
from simgrasp.labels import HandleLabel, load_handle_label, write_label_file
from simgrasp.perception import sample_surface

FAST = AutoLabelConfig(scan=ScanConfig(views=12))
"""Fewer views than the default 24 keep the tests fast; the labels still match."""
VIEWS_12 = ("--label.scan.views", "12")


def _iou(found: HandleLabel, exact: HandleLabel, mesh: object) -> float:
    """Intersection over union of the two labels on points sampled on the mesh."""
    points, _ = sample_surface(mesh, 20000, np.random.default_rng(0))  # type: ignore[arg-type]
    a, b = found.contains(points), exact.contains(points)
    return float((a & b).sum() / max((a | b).sum(), 1))


def test_cli_labels_a_generated_mug_and_the_file_round_trips(tmp_path: Path) -> None:
    asset = generate_tool("mug", 0)
    mesh_path = tmp_path / "mug.stl"
    asset.mesh.export(mesh_path)
    out, plot = tmp_path / "handles.json", tmp_path / "handles.png"
    args = ["label-handles", str(mesh_path), "--out", str(out), "--plot", str(plot)]
    assert main([*args, "--label.scan.views", "12"]) == 0
    label = load_handle_label(out)
    assert label.object_name == "mug" and label.regions
    assert _iou(label, asset.handle, asset.mesh) >= 0.6
    assert plot.stat().st_size > 10000
    again = tmp_path / "again.json"
    write_label_file(again, {"mug": label}, "copy")
    points = asset.mesh.vertices
    assert np.array_equal(load_handle_label(again, "mug").contains(points), label.contains(points))


def test_cli_labels_objects_by_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    """A generated name is scanned in its own frame (its exact label lies on the same
    surface); a catalog name reads its mesh and units and leaves its handles key alone;
    --scale with a name, or an unknown name, is one clear line."""
    asset = generate_tool("hammer", 0)
    out = tmp_path / "h.json"
    assert main(["label-handles", "gen_hammer_s0", "--out", str(out), *VIEWS_12]) == 0
    by_name = load_handle_label(out)
    assert by_name.object_name == "gen_hammer_s0"
    assert "(--label.seed 0)" in json.loads(out.read_text())["description"]  # what made it
    assert _iou(by_name, asset.handle, asset.mesh) >= 0.6
    asset.mesh.copy().apply_scale(1000.0).export(tmp_path / "hammer.stl")
    catalog = tmp_path / "objects.toml"
    catalog.write_text('[my_hammer]\nmesh = "hammer.stl"\nunits = "mm"\nhandles = "none.json"\n')
    monkeypatch.setenv("SIMGRASP_OBJECTS", str(catalog))
    assert main(["label-handles", "my_hammer", "--out", str(out), *VIEWS_12]) == 0
    assert _iou(load_handle_label(out, "my_hammer"), asset.handle, asset.mesh) >= 0.6
    capsys.readouterr()
    for bad, word in ((["gen_hammer_s0", "--scale", "2"], "--scale"), (["gen_nope"], "gen_nope")):
        assert main(["label-handles", *bad, "--out", str(out)]) == 2
        err = capsys.readouterr().err.strip()
        assert word in err and len(err.splitlines()) == 1


def test_mesh_in_millimetres_needs_units(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    asset = generate_tool("hammer", 0)
    mesh_path = tmp_path / "hammer_mm.ply"
    asset.mesh.copy().apply_scale(1000.0).export(mesh_path)
    out = tmp_path / "h.json"
    assert main(["label-handles", str(mesh_path), "--out", str(out)]) == 2
    assert "--units" in capsys.readouterr().err
    args = ["label-handles", str(mesh_path), "--units", "mm", "--out", str(out)]
    assert main([*args, "--label.scan.views", "12"]) == 0
    assert _iou(load_handle_label(out), asset.handle, asset.mesh) >= 0.6
    # the hint counts the scale given: millimetres read at half scale still need --units mm
    assert main(["label-handles", str(mesh_path), "--scale", "0.5", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "at scale 0.5" in err and "--units mm" in err and len(err.splitlines()) == 1


def test_a_generated_knife_gets_its_handle_and_not_its_blade() -> None:
    from simgrasp.assets.generated import generate_parts

    for seed in (24, 2):  # a flat and a round handle, both with finger grooves, no bolster
        asset = generate_tool("knife", seed)
        label = auto_handle_label(asset.mesh, asset.name, FAST).label
        assert _iou(label, asset.handle, asset.mesh) >= 0.9
        blade = next(p.mesh for p in generate_parts("knife", seed).parts if p.name == "blade")
        assert label.contains(blade.sample(5000, seed=0)).mean() <= 0.1


def test_a_thin_grooved_flat_handle_is_found_on_the_looser_flatness() -> None:
    """gen_knife_s14: a flat 18 x 3.7 mm handle with finger grooves, whose fits are flatter
    than ``max_flatness``: found only by the retry at ``retry_flatness``, and not its blade."""
    from simgrasp.assets.generated import generate_parts

    asset = generate_tool("knife", 14)
    parts = generate_parts("knife", 14).parts
    handle = np.concatenate([p.mesh.sample(4000, seed=0) for p in parts if p.is_handle])
    blade = next(p.mesh for p in parts if p.name == "blade").sample(5000, seed=0)
    label = auto_handle_label(asset.mesh, asset.name, FAST).label
    assert label.contains(handle).mean() >= 0.95
    assert label.contains(blade).mean() <= 0.1
    strict = replace(FAST, retry_flatness=0.0)
    assert auto_handle_label(asset.mesh, asset.name, strict).label.regions == ()


def test_the_looser_flatness_finds_no_handle_on_a_flat_bar_of_one_section() -> None:
    """A ruler (30 x 3 x 0.4 cm) is flat everywhere: the retry's parts would be the whole of
    it, so it gets no label (it gets one when that test is off)."""
    ruler = trimesh.creation.box([0.3, 0.03, 0.004])
    assert auto_handle_label(ruler, "ruler", FAST).label.regions == ()
    anything = replace(FAST, max_run_share=1.0)
    assert auto_handle_label(ruler, "ruler", anything).label.regions != ()


def test_handle_less_bodies_get_no_handle_region() -> None:
    for kind in ("can", "fruit"):
        asset = generate_tool(kind, 0)
        assert auto_handle_label(asset.mesh, asset.name, FAST).label.regions == ()


def test_bad_mesh_path_is_one_clear_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    missing = tmp_path / "nope.obj"
    assert main(["label-handles", str(missing), "--out", str(tmp_path / "h.json")]) == 2
    err = capsys.readouterr().err.strip()
    assert "nope.obj" in err and len(err.splitlines()) == 1


def test_loader_names_the_object_it_lacks(tmp_path: Path) -> None:
    labels = {"a": HandleLabel("a"), "b": HandleLabel("b")}
    path = write_label_file(tmp_path / "two.json", labels, "")
    assert load_handle_label(path, "b").object_name == "b"
    with pytest.raises(Exception, match="name one"):
        load_handle_label(path)
    with pytest.raises(Exception, match="'c'"):
        load_handle_label(path, "c")


MUG = "Mug_10f6e09036350e92b3f21f1137c3c347_0.0002682457830986903.h5"


def test_acronym_mug_handle_grasps_fall_in_the_automatic_label(tmp_path: Path) -> None:
    from simgrasp.evaluation.acronym_handles import (
        held_from_labels,
        read_acronym,
        subset_shares,
        trial_labels,
        trial_subset_shares,
    )

    root = require_data("acronym")
    item = read_acronym(root / "affordance" / "grasps" / MUG)
    label = auto_handle_label(item.mesh, item.name, replace(FAST, scan=ScanConfig())).label
    shares = subset_shares(item, label)
    handle = shares["good_grasp"]
    assert handle["on_handle"] / handle["grasps"] >= 0.9
    pour = shares["good_pour"]
    assert pour["on_handle"] / pour["grasps"] <= 0.05
    first = int(item.subsets["good_grasp"][0])
    rows = [
        {"index": first, "success": True, "on_handle": True},
        {"index": first + 1, "success": False, "on_handle": False},
    ]
    labels = tmp_path / "labels.jsonl"
    labels.write_text("".join(json.dumps(r) + "\n" for r in rows))
    held = held_from_labels(labels, len(item.object_T_hands))
    assert subset_shares(item, label, held=held)["good_grasp"]["grasps"] == 1
    scored = trial_subset_shares(item, *trial_labels(labels, len(item.object_T_hands)))
    assert scored["good_grasp"] == {"grasps": 1, "on_handle": 1}
    assert scored["good_pour"]["grasps"] == 0


FLAT_KNIFE = "Knife_89e8bae10847eb8a8721ead1444fbb07_0.01976018915084059.h5"


def test_a_flat_knife_handle_is_labeled_to_its_end_and_not_its_blade() -> None:
    """A tune-half ACRONYM table knife whose 3.3 mm flat handle the detector finds only in
    part: the label runs on along the handle's section to its end, and stops at the blade."""
    from simgrasp.evaluation.acronym_handles import read_acronym, subset_shares

    root = require_data("acronym")
    item = read_acronym(root / "affordance" / "grasps" / FLAT_KNIFE)
    label = auto_handle_label(item.mesh, item.name).label
    shares = subset_shares(item, label)
    handle, blade = shares["good_cut"], shares["good_grasp"]  # by location (see the README)
    assert handle["on_handle"] / handle["grasps"] >= 0.95
    assert blade["on_handle"] / blade["grasps"] <= 0.1
    without = replace(AutoLabelConfig(), cross_section=CrossSectionConfig(grow_ratio=0.0))
    short = subset_shares(item, auto_handle_label(item.mesh, item.name, without).label)
    assert short["good_cut"]["on_handle"] < handle["on_handle"]


def test_recorded_contacts_are_scored_again_against_another_label(tmp_path: Path) -> None:
    from simgrasp.evaluation.acronym_handles import trial_labels
    from simgrasp.labels import Box

    box = Box(np.zeros(3), np.eye(3), np.full(3, 0.01))
    label = HandleLabel("bar", (box,))
    inside, outside = [[0.0, 0.0, 0.012], [0.0, 0.0, -0.012]], [[0.05, 0.0, 0.0]] * 2
    rows = [
        {"index": 0, "success": True, "on_handle": False, "contact_points_object": inside},
        {"index": 1, "success": True, "on_handle": True, "contact_points_object": outside},
        {"index": 2, "success": False, "on_handle": False, "contact_points_object": inside},
    ]
    labels = tmp_path / "labels.jsonl"
    labels.write_text("".join(json.dumps(r) + "\n" for r in rows))
    held, recorded = trial_labels(labels, 4)
    assert held.tolist() == [True, True, False, False]
    assert recorded.tolist() == [False, True, False, False]
    rescored = trial_labels(labels, 4, label)[1]  # contacts within the 5 mm margin count
    assert rescored.tolist() == [True, False, False, False]
    labels.write_text(json.dumps({"index": 0, "success": True}) + "\n")
    with pytest.raises(Exception, match="not a label row"):
        trial_labels(labels, 4, label)


def _tube_points(radius: float, length: float, center_x: float = 0.0) -> np.ndarray:
    """Points on a tube of ``radius`` along z through (center_x, 0), ``length`` long (m)."""
    angle, z = np.meshgrid(np.linspace(0, 2 * np.pi, 120, endpoint=False), np.arange(-1, 1, 0.01))
    x = center_x + radius * np.cos(angle).ravel()
    return np.column_stack([x, radius * np.sin(angle).ravel(), z.ravel() * length / 2])


def test_kmeans_pieces_follow_a_loop_where_slabs_span_its_opening() -> None:
    """A loop of three quarters of a ring (3 cm radius, 6 x 12 mm section), as a strap with
    its roots: k-means boxes follow the ring and leave most of its opening free; boxes of
    slabs along its main axis span all of it."""
    rng = np.random.default_rng(0)
    angle = rng.uniform(-0.75 * np.pi, 0.75 * np.pi, 3000)
    radius = 0.03 + rng.uniform(-0.003, 0.003, 3000)
    height = rng.uniform(-0.006, 0.006, 3000)
    loop = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), height])
    grid = np.mgrid[-0.03:0.031:0.0025, -0.03:0.031:0.0025].reshape(2, -1).T
    opening = np.column_stack([grid, np.zeros(len(grid))])[np.linalg.norm(grid, axis=1) < 0.022]
    covered = {}
    for pieces in ("kmeans", "slabs"):
        boxes = piece_boxes(loop, replace(AutoLabelConfig(), pieces=pieces))
        label = HandleLabel("loop", tuple(boxes))
        assert len(boxes) == 3 and label.contains(loop).mean() == 1.0
        covered[pieces] = label.contains(opening).mean()
    assert covered["kmeans"] <= 0.2 and covered["slabs"] == 1.0
    first = piece_boxes(loop, AutoLabelConfig())
    again = piece_boxes(loop, replace(AutoLabelConfig(), seed=7))
    assert all(np.array_equal(a.center, b.center) for a, b in zip(first, again, strict=True)), (
        "k-means pieces start from the slabs: no seed may change them"
    )


def test_free_space_is_empty_around_a_free_tube_and_full_beside_a_wall() -> None:
    from simgrasp.autolabel.free_space import sideways_occupancy

    tube = _tube_points(0.005, 0.06)
    axis, center, semi = np.array([[0.0, 0.0, 1.0]]), np.zeros((1, 3)), np.array([0.005])
    occupancy = functools.partial(sideways_occupancy, slab=0.003, gap=0.003, ring=0.008)
    assert occupancy(tube, center, axis, semi)[0] == 0.0
    y, z = np.meshgrid(np.linspace(-0.03, 0.03, 61), np.linspace(-0.03, 0.03, 61))
    wall = np.column_stack([np.full(y.size, 0.012), y.ravel(), z.ravel()])
    beside = occupancy(np.vstack([tube, wall]), center, axis, semi)[0]
    assert beside >= 3 / 12
    # A plate continuing from the candidate's edge (a blade, a rim's wall) fills one side.
    plate = np.column_stack([0.005 + y.ravel() + 0.03, np.zeros(y.size), z.ravel()])
    edge = occupancy(np.vstack([tube, plate]), center, axis, semi)[0]
    assert 0.0 < edge < beside
    nan_semi = occupancy(tube, center, axis, np.array([np.nan]))
    assert nan_semi[0] == 1.0


def test_free_space_fallback_finds_no_handle_on_handle_less_bodies() -> None:
    config = replace(FAST, free_space_fallback=True)
    for kind in ("can", "fruit"):
        asset = generate_tool(kind, 0)
        assert auto_handle_label(asset.mesh, asset.name, config).label.regions == ()


FLAT_STRAP_MUG = "Mug_b7841572364fd9ce1249ffc39a0c3c0b_0.0003944227048461527.h5"
"""A tune-half ACRONYM mug whose strap is a flat band: no candidate passes the flatness test."""


def test_free_space_fallback_labels_a_flat_strap_the_detector_misses() -> None:
    from simgrasp.evaluation.acronym_handles import read_acronym, subset_shares

    root = require_data("acronym")
    item = read_acronym(root / "affordance" / "grasps" / FLAT_STRAP_MUG)
    full = replace(FAST, scan=ScanConfig(), revolution=RevolutionConfig(margin=0.0))
    assert auto_handle_label(item.mesh, item.name, full).label.regions == ()
    fallback = replace(full, free_space_fallback=True, axis_reach=0.0)  # the fallback alone
    label = auto_handle_label(item.mesh, item.name, fallback).label
    shares = subset_shares(item, label)
    handle, pour = shares["good_grasp"], shares["good_pour"]
    assert handle["on_handle"] / handle["grasps"] >= 0.5
    assert pour["on_handle"] / pour["grasps"] <= 0.05


def test_axis_reach_follows_a_tube_but_not_onto_a_blocked_blade() -> None:
    from simgrasp.autolabel.axis_reach import reached_along_axes

    tube = _tube_points(0.005, 0.08)  # z from -0.04 to 0.04
    y, z = np.meshgrid(np.linspace(-0.02, 0.02, 41), np.linspace(0.0, 0.04, 41))
    blade = np.column_stack([np.zeros(y.size), y.ravel(), 0.025 + z.ravel()])
    surface = np.vstack([tube, blade])
    center, axis = np.array([[0.0, 0.0, 0.01]]), np.array([[0.0, 0.0, 1.0]])
    free = np.zeros(len(surface), dtype=bool)
    reached = reached_along_axes(surface, center, axis, np.array([0.008]), reach=0.02, blocked=free)
    on_tube = reached[: len(tube)]
    z_tube = tube[:, 2]
    assert on_tube[np.abs(z_tube - 0.01) <= 0.019].all() and not on_tube[z_tube < -0.011].any()
    assert reached[len(tube) :].any()  # the blade's root lies within reach and radius
    blocked = np.r_[free[: len(tube)], np.ones(len(blade), dtype=bool)]
    kept_off = reached_along_axes(
        surface, center, axis, np.array([0.008]), reach=0.02, blocked=blocked
    )
    assert not kept_off[len(tube) :].any() and (kept_off[: len(tube)] == on_tube).all()
    none = reached_along_axes(surface, center, axis, np.array([0.008]), reach=0.0, blocked=free)
    assert not none.any()


def _guarded_knife() -> trimesh.Trimesh:
    """A knife-like mesh (m): a round handle (9 mm radius, z from -0.05 to 0.05), a guard
    36 mm wide at z 0.05-0.056 and a flat blade 30 mm wide, 2 mm thick above it to z 0.146."""
    handle = trimesh.creation.cylinder(radius=0.009, height=0.10, sections=48)
    guard = trimesh.creation.box([0.036, 0.010, 0.006])
    guard.apply_translation([0.0, 0.0, 0.053])
    blade = trimesh.creation.box([0.030, 0.002, 0.09])
    blade.apply_translation([0.0, 0.0, 0.101])
    return cast(trimesh.Trimesh, trimesh.util.concatenate([handle, guard, blade]))


def test_wide_sections_and_the_section_stop_keep_a_knife_label_off_its_blade() -> None:
    mesh = _guarded_knife()
    points, _ = sample_surface(mesh, 20000, np.random.default_rng(0))
    on_handle, on_blade = np.abs(points[:, 2]) < 0.045, points[:, 2] > 0.066

    def shares(config: AutoLabelConfig) -> tuple[float, float]:
        inside = auto_handle_label(mesh, "knife", config).label.contains(points)
        return float(inside[on_handle].mean()), float(inside[on_blade].mean())

    plain = replace(FAST, cross_section=CrossSectionConfig(min_ratio=0.0))
    untrimmed = shares(replace(plain, max_section_ratio=0.0))
    trimmed = shares(plain)  # the blade root's wide fits left out
    stopped = shares(replace(plain, stop_growth=1.5))  # and the guard ends the label
    thin_out = shares(FAST)  # the default: the blade's thin slabs leave the label
    assert min(untrimmed[0], trimmed[0], stopped[0], thin_out[0]) >= 0.95
    assert trimmed[1] <= untrimmed[1] - 0.05
    assert stopped[1] <= 0.02 and thin_out[1] <= 0.02 < untrimmed[1]


def test_uniform_section_leaves_out_wide_candidates_of_large_parts_only() -> None:
    from simgrasp.autolabel.auto_label import uniform_section
    from simgrasp.autolabel.config import Candidates

    semi = np.r_[np.full(30, 0.005), np.full(5, 0.012)]
    n = len(semi)
    ones = np.ones((n, 3))
    candidates = Candidates(
        ones, semi * 2, np.ones(n), np.arange(n), ones, ones, semi.astype(np.float64)
    )
    part = np.arange(n)
    assert (uniform_section(candidates, part, AutoLabelConfig()) == np.arange(30)).all()
    few = replace(AutoLabelConfig(), section_min_candidates=n + 1)
    assert (uniform_section(candidates, part, few) == part).all()
    undefined = replace(candidates, semi_major=np.full(n, np.nan))
    assert (uniform_section(undefined, part, AutoLabelConfig()) == part).all()


def test_section_stops_end_a_tube_at_a_disc_across_it() -> None:
    from scipy.spatial import cKDTree

    from simgrasp.autolabel.axis_reach import SectionStop, section_stops

    radius, angle = np.meshgrid(np.linspace(0.0, 0.02, 21), np.linspace(0, 2 * np.pi, 72))
    disc = np.column_stack(
        [
            (radius * np.cos(angle)).ravel(),
            (radius * np.sin(angle)).ravel(),
            np.full(radius.size, 0.015),
        ]
    )
    surface = np.vstack([_tube_points(0.005, 0.08), disc])
    stop = SectionStop(growth=1.5, ring=0.008, slab=0.002)
    own, center, axis = np.array([[0.005, 0.0, 0.0]]), np.zeros((1, 3)), np.array([[0.0, 0, 1]])
    args = (cKDTree(surface), surface, own, center, axis)
    low, high = section_stops(*args, np.array([0.005]), reach=0.03, stop=stop)[0]
    assert low == -np.inf and 0.012 <= high <= 0.016
    # A section as wide as the disc is no growth: no stop.
    assert np.isinf(section_stops(*args, np.array([0.02]), reach=0.03, stop=stop)).all()


def test_only_flat_candidates_thinner_than_the_part_block_its_reach() -> None:
    """A flat handle's own flat fits (as thick as the part, knife 89e8) leave the reach along
    the handle open; a blade's thin fits still block it."""
    from simgrasp.autolabel.config import Candidates
    from simgrasp.autolabel.label_surface import part_surface

    tube = _tube_points(0.005, 0.08)  # z from -0.04 to 0.04
    centers = np.array([[0.005, 0, 0], [0.005, 0, 0.001], [0.005, 0, 0.015], [0.005, 0, -0.015]])
    widths = np.array([0.010, 0.010, 0.009, 0.002])  # a thick and a thin flat candidate
    axes = np.tile([0.0, 0.0, 1.0], (4, 1))
    candidates = Candidates(
        centers, widths, np.array([1.0, 1.0, 3.0, 8.0]), np.arange(4), axes,
        np.zeros((4, 3)), np.full(4, 0.005),
    )  # fmt: skip
    part = np.array([0, 1])
    config = replace(AutoLabelConfig(), region_radius=0.004, block_width_ratio=0.65)
    near_thick = np.linalg.norm(tube - centers[2], axis=1) <= 0.003
    near_thin = np.linalg.norm(tube - centers[3], axis=1) <= 0.003
    ratio = part_surface(candidates, part, tube, config)
    assert ratio[near_thick].all() and not ratio[near_thin].any()
    every = part_surface(candidates, part, tube, replace(config, block_width_ratio=0.0))
    assert not every[near_thick].any() and not every[near_thin].any()


def test_resplit_drops_a_blade_root_joined_to_the_handle_only_by_its_guard() -> None:
    from simgrasp.autolabel.auto_label import label_from_candidates
    from simgrasp.autolabel.config import Candidates

    z = np.r_[np.arange(30) * 0.002, 0.060 + np.arange(5) * 0.002, 0.070 + np.arange(4) * 0.002]
    semi = np.r_[np.full(30, 0.005), np.full(5, 0.012), np.full(4, 0.005)]  # handle, guard, root
    n = len(z)
    centers = np.column_stack([np.zeros(n), np.zeros(n), z])
    candidates = Candidates(
        centers, np.full(n, 0.01), np.ones(n), np.arange(n), np.tile([0.0, 0, 1], (n, 1)),
        centers, semi,
    )  # fmt: skip
    surface = _tube_points(0.005, 0.2)
    joined = label_from_candidates(candidates, surface, "knife", AutoLabelConfig())
    assert len(joined.parts) == 1 and len(joined.parts[0]) == 34  # the guard left out only
    split = label_from_candidates(
        candidates, surface, "knife", replace(AutoLabelConfig(), resplit=True)
    )
    assert len(split.parts) == 1 and (split.parts[0] == np.arange(30)).all()


def test_the_default_labels_a_solid_fin_standing_off_a_mug() -> None:
    """The tune-half mug whose handle is a solid fin: no detector part, but the fin stands off
    the body of revolution, and the default labels it (0 of its 30 handle grasps before)."""
    from simgrasp.evaluation.acronym_handles import read_acronym, subset_shares

    root = require_data("acronym")
    item = read_acronym(root / "affordance" / "grasps" / FLAT_STRAP_MUG)
    result = auto_handle_label(item.mesh, item.name, replace(FAST, scan=ScanConfig()))
    assert not result.parts and len(result.standoff) == 1
    shares = subset_shares(item, result.label)
    handle, pour = shares["good_grasp"], shares["good_pour"]
    assert handle["on_handle"] / handle["grasps"] >= 0.5
    assert pour["on_handle"] / pour["grasps"] <= 0.02


def test_a_round_hammer_handle_is_no_body_its_head_stands_off() -> None:
    """A hammer's round handle passes the body-of-revolution test and its head stands off it;
    the head must not join the label, because the part it touches (the handle) is the body."""
    from simgrasp.autolabel.revolution import fit_revolution, standoff_pieces, standoff_points
    from simgrasp.autolabel.virtual_scan import scan_mesh

    asset = generate_tool("hammer", 1)
    views = scan_mesh(asset.mesh, FAST.scan)
    surface = np.concatenate([v.points for v in views])
    revolution = fit_revolution(
        surface, np.concatenate([v.normals for v in views]), FAST.revolution
    )
    assert revolution is not None
    standoff = standoff_points(surface, revolution, FAST.revolution.margin)
    assert standoff_pieces(surface, standoff, FAST.revolution)  # the head
    result = auto_handle_label(asset.mesh, asset.name, FAST)
    off = auto_handle_label(asset.mesh, asset.name, replace(FAST, revolution=RevolutionConfig(0)))
    assert result.parts and result.standoff == ()
    points, _ = sample_surface(asset.mesh, 20000, np.random.default_rng(0))
    assert np.array_equal(result.label.contains(points), off.label.contains(points))


def test_a_strap_label_stays_off_the_mug_wall() -> None:
    """A generated strap mug: the detector's part reaches onto the wall at the strap's roots;
    on a body of revolution the label keeps the strap and what stands off, not the wall."""
    asset = generate_tool("strap_mug", 0)
    points, _ = sample_surface(asset.mesh, 20000, np.random.default_rng(0))
    on = auto_handle_label(asset.mesh, asset.name, FAST)
    off = auto_handle_label(asset.mesh, asset.name, replace(FAST, revolution=RevolutionConfig(0)))
    assert on.parts and on.standoff
    assert _iou(on.label, asset.handle, asset.mesh) >= 0.7
    assert (
        _iou(on.label, asset.handle, asset.mesh) >= _iou(off.label, asset.handle, asset.mesh) + 0.1
    )
    wall = ~asset.handle.contains(points)
    assert on.label.contains(points)[wall].mean() < off.label.contains(points)[wall].mean()
