"""Each command's ``--help`` fits a screen, and no setting became unreachable for it: every leaf
of every command's settings tree is still a flag (listed by ``--help-all``), a ``--set`` key and
a config-file key. Every command of :data:`simgrasp.cli.COMMANDS` is covered, new ones too.
Nothing is run: the parsers are built and the settings trees built from what they parsed."""

from __future__ import annotations

import argparse
import functools
import shlex
import tomllib
import typing
from pathlib import Path
from typing import Any

import pytest
import yaml

from simgrasp.cli import COMMANDS, build_parser, command_module, main
from simgrasp.config.arguments import given_settings, settings_from_args
from simgrasp.config.files import toml_value
from simgrasp.config.help import first_sentence, fitted, headline
from simgrasp.config.listing import settings_listing
from simgrasp.config.schema import Leaf, flag_name, leaves, trees
from simgrasp.config.tree import build
from simgrasp.config.values import to_plain

MAX_HELP_LINES = 60
COMMAND_LIST = sorted(COMMANDS)


@functools.cache
def command_parser(command: str) -> argparse.ArgumentParser:
    """The sub-parser of ``simgrasp command``, with its settings' flags."""
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[command]


def leaf_actions(command: str) -> dict[str, argparse.Action]:
    """Dotted key -> the argparse action of each setting of ``command``."""
    by_dest = {action.dest: action for action in command_parser(command)._actions}
    return {
        key.split(":", 1)[1]: action
        for key, action in by_dest.items()
        if key.startswith(("setting:", "positional:"))
    }


