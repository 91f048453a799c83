"""``simgrasp view --export`` pages opened in a real headless Chromium (Debian's chromium and
chromium-driver, driven by selenium; no browser download): no outside request, no console
error, the scene drawn in the outcome colors, a filter changes what is drawn."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

CHROMIUM, DRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--enable-unsafe-swiftshader", "--window-size=1100,800",
]  # fmt: skip
OUTCOME_RGB = {"on_handle": (44, 160, 44), "off_handle": (31, 119, 180), "failed": (214, 39, 40)}


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    if not (CHROMIUM.exists() and DRIVER.exists()):
        reason = "needs chromium and chromium-driver (apt-get install chromium chromium-driver)"
        if os.environ.get("SIMGRASP_REQUIRE_DATA") == "1":
            pytest.fail(reason)
        pytest.skip(reason)
    os.environ["SE_OFFLINE"] = "true"  # selenium-manager never downloads
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in [*FLAGS, f"--user-data-dir={tmp_path_factory.mktemp('chromium')}"]:
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    driver = webdriver.Chrome(service=Service(executable_path=str(DRIVER)), options=options)
    yield driver
    driver.quit()


def _run(*args: str, cwd: Path) -> None:
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    subprocess.run([sys.executable, "-m", "simgrasp", *args], cwd=cwd, env=env, check=True)


@pytest.fixture(scope="module")
def label_page(tmp_path_factory) -> Path:
    work = tmp_path_factory.mktemp("view")
    _run("sample-grasps", "gen_hammer", "--n", "40", "--out", "g.npz", cwd=work)
    _run("label-grasps", "gen_hammer", "--grasps", "g.npz", "--protocol", "fast",
         "--out", "labels", "--no-picture", cwd=work)  # fmt: skip
    _run("view", "labels", "--export", "page.html", cwd=work)
    return work / "page.html"


def _screenshot(driver) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(driver.get_screenshot_as_png())).convert("RGB"))


def _near(image: np.ndarray, rgb: tuple[int, int, int], tolerance: int = 40) -> int:
    """How many pixels are within ``tolerance`` (sum of channel differences) of ``rgb``."""
    return int((np.abs(image.astype(int) - rgb).sum(axis=2) < tolerance).sum())


def _open(driver, page: Path) -> np.ndarray:
    driver.get_log("performance")  # drop what came before
    driver.get(page.as_uri())
    deadline = time.time() + 60
    while driver.execute_script("return document.body.dataset.ready") != "1":
        assert time.time() < deadline, "the page never became live"
        time.sleep(0.2)
    time.sleep(1.5)
    return _screenshot(driver)


BROWSER_SCHEMES = ("chrome:", "chrome-untrusted:", "chrome-search:", "devtools:")
"""The browser's own pages and resources (its new-tab page may load in the background while
a test runs: 84 ``chrome://new-tab-page...`` requests in one CI run): never the network."""


def _requests(driver) -> list[str]:
    """The URLs requested since the log was last read, the browser's own pages aside."""
    urls = []
    for entry in driver.get_log("performance"):
        message = json.loads(entry["message"])["message"]
        if message["method"] == "Network.requestWillBeSent":
            url = message["params"]["request"]["url"]
            if not url.startswith(BROWSER_SCHEMES):
                urls.append(url)
    return urls


def test_label_page_offline_colored_and_filtered(browser, label_page):
    assert label_page.stat().st_size < 10e6
    before = _open(browser, label_page)
    outside = [u for u in _requests(browser) if not u.startswith(("file:", "data:", "blob:"))]
    assert outside == []
    errors = [e for e in browser.get_log("browser") if e["level"] == "SEVERE"]
    assert errors == []
    background = (before == 255).all(axis=2)
    assert (~background).mean() > 0.05  # the scene is drawn, not a blank canvas
    assert _near(before, OUTCOME_RGB["on_handle"]) > 200
    assert _near(before, OUTCOME_RGB["off_handle"]) + _near(before, OUTCOME_RGB["failed"]) > 50
    box = browser.find_element("css selector", 'input[data-filter="outcome"][value="on_handle"]')
    box.click()
    time.sleep(1.0)
    after = _screenshot(browser)
    hidden = browser.execute_script(
        "return document.getElementById('scene').data.filter(t => t.meta && "
        "t.meta.outcome === 'on_handle').every(t => t.visible === false)"
    )
    assert hidden
    assert _near(after, OUTCOME_RGB["on_handle"]) < _near(before, OUTCOME_RGB["on_handle"]) / 4
    box.click()  # back on: every grasp drawn again


def test_label_page_failure_filter_handle_label_and_record(browser, label_page):
    """The failure-mode boxes hide what they name (``held`` covers both held outcomes), the
    handle label is drawn, and a click on a grasp shows its label record."""
    records = [json.loads(line) for line in (label_page.parent / "labels" / "labels.jsonl").open()]
    before = _open(browser, label_page)
    handle = browser.execute_script(
        "return document.getElementById('scene')._fullData.filter(t => t.name === 'handle label')"
        ".map(t => [t.type, t.x.length, t.opacity, t.visible])"
    )  # plotly's decoded traces (the page's own arrays are base64)
    assert handle and all(
        kind == "mesh3d" and count >= 8 and 0 < opacity < 1 and shown is True
        for kind, count, opacity, shown in handle
    )
    browser.find_element("css selector", 'input[data-filter="failure"][value="held"]').click()
    time.sleep(1.0)
    after = _screenshot(browser)
    drawn = browser.execute_script(
        "return document.getElementById('scene').data.filter(t => t.meta && "
        "t.meta.outcome !== undefined).map(t => [t.meta.failure, t.visible !== false])"
    )
    assert drawn and all(on == (failure != "held") for failure, on in drawn)
    for kind in ("on_handle", "off_handle"):
        assert _near(after, OUTCOME_RGB[kind]) < _near(before, OUTCOME_RGB[kind]) / 4 + 5, kind
    # plotly's own click event on a grasp's TCP marker (a 3D pick by pixel is not reproducible
    # across GL implementations): the record box shows that grasp's label record
    chosen = next(r for r in records if r["success"])
    browser.execute_script(
        "document.getElementById('scene').emit('plotly_click', "
        "{points: [{customdata: arguments[0]}]})",
        chosen["index"],
    )
    shown = json.loads(browser.find_element("id", "record").text)
    assert shown["index"] == chosen["index"] and shown["failure"] == chosen["failure"]
    assert shown["grasp"] == pytest.approx(chosen["grasp"])
    hover = browser.execute_script(
        "return document.getElementById('scene').data.filter(t => t.mode === 'markers' && "
        "t.meta && t.meta.outcome !== undefined).map(t => t.hovertemplate)"
    )
    assert hover and all(h.startswith("grasp %{customdata}") for h in hover)
