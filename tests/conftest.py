"""Shared set-up: the GL platform for MuJoCo, and the YCB root every YCB test reads (CI sets
SIMGRASP_YCB_DIR)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from simgrasp.gl_platform import configure_mujoco_gl

# MuJoCo fixes its GL platform at its first import, and test modules import mujoco directly:
# choose MUJOCO_GL (EGL, else OSMesa) before any of them is collected, so every test process
# renders with the same backend as the worker processes it spawns.
configure_mujoco_gl()

sys.path.insert(0, str(Path(__file__).parent))


@pytest.fixture(scope="session")
def ycb_dir() -> str:
    root = os.environ.get("SIMGRASP_YCB_DIR")
    if not root or not Path(root).is_dir():
        pytest.fail(
            "SIMGRASP_YCB_DIR must point at a YCB download (CI sets it to ../shared/ycb); "
            "run `simgrasp fetch-ycb` to get one"
        )
    return root