def printed(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """What ``simgrasp *argv`` prints before it exits 0 (a help)."""
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 0
    return capsys.readouterr().out


def sample(leaf: Leaf) -> Any:
    """A value for a setting that has no default."""
    choices = leaf.spec.choices() if callable(leaf.spec.choices) else leaf.spec.choices
    if choices:
        return choices[0]
    if typing.get_origin(leaf.annotation) is typing.Literal:
        return typing.get_args(leaf.annotation)[0]
    if typing.get_origin(leaf.annotation) is tuple:
        return ("x",)
    return {int: 1, float: 1.0, bool: False, Path: Path("x")}.get(leaf.annotation, "x")


def expected_tree(command: str) -> tuple[Any, dict[str, Any]]:
    """The default settings of ``command`` (required ones given a sample) and every leaf's
    value in it."""
    cls = command_module(command).Options
    required = {leaf.key: sample(leaf) for leaf in leaves(cls) if leaf.required}
    tree = build(cls, required)
    return tree, {leaf.key: to_plain(leaf.default) for leaf in leaves(cls, tree)}


@pytest.mark.parametrize("command", COMMAND_LIST)
def test_help_fits_a_screen_and_names_the_full_listing(
    command: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """At 80 columns: at most 60 lines, the main settings in full, every settings tree summed
    up in one entry, an example, and the way to every setting (``--help-all``)."""
    monkeypatch.setenv("COLUMNS", "80")
    text = printed([command, "--help"], capsys)
    lines = text.splitlines()
    assert len(lines) <= MAX_HELP_LINES, f"{command} --help: {len(lines)} lines\n{text}"
    assert f"simgrasp {command} --help-all" in " ".join(text.split())
    assert "example" in text and f"  simgrasp {command}" in text
    cls = command_module(command).Options
    actions = leaf_actions(command)
    for leaf in leaves(cls):
        if leaf.main:
            action = actions[leaf.key]
            shown = action.option_strings[-1] if action.option_strings else action.metavar
            assert f"  {shown}" in text, f"{command}: main setting {leaf.key} not in --help"
    for key in trees(cls):
        assert f"\n  {flag_name(key)}.* (" in text, f"{command}: tree {key} not in --help"
    assert printed([command, "-h"], capsys) == text


@pytest.mark.parametrize("command", COMMAND_LIST)
def test_help_all_lists_every_flag(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    text = printed([command, "--help-all"], capsys)
    for leaf, action in zip(
        leaves(command_module(command).Options), leaf_actions(command).values(), strict=True
    ):
        names = action.option_strings or [str(action.metavar)]
        assert all(name in text for name in names), f"{command}: {leaf.key} not in --help-all"


@pytest.mark.parametrize("command", COMMAND_LIST)
def test_every_setting_is_a_flag(command: str) -> None:
    """The flags are exactly the settings' (and their aliases) and the fixed ones; each flag,
    given its setting's default, sets that key to that value."""
    cls = command_module(command).Options
    actions = leaf_actions(command)
    keys = [leaf.key for leaf in leaves(cls)]
    assert sorted(actions) == sorted(keys)
    fixed = {"-h", "--help", "--help-all", "--config", "--set", "--print-config"}
    flags = {name for action in actions.values() for name in action.option_strings}
    assert set(command_parser(command)._option_string_actions) == flags | fixed
    tree, values = expected_tree(command)
    argv, given = [], set()
    for leaf in leaves(cls):
        words = flag_words(values[leaf.key], actions[leaf.key])
        if words is not None:
            argv += words if leaf.spec.positional else [actions[leaf.key].option_strings[0], *words]
            given.add(leaf.key)
    left = set(keys) - given  # each a none or an empty list, which are defaults only
    assert all(values[key] in (None, []) for key in left), left
    args = command_parser(command).parse_args(argv)
    assert set(given_settings(cls, args)) == given
    assert settings_from_args(cls, args) == tree


def flag_words(value: Any, action: argparse.Action) -> list[str] | None:
    """How a setting's value is typed after its flag (None: one that cannot be, an empty
    list or a tuple of fixed length left at none: the default anyway)."""
    takes_words = isinstance(action.nargs, int) or action.nargs in ("+", "*")
    if value is None and (takes_words or not action.option_strings):
        return None
    if isinstance(value, list) and (not value or takes_words):
        return [str(item) for item in value] or None
    return [value_text(value)]


def value_text(value: Any) -> str:
    """A plain value as typed on the command line: a comma list for a list of numbers or
    words, TOML for tables."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list) and all(isinstance(item, str | int | float) for item in value):
        return ",".join(map(str, value))
    return toml_value(value) if isinstance(value, list | dict) else str(value)


@pytest.mark.parametrize("command", COMMAND_LIST)
def test_every_setting_is_a_set_key(command: str) -> None:
    cls = command_module(command).Options
    tree, values = expected_tree(command)
    items = [f"--set={key}={value_text(value)}" for key, value in values.items()]
    args = command_parser(command).parse_args(items)
    assert set(given_settings(cls, args)) == set(values)
    assert settings_from_args(cls, args) == tree


@pytest.mark.parametrize("command", COMMAND_LIST)
def test_every_setting_is_a_config_file_key(command: str, tmp_path: Path) -> None:
    """A YAML file holding every key (none as null), and the TOML that ``simgrasp settings``
    prints (every setting at its default, required ones given here), both build the default
    tree."""
    cls = command_module(command).Options
    tree, values = expected_tree(command)
    path = tmp_path / "all.yaml"
    path.write_text(yaml.safe_dump(values))
    args = command_parser(command).parse_args(["--config", str(path)])
    assert set(given_settings(cls, args)) == set(values)
    assert settings_from_args(cls, args) == tree
    listing = settings_listing(cls)
    path = tmp_path / "listing.toml"
    path.write_text(listing)
    required = [f"--set={leaf.key}={values[leaf.key]}" for leaf in leaves(cls) if leaf.required]
    args = command_parser(command).parse_args(["--config", str(path), *required])
    assert settings_from_args(cls, args) == tree
    listed = {line.lstrip("# ").split(" = ")[0].strip('"') for line in listing.splitlines()}
    assert set(values) <= listed


@pytest.mark.parametrize("command", COMMAND_LIST)
def test_print_config_reads_back(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """What ``--print-config`` prints, given back with ``--config``, is the same settings (also
    for ``evaluate``, whose ``detector`` list sits beside ``detector.quadric.*``)."""
    cls = command_module(command).Options
    tree, values = expected_tree(command)
    required = [f"--set={leaf.key}={values[leaf.key]}" for leaf in leaves(cls) if leaf.required]
    assert main([command, *required, "--print-config"]) == 0
    path = tmp_path / "printed.toml"
    path.write_text(capsys.readouterr().out)
    args = command_parser(command).parse_args(["--config", str(path), *required])
    assert settings_from_args(cls, args) == tree


@pytest.mark.parametrize("command", COMMAND_LIST)
def test_the_examples_parse(command: str) -> None:
    """Each example of ``--help`` (up to a shell redirection) names only flags the command has
    and values its settings allow."""
    module = command_module(command)
    for example in getattr(module, "EXAMPLES", ()):
        words = shlex.split(example, comments=True)
        words = words[: words.index(">")] if ">" in words else words
        assert words[:2] == ["simgrasp", command], example
        settings_from_args(module.Options, command_parser(command).parse_args(words[2:]))


def test_settings_lists_a_commands_keys(capsys: pytest.CaptureFixture[str]) -> None:
    """``simgrasp settings detect --match quadric.voxel_size`` prints the matching keys with
    their default, type and first sentence, under the comment naming their tree."""
    assert main(["settings", "detect", "--match", "quadric.voxel_size"]) == 0
    assert capsys.readouterr().out.splitlines() == [
        "# --detector.*: The handle detector and the settings of each (only the chosen one's "
        "are used)",
        "detector.quadric.voxel_size = 0.003  # (float: >= 0) Voxel edge for down-sampling the "
        "input cloud (m); 0 disables down-sampling.",
        "",
        "# --single-view-detector.*: The single-view detector's settings",
        "single_view_detector.quadric.voxel_size = 0.003  # (float: >= 0) Voxel edge for "
        "down-sampling the input cloud (m); 0 disables down-sampling.",
    ]
    assert main(["settings", "detect", "--match", "no.such"]) == 1
    assert "no setting of detect" in capsys.readouterr().err


def test_a_key_under_another_setting_is_quoted() -> None:
    """``evaluate`` has a ``detector`` list and ``detector.quadric.*``: the listing quotes the
    latter, or TOML would refuse the file."""
    listing = settings_listing(command_module("evaluate").Options)
    assert 'detector = ["quadric"' in listing
    assert '"detector.quadric.voxel_size" = 0.003' in listing
    assert tomllib.loads(listing)["detector.quadric.voxel_size"] == 0.003


def test_the_short_texts() -> None:
    assert first_sentence("Fits (Birdal et al. 2018). More.") == "Fits (Birdal et al. 2018)."
    assert first_sentence("Uses ``x``, e.g. 3 m. More.") == "Uses x, e.g. 3 m."
    assert (
        headline("Every parameter (SI units: m, s): all. More.")
        == "Every parameter (SI units: m, s)"
    )
    assert fitted("one two three four", 10, 1) == "one two..."
    assert fitted("one two", 20, 1, suffix=" (default: 1)") == "one two (default: 1)"


def test_the_root_help_names_every_command_and_the_two_helps(
    capsys: pytest.CaptureFixture[str],
) -> None:
    text = printed(["--help"], capsys)
    assert all(f"    {command}" in text for command in COMMANDS)
    assert "COMMAND --help-all" in " ".join(text.split())
