"""Grasp trials on real YCB objects (SIMGRASP_YCB_DIR) with both grippers.

Handle grasps come from each object's shipped handle label (midpoint and axis of its longest
region); the far grasp is placed 10 cm beyond the object's footprint; the hammer's head is the
part of the mesh beyond the end of its labeled handle; the mug stands upright and is pinched
across its strap.
"""

from __future__ import annotations

import numpy as np
import pytest
from data_needs import ROBOTIQ
from test_trial import handle_center_axis, top_down_grasp

from simgrasp.assets.model import build_object_model
from simgrasp.assets.object import ObjectAsset
from simgrasp.assets.registry import load_object
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers import make_gripper
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.scene import Scene, build_scene

OBJECTS = ("048_hammer", "033_spatula")
GRIPPERS = ("builtin", ROBOTIQ)
OBJECT_GRIPPERS = [
    pytest.param(
        (o, g), marks=[pytest.mark.menagerie] if g == "robotiq_2f85" else [], id=str((o, g))
    )
    for o in OBJECTS
    for g in ("builtin", "robotiq_2f85")
]


@pytest.fixture(scope="module", params=OBJECT_GRIPPERS)
def ycb_scene(request: pytest.FixtureRequest, ycb_dir: str) -> Scene:
    object_name, gripper = request.param
    model = build_object_model(load_object(object_name, ycb_dir))
    return build_scene(model, make_gripper(gripper), seed=0)


def longest_region_grasp(scene: Scene) -> Grasp:
    regions = scene.object_model.asset.handle.regions
    assert regions, f"{scene.object_name} should have a labeled handle"

    def length(region) -> float:
        if hasattr(region, "half_extents"):
            return float(2 * region.half_extents.max())
        return float(np.linalg.norm(region.p1 - region.p0))

    center, axis = handle_center_axis(max(regions, key=length))
    return top_down_grasp(scene, center, axis)


def test_ycb_handle_grasp_lifts_on_handle(ycb_scene: Scene) -> None:
    """The handle grasp lifts and holds the object on its handle. The Menagerie 2F-85 (about
    45 N) may lose the light, long spatula to the weight-sized tugs (it spins out)."""
    result = run_trial(ycb_scene, longest_region_grasp(ycb_scene))
    if ycb_scene.gripper.gripper.name == "builtin":
        assert result.success is True, result.failure
    else:
        assert result.failure in (None, "dropped_in_perturbation"), result.failure
    assert result.on_handle
    config = TrialConfig()
    assert result.lift_height > config.lifted_fraction * config.lift_height


def test_ycb_far_grasp_is_missed(ycb_scene: Scene) -> None:
    mesh_world = ycb_scene.object_model.asset.mesh.copy()
    mesh_world.apply_transform(ycb_scene.world_T_object)
    grasp = longest_region_grasp(ycb_scene)
    world_T_tcp = grasp.world_T_tcp.copy()
    world_T_tcp[0, 3] = mesh_world.bounds[1, 0] + 0.12
    assert mesh_world.nearest.on_surface([world_T_tcp[:3, 3]])[1][0] > 0.10
    result = run_trial(ycb_scene, Grasp(world_T_tcp, grasp.width))
    assert result.failure == "missed"
    assert result.success is False


@pytest.fixture(scope="module", params=GRIPPERS)
def ycb_hammer_scene(request: pytest.FixtureRequest, ycb_dir: str) -> Scene:
    model = build_object_model(load_object("048_hammer", ycb_dir))
    scene = build_scene(model, make_gripper(request.param), seed=0)
    assert abs(scene.world_T_object[2, 2]) > 0.95, "seed 0 should lay the hammer flat"
    return scene


