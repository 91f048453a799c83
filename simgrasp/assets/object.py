"""The object interface every stage uses, whatever the object's source (YCB scan or generated)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import trimesh

from simgrasp.labels import HandleLabel


@dataclass(frozen=True)
class ObjectAsset:
    """A rigid object ready to be decomposed and simulated.

    Attributes:
        name: unique name, e.g. ``"033_spatula"`` or ``"gen_hammer_s3"``.
        mesh: the reference surface in the object's own frame (meters; for YCB, the scan's
            frame: z up, resting near z = 0).
        handle: labeled handle region(s), in the same frame.
        mass: kilograms (YCB: published mass; generated: density x volume).
        source: ``"ycb"``, ``"generated"`` or ``"mesh"`` (a mesh file spec,
            :mod:`simgrasp.assets.mesh_object`).
        mesh_file: the file the visual mesh came from (YCB ``textured.obj``), if any.
        texture_file: the texture image for ``mesh_file``, if any.
        friction: the surface's sliding friction, if the object's source sets one (else the
            model's default).
        handle_source: where ``handle`` came from: ``"shipped"`` (the package's YCB labels,
            a generated tool's exact one), ``"file"`` (a ``handles`` file the user gave) or
            ``"automatic"`` (:mod:`simgrasp.assets.auto_handles`, a mesh given none).
    """

    name: str
    mesh: trimesh.Trimesh
    handle: HandleLabel
    mass: float
    source: Literal["ycb", "generated", "mesh"]
    mesh_file: Path | None = None
    texture_file: Path | None = None
    friction: float | None = None
    handle_source: Literal["shipped", "file", "automatic"] = "shipped"
