"""Mesh sanity checks: fail clearly on unusable meshes, report (not fail) imperfect ones.

Fatal problems raise :class:`MeshError` naming the object and the file: a missing or
unreadable file, no faces, non-finite vertices, implausible units (a largest extent above
3 m looks like millimetres; below 5 mm looks like a double scaling). Scanned meshes are often
open or slightly non-manifold (the YCB chips-can Poisson reconstruction is not watertight);
those still load, and :class:`MeshReport` says so. Mass properties of such a mesh come from
its convex hull (:func:`mass_properties_solid`), since a signed volume of an open surface is
meaningless.

Units are meters; every mesh is in its object's own frame.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import trimesh

MAX_PLAUSIBLE_EXTENT_M = 3.0
MIN_PLAUSIBLE_EXTENT_M = 0.005


class MeshError(ValueError):
    """A mesh that cannot be used; the message names the object and the file."""


@dataclass(frozen=True)
class MeshReport:
    """Non-fatal findings about a mesh (object frame, meters).

    Attributes:
        object_name: the object the mesh belongs to.
        source: the file the mesh came from, if any.
        n_vertices: vertex count after merging duplicates.
        n_faces: triangle count.
        extents: axis-aligned bounding-box size (x, y, z), meters.
        boundary_edges: edges used by exactly one face (holes); 0 for a closed surface.
        non_manifold_edges: edges shared by more than two faces.
        winding_consistent: whether neighbouring faces agree on orientation.
        volume_from: ``"mesh"`` if the mesh itself is a valid solid for mass properties,
            ``"convex_hull"`` otherwise (see :func:`mass_properties_solid`).
    """

    object_name: str
    source: Path | None
    n_vertices: int
    n_faces: int
    extents: tuple[float, float, float]
    boundary_edges: int
    non_manifold_edges: int
    winding_consistent: bool
    volume_from: Literal["mesh", "convex_hull"]

    @property
    def watertight(self) -> bool:
        return self.boundary_edges == 0 and self.non_manifold_edges == 0

    @property
    def warnings(self) -> tuple[str, ...]:
        """Human-readable notes on the imperfections found (empty for a clean solid)."""
        notes = []
        if self.boundary_edges:
            notes.append(f"not watertight ({self.boundary_edges} boundary edges)")
        if self.non_manifold_edges:
            notes.append(f"non-manifold ({self.non_manifold_edges} edges shared by >2 faces)")
        if not self.winding_consistent:
            notes.append("inconsistent face winding")
        if self.volume_from == "convex_hull":
            notes.append("mass properties from the convex hull")
        return tuple(notes)


def unreadable_reason(exc: Exception) -> str:
    """One line saying why a mesh file could not be read: the exception's message (its type
    when the message is empty), whitespace collapsed and cut to a readable length."""
    message = " ".join(str(exc).split()) or type(exc).__name__
    return message if len(message) <= 200 else f"{message[:197]}..."


def _where(object_name: str, source: Path | str | None) -> str:
    return f"object {object_name!r}" + (f" (file {source})" if source is not None else "")


def validate_mesh(
    mesh: trimesh.Trimesh, object_name: str, source: Path | str | None = None
) -> trimesh.Trimesh:
    """Return ``mesh`` unchanged if usable, else raise :class:`MeshError`.

    Checks: at least one face, finite vertices, largest extent within
    [5 mm, 3 m] (meters expected).
    """
    where = _where(object_name, source)
    if not isinstance(mesh, trimesh.Trimesh):
        raise MeshError(f"{where}: expected a triangle mesh, got {type(mesh).__name__}")
    if len(mesh.faces) == 0 or len(mesh.vertices) == 0:
        raise MeshError(f"{where}: mesh is empty (no faces)")
    vertices = np.asarray(mesh.vertices)
    finite = np.isfinite(vertices).all(axis=1)
    if not finite.all():
        raise MeshError(
            f"{where}: {int((~finite).sum())} of {len(vertices)} vertices are NaN or infinite"
        )
    extents = vertices.max(axis=0) - vertices.min(axis=0)
    largest = float(extents.max())
    size = " x ".join(f"{e:.4g}" for e in extents)
    if largest > MAX_PLAUSIBLE_EXTENT_M:
        raise MeshError(
            f"{where}: extents {size} are implausible in meters: looks like millimetres; "
            "scale by 0.001"
        )
    if largest < MIN_PLAUSIBLE_EXTENT_M:
        raise MeshError(
            f"{where}: extents {size} m are implausibly small (largest below "
            f"{MIN_PLAUSIBLE_EXTENT_M * 1000:.0f} mm); was the mesh scaled twice?"
        )
    return mesh


def _edge_use_counts(mesh: trimesh.Trimesh) -> np.ndarray:
    """How many faces use each distinct (undirected) edge."""
    _, counts = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
    return counts


def mesh_report(
    mesh: trimesh.Trimesh, object_name: str, source: Path | str | None = None
) -> MeshReport:
    """Validate ``mesh`` (raising :class:`MeshError`) and describe its imperfections."""
    validate_mesh(mesh, object_name, source)
    counts = _edge_use_counts(mesh)
    _, volume_from = mass_properties_solid(mesh)
    extents = mesh.extents
    return MeshReport(
        object_name=object_name,
        source=Path(source) if source is not None else None,
        n_vertices=len(mesh.vertices),
        n_faces=len(mesh.faces),
        extents=(float(extents[0]), float(extents[1]), float(extents[2])),
        boundary_edges=int((counts == 1).sum()),
        non_manifold_edges=int((counts > 2).sum()),
        winding_consistent=bool(mesh.is_winding_consistent),
        volume_from=volume_from,
    )


def mass_properties_solid(
    mesh: trimesh.Trimesh,
) -> tuple[trimesh.Trimesh, Literal["mesh", "convex_hull"]]:
    """The solid to take volume, center of mass and inertia from, and which one it is.

    A closed, consistently wound mesh with positive volume is its own solid; anything else
    (an open scan, a non-manifold surface) falls back to its convex hull, which over-estimates
    the volume of concave objects but is always a valid solid.
    """
    if mesh.is_volume and mesh.volume > 0:
        return mesh, "mesh"
    return mesh.convex_hull, "convex_hull"


def load_mesh_file(path: Path | str, object_name: str) -> trimesh.Trimesh:
    """Load a triangle mesh (OBJ, STL, PLY, ...) as geometry only, and validate it.

    Materials and textures are not decoded (only vertices and faces are kept), duplicate
    vertices are merged, so seams split by texture coordinates are closed. The file's units
    must be meters; the mesh stays in the file's frame.
    """
    path = Path(path)
    where = _where(object_name, path)
    if not path.is_file():
        raise MeshError(f"{where}: mesh file does not exist")
    try:
        loaded = trimesh.load(path, force="mesh", process=False, skip_materials=True)
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise MeshError(f"{where}: cannot read mesh: {unreadable_reason(exc)}") from exc
    if not isinstance(loaded, trimesh.Trimesh):
        raise MeshError(f"{where}: mesh is empty (no faces)")
    vertices = np.asarray(loaded.vertices, dtype=float)
    faces = np.asarray(loaded.faces, dtype=np.int64)
    raw = trimesh.Trimesh(vertices, faces, process=False)
    validate_mesh(raw, object_name, path)
    return outward(trimesh.Trimesh(vertices, faces, process=True))


def outward(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """``mesh`` with its faces turned outward: a consistently wound surface whose signed
    volume is negative is inside out (the YCB chips-can Poisson scan), which renderers that
    cull back faces draw as the far inner wall; its faces are flipped in place."""
    if not mesh.is_winding_consistent:
        return mesh
    with warnings.catch_warnings():  # a flat mesh's centre of mass divides by its zero volume
        warnings.simplefilter("ignore", RuntimeWarning)
        inside_out = mesh.volume < 0
    if inside_out:
        mesh.invert()
    return mesh
