"""Where a knife's handle ends along the tool: its even run, at one end of the tool.

A knife's handle is a stretch of even section (a bar, a turned grip) at one end of the tool;
its blade tapers to a point, and a bolster is a short collar, thicker and wider, between them.
When the blade is as thick as the handle (a table knife of one piece of steel), the thickness
tests of :mod:`simgrasp.autolabel.cross_section` do not tell them apart, and the detector finds
round enough sections on both, so a part's region runs the tool's whole length. No handle
does, so such a region is cut (:func:`handle_span`) to the handle's **even run**: the longest
unbroken run of slabs whose thickness and width (each smoothed over ``even_window``) stay
within ``even_ratio`` of the run's own medians, that reaches an end of the tool (within
``end_reach``) and is at least ``min_run`` long, plus the slabs beyond it to that end (a
rounded butt). Optionally (``bolster_reach``, off by default), a region that does not run
the tool's length is cut there too when the tool thins to a blade within that distance past
the run's inner end (a bolster, a blade's root). Both cuts are off by default
(``span_share`` 0: see its note). Meters, slabs of a
:class:`~simgrasp.autolabel.cross_section.SectionProfile`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from simgrasp.autolabel.cross_section import CrossSectionConfig, SectionProfile

_SETTLE = 5
"""Times a run's reference section is taken again from its own medians."""


def handle_span(
    points: NDArray[np.float64],
    region_points: NDArray[np.float64],
    profile: SectionProfile,
    config: CrossSectionConfig,
) -> NDArray[np.bool_]:
    """(N,) which ``points`` lie in the slabs a part's region (``region_points``) keeps: all
    of them unless the region runs at least ``span_share`` of the tool's length, or the tool
    thins to a blade within ``bolster_reach`` past the handle's even run
    (:func:`even_run`), when only the run and the slabs beyond it to the tool's end are kept;
    all of them too when there is no such run, it misses the region, or the tests are off."""
    keep = np.ones(len(points), dtype=bool)
    if config.span_share <= 0 or len(region_points) == 0:
        return keep
    known = np.flatnonzero(np.isfinite(profile.thickness) & np.isfinite(profile.width))
    own = profile.slabs_of(region_points)
    run = even_run(profile, (int(own.min()), int(own.max())), config)
    if len(known) < 2 or run is None:
        return keep
    first, last, at_first = run
    span = (own.max() - own.min() + 1) / (known[-1] - known[0] + 1)
    if span < config.span_share and not _blade_beyond(profile, run, config):
        return keep
    slabs = profile.slabs_of(points)
    return slabs <= last if at_first else slabs >= first


def even_run(
    profile: SectionProfile, span: tuple[int, int], config: CrossSectionConfig
) -> tuple[int, int, bool] | None:
    """The handle's even run ``(first slab, last slab, whether it is at the tool's first
    end)``: the longest unbroken run of slabs whose smoothed thickness and width stay within
    ``even_ratio`` of the run's own medians (:func:`_settled_run`, from each slab in turn) that
    meets the slabs ``span`` (first, last: a part's region), reaches an
    end of the tool within ``end_reach`` and runs at least ``min_run``; None when no run
    does."""
    thickness, width = _smoothed(profile.thickness, config), _smoothed(profile.width, config)
    known = np.flatnonzero(np.isfinite(thickness) & np.isfinite(width))
    if len(known) < 2:
        return None
    reach = int(np.ceil(config.end_reach / profile.slab))
    best: tuple[int, int, bool] | None = None
    for k in known:
        slabs = _settled_run(thickness, width, int(k), config.even_ratio)
        if slabs is None:
            continue
        first, last = int(slabs[0]), int(slabs[-1])
        at_first, at_last = first - known[0] <= reach, known[-1] - last <= reach
        long = (last - first + 1) * profile.slab >= config.min_run
        meets = first <= span[1] and last >= span[0]
        longer = best is None or last - first > best[1] - best[0]
        if long and meets and (at_first or at_last) and longer:
            best = (first, last, bool(at_first))
    return best


def _settled_run(
    thickness: NDArray[np.float64], width: NDArray[np.float64], seed: int, ratio: float
) -> NDArray[np.int64] | None:
    """(R,) the slabs of the unbroken run through slab ``seed`` whose ``thickness`` and
    ``width`` stay within ``ratio`` of the run's own medians: started from the seed slab's
    section, then from the run's medians until the run no longer changes; None when the
    seed slab leaves its run or the run has not settled after ``_SETTLE`` times."""
    reference = (thickness[seed], width[seed])
    slabs = np.zeros(0, dtype=np.int64)
    for _ in range(_SETTLE):
        alike = _within(thickness, reference[0], ratio) & _within(width, reference[1], ratio)
        if not alike[seed]:
            return None
        runs = ndimage.label(alike)[0]
        run = np.flatnonzero(runs == runs[seed])
        if np.array_equal(run, slabs):
            return slabs
        slabs = run
        reference = (float(np.median(thickness[run])), float(np.median(width[run])))
    return None


def _blade_beyond(
    profile: SectionProfile, run: tuple[int, int, bool], config: CrossSectionConfig
) -> bool:
    """Whether a slab within ``bolster_reach`` past the run's inner end is under
    ``min_ratio`` times as thick as the run's median slab (a blade begins there: the slabs
    between are a bolster or the blade's root); never with either setting 0."""
    if config.bolster_reach <= 0 or config.min_ratio <= 0:
        return False
    first, last, at_first = run
    reference = float(np.nanmedian(profile.thickness[first : last + 1]))
    reach = int(np.ceil(config.bolster_reach / profile.slab))
    beyond = slice(last + 1, last + 1 + reach) if at_first else slice(max(first - reach, 0), first)
    return bool((profile.thickness[beyond] < config.min_ratio * reference).any())


def _smoothed(values: NDArray[np.float64], config: CrossSectionConfig) -> NDArray[np.float64]:
    """``values`` (S,) as the median of the known ones within ``even_window / 2`` either side
    (NaN where none is known)."""
    half = int(round(config.even_window / config.slab / 2))
    out = np.full(len(values), np.nan)
    for k in range(len(values)):
        window = values[max(k - half, 0) : k + half + 1]
        if np.isfinite(window).any():
            out[k] = np.nanmedian(window)
    return out


def _within(values: NDArray[np.float64], reference: float, ratio: float) -> NDArray[np.bool_]:
    """(S,) which ``values`` lie within ``ratio`` of ``reference``, either way (NaN: no)."""
    with np.errstate(invalid="ignore"):
        return (values >= reference / ratio) & (values <= reference * ratio)
