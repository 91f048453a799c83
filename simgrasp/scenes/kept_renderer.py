"""A depth renderer kept across scenes built alike (the trials of a sweep, an env's episodes).

A new :class:`SceneRenderer` costs about 0.25 s on software GL (GL context, upload of meshes
and textures, first draws): more than rendering four views with it. Scenes that
:func:`simgrasp.scenes.scene.build_scene` makes from the same ``ObjectModel`` instance, the same
gripper and the same ``SceneConfig`` (in clutter, with the same distractor models) differ only
in state that reaches the renderer through ``data``: the object's rest pose and the cameras
placed around it. The renderer of the first such scene draws the others exactly as a fresh
one would (tested). A scene built otherwise replaces it, so a :class:`RendererKeeper` holds at
most one renderer (one GL context).

A keeper belongs to whoever runs the scenes: a :class:`~simgrasp.grasping.session.Session`
(the chain, the commands) or an env, which closes it. A GL context hangs a ``fork``-ed child:
close the keeper before forking (or use the ``spawn`` start method, as simgrasp's own workers
do).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.render import SceneRenderer
from simgrasp.scenes.scene import Scene

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
    distractors: tuple[ObjectModel, ...] = ()

    def serves(self, scene: Scene) -> bool:
        return (
            self.object_model is scene.object_model
            and len(self.distractors) == len(scene.distractors)
            and all(a is d.model for a, d in zip(self.distractors, scene.distractors, strict=True))
            and self.gripper == scene.gripper.gripper.name
            and self.config == scene.config
            and self.layout == _layout(scene.model)
        )


def _layout(model: mujoco.MjModel) -> tuple[float, ...]:
    """Sizes and the depth range a renderer is made for: a guard that the scenes match."""
    counts = (model.nbody, model.ngeom, model.nmesh, model.ntex, model.nmat, model.ncam)
    return (*counts, model.nlight, float(model.stat.extent))


class RendererKeeper:
    """Holds one :class:`SceneRenderer` for consecutive scenes built alike."""

    def __init__(self) -> None:
        self._kept: _Kept | None = None

    def renderer_for(self, scene: Scene) -> SceneRenderer:
        """The kept renderer if it serves scenes built like ``scene``, else a new one (the old
        one closed). Do not close it yourself: :meth:`close` does."""
        if self._kept is not None and self._kept.serves(scene):
            return self._kept.renderer
        self.close()
        renderer = SceneRenderer(scene.model)
        self._kept = _Kept(
            scene.object_model,
            scene.gripper.gripper.name,
            scene.config,
            _layout(scene.model),
            renderer,
            tuple(d.model for d in scene.distractors),
        )
        return renderer

    def close(self) -> None:
        """Free the kept renderer's GL resources, if any (idempotent)."""
        if self._kept is not None:
            self._kept.renderer.close()
            self._kept = None

    def __enter__(self) -> RendererKeeper:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()
