"""What a run of trials keeps between trials, owned by one object that gives it back.

A :class:`Session` holds the depth renderer (one GL context, shared by the scenes built alike:
:class:`~simgrasp.scenes.kept_renderer.RendererKeeper`) and the object models it built (CoACD
hulls compiled into MuJoCo models, ~0.1-1 s each even with the hulls cached on disk). The
chain (:func:`~simgrasp.grasping.trials.chain.run_chain`), ``simgrasp.run_trial`` and the
commands are given one; without one, a call makes its own and closes it before returning.
Like mujoco's ``Rollout`` and Gymnasium's ``MujocoEnv``, it is a context manager::

    with simgrasp.Session() as session:
        results = [simgrasp.run_trial("gen_hammer", seed=k, session=session) for k in range(4)]

A GL context must not cross a ``fork``: close the session before forking (simgrasp's own
worker processes are spawned).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from simgrasp.scenes.kept_renderer import RendererKeeper

if TYPE_CHECKING:
    from simgrasp.assets.model import ObjectModel


class Session:
    """The renderer and object models of a run of trials (module docstring).

    Args:
        ycb_dir: the YCB data root object names are looked up in (default:
            ``$SIMGRASP_YCB_DIR``, see :func:`simgrasp.assets.model.model_for`).
    """

    def __init__(self, ycb_dir: str | os.PathLike[str] | None = None) -> None:
        self.ycb_dir = None if ycb_dir is None else os.fspath(ycb_dir)
        self.renderers = RendererKeeper()
        self._models: dict[str, ObjectModel] = {}

    def model(self, name: str) -> ObjectModel:
        """The model of the object ``name`` (a catalog name or a mesh path), built on first
        use and kept for the session's later trials."""
        if name not in self._models:
            from simgrasp.assets.model import model_for

            self._models[name] = model_for(name, self.ycb_dir)
        return self._models[name]

    def close(self) -> None:
        """Free the renderer's GL resources and forget the models (idempotent)."""
        self.renderers.close()
        self._models.clear()

    def __enter__(self) -> Session:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


_WORKER_SESSIONS: dict[str | None, Session] = {}
"""This process's worker sessions, by YCB folder (:func:`worker_session`)."""


def worker_session(ycb_dir: str | None = None) -> Session:
    """The session of the run engine's tasks in this process (its trials share the renderer
    and the object models). A spawned worker's session lives as long as the worker process;
    a run whose tasks ran in this process closes it with :func:`close_worker_sessions`."""
    if ycb_dir not in _WORKER_SESSIONS:
        _WORKER_SESSIONS[ycb_dir] = Session(ycb_dir)
    return _WORKER_SESSIONS[ycb_dir]


def close_worker_sessions() -> None:
    """Close and forget this process's worker sessions (the end of a run's tasks here)."""
    while _WORKER_SESSIONS:
        _WORKER_SESSIONS.popitem()[1].close()
