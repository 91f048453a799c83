"""Per-pixel geometry of a depth image: surface normals, incidence angles, depth edges and
the shadow cast by a light source (a projector) or seen by a second camera on a baseline.

All functions take the depth ``z`` as an (H, W) float32 image in meters (0 = no return; the
sensor models compute in float32: 0.1 um at 1 m) and the 3x3 OpenCV camera matrix ``K``
(x right, y down, z forward).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

Image = NDArray[np.floating]


def incidence_cos(z: Image, K: NDArray[np.float64]) -> Image:
    """|cos| of the angle between each pixel's viewing ray and its surface normal.

    With the ray ``r = ((u - cx)/fx, (v - cy)/fy, 1)`` and the point ``P = z r``, the cross
    product of ``dP/du`` and ``dP/dv`` is, up to the factor ``z / (fx fy)``,
    ``n = (-fx z_u, -fy z_v, fx r_x z_u + fy r_y z_v + z)`` with ``n . r = z``. Each depth
    derivative ``z_u, z_v`` is the smaller (in magnitude) of the forward and backward
    differences, so a pixel at a depth edge or next to a no-return pixel takes the slope of
    its own surface, not the jump. Pixels without a return get NaN.
    """
    height, width = z.shape
    fx, fy = float(K[0, 0]), float(K[1, 1])
    rx = ((np.arange(width) - K[0, 2]) / fx).astype(z.dtype)[None, :]
    ry = ((np.arange(height) - K[1, 2]) / fy).astype(z.dtype)[:, None]
    z_u = _smaller_difference(z, axis=1)
    z_u *= fx
    z_v = _smaller_difference(z, axis=0)
    z_v *= fy
    n_z = rx * z_u + ry * z_v + z
    squared = z_u * z_u + z_v * z_v + n_z * n_z
    squared *= rx * rx + ry * ry + 1.0
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = z / np.sqrt(squared)
    cos[z <= 0.0] = np.nan
    return cos


def incidence_angle(z: Image, K: NDArray[np.float64], limit_deg: float = 89.0) -> Image:
    """Angle (rad) between each pixel's viewing ray and its surface normal (see
    :func:`incidence_cos`), at most ``limit_deg``; 0 where there is no return."""
    cos = incidence_cos(z, K)
    np.clip(cos, 0.0, 1.0, out=cos)
    theta = np.arccos(cos, out=cos)
    np.fmin(theta, np.float32(np.radians(limit_deg)), out=theta)
    theta[z <= 0.0] = 0.0
    return theta


def _smaller_difference(z: Image, axis: int) -> Image:
    """Per pixel, the forward or backward difference along ``axis``, whichever is smaller in
    magnitude (the one difference there is on the image border)."""
    step = np.moveaxis(np.diff(z, axis=axis), axis, 0)
    out = np.empty_like(z)
    view = np.moveaxis(out, axis, 0)
    magnitude = np.abs(step)
    np.copyto(view[1:-1], step[:-1])
    np.copyto(view[1:-1], step[1:], where=magnitude[1:] < magnitude[:-1])
    view[0], view[-1] = step[0], step[-1]
    return out


def depth_edges(z: Image, relative_jump: float) -> NDArray[np.bool_]:
    """Pixels next to a depth discontinuity: a 4-neighbor more than ``relative_jump`` x the
    nearer depth farther, or a no-return neighbor next to a return (both sides are marked)."""
    edges = np.zeros(z.shape, dtype=bool)
    factor = 1.0 + relative_jump
    for a, b, ea, eb in (
        (z[1:], z[:-1], edges[1:], edges[:-1]),
        (z[:, 1:], z[:, :-1], edges[:, 1:], edges[:, :-1]),
    ):
        jump = np.maximum(a, b) > factor * np.minimum(a, b)
        ea |= jump
        eb |= jump
    return edges


def band(mask: NDArray[np.bool_], width_px: int) -> NDArray[np.bool_]:
    """``mask`` grown by ``width_px`` pixels (8-connected); ``width_px`` 0 returns a copy."""
    if width_px <= 0:
        return mask.copy()
    return ndimage.maximum_filter(mask.view(np.uint8), size=2 * width_px + 1).view(bool)


def baseline_shadow(z: Image, K: NDArray[np.float64], baseline: float) -> NDArray[np.bool_]:
    """Pixels hidden from a second center of projection ``baseline`` meters along +x of the
    camera (negative: along -x), such as a structured-light projector or a stereo pair's
    second imager.

    The second view is rectified with the camera, so its epipolar lines are the image rows and
    a pixel at column u and depth z lies at column ``u - fx baseline / z`` in it. Along a row,
    a visible surface's columns there increase with u; a pixel whose column is not below every
    column of the pixels on the baseline's side lies behind a nearer surface.
    """
    if baseline < 0.0:
        return baseline_shadow(z[:, ::-1], K, -baseline)[:, ::-1]
    width = z.shape[1]
    with np.errstate(divide="ignore"):
        column = (-float(K[0, 0]) * baseline) / z
    column += np.arange(width, dtype=z.dtype)[None, :]
    column[z <= 0.0] = np.inf
    min_right = np.minimum.accumulate(column[:, ::-1], axis=1)[:, ::-1]
    hidden = np.zeros(z.shape, dtype=bool)
    np.greater(column[:, :-1], min_right[:, 1:], out=hidden[:, :-1])
    return hidden


def open_rows(mask: NDArray[np.bool_], width_px: int) -> NDArray[np.bool_]:
    """``mask`` less its runs along a row shorter than ``width_px`` pixels (a morphological
    opening with a 1 x width_px segment), computed on the mask's bounding box only."""
    if width_px <= 1 or not mask.any():
        return mask
    rows = np.flatnonzero(mask.any(axis=1))
    cols = np.flatnonzero(mask.any(axis=0))
    box = np.s_[rows[0] : rows[-1] + 1, max(cols[0] - 1, 0) : cols[-1] + 2]
    opened = np.zeros_like(mask)
    segment = np.ones((1, width_px), dtype=bool)
    opened[box] = ndimage.binary_opening(mask[box], structure=segment)
    return opened
