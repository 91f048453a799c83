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
import typing
from pathlib import Path

import pytest
import yaml

import simgrasp
from simgrasp.cli import COMMANDS

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "mkdocs.yml"

pytestmark = pytest.mark.xdist_group("docs_build")  # one worker builds the site once


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


def test_every_page_outside_the_runs_is_in_the_nav() -> None:
    """A page under docs/ is reached from the navigation (the per-run result pages under
    docs/results/NAME/ are reached from the results index instead)."""
    nav = set(_nav_pages(yaml.safe_load(CONFIG.read_text())["nav"]))
    docs = ROOT / "docs"
    pages = {p.relative_to(docs).as_posix() for p in docs.rglob("*.md")}
    unlisted = sorted(p for p in pages - nav if not re.match(r"results/[^/]+/", p))
    assert not unlisted, f"pages missing from the nav of mkdocs.yml: {unlisted}"


def _allowed(build: typing.Callable[[str], object]) -> list[str]:
    """The names a checked setting allows, read from the one-line error that ``build`` (a
    settings tree made with the setting at a bad value) raises: ``... is not one of a, b``."""
    with pytest.raises(simgrasp.SimgraspError) as refused:
        build("no-such-name")
    return str(refused.value).split("is not one of ")[1].split(", ")


def test_the_concept_pages_name_every_choice() -> None:
    """The concept pages name every failure mode a trial record can hold and every protocol,
    gripper, proposer and sensor the command line offers."""
    failure = typing.get_type_hints(simgrasp.TrialResult)["failure"]
    failures = [a for arg in typing.get_args(failure) for a in typing.get_args(arg)]
    chain = simgrasp.ChainConfig.of

    def label(protocol: typing.Any) -> object:
        return simgrasp.LabelConfig("gen_mug", protocol=protocol)

    pages = {
        "trials.md": failures + _allowed(label),
        "grippers.md": _allowed(lambda n: chain(gripper=n)),
        "perception.md": _allowed(lambda n: chain(sensor__kind=n)),
    }
    assert len(failures) >= 7 and all(pages.values())
    missing = [
        f"{page}: {name}"
        for page, names in pages.items()
        for name in names
        if f"`{name}`" not in (ROOT / "docs" / "concepts" / page).read_text()
    ]
    proposers = (ROOT / "docs" / "extending" / "proposer.md").read_text()
    kinds = _allowed(lambda n: chain(detector__kind=n))
    missing += [f"proposer.md: {n}" for n in kinds if f"`{n}`" not in proposers]
    assert not missing, missing
