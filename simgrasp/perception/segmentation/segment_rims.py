"""Round containers seen from above: the inside and the outside of one rim, joined.

A pot or bowl seen from above shows the outside of its front wall and, over its front rim, the
inside of its back wall and its floor, farther away: the two meet nowhere in the image (a depth
jump at the front rim, grazing or missing pixels at the sides), so the grid cuts give two
segments. They share one rim: the top edges of both (their points within ``rim_band`` of their
highest, 98th percentile, which must agree within ``rim_height_tolerance``) lie on one circle
in the table plane, the outside's arc in front of its center and the inside's behind it. When a
circle fitted to both top edges has a radius of at most ``rim_max_radius`` and an RMS distance
of the points from it of at most ``rim_tolerance``, and the two arcs lie on opposite sides of
its center, the smaller object becomes a part of the larger (``part_of``), as a side part does.
Two boxes of one height side by side fail (their straight top edges fit no small circle), as do
two cans (two circles, not one).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simgrasp.perception.segmentation.segment_config import FIRST_OBJECT, SegmentConfig


def rim_parents(
    labels: NDArray[np.int32],
    points: NDArray[np.float32],
    height: NDArray[np.float32],
    plane: NDArray[np.float64],
    parents: NDArray[np.int32],
    config: SegmentConfig,
) -> NDArray[np.int32]:
    """``parents`` (indexed by label, see :func:`part_parents`) with the insides of round
    containers joined to their outsides (module docstring). ``labels`` (N,) per point,
    ``points`` (N, 3) and ``height`` (N,) above the table ``plane`` (m)."""
    if config.rim_band <= 0:
        return parents
    roots = [int(r) for r in np.unique(parents[FIRST_OBJECT:]) if r >= FIRST_OBJECT]
    root_of = parents[labels]
    members = {root: root_of == root for root in roots}
    rims = {root: _rim(members[root], height, config) for root in roots}
    sizes = {root: int(members[root].sum()) for root in roots}
    basis = _plane_basis(plane)
    joined = parents.copy()
    for small in sorted(roots, key=lambda r: sizes[r]):
        for large in sorted(roots, key=lambda r: -sizes[r]):
            if sizes[large] <= sizes[small] or joined[large] != large:
                continue
            if _one_rim(rims[small], rims[large], points, basis, config):
                joined[joined == small] = large
                break
    return joined


def _rim(
    members: NDArray[np.bool_], height: NDArray[np.float32], config: SegmentConfig
) -> tuple[float, NDArray[np.int64]]:
    """An object's top height (98th percentile, m) and the indices of its points within
    ``rim_band`` of it."""
    index = np.flatnonzero(members)
    if len(index) == 0:
        return float("nan"), index
    top = float(np.percentile(height[index], 98))
    return top, index[height[index] >= top - config.rim_band]


def _one_rim(
    first: tuple[float, NDArray[np.int64]],
    second: tuple[float, NDArray[np.int64]],
    points: NDArray[np.float32],
    basis: NDArray[np.float64],
    config: SegmentConfig,
) -> bool:
    """Whether two objects' top edges are the two sides of one round rim."""
    if not abs(first[0] - second[0]) <= config.rim_height_tolerance:
        return False
    if min(len(first[1]), len(second[1])) < 3:
        return False
    flat_first = points[first[1]].astype(np.float64) @ basis
    flat_second = points[second[1]].astype(np.float64) @ basis
    center, radius, rms = _circle(np.concatenate([flat_first, flat_second]))
    if not (radius <= config.rim_max_radius and rms <= config.rim_tolerance):
        return False
    side_first = (flat_first - center).mean(axis=0)
    side_second = (flat_second - center).mean(axis=0)
    return bool(side_first @ side_second < 0)


def _circle(flat: NDArray[np.float64]) -> tuple[NDArray[np.float64], float, float]:
    """Least-squares circle (Kasa) through 2-D points: center, radius and the RMS distance
    of the points from it (m)."""
    design = np.column_stack([flat, np.ones(len(flat))])
    target = -(flat**2).sum(axis=1)
    (d, e, f), *_ = np.linalg.lstsq(design, target, rcond=None)
    center = -np.array([d, e]) / 2
    radius = float(np.sqrt(max(center @ center - f, 0.0)))
    rms = float(np.sqrt(np.mean((np.linalg.norm(flat - center, axis=1) - radius) ** 2)))
    return center, radius, rms


def _plane_basis(plane: NDArray[np.float64]) -> NDArray[np.float64]:
    """(3, 2) two orthonormal directions spanning the table plane."""
    normal = plane[:3] / np.linalg.norm(plane[:3])
    helper = np.eye(3)[np.argmin(np.abs(normal))]
    first = np.cross(normal, helper)
    first /= np.linalg.norm(first)
    return np.column_stack([first, np.cross(normal, first)])
