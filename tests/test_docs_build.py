"""The documentation site builds offline with warnings as errors (``make docs``), has a page
per command, renders the API reference from the docstrings, and the README's Python tour runs
as a newcomer would paste it."""

from __future__ import annotations

import html
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

import simgrasp
from simgrasp.cli import COMMANDS

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "mkdocs.yml"


def _nav_pages(entry: object) -> list[str]:
    """Every page file the ``nav`` entry lists, depth first."""
    if isinstance(entry, str):
        return [entry]
    if isinstance(entry, dict):
        return [page for value in entry.values() for page in _nav_pages(value)]
    if isinstance(entry, list):
        return [page for item in entry for page in _nav_pages(item)]
    return []


def _text(page: Path) -> str:
    """A built page's text: tags and white space dropped, entities decoded."""
    return re.sub(r"\s+", "", html.unescape(re.sub(r"<[^>]+>", " ", page.read_text())))


def _first_sentence(obj: object) -> str:
    """The first sentence of ``obj``'s docstring as :func:`_text` reads it on the page
    (no backquotes, no white space)."""
    sentence = re.sub(r"\s+", " ", inspect.getdoc(obj) or "").split(". ")[0]
    return re.sub(r"\s+", "", sentence.replace("`", ""))


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built once by ``mkdocs build --strict`` (a warning fails it)."""
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    command = [sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet"]
    done = subprocess.run(
        [*command, "--config-file", str(CONFIG), "--site-dir", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return out


def test_every_command_has_a_page_in_the_nav() -> None:
    nav = _nav_pages(yaml.safe_load(CONFIG.read_text())["nav"])
    missing = [name for name in COMMANDS if f"commands/{name}.md" not in nav]
    assert not missing, f"commands without a page in mkdocs.yml's nav: {missing}"
    assert all((ROOT / "docs" / page).is_file() for page in nav)


def test_the_site_builds_with_every_nav_page(site: Path) -> None:
    nav = _nav_pages(yaml.safe_load(CONFIG.read_text())["nav"])
    for page in nav:
        source = Path(page).with_suffix("")
        folder = source.parent if source.name in ("index", "README") else source
        assert (site / folder / "index.html").is_file(), f"{page} was not built"
    # the per-run pages are built too, and the data beside them left out
    assert (site / "results" / "evaluate" / "report" / "index.html").is_file()
    assert not list(site.rglob("*.jsonl")) and not list(site.rglob("*.npz"))


def test_the_api_reference_shows_the_docstrings(site: Path) -> None:
    front = _text(site / "api" / "index.html")
    for function in (simgrasp.detect_handles, simgrasp.run_trial, simgrasp.label_grasps):
        assert _first_sentence(function) in front, function.__name__
    results = _text(site / "api" / "results" / "index.html")
    assert _first_sentence(simgrasp.TrialResult) in results
    assert "grasppointonthehandleaxis(m)" in results  # Handle's attribute table


@pytest.mark.slow
def test_the_readme_python_tour_runs(tmp_path: Path) -> None:
    """The README's Python block, pasted into a fresh interpreter, runs and prints."""
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"^```python\n(.*?)^```", readme, flags=re.S | re.M)
    assert len(blocks) == 1, "the README holds one Python tour"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(
        [sys.executable, "-c", blocks[0]],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert re.search(r"\d+ of 20 held, \d+ by the handle", done.stdout), done.stdout
