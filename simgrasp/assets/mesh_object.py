"""Objects from any mesh file: ``PATH[?scale=S&mass=M&friction=F&handles=FILE]``.

An object spec names a mesh file (``.obj``, ``.stl``, ``.ply``, ``.off``, ``.glb``, ``.gltf``)
and, after a ``?``, how to read it as a rigid object (``&``-separated ``key=value``):

- ``scale`` (the mesh times it is in meters) or ``units`` (``mm``, ``cm`` or ``m``), default m;
- ``mass`` (kg) or ``density`` (kg/m^3, times the solid's volume), default
  :data:`DEFAULT_DENSITY`;
- ``friction``: the sliding friction of the object's surface (default: the model's 0.8);
- ``handles``: a handle label file in the format of ``models/handles/ycb_handles.json``; its
  entry named as the mesh file's stem, or its only entry, is the object's handle (default: the
  automatic label ``simgrasp label-handles`` finds, :mod:`simgrasp.assets.auto_handles`).

The spec is the object's name everywhere (``trial``, ``evaluate``, ``label-grasps``, the env,
the records), so a worker process rebuilds the same object from it. The mesh stays in its
file's frame (scaled, never re-centered: grasp files such as ACRONYM's are in that frame).

Bad meshes fail with one line naming the file: unreadable or empty, zero volume, a size that
is implausible in meters (with the scale that would fix it), more than
:data:`MAX_LOOSE_PARTS` loose parts. A mesh that is not watertight is usable: a note says so,
its mass comes from its convex hull's volume and its collisions from CoACD's parts.
"""

from __future__ import annotations

import sys
import warnings
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Literal
from urllib.parse import parse_qsl, urlencode

import numpy as np
import trimesh

from simgrasp.assets.auto_handles import automatic_handle_label
from simgrasp.assets.mesh_check import (
    MAX_PLAUSIBLE_EXTENT_M,
    MIN_PLAUSIBLE_EXTENT_M,
    MeshError,
    mass_properties_solid,
    outward,
    unreadable_reason,
    validate_mesh,
)
from simgrasp.assets.object import ObjectAsset
from simgrasp.errors import DataNotFoundError, SimgraspError, fix_for_caller
from simgrasp.labels import HandleLabel, load_label_file

MESH_SUFFIXES = (".obj", ".stl", ".ply", ".off", ".glb", ".gltf")
UNITS = {"mm": 0.001, "cm": 0.01, "m": 1.0}
DEFAULT_DENSITY = 500.0
"""kg/m^3 of a mesh object given neither ``mass`` nor ``density`` (between wood and water)."""
MAX_LOOSE_PARTS = 1000
"""More disconnected pieces than this is a triangle soup, not an object (CoACD would take
hours and the hulls would not follow it)."""
MIN_VOLUME_M3 = 1e-9
"""A solid below 1 mm^3 has no volume to simulate (a flat or degenerate mesh)."""
_KEYS = ("scale", "units", "mass", "density", "friction", "handles")


@dataclass(frozen=True)
class MeshObjectSpec:
    """How to read one mesh file as an object (see the module docstring; m, kg)."""

    path: Path
    scale: float | None = None
    units: str | None = None
    mass: float | None = None
    density: float | None = None
    friction: float | None = None
    handles: Path | None = None

    def __post_init__(self) -> None:
        if self.scale is not None and self.units is not None:
            raise SimgraspError(f"object {self.path}: give a scale or units, not both")
        if self.units is not None and self.units not in UNITS:
            raise SimgraspError(f"object {self.path}: units must be one of {', '.join(UNITS)}")
        if self.mass is not None and self.density is not None:
            raise SimgraspError(f"object {self.path}: give a mass or a density, not both")
        for name in ("scale", "mass", "density", "friction"):
            value = getattr(self, name)
            if value is not None and not (np.isfinite(value) and value > 0):
                raise SimgraspError(f"object {self.path}: {name} must be positive, got {value}")

    @property
    def factor(self) -> float:
        """What the file's coordinates are multiplied by to get meters."""
        if self.scale is not None:
            return self.scale
        return UNITS[self.units or "m"]

    def name(self) -> str:
        """The spec as an object name (``PATH?key=value...``; only the keys given)."""
        query = {k: str(getattr(self, k)) for k in _KEYS if getattr(self, k) is not None}
        return str(self.path) + (f"?{urlencode(query)}" if query else "")


def split_spec(name: str) -> tuple[str, str]:
    """An object name's base and query (``BASE?key=value&...``; the query ``""`` when none).
    A name ending in a mesh suffix is all base, ``?`` or not (a file named ``odd?name.stl``);
    otherwise the query starts at the last ``?`` (its own are percent-encoded)."""
    if "?" not in name or name.lower().endswith(MESH_SUFFIXES):
        return name, ""
    base, _, query = name.rpartition("?")
    return base, query


