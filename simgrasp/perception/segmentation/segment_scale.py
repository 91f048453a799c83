"""The organized segmenter at the scale of the sensor in front of it.

Every pixel-sized setting of :class:`SegmentConfig` (normal blocks, attach and contact reach,
least segment and side-part sizes) was chosen on Kinect-class frames: osd-learn's 640 x 480
scenes about 0.8 m away, where one pixel covers about 1.4 mm of a surface facing the sensor.
A RealSense frame of 1280 x 720 from 0.5 m covers about 0.65 mm a pixel: the same windows then
span half the surface, the normals see twice the noise relative to their baseline, and a
bumpy object breaks into pieces. The cloud's own pixel footprint, measured here, sets an
integer scale ``k``: normal blocks ``k`` pixels a side, pixel reaches ``k`` times longer and
point counts ``k * k`` times larger, so the settings keep the surface sizes they were chosen
at. Frames as coarse as the reference or coarser keep ``k = 1`` (the settings as given).
Figures: ``docs/results/segment-cv/README.md``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from simgrasp.perception.scene_cloud import SceneCloud
from simgrasp.perception.segmentation.segment_config import SegmentConfig

ROW_STRIDE = 16
"""Every this many rows are measured for the footprint: the median hardly moves (osd-learn's
45 scenes: within 1 % of every row's), and it costs about 0.3 ms at 640 x 480."""


def pixel_footprint(scene: SceneCloud, valid: NDArray[np.bool_]) -> float:
    """The width (m) one pixel of the organized ``scene`` covers on a surface facing the sensor
    at the scene's median range: the median angle between the rays of horizontally
    neighbouring ``valid`` pixels (rad) times the median range of the ``valid`` points (m).
    NaN when no two neighbours are valid."""
    rows = scene.grid()[::ROW_STRIDE] - scene.viewpoint.astype(np.float32)
    kept = valid.reshape(scene.height, scene.width)[::ROW_STRIDE]
    squared = np.einsum("ijk,ijk->ij", rows, rows)
    rays = rows / np.sqrt(np.where(kept, squared, 1.0))[..., None]
    pairs = kept[:, 1:] & kept[:, :-1]
    if not pairs.any():
        return float("nan")
    steps = np.diff(rays, axis=1)
    chords = np.einsum("ijk,ijk->ij", steps, steps)[pairs]  # squared: the median commutes
    return float(np.sqrt(np.median(chords) * np.median(squared[kept])))


def pixel_scale(footprint: float, reference: float) -> int:
    """``k``: ``reference / footprint`` rounded half up, at least 1 (1 when either is not a
    positive number: ``reference`` 0 turns scaling off)."""
    if not (reference > 0 and footprint > 0):
        return 1
    return max(1, int(np.floor(reference / footprint + 0.5)))


def scaled(config: SegmentConfig, k: int) -> SegmentConfig:
    """``config`` with its pixel settings at scale ``k`` (module docstring); itself at 1."""
    if k == 1:
        return config
    return replace(
        config,
        normal_bin_px=config.normal_bin_px * k,
        cut_close_px=config.cut_close_px * k,
        attach_radius_px=config.attach_radius_px * k,
        part_contact_px=config.part_contact_px * k,
        part_edge_px=config.part_edge_px * k,
        part_min_contact=config.part_min_contact * k,
        part_max_points=config.part_max_points * k * k,
        min_object_points=config.min_object_points * k * k,
    )
