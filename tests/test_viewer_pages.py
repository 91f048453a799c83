"""The detection and report pages of ``simgrasp view`` in a real headless Chromium (the browser
and helpers of ``test_viewer_browser``): no outside request, no console error, the scene drawn
in its colors, a filter changes what is drawn, a click shows a record; and a PATH the viewer
cannot draw is one line."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import trimesh
from test_viewer_browser import _near, _open, _requests, _run, _screenshot
from test_viewer_browser import browser as browser  # the module's Chromium fixture

from simgrasp.cli import main


def _hex(color: str) -> tuple[int, int, int]:
    return int(color[1:3], 16), int(color[3:5], 16), int(color[5:7], 16)


def _clean_load(driver, page: Path) -> np.ndarray:
    """Open ``page``; it asked nothing from outside and logged no error; not blank."""
    shot = _open(driver, page)
    outside = [u for u in _requests(driver) if not u.startswith(("file:", "data:", "blob:"))]
    assert outside == []
    assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []
    assert (~(shot == 255).all(axis=2)).mean() > 0.05  # the scene is drawn, not a blank canvas
    return shot


def _toggle(driver, group: str, value: str) -> np.ndarray:
    selector = f'input[data-filter="{group}"][value="{value}"]'
    driver.find_element("css selector", selector).click()
    time.sleep(1.0)
    return _screenshot(driver)


@pytest.fixture(scope="module")
def detect_page(tmp_path_factory) -> Path:
    """The page of ``detect --json`` on a 20,000-point cloud of the generated mug's surface."""
    from simgrasp.assets.registry import load_object

    work = tmp_path_factory.mktemp("detect")
    points, _ = trimesh.sample.sample_surface(load_object("gen_mug").mesh, 20_000, seed=0)
    np.save(work / "mug.npy", points)
    with (work / "d.json").open("w") as out:
        subprocess.run(
            [sys.executable, "-m", "simgrasp", "detect", "mug.npy", "--json"],
            cwd=work, stdout=out, check=True,
        )  # fmt: skip
    _run("view", "d.json", "--export", "page.html", cwd=work)
    return work / "page.html"


def test_detect_page_draws_kinds_and_handles_and_filters_them(browser, detect_page):
    from simgrasp.viewer.detect_page import HANDLE_COLOR, KIND_COLORS

    report = json.loads((detect_page.parent / "d.json").read_text())
    kinds = {c["kind"] for c in report["candidates"]}
    assert report["handles"] and kinds <= set(KIND_COLORS)
    before = _clean_load(browser, detect_page)
    kind = max(kinds, key=lambda k: sum(c["kind"] == k for c in report["candidates"]))
    assert _near(before, _hex(KIND_COLORS[kind])) > 100
    assert _near(before, _hex(HANDLE_COLOR)) > 100
    _toggle(browser, "layer", "axes")
    after = _toggle(browser, "kind", kind)
    assert _near(after, _hex(KIND_COLORS[kind])) < _near(before, _hex(KIND_COLORS[kind])) / 4
    shown = browser.execute_script(
        "return document.getElementById('scene').data.filter(t => t.meta && t.meta.filters && "
        "t.meta.filters.kind === arguments[0]).map(t => t.visible)",
        kind,
    )
    assert shown == [False, False]
    # plotly's own click event on the first handle's marker (a 3D pick by pixel is not
    # reproducible across GL implementations): the panel shows the handle's record
    browser.execute_script(
        "document.getElementById('scene').emit('plotly_click', {points: [{customdata: 'h0'}]})"
    )
    shown = json.loads(browser.find_element("id", "record").text)
    assert shown["score"] == pytest.approx(report["handles"][0]["score"])
    assert shown["span"] == pytest.approx(report["handles"][0]["span"])


@pytest.fixture(scope="module")
def scene_page(tmp_path_factory) -> Path:
    """The page of ``detect --segment --json`` on an exported clutter scene (kinect depth)."""
    work = tmp_path_factory.mktemp("scene")
    _run("scenes", "export", "--clutter", "2", "--clutter-objects", "generated", "--seeds", "1",
         "--views", "1", "--sensor", "kinect", "--out", "scenes", cwd=work)  # fmt: skip
    (scene,) = (work / "scenes").glob("*.pcd")
    with (work / "d.json").open("w") as out:
        subprocess.run(
            [sys.executable, "-m", "simgrasp", "detect", str(scene), "--segment", "--json"],
            cwd=work, stdout=out, check=True,
        )  # fmt: skip
    _run("view", "d.json", "--export", "page.html", cwd=work)
    return work / "page.html"