def is_mesh_spec(name: str) -> bool:
    """Whether an object name is a mesh file spec (its path ends in a mesh suffix)."""
    return split_spec(name)[0].lower().endswith(MESH_SUFFIXES)


def file_stem(name: str) -> str:
    """The name to give the files written for object ``name``: a mesh spec's file stem
    (``mug`` of ``/data/mug.obj?units=mm``, which as a file name would hold a ``?`` and, joined
    to an output folder, point beside the mesh), else ``name`` itself."""
    return Path(split_spec(name)[0]).stem if is_mesh_spec(name) else name


def parse_mesh_spec(name: str) -> MeshObjectSpec:
    """The :class:`MeshObjectSpec` of ``PATH[?key=value&...]``."""
    path, query = split_spec(name)
    values: dict[str, object] = {}
    for key, value in parse_qsl(query, keep_blank_values=True, strict_parsing=False):
        if key not in _KEYS:
            raise SimgraspError(f"object {path}: unknown key {key!r}; use {', '.join(_KEYS)}")
        if key == "units":
            values[key] = value
        elif key == "handles":
            values[key] = Path(value)
        else:
            try:
                values[key] = float(value)
            except ValueError:
                raise SimgraspError(
                    f"object {path}: {key} must be a number, got {value!r}"
                ) from None
    return MeshObjectSpec(Path(path), **values)  # type: ignore[arg-type]


def with_options(name: str, **options: float | str | Path | None) -> str:
    """``name`` with the options given (not None) added to its spec: the command line's
    ``--scale``/``--units``/``--mass``/``--density``/``--friction``/``--handles``; they replace
    the spec's own (``--scale`` its ``units``, ``--mass`` its ``density`` and the reverse). A
    name that is no mesh file takes only ``handles`` (other options: an error naming them)."""
    given = {k: v for k, v in options.items() if v is not None}
    if not given:
        return name
    check_options(given)
    if not is_mesh_spec(name):
        if mesh_only := sorted(set(given) - {"handles"}):
            verb = "applies" if len(mesh_only) == 1 else "apply"
            raise SimgraspError(
                f"--{'/--'.join(mesh_only)} only {verb} to a mesh file object, not {name!r}"
            )
        return f"{split_spec(name)[0]}?{urlencode({'handles': str(given['handles'])})}"
    spec = parse_mesh_spec(name)
    fields: dict[str, object] = {k: getattr(spec, k) for k in _KEYS}
    fields.update({k: Path(str(v)) if k == "handles" else v for k, v in given.items()})
    if "scale" in given:
        fields["units"] = None
    if "units" in given:
        fields["scale"] = None
    if "mass" in given:
        fields["density"] = None
    if "density" in given:
        fields["mass"] = None
    return MeshObjectSpec(spec.path, **fields).name()  # type: ignore[arg-type]


def check_options(given: dict[str, float | str | Path]) -> None:
    """Refuse command-line object options that contradict each other (``--scale`` and
    ``--units``, ``--mass`` and ``--density``) or a ``--handles`` file that is a mesh."""
    for one, other in (("scale", "units"), ("mass", "density")):
        if one in given and other in given:
            raise SimgraspError(f"give --{one} or --{other}, not both")
    handles = given.get("handles")
    if handles is not None and str(handles).lower().endswith(MESH_SUFFIXES):
        raise SimgraspError(
            f"--handles {handles}: a mesh file, not a JSON handle label file (the format of "
            "models/handles/ycb_handles.json)"
        )


def read_mesh(spec: MeshObjectSpec) -> trimesh.Trimesh:
    """The file's triangles times the spec's factor (meters), checked (one-line errors), with
    no handle label: what :func:`load_mesh_object` simulates and ``label-handles`` scans."""
    path = spec.path
    if not path.is_file():
        raise DataNotFoundError(f"object mesh {path} does not exist")
    try:
        loaded = trimesh.load(path, force="mesh", process=False, skip_materials=True)
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise SimgraspError(
            f"object mesh {path}: cannot read it ({unreadable_reason(exc)})"
        ) from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise SimgraspError(f"object mesh {path}: no triangles in the file (empty mesh)")
    vertices = np.asarray(loaded.vertices, dtype=float) * spec.factor
    raw = trimesh.Trimesh(vertices, np.asarray(loaded.faces, dtype=np.int64), process=False)
    try:
        validate_mesh(raw, path.stem, path)
    except MeshError as exc:
        raise SimgraspError(size_hint(str(exc), raw, spec.path, spec.factor)) from None
    mesh = outward(trimesh.Trimesh(raw.vertices, raw.faces, process=True))
    parts = mesh.body_count
    if parts > MAX_LOOSE_PARTS:
        raise SimgraspError(
            f"object mesh {path}: {parts} loose parts (more than {MAX_LOOSE_PARTS}): a triangle "
            "soup, not one object; merge or remesh it first"
        )
    return mesh


