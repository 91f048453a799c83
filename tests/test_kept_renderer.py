"""The renderer kept across scenes built alike draws exactly what a fresh renderer draws."""

from __future__ import annotations

import numpy as np
import pytest

from simgrasp.assets.model import build_object_model
from simgrasp.assets.registry import load_object
from simgrasp.grippers import make_gripper
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.kept_renderer import RendererKeeper
from simgrasp.scenes.observe import render_views
from simgrasp.scenes.render import SceneRenderer
from simgrasp.scenes.scene import build_scene

CONFIG = SceneConfig(num_views=2)


def test_a_scene_built_alike_is_drawn_as_by_a_fresh_renderer(ycb_dir: str) -> None:
    """Seed 1's hammer lies elsewhere, seen by cameras elsewhere, than seed 0's: the renderer
    made for seed 0 must still give seed 1's exact depth, segmentation and camera poses."""
    model = build_object_model(load_object("048_hammer", ycb_dir))
    first = build_scene(model, make_gripper("builtin"), CONFIG, seed=0)
    second = build_scene(model, make_gripper("builtin"), CONFIG, seed=1)
    assert not np.allclose(first.world_T_object, second.world_T_object)
    with RendererKeeper() as keeper:
        renderer = keeper.renderer_for(first)
        render_views(first, renderer)
        assert keeper.renderer_for(second) is renderer
        kept = render_views(second, renderer)
    assert renderer.closed
    with SceneRenderer(second.model) as fresh_renderer:
        fresh = render_views(second, fresh_renderer)
    for a, b in zip(kept, fresh, strict=True):
        assert (a.depth > 0).sum() > 1000  # the views see something
        np.testing.assert_array_equal(a.depth, b.depth)
        np.testing.assert_array_equal(a.geom_ids, b.geom_ids)
        np.testing.assert_array_equal(a.world_T_cam, b.world_T_cam)


@pytest.mark.menagerie
def test_a_scene_built_otherwise_replaces_the_kept_renderer() -> None:
    hammer = build_object_model(load_object("gen_hammer"))
    mug = build_object_model(load_object("gen_mug"))
    scenes = [
        build_scene(hammer, make_gripper("builtin"), CONFIG, seed=0),
        build_scene(hammer, make_gripper("builtin"), SceneConfig(num_views=1), seed=0),
        build_scene(mug, make_gripper("builtin"), CONFIG, seed=0),
        build_scene(mug, make_gripper("robotiq_2f85"), CONFIG, seed=0),
    ]
    with RendererKeeper() as keeper:
        renderers = [keeper.renderer_for(scene) for scene in scenes]
        assert len({id(r) for r in renderers}) == len(scenes)
        assert all(r.closed for r in renderers[:-1])  # one GL context kept at a time
        assert not renderers[-1].closed
    assert renderers[-1].closed


def test_a_session_owns_its_renderer_and_models() -> None:
    """The chain renders with the session it is given and leaves it open; closing the session
    frees the GL context, and a session used as a context manager closes itself."""
    from simgrasp.grasping.session import Session
    from simgrasp.grasping.trials.chain import run_chain
    from simgrasp.grasping.trials.chain_config import ChainConfig

    config = ChainConfig.of(scene__num_views=1)
    with Session() as session:
        model = session.model("gen_hammer")
        assert session.model("gen_hammer") is model  # built once
        first = run_chain(model, config, seed=0, session=session)
        renderer = session.renderers.renderer_for(
            build_scene(model, make_gripper("builtin"), config.scene, seed=1)
        )
        assert not renderer.closed  # the chain's renderer, kept for scenes built alike
        again = run_chain(model, config, seed=0, session=session)
    assert renderer.closed
    alone = run_chain(build_object_model(load_object("gen_hammer")), config, seed=0)
    assert first.to_json() | {"timings_s": None} == again.to_json() | {"timings_s": None}
    assert alone.to_json() | {"timings_s": None} == first.to_json() | {"timings_s": None}
