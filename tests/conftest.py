"""Shared set-up: the GL platform for MuJoCo, and the external data tests need (YCB meshes,
the Menagerie Robotiq, the real scenes; see ``data_needs.py``): a test that needs missing data
is skipped, and one closing line says how many were and how to get the data."""

from __future__ import annotations

import sys
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import settings

from simgrasp.gl_platform import configure_mujoco_gl

# MuJoCo fixes its GL platform at its first import, and test modules import mujoco directly:
# choose MUJOCO_GL (EGL, else OSMesa) before any of them is collected, so every test process
# renders with the same backend as the worker processes it spawns.
configure_mujoco_gl()

sys.path.insert(0, str(Path(__file__).parent))

# Property tests draw the same examples on every run and machine (the project's one-seed rule):
# a failure is reproducible, never a coin toss between two CI runs.
settings.register_profile("simgrasp", derandomize=True, database=None)
settings.load_profile("simgrasp")

from data_needs import KINDS, REQUIRE_ENV, SKIP_PREFIX, require_data  # noqa: E402


def pytest_configure(config: pytest.Config) -> None:
    for kind in KINDS.values():
        config.addinivalue_line("markers", f"{kind.marker}: needs {kind.what} ({kind.env})")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if "ycb_dir" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.ycb)


def pytest_runtest_setup(item: pytest.Item) -> None:
    for marker in KINDS:
        if item.get_closest_marker(marker) is not None:
            require_data(marker)


@pytest.fixture(scope="session")
def renderers() -> Iterator[Any]:
    """One renderer keeper for a test process's tests (scenes built alike share a GL context),
    closed at the end (imported here: mujoco after :func:`configure_mujoco_gl`)."""
    from simgrasp.scenes.kept_renderer import RendererKeeper

    with RendererKeeper() as keeper:
        yield keeper


@pytest.fixture(scope="session")
def ycb_dir() -> str:
    return str(require_data("ycb"))


@pytest.fixture(scope="session")
def real_dir() -> Path:
    return require_data("real")


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_terminal_summary(terminalreporter, exitstatus: int, config: pytest.Config):
    """One closing line (after pytest's own short summary): how many tests were skipped for
    missing data, which data, and how to get it."""
    yield
    counts: Counter[str] = Counter()
    for report in terminalreporter.stats.get("skipped", []):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else ""
        reason = reason.removeprefix("Skipped: ")
        if reason.startswith(SKIP_PREFIX):
            counts[reason.removeprefix(SKIP_PREFIX).split(" (")[0].strip()] += 1
    if not counts:
        return
    kinds = [kind for kind in KINDS.values() if counts[kind.what]]
    what = ", ".join(f"{counts[k.what]} need {k.what} (no {k.env})" for k in kinds)
    hows = "; ".join(k.how for k in kinds)
    terminalreporter.write_line(
        f"simgrasp: {sum(counts.values())} tests skipped for missing data: {what}. "
        f"To run them: {hows}. {REQUIRE_ENV}=1 turns these skips into failures.",
        yellow=True,
        bold=True,
    )
