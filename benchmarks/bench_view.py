"""Is a 2,000-grasp label page fluid? Load and camera-turn times of ``simgrasp view`` pages in
headless Debian Chromium (offline, the browser tests' flags), against the same page with 200
grasps as a same-run baseline (medians, and the 2,000 / 200 ratio).

Takes a label-grasps folder of at least 2,000 drawable grasps (made once, a few minutes on one
core)::

    simgrasp sample-grasps gen_hammer --n 2000 --out /tmp/g2000.npz
    simgrasp label-grasps gen_hammer --grasps /tmp/g2000.npz --protocol fast --workers 1 \\
        --out /tmp/labels_2000
    python benchmarks/bench_view.py /tmp/labels_2000 --loads 3 --turns 12

The 200-grasp baseline is the first 200 records of the same folder. Per page:

- ``load_ms``: from the navigation's start to the second animation frame after the page is
  live (its plot drawn), its drawing finished (the page's own clock, ``performance.now()``),
  median over ``--loads``;
- ``turn_ms``: one camera step around a circle (``Plotly.relayout`` of ``scene.camera.eye``,
  ``--turns`` per circle) until two animation frames later, their drawing finished: what a
  user feels when dragging; median over a circle after a warm-up circle;
- ``draw_ms``: plotly's WebGL redraw of the scene alone (``glplot.redraw()``) at the same
  steps, median.

"Drawing finished" is a one-pixel read back of the scene's WebGL context (Chromium draws in
its GPU process, after the animation frame). With the tests' flags (``--disable-gpu``,
SwiftShader) WebGL is rendered in software on the CPU: absolute times are far above a browser
with a GPU, and grow with the CPU's load; the same-run ratio is the figure to compare.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.config.fields import setting

CHROMIUM, DRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--enable-unsafe-swiftshader", "--window-size=1100,800",
]  # fmt: skip
"""The flags of ``tests/test_viewer_browser.py``."""

FLUSH = """
function flush(gd) {  // wait until the GPU process has drawn what was sent (a 1-pixel read)
  const gl = gd._fullLayout.scene._scene.glplot.gl;
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
}
"""
"""Forces the scene's queued WebGL work to finish (WebGL draws asynchronously, in Chromium's
GPU process: an animation frame can come before its drawing is done)."""

LOADED = """
const done = arguments[arguments.length - 1];
const frames = () => requestAnimationFrame(() => requestAnimationFrame(() => {
  flush(document.getElementById('scene'));
  done(performance.now());
}));
if (document.body.dataset.ready === '1') { frames(); } else {
  new MutationObserver((_, watch) => {
    if (document.body.dataset.ready === '1') { watch.disconnect(); frames(); }
  }).observe(document.body, {attributes: true});
}
"""
"""Async script: ``performance.now()`` two animation frames after the page is live, its
drawing finished."""

TURN = """
const [x, y, z, done] = arguments;
const gd = document.getElementById('scene'), glplot = gd._fullLayout.scene._scene.glplot;
flush(gd);
const start = performance.now();
Plotly.relayout(gd, {'scene.camera.eye': {x: x, y: y, z: z}}).then(() =>
  requestAnimationFrame(() => requestAnimationFrame(() => {
    flush(gd);
    const turned = performance.now() - start, begin = performance.now();
    glplot.redraw();
    flush(gd);
    done([turned, performance.now() - begin]);
  })));
"""
"""Async script: one camera step (ms to two frames later) and one forced redraw (ms)."""


def subset_folder(labels: Path, count: int, out: Path) -> Path:
    """A label-grasps folder of the first ``count`` drawable records of ``labels``."""
    from simgrasp.viewer.grasp_page import read_labels

    _, records = read_labels(labels)
    if len(records) < count:
        sys.exit(f"{labels} has {len(records)} drawable grasps, fewer than {count}")
    out.mkdir(parents=True, exist_ok=True)
    shutil.copy(labels / "run.json", out / "run.json")
    lines = [json.dumps(r) for r in records[:count]]
    (out / "labels.jsonl").write_text("\n".join(lines) + "\n")
    return out


def browser(profile: Path) -> Any:
    """Headless Debian Chromium through chromedriver (selenium never downloads)."""
    os.environ["SE_OFFLINE"] = "true"
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in [*FLAGS, f"--user-data-dir={profile}"]:
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(executable_path=str(DRIVER)), options=options)
    driver.set_script_timeout(120)
    return driver


def measure(driver: Any, page: Path, loads: int, turns: int) -> dict[str, float]:
    """Median load, camera-step and redraw times (ms) of ``page``."""
    load_times = []
    for _ in range(loads):
        driver.get("about:blank")
        driver.get(page.as_uri())
        load_times.append(driver.execute_async_script(FLUSH + LOADED))
    steps: list[list[float]] = []
    for circle in range(2):  # the first circle warms up
        for k in range(turns):
            angle = 2 * math.pi * k / turns
            eye = (1.8 * math.cos(angle), 1.8 * math.sin(angle), 0.8)
            step = driver.execute_async_script(FLUSH + TURN, *eye)
            if circle == 1:
                steps.append(step)
    return {
        "load_ms": statistics.median(load_times),
        "turn_ms": statistics.median(s[0] for s in steps),
        "draw_ms": statistics.median(s[1] for s in steps),
        "mb": page.stat().st_size / 1e6,
    }


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    labels: Path = setting(positional=True)
    """A label-grasps folder holding at least --grasps drawable grasps."""
    grasps: PositiveInt = 2000
    """Grasps of the measured page (the folder's first records)."""
    baseline: PositiveInt = 200
    """Grasps of the same-run baseline page (the folder's first records)."""
    loads: PositiveInt = 3
    """Timed loads of each page; the median is printed."""
    turns: PositiveInt = 12
    """Camera steps around a circle (a warm-up circle, then a timed one)."""


def run(options: Options) -> None:
    """Export both pages, time them in the browser and print their figures and ratios."""
    if not (CHROMIUM.exists() and DRIVER.exists()):
        sys.exit("needs Debian's chromium and chromium-driver (make install)")
    from simgrasp.viewer.grasp_page import grasp_page

    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        pages = {}
        for count in (options.baseline, options.grasps):
            folder = subset_folder(options.labels, count, work / f"labels_{count}")
            start = time.perf_counter()
            pages[count] = work / f"page_{count}.html"
            pages[count].write_text(grasp_page(folder))
            print(f"{count} grasps: exported in {time.perf_counter() - start:.1f} s")
        driver = browser(work / "profile")
        try:
            results = {
                n: measure(driver, p, options.loads, options.turns) for n, p in pages.items()
            }
        finally:
            driver.quit()
    for count, result in results.items():
        print(f"{count:5d} grasps: " + ", ".join(f"{k} {v:.1f}" for k, v in result.items()))
    big, small = results[options.grasps], results[options.baseline]
    print(
        f"ratio {options.grasps} / {options.baseline}: "
        + ", ".join(f"{k} {big[k] / small[k]:.2f}" for k in ("load_ms", "turn_ms", "draw_ms"))
    )


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