def hammer_head(asset: ObjectAsset) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(head center, handle axis, across-the-head direction, head length), object frame: the
    head is the mesh beyond the labeled handle's far end (1 cm margin)."""
    vertices = asset.mesh.vertices
    inside = asset.handle.contains(vertices)
    centroid = vertices[inside].mean(axis=0)
    axis = np.linalg.svd(vertices[inside] - centroid)[2][0]
    along = (vertices - centroid) @ axis
    if np.sum(along > along[inside].max()) < np.sum(along < along[inside].min()):
        axis, along = -axis, -along
    head = vertices[along > along[inside].max() + 0.01]
    assert len(head) > 100, "the hammer's head should extend beyond its handle label"
    across = np.cross([0.0, 0.0, 1.0], axis)
    across /= np.linalg.norm(across)
    head_across = (head - head.mean(axis=0)) @ across
    return head.mean(axis=0), axis, across, float(np.ptp(head_across))


def test_ycb_hammer_head_grasp_is_not_on_handle(ycb_hammer_scene: Scene) -> None:
    """Closing across one arm of the head: the built-in gripper lifts the hammer by it, the
    weaker 2F-85 lets it slip (a 0.66 kg hammer held 5 cm off its axis); never on the handle."""
    center, _, across, head_length = hammer_head(ycb_hammer_scene.object_model.asset)
    arm = center + across * 0.3 * head_length  # mid-arm, past the neck where the handle joins
    result = run_trial(ycb_hammer_scene, top_down_grasp(ycb_hammer_scene, arm, across))
    if ycb_hammer_scene.gripper.gripper.name == "builtin":
        assert result.success is True, result.failure
    else:
        assert result.failure in (None, "slipped_in_lift", "dropped_in_perturbation")
    assert not result.on_handle
    assert result.handle_fraction < 0.5


def test_ycb_hammer_too_wide_head_is_not_lifted(ycb_hammer_scene: Scene) -> None:
    """Closing along the head's length (longer than the stroke) cannot lift the hammer."""
    center, axis, _, head_length = hammer_head(ycb_hammer_scene.object_model.asset)
    assert head_length > ycb_hammer_scene.gripper.gripper.max_opening
    result = run_trial(ycb_hammer_scene, top_down_grasp(ycb_hammer_scene, center, axis))
    assert result.success is False
    assert result.failure in ("approach_collision", "missed", "slipped_in_lift")
    assert result.lift_height < 0.05


def strap_pinch(asset: ObjectAsset) -> np.ndarray:
    """Object-frame pinch across the YCB mug's handle strap: at mid-height of its label, the
    strap's outer vertical bar (the label's vertices within 9 mm of its outermost x), the jaws
    closing across the bar's 14 mm width (y) and approaching toward the mug's axis (-x)."""
    vertices = asset.mesh.vertices[asset.handle.contains(asset.mesh.vertices)]
    mid = vertices[np.abs(vertices[:, 2] - np.median(vertices[:, 2])) < 0.004]
    bar = mid[mid[:, 0] > mid[:, 0].max() - 0.009]
    center = (bar.min(axis=0) + bar.max(axis=0)) / 2
    assert 0.010 < np.ptp(bar[:, 1]) < 0.016, "the strap should be about 14 mm wide"
    object_T_tcp = np.eye(4)
    object_T_tcp[:3, :3] = np.column_stack([(0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0)])
    object_T_tcp[:3, 3] = center
    return object_T_tcp


@pytest.mark.parametrize("gripper", GRIPPERS)
def test_upright_mug_is_held_by_its_strap(gripper: str, ycb_dir: str) -> None:
    """A pinch across the standing mug's thin strap lifts the mug and survives the tugs: the
    built-in gripper's pads must settle on a part only 14 mm wide rather than bounce on it."""
    model = build_object_model(load_object("025_mug", ycb_dir))
    scene = build_scene(model, make_gripper(gripper), SceneConfig(placement="upright"), seed=0)
    grasp = Grasp.from_object_frame(
        strap_pinch(model.asset), scene.world_T_object, scene.gripper.gripper.max_opening
    )
    result = run_trial(scene, grasp)
    assert result.success is True, result.failure
    assert result.on_handle
