"""Command-line options that say how to read a mesh file as an object, declared once."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from simgrasp.config import setting


@dataclass(frozen=True, kw_only=True)
class MeshObjectOptions:
    """``--scale``/``--units``/``--mass``/``--density``/``--friction``/``--handles`` of an
    OBJECT given as a mesh file (:mod:`simgrasp.assets.mesh_object`)."""

    scale: float | None = None
    """Mesh object: multiply the file's coordinates by this to get meters."""
    units: Literal["mm", "cm", "m"] | None = setting(None, main=True)
    """Mesh object: the file's units (instead of --scale)."""
    mass: float | None = None
    """Mesh object: mass (kg)."""
    density: float | None = None
    """Mesh object: density (kg/m^3; default 500) times its volume, instead of --mass."""
    friction: float | None = None
    """Mesh object: sliding friction of its surface."""
    handles: Path | None = None
    """Handle label file (format of models/handles/ycb_handles.json) for the object."""

    def object_name(self, name: str) -> str:
        """``name`` with these options folded into its mesh spec."""
        from simgrasp.assets.mesh_object import with_options

        return with_options(
            name,
            scale=self.scale,
            units=self.units,
            mass=self.mass,
            density=self.density,
            friction=self.friction,
            handles=self.handles,
        )
