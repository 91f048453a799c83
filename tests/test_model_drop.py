"""Object models compile in MuJoCo and settle on a plane from a stable pose."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from simgrasp.assets.generated import GENERATED_KINDS
from simgrasp.assets.model import (
    COLLISION_GROUP,
    MAX_TEXTURE_SIDE,
    MIN_RADIUS_OF_GYRATION,
    VISUAL_GROUP,
    ObjectModel,
    build_object_model,
)
from simgrasp.assets.registry import load_object
from simgrasp.assets.stable import StablePose, sample_rest_pose, stable_poses, upright_poses
from simgrasp.seeding import rng_for

DROP_HEIGHT = 0.004  # m
SETTLE_TIME = 2.0  # s of simulated time
MAX_PENETRATION = 0.003  # m below the plane


def _drop(model: ObjectModel, seed: int) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[1, 1, 0.1])
    world_T_object = sample_rest_pose(model, rng_for(seed, "drop", model.asset.name))
    world_T_object[2, 3] += DROP_HEIGHT
    model.add_to(spec, world_T_object)
    compiled = spec.compile()
    data = mujoco.MjData(compiled)
    while data.time < SETTLE_TIME:
        mujoco.mj_step(compiled, data)
    return compiled, data


def _assert_settled(model: ObjectModel, compiled: mujoco.MjModel, data: mujoco.MjData) -> None:
    name = model.asset.name
    assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel)), f"{name}: NaN"
    assert np.abs(data.qvel[:3]).max() < 0.02, f"{name}: still moving {data.qvel[:3]}"
    assert np.abs(data.qvel[3:]).max() < 0.3, f"{name}: still spinning {data.qvel[3:]}"
    body = compiled.body("object")
    world_R_object = data.xmat[body.id].reshape(3, 3)
    vertices_world = np.concatenate([h.vertices for h in model.hulls]) @ world_R_object.T
    vertices_world += data.xpos[body.id]
    assert vertices_world[:, 2].min() > -MAX_PENETRATION, f"{name}: sank into the plane"
    assert vertices_world[:, 2].min() < 0.002, f"{name}: floating above the plane"


def _assert_structure(model: ObjectModel, compiled: mujoco.MjModel) -> None:
    body_id = compiled.body("object").id
    assert compiled.body_mass[body_id] == pytest.approx(model.asset.mass)
    geoms = [compiled.geom(i) for i in range(compiled.ngeom) if compiled.geom_bodyid[i] == body_id]
    hulls = [g for g in geoms if g.name.startswith("object_hull")]
    assert len(hulls) == len(model.hulls)
    assert all(g.group[0] == COLLISION_GROUP and g.condim[0] in (4, 6) for g in hulls)
    (visual,) = [g for g in geoms if g.name == "object_visual"]
    assert visual.group[0] == VISUAL_GROUP and visual.contype[0] == visual.conaffinity[0] == 0


@pytest.mark.parametrize("seed", [0, 3])
@pytest.mark.parametrize("kind", GENERATED_KINDS)
def test_generated_tools_settle_on_a_plane(kind: str, seed: int) -> None:
    model = build_object_model(load_object(f"gen_{kind}", seed=seed))
    compiled, data = _drop(model, seed)
    _assert_structure(model, compiled)
    _assert_settled(model, compiled, data)


@pytest.mark.slow
def test_all_ycb_objects_settle_on_a_plane(ycb_dir: str) -> None:
    from simgrasp.assets.ycb import available_ycb_objects

    names = available_ycb_objects(ycb_dir)
    assert len(names) == 20
    for name in names:
        model = build_object_model(load_object(name, ycb_dir))
        compiled, data = _drop(model, 0)
        _assert_structure(model, compiled)
        _assert_settled(model, compiled, data)


def test_two_objects_coexist_and_inertia_follows_the_mass() -> None:
    hammer = build_object_model(load_object("gen_hammer", seed=1))
    mug = build_object_model(load_object("gen_mug", seed=1))
    spec = mujoco.MjSpec()
    pose = np.eye(4)
    hammer.add_to(spec, pose, name="a")
    pose[0, 3] = 0.5
    mug.add_to(spec, pose, name="b")
    compiled = spec.compile()
    assert compiled.body("a").mass[0] == pytest.approx(hammer.asset.mass)
    assert compiled.body("b").mass[0] == pytest.approx(mug.asset.mass)
    # the steel-free uniform solid: inertia scales with mass, principal moments positive
    assert np.all(compiled.body("a").inertia > 0)
    with pytest.raises(ValueError, match="4x4"):
        hammer.add_to(mujoco.MjSpec(), np.eye(3))


def test_stable_poses_rest_on_the_plane() -> None:
    model = build_object_model(load_object("gen_can", seed=2))
    poses = stable_poses(model)
    assert sum(p.probability for p in poses) == pytest.approx(1.0)
    assert poses[0].probability >= poses[-1].probability
    for pose in poses:
        vertices_rest = model.asset.mesh.vertices @ pose.rest_T_object[:3, :3].T
        vertices_rest += pose.rest_T_object[:3, 3]
        assert vertices_rest[:, 2].min() == pytest.approx(0.0, abs=1e-6)
    # a can rests on a flat end (object z vertical) or on its side (object z horizontal)
    for pose in poses:
        up_in_object = pose.rest_T_object[2, :3]
        assert abs(up_in_object[2]) == pytest.approx(1.0, abs=1e-6) or abs(
            up_in_object[2]
        ) == pytest.approx(0.0, abs=1e-6)
    a = sample_rest_pose(model, rng_for(5, "t"))
    b = sample_rest_pose(model, rng_for(5, "t"))
    assert np.array_equal(a, b)


def test_upright_poses_keep_the_standing_ones_renormalized() -> None:
    model = build_object_model(load_object("gen_can", seed=2))
    poses = stable_poses(model)
    upright = upright_poses(poses, "gen_can")
    assert 0 < len(upright) < len(poses)
    assert sum(p.probability for p in upright) == pytest.approx(1.0)
    assert all(p.rest_T_object[2, 2] == pytest.approx(1.0, abs=1e-6) for p in upright)
    pose = sample_rest_pose(model, rng_for(5, "t"), placement="upright")
    assert pose[2, 2] == pytest.approx(1.0, abs=1e-6)


def test_an_object_that_never_stands_upright_is_a_clear_error() -> None:
    on_its_side = np.eye(4)
    on_its_side[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]  # object +z along world -y
    with pytest.raises(ValueError, match="'gen_thing' has no stable pose with its \\+z axis up"):
        upright_poses([StablePose(on_its_side, 1.0)], "gen_thing")


def test_thin_tools_get_the_inertia_floor_and_thick_ones_keep_theirs(ycb_dir: str) -> None:
    floor = MIN_RADIUS_OF_GYRATION**2
    fork = build_object_model(load_object("030_fork", ycb_dir))
    moments = np.linalg.eigvalsh(fork.inertial.inertia_com) / fork.inertial.mass
    assert moments.min() == pytest.approx(floor, rel=1e-9)  # raised: about the long axis
    assert moments.max() > 10 * floor  # end over end it is the fork's own
    hammer = build_object_model(load_object("048_hammer", ycb_dir))
    moments = np.linalg.eigvalsh(hammer.inertial.inertia_com) / hammer.inertial.mass
    assert moments.min() > 2 * floor  # well above the floor: its own, untouched


def test_scan_texture_is_downscaled_keeping_its_colors(ycb_dir: str) -> None:
    """The YCB hammer's 4096 x 4096 texture enters the model at MAX_TEXTURE_SIDE, the same
    picture at a lower resolution (mean color within 1 %)."""
    from PIL import Image

    asset = load_object("048_hammer", ycb_dir)
    assert asset.texture_file is not None
    with Image.open(asset.texture_file) as image:
        assert max(image.size) > MAX_TEXTURE_SIDE  # else this test checks nothing
        original_mean = np.asarray(image.convert("RGB"), dtype=float).mean(axis=(0, 1))
    spec = mujoco.MjSpec()
    build_object_model(asset).add_to(spec, np.eye(4))
    compiled = spec.compile()
    assert compiled.ntex == 1
    assert (compiled.tex_width[0], compiled.tex_height[0]) == (MAX_TEXTURE_SIDE,) * 2
    texels = compiled.tex_data.reshape(-1, 3).astype(float)
    np.testing.assert_allclose(texels.mean(axis=0), original_mean, rtol=0.01)
