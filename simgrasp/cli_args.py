"""Argument types shared by several sub-commands (ranges, comma lists)."""

from __future__ import annotations

import argparse

import numpy as np

from simgrasp.assets.placement import DEFAULT_PLACEMENT, PLACEMENTS
from simgrasp.scenes.views import CHAIN_VIEWS, MAX_VIEWS

MAX_RANGE_VALUES = 1000
"""Most values a ``START:STOP:STEP`` range may expand to: every value is a sweep setting (a
column of trials), so more is a typo (a tiny STEP), not a sweep."""


def float_range(text: str) -> tuple[float, ...]:
    """Parse ``START:STOP:STEP`` (inclusive of STOP) or a comma list, e.g. ``0:0.1:0.02``; all
    values finite, a range at most :data:`MAX_RANGE_VALUES` long."""
    try:
        values = _expand_range(text) if ":" in text else tuple(float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            "expected START:STOP:STEP with STEP > 0 and STOP >= START, or a comma list; "
            f"got {text!r}"
        ) from None
    if not all(np.isfinite(values)):
        raise argparse.ArgumentTypeError(f"every value must be finite (no inf or nan): {text!r}")
    return values


def _expand_range(text: str) -> tuple[float, ...]:
    start, stop, step = (float(v) for v in text.split(":"))
    if not np.isfinite([start, stop, step]).all():
        return (start, stop, step)  # refused by the finite check
    if step <= 0 or stop < start:
        raise ValueError
    count = int(np.floor((stop - start) / step + 1e-9)) + 1
    if count > MAX_RANGE_VALUES:
        raise argparse.ArgumentTypeError(
            f"{text!r} expands to {count:.3g} values; at most {MAX_RANGE_VALUES} are allowed "
            "(each is a sweep setting run for every object and seed): use a larger STEP"
        )
    return tuple(round(start + i * step, 10) for i in range(count))


def comma_list(text: str) -> tuple[str, ...]:
    """Parse ``a,b,c`` into a tuple of non-empty names."""
    items = tuple(item.strip() for item in text.split(",") if item.strip())
    if not items:
        raise argparse.ArgumentTypeError(f"expected a comma-separated list, got {text!r}")
    return items


def add_views_argument(parser: argparse.ArgumentParser) -> None:
    """``--views N``: how many default cameras the full chain renders and fuses."""
    parser.add_argument(
        "--views",
        type=int,
        choices=range(1, MAX_VIEWS + 1),
        default=CHAIN_VIEWS,
        metavar="N",
        help=f"depth cameras spread around the table whose object pixels are fused into the "
        f"cloud, 1..{MAX_VIEWS} (default {CHAIN_VIEWS})",
    )


def add_placement_argument(parser: argparse.ArgumentParser) -> None:
    """``--placement stable|upright``: how the scene rests its object on the table."""
    parser.add_argument(
        "--placement",
        choices=PLACEMENTS,
        default=DEFAULT_PLACEMENT,
        help="object rest pose: a stable pose by the probability of landing in it from a random "
        "drop (a mug often lies on its side), or only upright ones (standing on its own base, "
        "as a person sets a mug down)",
    )
