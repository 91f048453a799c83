"""A GL context must not cross a ``fork``: a child forked from a process that made one hangs
in its first GL call (EGL and OSMesa alike). Such a child renders depth with the GL-free ray
caster instead (:func:`simgrasp.scenes.render.select_backend`), so gymnasium's default
``fork`` vector envs work after the parent used an env; only a forced GL backend or an RGB
picture there fails, at once and saying what to do. This module never imports mujoco."""

from __future__ import annotations

import os

SPAWN_HINT = (
    "start worker processes with spawn, e.g. gymnasium.make_vec(..., "
    'vectorization_mode="async", vector_kwargs={"context": "spawn"}) or '
    'multiprocessing.get_context("spawn")'
)

_gl_owner: int | None = None
"""The pid of the process that made a GL context, in it and in its forked children."""
_forked_from_gl = False


def note_gl_context() -> None:
    """Record that this process is making a GL context (call before creating it)."""
    global _gl_owner
    check_gl_allowed()
    _gl_owner = os.getpid()


def _after_fork_in_child() -> None:
    global _forked_from_gl
    _forked_from_gl = _forked_from_gl or _gl_owner is not None


os.register_at_fork(after_in_child=_after_fork_in_child)


def forked_from_gl() -> bool:
    """Whether this process was forked from one that had made a GL context."""
    return _forked_from_gl


def check_gl_allowed() -> None:
    """Raise RuntimeError in a process forked from one that made a GL context."""
    if _forked_from_gl:
        raise RuntimeError(
            f"this process was forked from process {_gl_owner}, which had made a GL context "
            f"for rendering; GL hangs in such a child: {SPAWN_HINT}"
        )
