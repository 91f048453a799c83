"""What the benchmarks that measure YCB objects do without the meshes: say so in one line."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any


def skipped_without_ycb(run: Callable[[Any], None], script: str) -> Callable[[Any], None]:
    """``run`` (a benchmark's ``run(options)``), but a missing YCB mesh exits with one line
    naming ``script`` instead of a traceback: nothing in these benchmarks runs without them."""

    def checked(options: Any) -> None:
        try:
            run(options)
        except FileNotFoundError as exc:  # also a DataNotFoundError, before script_main's catch
            sys.exit(f"{script}: skipped, it measures YCB objects: {exc}")

    return checked
