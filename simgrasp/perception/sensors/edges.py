"""Depth-edge artifacts shared by the sensor models: lateral jitter and flying pixels."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def lateral_jitter(
    z: NDArray[np.floating],
    pixels: tuple[NDArray[np.int64], NDArray[np.int64]],
    sigma_px: NDArray[np.floating],
    rng: np.random.Generator,
) -> NDArray[np.floating]:
    """Each of the ``pixels`` (rows, columns) takes the depth of the pixel at a random offset
    (per axis ``round(N(0, sigma_px))`` pixels, its own sigma, clipped to the image): the
    silhouette moves sideways by the sensor's lateral noise. Draws two normals per pixel."""
    height, width = z.shape
    rows, cols = pixels
    offsets = np.rint(rng.standard_normal((2, rows.size), dtype=np.float32) * sigma_px).astype(
        np.int64
    )
    out = z.copy()
    out[rows, cols] = z[
        np.clip(rows + offsets[0], 0, height - 1), np.clip(cols + offsets[1], 0, width - 1)
    ]
    return out


def flying_pixels(
    z: NDArray[np.floating],
    edges: NDArray[np.bool_],
    probability: float,
    rng: np.random.Generator,
) -> NDArray[np.floating]:
    """With ``probability``, an edge pixel with a return takes a depth drawn uniformly between
    its own and that of the 3x3 neighbor across the edge (the farthest-off valid neighbor):
    a point floating between foreground and background. Draws two uniforms per edge pixel."""
    rows, cols = np.nonzero(edges & (z > 0.0))
    draw, mix = rng.random((2, rows.size), dtype=np.float32)
    padded = np.pad(z, 1)
    neighbors = np.stack(
        [padded[rows + 1 + dr, cols + 1 + dc] for dr in (-1, 0, 1) for dc in (-1, 0, 1)]
    )
    nearest = np.where(neighbors > 0.0, neighbors, np.inf).min(axis=0)
    farthest = neighbors.max(axis=0)
    own = z[rows, cols]
    other = np.where(farthest - own > own - nearest, farthest, nearest)
    fly = draw < probability
    out = z.copy()
    out[rows[fly], cols[fly]] = (own + mix * (other - own))[fly]
    return out
