"""One depth renderer kept per process across scenes built alike (the trials of a sweep).

A new :class:`SceneRenderer` costs about 0.25 s on software GL (GL context, upload of meshes
and textures, first draws): more than rendering four views with it. Scenes that
:func:`simgrasp.scenes.scene.build_scene` makes from the same ``ObjectModel`` instance, the same
gripper and the same ``SceneConfig`` differ only in state that reaches the renderer through
``data``: the object's rest pose and the cameras placed around it. The renderer of the first
such scene draws the others exactly as a fresh one would (tested). A scene built otherwise
replaces it, so at most one renderer (one GL context) is kept; it is closed at exit. A GL
context hangs a ``fork``-ed child: call :func:`close_kept_renderer` before forking (or use
the ``spawn`` start method, as simgrasp's own workers do).
"""

from __future__ import annotations

import atexit
from dataclasses import dataclass
from typing import TYPE_CHECKING

from simgrasp.scenes.render import SceneRenderer  # before mujoco: it picks the GL platform
from simgrasp.scenes.scene import Scene, SceneConfig

if TYPE_CHECKING:
    import mujoco

    from simgrasp.assets.model import ObjectModel


@dataclass(frozen=True, eq=False)
class _Kept:
    object_model: ObjectModel
    gripper: str
    config: SceneConfig
    layout: tuple[float, ...]
    renderer: SceneRenderer

    def serves(self, scene: Scene) -> bool:
        return (
            self.object_model is scene.object_model
            and self.gripper == scene.gripper.gripper.name
            and self.config == scene.config
            and self.layout == _layout(scene.model)
        )


_kept: _Kept | None = None


def _layout(model: mujoco.MjModel) -> tuple[float, ...]:
    """Sizes and the depth range a renderer is made for: a guard that the scenes match."""
    counts = (model.nbody, model.ngeom, model.nmesh, model.ntex, model.nmat, model.ncam)
    return (*counts, model.nlight, float(model.stat.extent))


def kept_renderer(scene: Scene) -> SceneRenderer:
    """The process's renderer for scenes built like ``scene`` (made on first use; a scene built
    from another object model, gripper or config replaces it). Do not close it: it is closed
    when replaced, by :func:`close_kept_renderer`, or at exit."""
    global _kept
    if _kept is not None and _kept.serves(scene):
        return _kept.renderer
    close_kept_renderer()
    renderer = SceneRenderer(scene.model)
    _kept = _Kept(
        scene.object_model, scene.gripper.gripper.name, scene.config, _layout(scene.model), renderer
    )
    return renderer


def close_kept_renderer() -> None:
    """Free the kept renderer's GL resources, if any (idempotent)."""
    global _kept
    if _kept is not None:
        _kept.renderer.close()
        _kept = None


atexit.register(close_kept_renderer)
