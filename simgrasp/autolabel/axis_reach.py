"""A handle part's surface followed along its candidates' axes, up to where its section grows.

The detector's candidates cover a strap unevenly: where it found none, the surface within a
fixed distance of the candidates misses the rest of the strap. Each candidate also says which
way the handle runs (``axis``, through ``handle_point``) and how thick it is (its larger
transverse semi-axis), so the part's surface is extended along those axes: scanned points
within ``reach`` along a candidate's axis and within its semi-axis plus ``pad`` of the axis.
Points near a narrow but flat candidate (a blade's or a wall's evidence) are not reached, so
a knife's handle does not run on into its blade.

Optionally (:func:`section_stops`) each candidate's region also ends where the surface's
section across its axis grows: walking from the candidate along its axis in slabs, the first
slab whose points (within the semi-axis plus a ring of the axis) spread wider than
``growth`` times the candidate's diameter is a guard, a blade's root or the body a strap
joins; neither the points near the candidate nor the reached ones go past it. Mesh frame,
meters.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree


@dataclass(frozen=True)
class SectionStop:
    """Where a candidate's region ends along its axis (m): at the first slab of ``slab``
    thickness whose points within the semi-axis plus ``ring`` of the axis spread (largest
    extent across the axis) more than ``growth`` times the candidate's diameter."""

    growth: float
    ring: float
    slab: float


def section_stops(
    tree: cKDTree,
    surface: NDArray[np.float64],
    centers: NDArray[np.float64],
    handle_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    semi_axes: NDArray[np.float64],
    *,
    reach: float,
    stop: SectionStop,
) -> NDArray[np.float64]:
    """(K, 2) per candidate the interval of positions along its axis (from its handle point)
    before the section grows, walking both ways from the slab of its ``centers`` (K, 3)
    (``-inf`` / ``inf`` where it does not within ``reach`` plus a slab; that own slab is
    always inside); ``tree`` indexes ``surface``."""
    stops = np.tile([-np.inf, np.inf], (len(handle_points), 1))
    rows = zip(centers, handle_points, axes, semi_axes, strict=True)
    for k, (own, center, axis, semi) in enumerate(rows):
        if not (np.all(np.isfinite(center)) and np.all(np.isfinite(axis)) and np.isfinite(semi)):
            continue
        start = int(np.rint(((own - center) @ axis) / stop.slab))
        outer = semi + stop.ring
        near = np.asarray(tree.query_ball_point(center, float(np.hypot(reach, outer))), int)
        if len(near) == 0:
            continue
        offsets = surface[near] - center
        along = offsets @ axis
        across = offsets - along[:, None] * axis
        inside = np.linalg.norm(across, axis=1) <= outer
        extent = _slab_extents(along[inside], across[inside], axis, stop.slab)
        grown = {s for s, e in extent.items() if s != start and e > stop.growth * 2.0 * semi}
        if grown:
            above = [s for s in grown if s > start]
            below = [s for s in grown if s < start]
            if above:
                stops[k, 1] = (min(above) - 0.5) * stop.slab
            if below:
                stops[k, 0] = (max(below) + 0.5) * stop.slab
    return stops


def _slab_extents(
    along: NDArray[np.float64],
    across: NDArray[np.float64],
    axis: NDArray[np.float64],
    slab: float,
) -> dict[int, float]:
    """Per slab index (position along the axis over ``slab``, rounded) the largest extent of
    its points' ``across`` offsets (N, 3) along two directions normal to ``axis``."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    coords = np.column_stack([across @ u, across @ v])
    index = np.rint(along / slab).astype(np.int64)
    extents: dict[int, float] = {}
    for s in np.unique(index):
        chosen = coords[index == s]
        extents[int(s)] = float(np.max(np.ptp(chosen, axis=0)))
    return extents


def reached_along_axes(
    surface: NDArray[np.float64],
    handle_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    radii: NDArray[np.float64],
    *,
    reach: float,
    blocked: NDArray[np.bool_],
    stops: NDArray[np.float64] | None = None,
) -> NDArray[np.bool_]:
    """(N,) which ``surface`` points (N, 3) lie within ``reach`` along one of the axes (K
    unit ``axes`` through ``handle_points``) and within that candidate's ``radii`` (K,) of
    it, leaving out the ``blocked`` (N,) points and, with ``stops`` (K, 2), those outside the
    candidate's interval along its axis; candidates with non-finite entries reach nothing."""
    reached = np.zeros(len(surface), dtype=bool)
    if reach <= 0 or len(surface) == 0:
        return reached
    if stops is None:
        stops = np.tile([-np.inf, np.inf], (len(handle_points), 1))
    tree = cKDTree(surface)
    for center, axis, radius, (low, high) in zip(handle_points, axes, radii, stops, strict=True):
        if not (np.all(np.isfinite(center)) and np.all(np.isfinite(axis)) and np.isfinite(radius)):
            continue
        near = np.asarray(tree.query_ball_point(center, float(np.hypot(reach, radius))), int)
        offsets = surface[near] - center
        along = offsets @ axis
        across = np.linalg.norm(offsets - along[:, None] * axis, axis=1)
        inside = (np.abs(along) <= reach) & (across <= radius) & (along > low) & (along < high)
        reached[near[inside]] = True
    return reached & ~blocked


def near_within_stops(
    tree: cKDTree,
    surface: NDArray[np.float64],
    centers: NDArray[np.float64],
    handle_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    stops: NDArray[np.float64],
    radius: float,
) -> NDArray[np.bool_]:
    """(N,) which ``surface`` points lie within ``radius`` of one of the candidates'
    ``centers`` (K, 3) and inside that candidate's ``stops`` interval along its axis (no
    limit where the axis is not finite); ``tree`` indexes ``surface``."""
    if not np.isfinite(stops).any():
        return cKDTree(centers).query(surface)[0] <= radius
    found = np.zeros(len(surface), dtype=bool)
    for center, point, axis, (low, high) in zip(centers, handle_points, axes, stops, strict=True):
        near = np.asarray(tree.query_ball_point(center, radius), int)
        if len(near) and np.all(np.isfinite(axis)) and np.all(np.isfinite(point)):
            along = (surface[near] - point) @ axis
            near = near[(along > low) & (along < high)]
        found[near] = True
    return found
