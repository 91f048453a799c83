"""Argument types shared by several sub-commands (ranges, comma lists)."""

from __future__ import annotations

import argparse

import numpy as np

from simgrasp.assets.placement import DEFAULT_PLACEMENT, PLACEMENTS
from simgrasp.scenes.views import CHAIN_VIEWS, MAX_VIEWS


def float_range(text: str) -> tuple[float, ...]:
    """Parse ``START:STOP:STEP`` (inclusive of STOP) or a comma list, e.g. ``0:0.1:0.02``."""
    try:
        if ":" in text:
            start, stop, step = (float(v) for v in text.split(":"))
            if step <= 0 or stop < start:
                raise ValueError
            count = int(np.floor((stop - start) / step + 1e-9)) + 1
            return tuple(round(start + i * step, 10) for i in range(count))
        return tuple(float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            "expected START:STOP:STEP with STEP > 0 and STOP >= START, or a comma list; "
            f"got {text!r}"
        ) from None


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