def size_hint(message: str, mesh: trimesh.Trimesh, path: Path | str, factor: float) -> str:
    """``message`` with the units or scale that would make ``mesh`` (m, the file at ``path``
    times ``factor``) a hand-sized object, when its size is what is wrong."""
    largest = float(np.ptp(mesh.vertices, axis=0).max())
    if largest > MAX_PLAUSIBLE_EXTENT_M or largest < MIN_PLAUSIBLE_EXTENT_M:
        for units, unit_factor in (("mm", 0.001), ("cm", 0.01), ("m", 1.0)):
            size = largest / factor * unit_factor
            if MIN_PLAUSIBLE_EXTENT_M * 4 <= size <= MAX_PLAUSIBLE_EXTENT_M / 3:
                return (
                    f"object mesh {path}: largest extent {largest:.4g} m at scale "
                    f"{factor:g} is not a graspable object; if the file is in {units}, "
                    + fix_for_caller(
                        f"pass --units {units} (or --scale {unit_factor:g})",
                        f'name it "{path}?units={units}" (or "?scale={unit_factor:g}")',
                    )
                )
        return (
            f"object mesh {path}: largest extent {largest:.4g} m at scale {factor:g} "
            "is not a graspable object; "
            + fix_for_caller("pass --scale S", f'name it "{path}?scale=S"')
            + " so that it measures 5 mm-3 m"
        )
    return message


def relabeled(asset: ObjectAsset, name: str) -> ObjectAsset:
    """A named object (YCB, generated, catalog) ``name = BASE?handles=FILE`` with the handle
    label of FILE (its entry named BASE or the object's name, or its only entry)."""
    base, spec_query = split_spec(name)
    query = dict(parse_qsl(spec_query))
    if set(query) != {"handles"}:
        raise SimgraspError(f"object {name!r}: only a mesh file takes options other than handles")
    label = _label_of(Path(query["handles"]), (base, asset.name), name)
    return replace(asset, name=name, handle=label, handle_source="file")


def _handle(
    spec: MeshObjectSpec, name: str, mesh: trimesh.Trimesh
) -> tuple[HandleLabel, Literal["file", "automatic"]]:
    """The handle label of the spec's ``handles`` file (entry by mesh stem, or the only one),
    else the mesh's automatic one, and which it is."""
    if spec.handles is None:
        return automatic_handle_label(mesh, name), "automatic"
    return _label_of(spec.handles, (spec.path.stem,), name), "file"


def _label_of(path: Path, keys: tuple[str, ...], name: str) -> HandleLabel:
    """The entry of label file ``path`` named by one of ``keys``, or its only entry."""
    labels = load_label_file(path)
    stem = next((key for key in keys if key in labels), None)
    if stem is not None:
        label = labels[stem]
    elif len(labels) == 1:
        label = next(iter(labels.values()))
    else:
        raise SimgraspError(
            f"handle file {path} has {len(labels)} objects and none named {keys[0]!r}"
        )
    return HandleLabel(name, label.regions, label.whole_object)


def _mass(spec: MeshObjectSpec, mesh: trimesh.Trimesh) -> float:
    """The spec's mass, or its density times the solid's volume (kg)."""
    try:
        with warnings.catch_warnings():  # a flat mesh's centre of mass divides by zero volume
            warnings.simplefilter("ignore", RuntimeWarning)
            solid, volume_from = mass_properties_solid(mesh)
            volume = abs(float(solid.volume))
    except Exception:  # qhull fails on a flat point set: no volume
        volume, volume_from = 0.0, "convex_hull"
    if not volume > MIN_VOLUME_M3:
        raise SimgraspError(
            f"object mesh {spec.path}: zero volume ({volume:.3g} m^3): a flat or degenerate "
            "mesh cannot be simulated as a solid"
        )
    if volume_from == "convex_hull":
        print(
            f"note: object mesh {spec.path} is not watertight: its mass comes from its convex "
            "hull's volume, its collisions from CoACD's convex parts",
            file=sys.stderr,
        )
    if spec.mass is not None:
        return spec.mass
    return (spec.density or DEFAULT_DENSITY) * volume


def load_mesh_object(name: str) -> ObjectAsset:
    """The object of a mesh spec ``name`` (module docstring)."""
    spec = parse_mesh_spec(name)
    mesh = read_mesh(spec)
    mass = _mass(spec, mesh)
    handle, handle_source = _handle(spec, name, mesh)
    return ObjectAsset(
        name=name,
        mesh=mesh,
        handle=handle,
        mass=mass,
        source="mesh",
        friction=spec.friction,
        handle_source=handle_source,
    )