def test_scene_page_colors_each_segment_with_a_toggle(browser, scene_page):
    from simgrasp.viewer.detect_page import SEGMENT_COLORS

    objects = json.loads((scene_page.parent / "d.json").read_text())["segmentation"]["objects"]
    assert len(objects) >= 2
    before = _clean_load(browser, scene_page)
    first, second = _hex(SEGMENT_COLORS[0]), _hex(SEGMENT_COLORS[1])
    assert _near(before, first) > 50 and _near(before, second) > 50
    after = _toggle(browser, "layer", "segments")
    assert _near(after, first) < _near(before, first) / 4
    plain = browser.execute_script(
        "return document.getElementById('scene').data.filter(t => t.meta && t.meta.filters && "
        "t.meta.filters.layer === 'points').map(t => t.visible)"
    )
    assert plain == [False]  # the plain points stay off until their own box is checked
    _toggle(browser, "layer", "points")
    plain = browser.execute_script(
        "return document.getElementById('scene').data.filter(t => t.meta && t.meta.filters && "
        "t.meta.filters.layer === 'points').map(t => t.visible)"
    )
    assert plain == [True]


@pytest.mark.real
def test_real_scene_page_draws_each_segment(browser, tmp_path):
    """``detect --segment`` on a real osd-learn scene (a pot with side tabs), drawn offline."""
    from simgrasp.assets.real import default_real_dir
    from simgrasp.viewer.detect_page import SEGMENT_COLORS

    scene = default_real_dir() / "osd-learn" / "learn40.pcd"
    with (tmp_path / "d.json").open("w") as out:
        subprocess.run(
            [sys.executable, "-m", "simgrasp", "detect", str(scene), "--segment", "--json"],
            cwd=tmp_path, stdout=out, check=True,
        )  # fmt: skip
    _run("view", "d.json", "--export", "page.html", cwd=tmp_path)
    shot = _clean_load(browser, tmp_path / "page.html")
    first, second = _hex(SEGMENT_COLORS[0]), _hex(SEGMENT_COLORS[1])
    assert _near(shot, first) > 200 and _near(shot, second) > 200
    after = _toggle(browser, "layer", "segments")
    assert _near(after, first) < _near(shot, first) / 4


@pytest.fixture(scope="module")
def report_page(tmp_path_factory) -> Path:
    """The page of a 4-trial evaluate run (two generated tools, quadric and centroid)."""
    work = tmp_path_factory.mktemp("report")
    _run("evaluate", "--objects", "gen_hammer,gen_mug", "--detector", "quadric,centroid",
         "--seeds", "1", "--workers", "1", "--no-progress", "--out", "ev", cwd=work)  # fmt: skip
    _run("view", "ev", "--export", "page.html", cwd=work)
    return work / "page.html"


def test_report_page_shows_tables_plots_and_each_trial(browser, report_page):
    from simgrasp.viewer.report_page import read_trials, trial_outcome
    from simgrasp.viewer.shapes import COLORS

    records = read_trials(report_page.parent / "ev")
    outcomes = [trial_outcome(r) for r in records]
    shot = _clean_load(browser, report_page)
    for kind in set(outcomes) & set(COLORS):
        assert _near(shot, _hex(COLORS[kind])) > 30, kind
    tables = browser.find_elements("css selector", "#report table")
    assert len(tables) >= 4
    images = browser.find_elements("css selector", "#report img")
    assert len(images) == 2
    assert all(browser.execute_script("return arguments[0].naturalWidth", i) > 100 for i in images)
    # the first trial with a grasp is drawn on load: its object's mesh and the grasp
    drawn = browser.execute_script("return document.getElementById('scene').data.map(t => t.type)")
    assert drawn == ["mesh3d", "scatter3d"]
    first = int(browser.execute_script("return document.body.dataset.selected"))
    last = len(records) - 1
    browser.find_element("css selector", f'tr.trial[data-trial="{last}"]').click()
    time.sleep(1.0)
    drawn = browser.execute_script(
        "return document.getElementById('scene').data.map(t => [t.type, t.line && t.line.color])"
    )
    if outcomes[last] != "no_grasp":  # the clicked trial's grasp, in its outcome color
        assert ["scatter3d", COLORS[outcomes[last]]] in drawn
    if last != first:
        moved = _screenshot(browser)
        assert (np.abs(moved.astype(int) - shot).sum(axis=2) > 30).mean() > 0.002
    shown = json.loads(browser.find_element("id", "record").text)
    assert (shown["object"], shown["seed"], shown["detector"]) == (
        records[last]["object"], records[last]["seed"], records[last]["detector"],
    )  # fmt: skip
    assert browser.execute_script("return document.body.dataset.selected") == str(last)
    _toggle(browser, "object", "gen_mug")
    rows = browser.find_elements("css selector", "tr.trial")
    hidden = {r.get_attribute("data-object") for r in rows if not r.is_displayed()}
    assert hidden == {"gen_mug"}
    assert sum(r.is_displayed() for r in rows) == sum(r["object"] != "gen_mug" for r in records)


