"""The commands that README.md and the pages under docs/ (the site's pages and the committed
results) print (``simgrasp ...``, ``python scripts/...``, ``python benchmarks/...``) use flags
that exist today: a flag renamed or removed since a page or a run was written fails here, not
in the hands of a reader who copies the command."""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import sys
from collections import Counter
from pathlib import Path
from unittest import mock

from simgrasp.cli import COMMANDS, build_parser
from simgrasp.config.arguments import add_settings_arguments

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
COMMAND = re.compile(r"^\s*(?:[A-Z_]+=\S+\s+)*simgrasp\s+([a-z][a-z-]*)(.*)$")
SCRIPT = re.compile(r"^\s*(?:[A-Z_]+=\S+\s+)*python\s+((?:scripts|benchmarks)/\w+\.py)(.*)$")
CHAIN = re.compile(r"&&|\|\||;|\|")
"""What separates the commands of one shell line."""
FLAG = re.compile(r"(?<![\w-])--[a-z][\w.-]*")


def _commands(path: Path, command: re.Pattern[str] = COMMAND) -> list[tuple[int, str, str]]:
    """(line number, command, its arguments with continuation lines joined) of every match of
    ``command`` (``simgrasp COMMAND ...``; :data:`SCRIPT`: a script's path) in a fenced or
    4-space indented block of ``path``, also where a shell line chains several commands."""
    found, fenced, lines, joined = [], False, path.read_text().splitlines(), 0
    for number, line in enumerate(lines, 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if number <= joined or not (fenced or line.startswith("    ")):
            continue
        following = number
        while line.rstrip().endswith("\\") and following < len(lines):
            line = line.rstrip()[:-1] + " " + lines[following]
            following += 1
        joined = following
        for part in CHAIN.split(line.split("#", 1)[0]):
            if (match := command.match(part)) is not None:
                found.append((number, match.group(1), match.group(2)))
    return found


def _known_flags(command: str) -> set[str]:
    """Every option string of ``simgrasp command``."""
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return set(sub.choices[command]._option_string_actions)


def test_documented_commands_use_flags_the_cli_knows() -> None:
    known: dict[str, set[str]] = {}
    problems = []
    checked = 0
    for path in DOCS:
        for number, command, rest in _commands(path):
            where = f"{path.relative_to(ROOT)}:{number}"
            if command not in COMMANDS:
                problems.append(f"{where}: no command {command!r}")
                continue
            flags = known.setdefault(command, _known_flags(command))
            checked += 1
            problems += [
                f"{where}: simgrasp {command} has no {flag}"
                for flag in FLAG.findall(rest)
                if flag not in flags
            ]
    assert checked > 50, f"only {checked} documented commands found: is the pattern stale?"
    assert not problems, "\n".join(problems)


def _settings_flags(script: Path) -> set[str]:
    """Every option string of a script whose flags its ``Options`` dataclass makes
    (:func:`~simgrasp.config.arguments.script_main`): the script loaded as a module (its ``main``
    not run; ``scripts/`` importable for its sibling imports) and ``Options`` made into flags as
    ``script_main`` makes them. The environment a script sets as it loads (thread counts) is
    restored, and the scripts it loaded are forgotten."""
    name = f"_documented_{script.stem}"
    spec = importlib.util.spec_from_file_location(name, script)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    loaded = set(sys.modules)
    parser = argparse.ArgumentParser()
    with (
        mock.patch.dict(os.environ),
        mock.patch.object(sys, "path", [str(script.parent), *sys.path]),
    ):
        sys.modules[name] = module  # its dataclass looks its module up there
        try:
            spec.loader.exec_module(module)
            add_settings_arguments(parser, module.Options)
        finally:
            for key in set(sys.modules) - loaded:
                if Path(getattr(sys.modules[key], "__file__", None) or "").parent == script.parent:
                    del sys.modules[key]
    return set(parser._option_string_actions)


def test_documented_scripts_use_flags_they_define() -> None:
    """Each ``--flag`` of a documented script command is one the script defines: for a script
    whose ``Options`` make its flags (``script_main``), an option string of that parser; for one
    on argparse, a string its source holds (or ``--help``)."""
    problems: list[str] = []
    checked: Counter[str] = Counter()
    made: dict[str, set[str]] = {}
    for path in DOCS:
        for number, script, rest in _commands(path, SCRIPT):
            where = f"{path.relative_to(ROOT)}:{number}"
            if not (ROOT / script).is_file():
                problems.append(f"{where}: no {script}")
                continue
            source = (ROOT / script).read_text()
            if "script_main" in source:
                if script not in made:
                    made[script] = _settings_flags(ROOT / script)
                checked["settings"] += 1
                unknown = [flag for flag in FLAG.findall(rest) if flag not in made[script]]
            else:
                checked["argparse"] += 1
                unknown = [
                    flag
                    for flag in FLAG.findall(rest)
                    if flag != "--help" and f'"{flag}"' not in source
                ]
            problems += [f"{where}: {script} has no {flag}" for flag in unknown]
    counts = dict(checked)
    assert sum(checked.values()) > 10, f"only {counts} documented script commands found"
    assert checked["settings"] > 5, f"only {counts}: are the settings scripts still loaded?"
    assert not problems, "\n".join(problems)


def test_a_script_is_loaded_without_running_it(capsys) -> None:
    """Loading a script for its flags runs nothing (no output) and leaves the environment as it
    was."""
    before = dict(os.environ)
    flags = _settings_flags(ROOT / "scripts" / "train_candidate_classifier.py")
    assert {"--degradations", "--seeds", "--print-config"} <= flags and "--no-such" not in flags
    assert dict(os.environ) == before
    assert capsys.readouterr() == ("", "")


def test_a_stale_flag_is_found(tmp_path: Path) -> None:
    """The checker itself: an unknown flag of the second command of a chained, continued
    line is reported against that command, the first command's flags against its own."""
    page = tmp_path / "page.md"
    chained = (
        "simgrasp detect c.npy --json > d.json && \\\n      simgrasp view d.json --no-such-flag 1"
    )
    page.write_text(f"Run:\n\n    {chained}\n")
    found = _commands(page)
    assert [(number, command) for number, command, _ in found] == [(3, "detect"), (3, "view")]
    stale = [f for _, c, rest in found for f in FLAG.findall(rest) if f not in _known_flags(c)]
    assert stale == ["--no-such-flag"]
