"""The trial replay page (``simgrasp view t.json``) in a real headless Chromium (the browser
of ``test_viewer_browser.py``): offline, no console error, the scene drawn in its colors,
the slider moves the gripper and the object and names the phase."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from test_viewer_browser import _near, _open, _requests, _screenshot, browser  # noqa: F401

GRIPPER_RGB = (91, 111, 138)  # trial_page.GRIPPER_COLOR, before shading
TABLE_RGB = (200, 180, 140)  # the table's color, before shading


def _simgrasp(*args: str, cwd: Path) -> str:
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    done = subprocess.run(
        [sys.executable, "-m", "simgrasp", *args], cwd=cwd, env=env, check=True,
        capture_output=True, text=True,
    )  # fmt: skip
    return done.stdout


@pytest.fixture(scope="module")
def trial_page(tmp_path_factory) -> Path:
    work = tmp_path_factory.mktemp("trial-view")
    (work / "t.json").write_text(_simgrasp("trial", "gen_hammer", "--record", "--json", cwd=work))
    _simgrasp("view", "t.json", "--export", "t.html", cwd=work)
    return work / "t.html"


def _gripper_top(driver) -> float:
    return driver.execute_script(
        "const t = document.getElementById('scene').data.find(t => t.meta && "
        "t.meta.body === 'gripper'); return Math.max(...t.z);"
    )


def test_trial_page_replays_with_slider_and_phases(browser, trial_page):  # noqa: F811
    assert trial_page.stat().st_size < 6e6
    first = _open(browser, trial_page)
    outside = [u for u in _requests(browser) if not u.startswith(("file:", "data:", "blob:"))]
    assert outside == []
    assert [e for e in browser.get_log("browser") if e["level"] == "SEVERE"] == []
    assert (~(first == 255).all(axis=2)).mean() > 0.05  # the scene is drawn
    # the gripper and the table top in their colors (far more pixels than a legend swatch)
    assert _near(first, GRIPPER_RGB) > 500 and _near(first, TABLE_RGB) > 5000
    assert browser.find_element("id", "phase").text == "approach and close"
    assert "on_handle" in browser.find_element("id", "side").text
    low = _gripper_top(browser)
    slider = browser.find_element("id", "slider")
    last = int(slider.get_attribute("max"))
    slider.send_keys("\ue010")  # End: the browser moves the slider to its last frame
    time.sleep(1.0)
    assert browser.execute_script("return document.body.dataset.frame") == str(last)
    assert browser.find_element("id", "phase").text == "done"
    assert _gripper_top(browser) > low + 0.1  # lifted 20 cm
    moved = _screenshot(browser)
    if os.environ.get("SIMGRASP_SHOTS"):
        for name, image in (("first", first), ("last", moved)):
            from PIL import Image

            Image.fromarray(image).save(Path(os.environ["SIMGRASP_SHOTS"]) / f"{name}.png")
    assert (np.abs(moved.astype(int) - first).sum(axis=2) > 30).mean() > 0.005
    browser.execute_script("window.showFrame(Math.round(arguments[0] / 2))", last)
    time.sleep(0.5)
    assert browser.find_element("id", "phase").text in ("lift and hold", "perturb")


def test_trial_page_of_a_ycb_object(browser, ycb_dir, tmp_path):  # noqa: F811
    """A YCB object's trial page (built locally, never committed) loads and draws its mesh."""
    record = _simgrasp("trial", "025_mug", "--ycb-dir", ycb_dir, "--record", "--json", cwd=tmp_path)
    (tmp_path / "t.json").write_text(record)
    _simgrasp("view", "t.json", "--ycb-dir", ycb_dir, "--export", "t.html", cwd=tmp_path)
    image = _open(browser, tmp_path / "t.html")
    outside = [u for u in _requests(browser) if not u.startswith(("file:", "data:", "blob:"))]
    assert outside == []
    assert [e for e in browser.get_log("browser") if e["level"] == "SEVERE"] == []
    assert (~(image == 255).all(axis=2)).mean() > 0.05
    vertices = browser.execute_script(
        "return document.getElementById('scene').data.find(t => t.meta && "
        "t.meta.body === 'object').x.length"
    )
    assert vertices > 1000  # the scanned mesh, not a stand-in
    browser.execute_script("window.showFrame(1e9)")
    assert browser.find_element("id", "phase").text == "done"
