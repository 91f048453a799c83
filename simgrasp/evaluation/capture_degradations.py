"""A single-view capture made worse as another capture of the same object might be: fewer
points, more range noise, dropouts, a wrong sensor pose. Applied alike to real clouds and to
simulated views (``scripts/real_robustness.py``), so that a detector's robustness can be
measured, and chosen, on simulation, then checked on real captures.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

DEGRADATIONS = ("as captured", "half", "quarter", "noise1mm", "noise2mm", "holes", "viewpoint10cm")
"""The degradations, in table order:

- ``half`` / ``quarter``: a random half or quarter of the points (a sparser or farther sensor);
- ``noise1mm`` / ``noise2mm``: Gaussian range noise of 1 or 2 mm along each point's ray from
  the viewpoint (a noisier sensor);
- ``holes``: the points within :data:`HOLE_RADIUS` of three random points removed (dropouts);
- ``viewpoint10cm``: the viewpoint given 10 cm off in a random direction (a wrong or guessed
  sensor pose: normals are turned toward it)."""
HOLE_RADIUS = 0.015
"""Radius (m) of each of the three holes."""


def degraded(
    points: NDArray[np.float64], viewpoint: NDArray[np.float64], kind: str, rng: np.random.Generator
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``points`` (N, 3, m, any frame) and the ``viewpoint`` (3,) they were seen from, in the
    same frame, after degradation ``kind`` (one of :data:`DEGRADATIONS`), drawn from ``rng``."""
    if kind == "as captured":
        return points, viewpoint
    if kind in ("half", "quarter"):
        keep = len(points) // (2 if kind == "half" else 4)
        return points[np.sort(rng.choice(len(points), keep, replace=False))], viewpoint
    if kind in ("noise1mm", "noise2mm"):
        rays = points - viewpoint
        rays /= np.linalg.norm(rays, axis=1, keepdims=True)
        sigma = 0.001 if kind == "noise1mm" else 0.002
        return points + rays * rng.normal(0.0, sigma, (len(points), 1)), viewpoint
    if kind == "holes":
        centers = points[rng.choice(len(points), 3, replace=False)]
        gaps = np.linalg.norm(points[:, None] - centers[None], axis=2).min(axis=1)
        return points[gaps > HOLE_RADIUS], viewpoint
    if kind == "viewpoint10cm":
        direction = rng.normal(size=3)
        return points, viewpoint + 0.1 * direction / np.linalg.norm(direction)
    raise ValueError(f"unknown degradation {kind!r}; choose from {', '.join(DEGRADATIONS)}")
