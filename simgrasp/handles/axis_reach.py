"""A handle part's surface followed along its candidates' axes.

The detector's candidates cover a strap unevenly: where it found none, the surface within a
fixed distance of the candidates misses the rest of the strap. Each candidate also says which
way the handle runs (``axis``, through ``handle_point``) and how thick it is (its larger
transverse semi-axis), so the part's surface is extended along those axes: scanned points
within ``reach`` along a candidate's axis and within its semi-axis plus ``pad`` of the axis.
Points near a narrow but flat candidate (a blade's or a wall's evidence) are not reached, so
a knife's handle does not run on into its blade. Mesh frame, meters.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree


def reached_along_axes(
    surface: NDArray[np.float64],
    handle_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    radii: NDArray[np.float64],
    *,
    reach: float,
    blocked: NDArray[np.bool_],
) -> NDArray[np.bool_]:
    """(N,) which ``surface`` points (N, 3) lie within ``reach`` along one of the axes (K
    unit ``axes`` through ``handle_points``) and within that candidate's ``radii`` (K,) of
    it, leaving out the ``blocked`` (N,) points; candidates with non-finite entries reach
    nothing."""
    reached = np.zeros(len(surface), dtype=bool)
    if reach <= 0 or len(surface) == 0:
        return reached
    tree = cKDTree(surface)
    for center, axis, radius in zip(handle_points, axes, radii, strict=True):
        if not (np.all(np.isfinite(center)) and np.all(np.isfinite(axis)) and np.isfinite(radius)):
            continue
        near = np.asarray(tree.query_ball_point(center, float(np.hypot(reach, radius))), int)
        offsets = surface[near] - center
        along = offsets @ axis
        across = np.linalg.norm(offsets - along[:, None] * axis, axis=1)
        reached[near[(np.abs(along) <= reach) & (across <= radius)]] = True
    return reached & ~blocked
