"""``simgrasp label-handles OBJECT --out handles.json``: find the handle of any mesh.

OBJECT is a mesh file (.obj .stl .ply .off .glb ...), scaled to meters (``--scale`` times
``--units``), or the name of an object the other commands take (a YCB id, ``gen_<kind>_s<N>``,
a catalog name; in its own frame, as :func:`simgrasp.assets.registry.load_object_mesh` loads
it: to compare the automatic label with a shipped or exact one). It is scanned from many
directions, our quadric detector runs on every scan and its candidates are clustered into the
oriented boxes of ``models/handles/ycb_handles.json`` (:mod:`simgrasp.autolabel.auto_label`), in
the scaled mesh's own frame. ``--plot`` draws the label on the scanned surface for review.
Read the result with ``simgrasp.labels.load_handle_label``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from simgrasp.assets.mesh_object import MESH_SUFFIXES
from simgrasp.autolabel.config import AutoLabelConfig
from simgrasp.config import setting
from simgrasp.errors import SimgraspError

if TYPE_CHECKING:
    import trimesh

MeshUnits = Literal["m", "cm", "mm"]
METERS_PER_UNIT: dict[str, float] = {"m": 1.0, "cm": 0.01, "mm": 0.001}


EXAMPLES = ("simgrasp label-handles wrench.stl --units mm --out handles.json",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options:
    object: str = setting(positional=True, metavar="OBJECT")
    """Mesh file (.obj .stl .ply .off .glb .gltf), in --units times --scale; or an object
    name (a YCB id, gen_<kind>_s<N>, a catalog name), in meters."""
    scale: float = 1.0
    """Multiply a mesh file by this (e.g. an ACRONYM file's object/scale) ..."""
    units: MeshUnits = setting("m", main=True)
    """... and by the meters per unit of these units."""
    name: str | None = None
    """Object name in the output file (default: the mesh file's stem, or the object name)."""
    out: Path = setting(Path("handles.json"), output="file", suffixes=(".json",), main=True)
    """Output label file (the format of models/handles/ycb_handles.json)."""
    plot: Path | None = setting(None, metavar="OUT.png", output="plot", main=True)
    """Also write a picture of the label on the scanned surface."""
    label: AutoLabelConfig = field(default_factory=AutoLabelConfig)


def run(options: Options) -> int:
    from simgrasp.autolabel.auto_label import auto_handle_label
    from simgrasp.labels import write_label_file
    from simgrasp.stdout_guard import stdout_to_stderr

    path = Path(options.object)
    if path.is_file() or path.suffix.lower() in MESH_SUFFIXES:
        name = options.name or path.stem
        mesh = load_scaled_mesh(path, options.scale, options.units, name)
        source = f"{path.name} (scale {options.scale:g}, units {options.units})"
    else:
        name = options.name or options.object
        mesh = object_mesh(options)
        source = f"object {options.object}"
    with stdout_to_stderr():
        result = auto_handle_label(mesh, name, options.label)
    description = (
        f"Automatic handle label of {source} by simgrasp label-handles "
        f"(--label.seed {options.label.seed}), in the scaled mesh's frame, meters."
    )
    options.out.parent.mkdir(parents=True, exist_ok=True)
    write_label_file(options.out, {name: result.label}, description)
    regions = len(result.label.regions)
    print(f"{name}: {len(result.parts)} handle part(s), {regions} box(es) -> {options.out}")
    if options.plot:
        from simgrasp.plots.auto_label import draw_auto_label

        options.plot.parent.mkdir(parents=True, exist_ok=True)
        print(f"  plot written to {draw_auto_label(result, options.plot)}")
    return 0


def object_mesh(options: Options) -> trimesh.Trimesh:
    """The mesh of the object named by ``options.object`` (not a mesh file), in its own frame:
    ``--scale`` and ``--units`` belong to mesh files and are refused here."""
    from simgrasp.assets.registry import load_object_mesh

    if options.scale != 1.0 or options.units != "m":
        raise SimgraspError(
            f"--scale and --units apply to a mesh file; {options.object!r} is an object name "
            "(already in meters)"
        )
    return load_object_mesh(options.object)


def load_scaled_mesh(path: Path, scale: float, units: str, name: str) -> trimesh.Trimesh:
    """The mesh at ``path`` times ``scale`` and the meters per ``units``, checked
    (:func:`simgrasp.assets.mesh_check.validate_mesh`: faces, finite, plausible size)."""
    import numpy as np
    import trimesh

    from simgrasp.assets.mesh_check import MeshError, validate_mesh
    from simgrasp.assets.mesh_object import size_hint

    if not scale > 0 or not np.isfinite(scale):
        raise SimgraspError(f"--scale must be a positive number, got {scale}")
    if units not in METERS_PER_UNIT:
        raise SimgraspError(f"unknown --units {units!r}; use one of m, cm, mm")
    if not path.is_file():
        raise SimgraspError(f"mesh file {path} does not exist")
    try:
        loaded = trimesh.load(path, force="mesh", skip_materials=True)
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise SimgraspError(f"cannot read mesh {path}: {type(exc).__name__}: {exc}") from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise SimgraspError(f"mesh {path} is empty (no faces)")
    factor = scale * METERS_PER_UNIT[units]
    loaded.apply_scale(factor)
    try:
        validate_mesh(loaded, name, path)
    except MeshError as exc:
        hint = size_hint(f"{exc} (check --scale / --units)", loaded, path, factor)
        raise SimgraspError(hint) from exc
    return loaded
