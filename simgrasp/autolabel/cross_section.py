"""Where a long tool's cross-section thins: a knife's blade, a spatula's plate, a screwdriver's
shaft, past the handle.

A handle is held across its section, and on a long tool the section stays about as thick along
the handle, then falls where the blade or the shaft begins. :func:`section_profile` takes the
scanned surface of an elongated object (its main extent at least ``min_elongation`` times the
next, by principal axes), cuts it into slabs ``slab`` thick along the main axis and measures
each slab's thickness: the 5-95 percentile spread of its points along their own minor
principal axis across the main axis (a round handle: its diameter; a blade: its few
millimetres). :func:`thick_enough` keeps the points whose slab is at least ``min_ratio`` times
as thick as the slabs a handle part was found in, so a handle's label ends where the blade
begins instead of running past the guard; and (:func:`section_run`) the label also runs on
over the slabs whose section stays like the part's (thickness and width, the spread along
the slab's major axis), so it reaches the end of a handle the detector found only in part.
Settings chosen on the tune half of the ACRONYM knives (docs/results/handle-labels/README.md).
Meters, the frame of the points.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from simgrasp.config.checks import Checked, NonNegative, Positive, PositiveInt


@dataclass(frozen=True)
class CrossSectionConfig(Checked):
    """Settings of the thickness profile along a long tool (m, ratios)."""

    min_ratio: NonNegative = 0.75
    """A part's region keeps the slabs at least this share as thick as the median of the slabs
    its candidates lie in (0: off)."""
    head_width_ratio: NonNegative = 1.2
    """A part's region leaves out the slabs more than this many times as wide (the spread
    along the slab's major axis) as the median of the slabs its candidates lie in, and at
    least ``head_thickness_ratio`` times as thick: a head beyond a bar (a wrench's ring, a
    hammer's head) grows both ways, a spatula's plate only widens (0: off). Chosen on
    generated long tools, with the ACRONYM tune half unchanged
    (docs/results/handle-labels/README.md)."""
    head_thickness_ratio: NonNegative = 1.0
    """... the thickness factor of that test."""
    min_elongation: Positive = 3.0
    """Only objects whose main extent is at least this many times the next get a profile (a
    mug or a pan does not)."""
    slab: Positive = 0.002
    """Slab thickness along the main axis."""
    min_points: PositiveInt = 20
    """Slabs with fewer scanned points have no thickness (kept)."""
    grow_ratio: NonNegative = 1.5
    """A part's region also takes every slab of the unbroken runs of slabs, meeting the slabs
    its candidates span, whose thickness and width (the spread along the slab's major axis)
    stay within this factor of the part's median slab, either way: the rest of a handle the
    detector found in part (a flat handle's flat end), up to a blade (thinner) or a head
    (wider). A part on a blade or a shaft does not grow: one beside an unbroken run of slabs
    at least ``1 / min_ratio`` times as thick and ``min_run`` long (a handle) (0: off).
    Chosen on the tune half of the ACRONYM knives with the generated long tools unchanged
    (docs/results/handle-labels/README.md)."""
    min_run: NonNegative = 0.03
    """A part whose run (the slabs of :func:`section_run`, by the ``grow_ratio`` test alone:
    no thinness guard) is shorter than this is dropped when another part's run is at least
    this long: a handle is a stretch of even section a pad can hold along (a 20 mm pad and
    5 mm either side, fixed before any run), while a blade's tapering tip or a wrench's head
    runs a few millimetres (0: off; docs/results/handle-labels/README.md)."""


@dataclass(frozen=True)
class SectionProfile:
    """The thickness and width (m) of an elongated object's slabs: ``thickness`` (S,) and
    ``width`` (S,) (NaN where a slab has too few points), slab ``k`` covering ``start + k *
    slab`` to ``start + (k + 1) * slab`` along the unit ``axis`` (3,) from ``center`` (3,)."""

    center: NDArray[np.float64]
    axis: NDArray[np.float64]
    start: float
    slab: float
    thickness: NDArray[np.float64]
    width: NDArray[np.float64]

    def slabs_of(self, points: NDArray[np.float64]) -> NDArray[np.int64]:
        """(N,) the slab of each point, clipped to the profile's ends."""
        along = (points - self.center) @ self.axis
        slabs = np.floor((along - self.start) / self.slab).astype(np.int64)
        return np.clip(slabs, 0, len(self.thickness) - 1)

    def median_of(self, slabs: NDArray[np.int64]) -> tuple[float, float]:
        """The median thickness and width (m) over ``slabs`` (NaN where none is known)."""
        return float(np.nanmedian(self.thickness[slabs])), float(np.nanmedian(self.width[slabs]))


def section_profile(
    points: NDArray[np.float64], config: CrossSectionConfig
) -> SectionProfile | None:
    """The thickness profile of the object that ``points`` (N, 3) scan, or None when it is not
    elongated (see :class:`CrossSectionConfig`)."""
    center = points.mean(axis=0)
    axes = np.linalg.svd(points - center, full_matrices=False)[2]
    local = (points - center) @ axes.T
    extents = np.percentile(local, 95, axis=0) - np.percentile(local, 5, axis=0)
    if extents[0] < config.min_elongation * extents[1]:
        return None
    start = float(local[:, 0].min())
    slabs = np.floor((local[:, 0] - start) / config.slab).astype(np.int64)
    thickness = np.full(slabs.max() + 1, np.nan)
    width = np.full(slabs.max() + 1, np.nan)
    for k in np.unique(slabs):
        across = local[slabs == k, 1:]
        if len(across) >= config.min_points:
            thickness[k], width[k] = _spreads(across)
    return SectionProfile(center, axes[0], start, config.slab, thickness, width)


def thick_enough(
    points: NDArray[np.float64],
    part_points: NDArray[np.float64],
    profile: SectionProfile,
    config: CrossSectionConfig,
) -> NDArray[np.bool_]:
    """(N,) which ``points`` lie in slabs at least ``min_ratio`` times as thick as the median
    slab of ``part_points`` (a handle part's candidates); all of them when that is unknown."""
    reference = profile.median_of(profile.slabs_of(part_points))[0]
    if not np.isfinite(reference):
        return np.ones(len(points), dtype=bool)
    thickness = profile.thickness[profile.slabs_of(points)]
    return ~(thickness < config.min_ratio * reference)


def off_head(
    points: NDArray[np.float64],
    part_points: NDArray[np.float64],
    profile: SectionProfile,
    config: CrossSectionConfig,
) -> NDArray[np.bool_]:
    """(N,) which ``points`` lie outside the slabs both wider and thicker than the median slab
    of ``part_points`` by ``head_width_ratio`` and ``head_thickness_ratio``; all of them when
    that median is unknown or the test is off."""
    thick, wide = profile.median_of(profile.slabs_of(part_points))
    if config.head_width_ratio <= 0 or not (np.isfinite(wide) and np.isfinite(thick)):
        return np.ones(len(points), dtype=bool)
    slabs = profile.slabs_of(points)
    head = (profile.width[slabs] > config.head_width_ratio * wide) & (
        profile.thickness[slabs] >= config.head_thickness_ratio * thick
    )
    return ~head


def section_run(
    points: NDArray[np.float64],
    part_points: NDArray[np.float64],
    profile: SectionProfile,
    config: CrossSectionConfig,
) -> NDArray[np.bool_]:
    """(N,) which ``points`` lie in the unbroken runs of slabs whose thickness and width stay
    within ``grow_ratio`` of a handle part's median slab (``part_points``: its candidates) and
    that meet the slabs its candidates span (see :class:`CrossSectionConfig`); none when that
    median is unknown or the part lies on a blade (:func:`_on_a_blade`)."""
    own = profile.slabs_of(part_points)
    run = _run_slabs(profile, own, config.grow_ratio)
    if run is None or _on_a_blade(profile, profile.median_of(own)[0], config):
        return np.zeros(len(points), dtype=bool)
    return run[profile.slabs_of(points)]


def _on_a_blade(profile: SectionProfile, thickness: float, config: CrossSectionConfig) -> bool:
    """Whether a part of median slab ``thickness`` (m) lies on a blade or a shaft: the tool
    has an unbroken run of slabs at least ``1 / min_ratio`` times as thick that is at least
    ``min_run`` long (a handle beyond it; a wrench's heads are thicker but short); never with
    ``min_ratio`` 0."""
    if config.min_ratio <= 0:
        return False
    thicker = profile.thickness >= thickness / config.min_ratio
    runs, count = ndimage.label(thicker)
    longest = np.bincount(runs.ravel(), minlength=count + 1)[1:].max(initial=0)
    return bool(longest * profile.slab >= max(config.min_run, profile.slab))


def long_runs(
    parts_points: list[NDArray[np.float64]],
    profile: SectionProfile | None,
    config: CrossSectionConfig,
) -> list[bool]:
    """Which parts (each given by its candidates' points) to keep: all of them without a
    ``profile``, when ``min_run`` is off, when ``grow_ratio`` is under 1 (no measure of
    alike) or when no part's run reaches ``min_run``; else those whose run reaches it (see
    :class:`CrossSectionConfig`)."""
    if profile is None or config.min_run <= 0 or config.grow_ratio < 1:
        return [True] * len(parts_points)
    lengths = []
    for points in parts_points:
        run = _run_slabs(profile, profile.slabs_of(points), config.grow_ratio)
        lengths.append(0.0 if run is None else float(run.sum()) * profile.slab)
    long = [length >= config.min_run for length in lengths]
    return long if any(long) else [True] * len(parts_points)


def alike_share(
    points: NDArray[np.float64],
    part_points: NDArray[np.float64],
    profile: SectionProfile,
    config: CrossSectionConfig,
) -> float:
    """The share of ``points`` in slabs whose thickness and width stay within ``grow_ratio``
    of the median slab of ``part_points`` (a part's candidates), wherever they lie: near 1 on
    an object of one section all along (a ruler); NaN when that median is unknown, there are
    no points or ``grow_ratio`` is under 1 (no measure of alike)."""
    alike = None
    if config.grow_ratio >= 1 and len(points):
        alike = _alike_slabs(profile, profile.slabs_of(part_points), config.grow_ratio)
    if alike is None:
        return float("nan")
    return float(alike[profile.slabs_of(points)].mean())


def _run_slabs(
    profile: SectionProfile, own: NDArray[np.int64], ratio: float
) -> NDArray[np.bool_] | None:
    """(S,) which slabs lie in the unbroken runs of slabs alike the median of slabs ``own``
    (:func:`_alike_slabs`) that meet the span of ``own``; None when that median is unknown."""
    alike = _alike_slabs(profile, own, ratio)
    if alike is None:
        return None
    run_of_slab = ndimage.label(alike)[0]  # 0: not alike; 1, 2, ...: unbroken runs
    meeting = np.setdiff1d(run_of_slab[own.min() : own.max() + 1], [0])
    return np.isin(run_of_slab, meeting)


def _alike_slabs(
    profile: SectionProfile, own: NDArray[np.int64], ratio: float
) -> NDArray[np.bool_] | None:
    """(S,) which slabs' thickness and width stay within ``ratio`` of the median of slabs
    ``own``, either way; None when that median is unknown."""
    thick, wide = profile.median_of(own)
    if not (np.isfinite(thick) and np.isfinite(wide)):
        return None
    return (
        (profile.thickness >= thick / ratio)
        & (profile.thickness <= thick * ratio)
        & (profile.width >= wide / ratio)
        & (profile.width <= wide * ratio)
    )


def _spreads(across: NDArray[np.float64]) -> tuple[float, float]:
    """The 5-95 percentile spreads (m) of 2-D points along their minor and major principal
    axes (thickness, width)."""
    centered = across - across.mean(axis=0)
    principal = np.linalg.svd(centered, full_matrices=False)[2]
    minor, major = centered @ principal[-1], centered @ principal[0]
    return (
        float(np.percentile(minor, 95) - np.percentile(minor, 5)),
        float(np.percentile(major, 95) - np.percentile(major, 5)),
    )
