"""The procedural tool families: built per seed, exact labels on the handle and off the body,
loadable by name and as the ``families`` set, and simulated through the normal object path."""

from __future__ import annotations

import json

import mujoco
import numpy as np
import pytest
from scipy.spatial import cKDTree

from simgrasp.assets.families import FAMILIES, FAMILY_KINDS
from simgrasp.assets.generated import GENERATED_KINDS, generate_parts, generate_tool
from simgrasp.assets.model import build_object_model
from simgrasp.assets.object_sets import GENERATED_OBJECTS, OBJECT_SETS, expand_objects
from simgrasp.assets.registry import load_object
from simgrasp.assets.stable import sample_rest_pose
from simgrasp.seeding import rng_for

SEEDS = (0, 1)
JUNCTION = 0.014
"""m: surface of other parts this near the handle may lie in its label (where parts join)."""


@pytest.mark.parametrize("kind", FAMILY_KINDS)
def test_each_kind_builds_per_seed_deterministically(kind: str) -> None:
    first, again, other = generate_tool(kind, 3), generate_tool(kind, 3), generate_tool(kind, 4)
    assert first.name == f"gen_{kind}_s3" and first.source == "generated"
    assert np.array_equal(first.mesh.vertices, again.mesh.vertices)
    assert json.dumps(first.handle.to_json()) == json.dumps(again.handle.to_json())
    assert not np.allclose(first.mesh.extents, other.mesh.extents)
    for seed in SEEDS:
        asset = generate_tool(kind, seed)
        assert asset.mesh.is_watertight, asset.name
        low, high = asset.mesh.bounds
        assert low[2] == pytest.approx(0.0, abs=1e-9)
        assert (low[:2] + high[:2]) == pytest.approx([0.0, 0.0], abs=1e-9)
        assert 0.02 < asset.mass < 1.5, f"{asset.name}: implausible mass {asset.mass}"
        assert 0.08 < asset.mesh.extents.max() < 0.5, f"{asset.name}: implausible size"
        assert asset.handle.regions and not asset.handle.whole_object


@pytest.mark.parametrize("kind", FAMILY_KINDS)
def test_label_covers_the_handle_and_not_the_body(kind: str) -> None:
    for seed in SEEDS:
        tool = generate_parts(kind, seed)
        handle = [p for p in tool.parts if p.is_handle]
        rest = [p for p in tool.parts if not p.is_handle]
        assert handle and rest, f"{kind}: a handle part and a body"
        handle_points = np.concatenate([p.mesh.sample(1500, seed=seed) for p in handle])
        rest_points = np.concatenate([p.mesh.sample(3000, seed=seed) for p in rest])
        # exposed handle surface (outside the body) is labeled, all of it
        exposed = ~np.any([p.mesh.contains(handle_points) for p in rest], axis=0)
        covered = tool.handle.contains(handle_points[exposed])
        assert covered.all(), f"{kind} s{seed}: {1 - covered.mean():.1%} of the handle missed"
        # the body away from the joints is not
        far = cKDTree(handle_points).query(rest_points)[0] > JUNCTION
        labeled = tool.handle.contains(rest_points[far])
        assert not labeled.any(), f"{kind} s{seed}: {labeled.mean():.1%} of the body labeled"


def test_the_families_set_and_names() -> None:
    kinds = [kind for family in FAMILIES.values() for kind in family]
    assert sorted(kinds) == sorted(FAMILY_KINDS) and len(kinds) == len(set(kinds))
    assert not set(FAMILY_KINDS) & set(GENERATED_KINDS)
    assert OBJECT_SETS["families"] == tuple(f"gen_{kind}" for kind in FAMILY_KINDS)
    assert len(GENERATED_OBJECTS) == 7 and "gen_cup" not in OBJECT_SETS["all"]
    assert expand_objects(["families", "gen_cup"]).count("gen_cup") == 1
    assert load_object("gen_frying_pan_s5").name == "gen_frying_pan_s5"
    assert load_object("gen_chef_knife", seed=2).name == "gen_chef_knife_s2"
    with pytest.raises(ValueError, match="gen_kettle"):
        load_object("gen_teapot")


def test_a_family_object_settles_in_mujoco_through_coacd() -> None:
    model = build_object_model(load_object("gen_cup_s0"))
    assert 1 <= len(model.hulls) <= 12
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[1, 1, 0.1])
    world_T_object = sample_rest_pose(model, rng_for(0, "drop", model.asset.name))
    world_T_object[2, 3] += 0.004
    model.add_to(spec, world_T_object)
    compiled = spec.compile()
    data = mujoco.MjData(compiled)
    while data.time < 1.5:
        mujoco.mj_step(compiled, data)
    body = compiled.body("object")
    assert compiled.body_mass[body.id] == pytest.approx(model.asset.mass)
    assert np.all(np.isfinite(data.qpos))
    assert np.abs(data.qvel).max() < 0.05, f"still moving {data.qvel}"
