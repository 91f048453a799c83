"""Generated tools: handle labels cover exactly the handle parts; sizes fit the gripper."""

from __future__ import annotations

from typing import cast

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from simgrasp.assets.generated import GENERATED_KINDS, generate_parts, generate_tool
from simgrasp.assets.object_sets import CHECK_KINDS, GENERATED_OBJECTS, TRAINING_KINDS
from simgrasp.assets.registry import load_object

SEEDS = (0, 1, 2)
GRIPPER_OPENING = 0.085


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("kind", GENERATED_KINDS)
def test_label_contains_handle_part_and_not_the_rest(kind: str, seed: int) -> None:
    tool = generate_parts(kind, seed)
    handle_points = np.concatenate(
        [p.mesh.sample(4000, seed=seed) for p in tool.parts if p.is_handle]
    )
    rest_parts = [p for p in tool.parts if not p.is_handle]
    assert handle_points.size, f"{kind} has no handle part"
    if not rest_parts:  # can, fruit: graspable everywhere
        assert tool.handle.whole_object
        assert tool.handle.contains(handle_points).all()
        return
    rest_points = np.concatenate([p.mesh.sample(8000, seed=seed) for p in rest_parts])
    # Where parts join, surface points of one part lie inside the other; compare exposed
    # points only: handle points outside the rest, rest points away from the handle.
    junction = 0.014  # m: the mug label's capsule radius bound (tube radius + margins)
    handle_far = ~np.any([p.mesh.contains(handle_points) for p in rest_parts], axis=0)
    rest_far = cKDTree(handle_points).query(rest_points)[0] > junction
    inside_handle = tool.handle.contains(handle_points[handle_far])
    inside_rest = tool.handle.contains(rest_points[rest_far])
    assert inside_handle.mean() == 1.0, f"{kind}: {1 - inside_handle.mean():.1%} handle missed"
    assert not inside_rest.any(), f"{kind}: {inside_rest.mean():.1%} of the rest labeled"
    # and overall (the rest's exposed surface, by area), the label is the handle, not the object
    rest_mesh = cast(trimesh.Trimesh, trimesh.util.concatenate([p.mesh for p in rest_parts]))
    rest = rest_mesh.sample(8000, seed=seed)
    exposed = ~np.any([p.mesh.contains(rest) for p in tool.parts if p.is_handle], axis=0)
    assert tool.handle.contains(rest[exposed]).mean() < 0.1


@pytest.mark.parametrize("kind", GENERATED_KINDS)
def test_sizes_fit_a_parallel_gripper_and_rest_on_the_plane(kind: str) -> None:
    for seed in SEEDS:
        asset = generate_tool(kind, seed)
        assert asset.name == f"gen_{kind}_s{seed}"
        assert asset.mesh.is_watertight
        low, high = asset.mesh.bounds
        assert low[2] == pytest.approx(0.0, abs=1e-9)
        assert (low[:2] + high[:2]) == pytest.approx([0.0, 0.0], abs=1e-9)
        assert 0.02 < asset.mass < 1.5, f"{asset.name}: implausible mass {asset.mass}"
        if asset.handle.whole_object:
            assert min(asset.mesh.extents[:2]) < GRIPPER_OPENING
            continue
        for region in asset.handle.regions:
            # thickness across the handle: box cross extents or capsule diameter
            if hasattr(region, "half_extents"):
                thickness = 2 * np.sort(region.half_extents)[:2]
            else:
                thickness = np.array([2 * region.radius])
            assert np.all(thickness <= 0.04 + 0.004), f"{asset.name}: handle too thick"
            # a strap is 9-16 mm wide, a table knife's flat handle 3-9 mm thick, a spanner's
            # bar 5-8 mm
            thinnest = {"strap_mug": 0.01, "knife": 0.003, "wrench": 0.005}.get(kind, 0.02)
            assert np.all(thickness >= thinnest - 0.001), f"{asset.name}: handle too thin"


def test_mug_body_is_realistic() -> None:
    tool = generate_parts("mug", 5)
    body = next(p for p in tool.parts if p.name == "body")
    assert 0.072 <= body.mesh.extents[0] <= 0.088
    # the cavity is open: the body's center at mid-height is outside every part
    center = body.mesh.bounds.mean(axis=0)
    assert not any(p.mesh.contains([center])[0] for p in tool.parts)


def test_seeds_change_sizes_reproducibly() -> None:
    a, b, c = generate_tool("hammer", 1), generate_tool("hammer", 1), generate_tool("hammer", 2)
    assert np.array_equal(a.mesh.vertices, b.mesh.vertices)
    assert not np.allclose(a.mesh.extents, c.mesh.extents)


def test_registry_names_and_errors() -> None:
    assert load_object("gen_pan", seed=4).name == "gen_pan_s4"
    assert load_object("gen_pan_s7").name == "gen_pan_s7"
    swept = tuple(f"gen_{k}" for k in GENERATED_KINDS if k not in TRAINING_KINDS + CHECK_KINDS)
    assert swept == GENERATED_OBJECTS and "gen_strap_mug" not in GENERATED_OBJECTS
    assert "gen_knife" not in GENERATED_OBJECTS and load_object("gen_knife_s3").mass > 0
    assert load_object("gen_strap_mug_s2").name == "gen_strap_mug_s2"
    with pytest.raises(ValueError, match="gen_mug"):
        load_object("gen_teapot")
    with pytest.raises(ValueError, match="generated objects are"):
        load_object("no_such_object_xyz")
    with pytest.raises(ValueError, match="known kinds"):
        generate_tool("teapot", 0)


def test_strap_mug_handle_is_a_flat_strap() -> None:
    for seed in SEEDS:
        tool = generate_parts("strap_mug", seed)
        handle = next(p for p in tool.parts if p.is_handle)
        body = next(p for p in tool.parts if p.name == "body")
        assert 0.009 <= handle.mesh.extents[1] <= 0.016  # the strap's width, across the loop
        loop = handle.mesh.extents[0] - (body.mesh.bounds[1, 0] - handle.mesh.bounds[0, 0])
        assert loop > 0.01  # the loop stands off the wall
