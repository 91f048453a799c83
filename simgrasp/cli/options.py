"""Options shared by several commands, declared once."""

from __future__ import annotations

import math
from dataclasses import dataclass

from simgrasp.config.checks import Checked
from simgrasp.errors import SimgraspError

MAX_RANGE_VALUES = 1000
"""``START:STOP:STEP`` expands to at most this many values: a sweep point each, so more is a
typo (``1e-12`` for ``1e-2``), not a plan."""


@dataclass(frozen=True, kw_only=True)
class YcbSource(Checked):
    """Where YCB objects are read from (and the base of every command's options: their
    fields are checked when the options are built)."""

    ycb_dir: str | None = None
    """YCB download root holding 025_mug/ etc. (default: $SIMGRASP_YCB_DIR)."""


def float_range(text: str) -> tuple[float, ...]:
    """``START:STOP:STEP`` (inclusive of STOP) or a comma list, e.g. ``0:0.1:0.02``."""
    try:
        values = tuple(float(v) for v in text.split(":" if ":" in text else ","))
        if ":" in text:
            start, stop, step = values
    except ValueError:
        raise SimgraspError(
            f"expected START:STOP:STEP with STEP > 0 and STOP >= START, or a comma list; "
            f"got {text!r}"
        ) from None
    if not all(math.isfinite(v) for v in values):
        raise SimgraspError(f"every value must be finite (no inf or nan): {text!r}")
    if ":" not in text:
        return values
    if step <= 0 or stop < start:
        raise SimgraspError(f"expected START:STOP:STEP with STEP > 0 and STOP >= START: {text!r}")
    count = math.floor((stop - start) / step + 1e-9) + 1
    if count > MAX_RANGE_VALUES:
        raise SimgraspError(
            f"{text!r} expands to {count:.3g} values; at most {MAX_RANGE_VALUES} are allowed "
            "(each is a sweep setting run for every object and seed): use a larger STEP"
        )
    return tuple(round(start + i * step, 10) for i in range(count))