@pytest.mark.parametrize("case", ["missing", "other_folder", "old_json", "gone_cloud", "bad_log"])
def test_a_path_the_viewer_cannot_draw_is_one_line(case, tmp_path, capsys):
    path, expected = tmp_path / "x", ""
    if case == "missing":
        expected = "no such file or folder"
    elif case == "other_folder":
        path.mkdir()
        expected = "not a path simgrasp view shows"
    elif case in ("old_json", "gone_cloud"):
        report = {"detector": "quadric", "handles": [], "candidates": [], "neighborhoods": 0}
        if case == "gone_cloud":
            report["input"] = {"path": str(tmp_path / "moved" / "c.npy"), "units": "m"}
        path = tmp_path / "d.json"
        path.write_text(json.dumps(report))
        expected = "records no input cloud" if case == "old_json" else "c.npy is gone"
    else:
        path.mkdir()
        (path / "report.md").write_text("# report\n")
        (path / "trials.jsonl").write_text('{"object": "gen_mug"}\nnot json\n{"object": "x"}\n')
        expected = "trials.jsonl line 2 is not a JSON record"
    assert main(["view", str(path), "--export", str(tmp_path / "page.html")]) == 2
    err = capsys.readouterr().err
    assert expected in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "page.html").exists()


def test_a_data_set_folder_points_at_one_of_its_files(tmp_path: Path) -> None:
    """``label-grasps --grasps GLOB`` writes one label folder per file and a summary: view
    names the data set and one folder it can show, in one line."""
    from simgrasp.errors import SimgraspError
    from simgrasp.viewer.kinds import kind_of

    one = tmp_path / "Mug_a"
    one.mkdir()
    (one / "run.json").write_text("{}")
    (one / "labels.jsonl").write_text("")
    (tmp_path / "summary.json").write_text(json.dumps({"files": [{"dir": "Mug_a"}]}))
    with pytest.raises(SimgraspError, match="data set of 1 grasp files") as error:
        kind_of(tmp_path)
    assert f"simgrasp view {one}" in str(error.value) and "\n" not in str(error.value)
    assert kind_of(one).page is not None


def test_a_torn_last_label_line_is_left_out_with_a_note(tmp_path: Path, capsys) -> None:
    """A killed label-grasps run may leave half a last line: the page is drawn from the whole
    records, and stderr says one line was left out; a bad line before the last is an error."""
    from simgrasp.errors import SimgraspError
    from simgrasp.viewer.grasp_page import read_labels

    record = {"grasp": [0, 0, 0, 1, 0, 0, 0], "failure": None, "success": True}
    (tmp_path / "run.json").write_text("{}")
    (tmp_path / "labels.jsonl").write_text(json.dumps(record) + '\n{"grasp": [0, 0')
    _, records = read_labels(tmp_path)
    assert records == [record]
    assert "left out a torn last line" in capsys.readouterr().err
    (tmp_path / "labels.jsonl").write_text('{"grasp"\n' + json.dumps(record) + "\n")
    with pytest.raises(SimgraspError, match="labels.jsonl line 1 is not JSON"):
        read_labels(tmp_path)


def test_a_detection_is_not_drawn_over_a_cloud_replaced_since(tmp_path: Path, capsys) -> None:
    """``detect --json`` records its cloud's SHA-256: the same file is drawn, a file of that
    name with other points is one line saying it changed."""
    from simgrasp.cli import main

    from shapes import mug_like

    mug = mug_like(seed=0)
    cloud, report = tmp_path / "mug.npy", tmp_path / "d.json"
    np.save(cloud, np.hstack([mug.points, mug.normals]))
    assert main(["detect", str(cloud), "--json"]) == 0
    report.write_text(capsys.readouterr().out)
    assert main(["view", str(report), "--export", str(tmp_path / "same.html")]) == 0
    np.save(cloud, np.hstack([mug.points + 0.01, mug.normals]))
    assert main(["view", str(report), "--export", str(tmp_path / "page.html")]) == 2
    err = capsys.readouterr().err
    assert f"{cloud} changed since the detection" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "page.html").exists()
