"""The data a test may need beyond the repository, and how a test says so.

Four kinds, each a pytest marker and an environment variable:

- ``ycb``: YCB meshes, ``SIMGRASP_YCB_DIR`` (the ``ycb_dir`` fixture marks its tests itself);
- ``menagerie``: the Robotiq 2F-85 of a MuJoCo Menagerie checkout, ``MENAGERIE_ROOT``;
- ``real``: the real sensor scenes, ``SIMGRASP_REAL_DIR`` (default ``../shared/real`` beside
  the repository);
- ``acronym``: the ACRONYM example and affordance files, ``SIMGRASP_ACRONYM_DIR`` (default
  ``../shared/acronym``).

A test that needs missing data is skipped, with a reason starting with :data:`SKIP_PREFIX`;
``SIMGRASP_REQUIRE_DATA=1`` (set by ``.ci/run``) turns that skip into a failure.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import pytest

REQUIRE_ENV = "SIMGRASP_REQUIRE_DATA"
SKIP_PREFIX = "needs data:"
REAL_DEFAULT = Path(__file__).resolve().parents[2] / "shared" / "real"
ACRONYM_DEFAULT = Path(__file__).resolve().parents[2] / "shared" / "acronym"


@dataclass(frozen=True)
class DataKind:
    """One kind of external data: its marker, variable, what it is and how to get it."""

    marker: str
    env: str
    what: str
    how: str
    probe: str = ""
    """A path under the root that must exist ('' = the root itself)."""
    default: Path | None = None


KINDS = {
    kind.marker: kind
    for kind in (
        DataKind(
            "ycb",
            "SIMGRASP_YCB_DIR",
            "YCB meshes",
            "`simgrasp fetch-ycb --dest DIR` then SIMGRASP_YCB_DIR=DIR",
        ),
        DataKind(
            "menagerie",
            "MENAGERIE_ROOT",
            "the Menagerie Robotiq 2F-85",
            "MENAGERIE_ROOT=a mujoco_menagerie checkout",
            probe="robotiq_2f85/2f85.xml",
        ),
        DataKind(
            "real",
            "SIMGRASP_REAL_DIR",
            "the real sensor scenes",
            f"SIMGRASP_REAL_DIR=their directory (default {REAL_DEFAULT})",
            default=REAL_DEFAULT,
        ),
        DataKind(
            "acronym",
            "SIMGRASP_ACRONYM_DIR",
            "the ACRONYM example and affordance files",
            f"SIMGRASP_ACRONYM_DIR=their directory (default {ACRONYM_DEFAULT})",
            probe="examples/grasps",
            default=ACRONYM_DEFAULT,
        ),
    )
}

ROBOTIQ = pytest.param("robotiq_2f85", marks=pytest.mark.menagerie, id="robotiq_2f85")
"""The Robotiq gripper name as a test parameter that needs the Menagerie."""


def data_root(marker: str) -> Path | None:
    """The directory of a data kind, or None if it is not there."""
    kind = KINDS[marker]
    value = os.environ.get(kind.env)
    root = Path(value) if value else kind.default
    if root is None or not (root / kind.probe).exists():
        return None
    return root


def require_data(marker: str) -> Path:
    """The directory of a data kind; skip the test (fail it under SIMGRASP_REQUIRE_DATA=1)
    when it is missing."""
    root = data_root(marker)
    if root is not None:
        return root
    kind = KINDS[marker]
    reason = f"{SKIP_PREFIX} {kind.what} ({kind.env} unset or missing)"
    if os.environ.get(REQUIRE_ENV, "") not in ("", "0"):
        pytest.fail(f"{reason}, and {REQUIRE_ENV} is set", pytrace=False)
    pytest.skip(reason)
