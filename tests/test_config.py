"""Settings trees: config files, --set and flags (precedence), unknown keys, --print-config and
the generated --help."""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest
from cli_parsers import command_parser

from simgrasp.cli import COMMANDS, command_module, main
from simgrasp.config import Checked, setting
from simgrasp.config.arguments import flag_name, script_main
from simgrasp.config.checks import PositiveInt
from simgrasp.config.schema import leaves
from simgrasp.config.tree import build, diff, flatten
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.config import QuadricDetectorConfig


def effective(argv: list[str], capsys: pytest.CaptureFixture[str]) -> dict:
    assert main([*argv, "--print-config"]) == 0
    return tomllib.loads(capsys.readouterr().out)


def test_detect_print_config_lists_every_detector_threshold(capsys) -> None:
    config = effective(["detect", "cloud.npy"], capsys)
    for cls, section in ((QuadricDetectorConfig, "quadric"), (TenPasConfig, "tenpas")):
        names = {leaf.key for leaf in leaves(cls)}
        # None-valued settings are printed as comments (TOML has no null)
        printed = set(config["detector"][section]) | {
            name for name in names if getattr(cls(), name) is None
        }
        assert names == printed, names ^ printed


def test_file_then_set_then_flags(tmp_path: Path, capsys) -> None:
    path = tmp_path / "run.toml"
    path.write_text(
        "seed = 4\nnoise = 0.01\n[detector.quadric]\nshell_test = false\nmax_points = 64\n"
        "[scene]\nplacement = 'upright'\n"
    )
    config = effective(["trial", "gen_mug", "--config", str(path)], capsys)
    assert config["seed"] == 4 and config["noise"] == 0.01
    assert config["detector"]["quadric"]["shell_test"] is False
    assert config["scene"]["placement"] == "upright"
    # --set wins over the file, a flag over both
    argv = ["trial", "gen_mug", "--config", str(path), "--set", "seed=5", "--set", "noise=0.02"]
    config = effective([*argv, "--seed", "6", "--detector.quadric.max-points", "32"], capsys)
    assert config["seed"] == 6 and config["noise"] == 0.02
    assert config["detector"]["quadric"]["max_points"] == 32
    assert config["detector"]["quadric"]["shell_test"] is False


def test_yaml_config(tmp_path: Path, capsys) -> None:
    path = tmp_path / "run.yaml"
    path.write_text(
        "detector:\n  kind: tenpas\n  tenpas:\n    min_shells: 4\nviews: 2\n".replace(
            "views: 2", "scene:\n  num_views: 2"
        )
    )
    config = effective(["trial", "gen_mug", "--config", str(path)], capsys)
    assert config["detector"]["kind"] == "tenpas"
    assert config["detector"]["tenpas"]["min_shells"] == 4
    assert config["scene"]["num_views"] == 2


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["--set", "detector.quadric.shell_tst=false"],
            "unknown setting 'detector.quadric.shell_tst'",
        ),
        (["--set", "seed"], "expected KEY=VALUE"),
        (["--set", "noise=loud"], "noise: expected float"),
        (["--set", "scene.placement=sideways"], "'sideways' is not one of stable, upright"),
        (["--detector.quadric.max-points", "many"], "detector.quadric.max_points: expected"),
        (["--noise", "2"], "noise: 2.0 is not in [0, 1)"),
        (["--json", "out.json"], "json: expected bool, got 'out.json'"),
        (["--set", "seed=1.5"], "seed: expected int, got 1.5"),
        (["--set", "noise=true"], "noise: expected float, got True"),
        (["--noise", "nan"], "noise: nan is not a number"),
        (["--grasp", "0", "0", "nan", "1", "0", "0", "0"], "grasp: value 3: nan is not a number"),
    ],
)
def test_bad_settings_are_one_line_errors(argv, message, capsys) -> None:
    assert main(["trial", "gen_mug", *argv, "--print-config"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err


def test_unknown_key_in_a_file_names_the_key_and_file(tmp_path: Path, capsys) -> None:
    path = tmp_path / "bad.toml"
    path.write_text("[detector.quadric]\nshell_test = false\nshel_gap = 0.01\n")
    assert main(["detect", "cloud.npy", "--config", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"--config {path}: unknown setting 'detector.quadric.shel_gap'" in err
    assert "did you mean detector.quadric.shell_gap" in err


def test_a_flag_of_another_command_is_not_taken_as_an_abbreviation(capsys) -> None:
    """``demo`` has no ``--detector``: argparse's prefix matching would read it as one of
    many ``--detector.*`` flags (a line listing all of them); a typo picks no flag either."""
    assert main(["demo", "--detector", "tenpas", "--print-config"]) == 2
    err = capsys.readouterr().err
    assert "unrecognized arguments: --detector tenpas" in err and err.count("\n") == 1
    assert main(["trial", "gen_mug", "--detector.quadric.shell-t", "false", "--print-config"]) == 2
    assert "unrecognized arguments: --detector.quadric.shell-t" in capsys.readouterr().err


def test_bad_config_files(tmp_path: Path, capsys) -> None:
    broken = tmp_path / "broken.toml"
    broken.write_text("seed = = 3\n")
    for path, message in (
        (tmp_path / "missing.toml", "no such file"),
        (broken, "not valid TOML"),
        (tmp_path / "x.ini", "expected a .toml, .yaml or .yml file"),
    ):
        if path.suffix == ".ini":
            path.write_text("a=1")
        assert main(["trial", "gen_mug", "--config", str(path)]) == 2
        assert message in capsys.readouterr().err


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_every_flag_is_in_help_with_its_default(command: str) -> None:
    """Each generated flag is listed by --help with its default (or 'required'), and every
    setting has a docstring."""
    sub = command_parser(command)
    text = re.sub(r"\s+", " ", sub.format_help())
    for leaf in leaves(command_module(command).Options):
        name = leaf.key.upper() if leaf.spec.positional else flag_name(leaf.key)
        assert name in text, name
        assert leaf.doc, f"{command}: {leaf.key} has no docstring"
        assert ("required" if leaf.required else "default:") in text


def test_a_tree_round_trips_through_its_flat_form() -> None:
    config = ChainConfig.of(detector__kind="tenpas", scene__num_views=2, noise=0.03)
    assert build(ChainConfig, flatten(config)) == config
    assert diff(config, ChainConfig()) == {
        "detector.kind": "tenpas",
        "noise": 0.03,
        "scene.num_views": 2,
    }
    with pytest.raises(SimgraspError, match="unknown setting 'detector.colour'"):
        build(ChainConfig, {"detector.colour": "red"})


def test_the_chain_detector_opening_is_the_grippers() -> None:
    """A chain's detectors take the gripper's opening; the setting is not offered there."""
    keys = {leaf.key for leaf in leaves(ChainConfig)}
    assert "detector.quadric.shell_gap" in keys
    assert "detector.quadric.gripper_max_opening" not in keys


@dataclass(frozen=True, kw_only=True)
class _ScriptOptions:
    count: int = 1
    """How many."""


def test_a_script_prints_its_config_without_running_and_errors_in_one_line(capsys) -> None:
    """``scripts/`` entry points (:func:`script_main`): --print-config does not run the job,
    flags reach it, and its errors are one line with exit status 2."""
    calls: list[int] = []

    def run(options: _ScriptOptions) -> str:
        calls.append(options.count)
        if options.count < 0:
            raise SimgraspError("count must not be negative")
        return f"ran {options.count}"

    assert script_main(_ScriptOptions, run, "test", ["--count", "3", "--print-config"]) == 0
    assert tomllib.loads(capsys.readouterr().out) == {"count": 3} and calls == []
    assert script_main(_ScriptOptions, run, "test", ["--count", "2"]) == 0
    assert capsys.readouterr().out == "ran 2\n" and calls == [2]
    assert script_main(_ScriptOptions, run, "test", ["--count", "-1"]) == 2
    err = capsys.readouterr().err
    assert err == "error: count must not be negative\n"


def test_a_run_returning_an_int_gives_the_exit_status() -> None:
    """A script's check (``check_function_length.py``) prints what it found and fails with 1."""
    assert script_main(_ScriptOptions, lambda options: 1, "test", []) == 1


@dataclass(frozen=True, kw_only=True)
class _ManyOptions(Checked):
    paths: tuple[Path, ...] = setting(positional=True, many=True)
    """Files to read."""
    sizes: tuple[PositiveInt, ...] = setting((1,), many=True)
    """Sizes to try."""


def _many(argv: list[str]) -> tuple[int, _ManyOptions | None]:
    """Exit status of a script on ``_ManyOptions`` and the options its run got (None: not run)."""
    got: list[_ManyOptions] = []
    return script_main(_ManyOptions, got.append, "test", argv), got[0] if got else None


def test_a_many_setting_takes_several_values(tmp_path: Path, capsys) -> None:
    """``setting(many=True)``: a positional takes several values, a flag several and repeated
    (each value also a comma list); ``--set`` and ``--config`` give the list as for any list."""
    status, options = _many(["a.npy", "b.npy", "--sizes", "2", "3", "--sizes", "4,5"])
    assert status == 0 and options is not None
    assert options.paths == (Path("a.npy"), Path("b.npy")) and options.sizes == (2, 3, 4, 5)
    _, options = _many(["--set", "paths=c.npy,d.npy", "--set", "sizes=6,7"])
    assert options is not None and options.paths == (Path("c.npy"), Path("d.npy"))
    assert options.sizes == (6, 7)
    config = tmp_path / "many.toml"
    config.write_text('paths = ["e.npy"]\nsizes = [8, 9]\n')
    _, options = _many(["--config", str(config), "f.npy"])
    assert options is not None and options.paths == (Path("f.npy"),) and options.sizes == (8, 9)
    assert _many([]) == (2, None)  # required and none given: the usual one-line error
    assert capsys.readouterr().err == "error: missing PATHS (Files to read)\n"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["a.npy", "--sizes", "2", "big"], "sizes: expected list of int, got 'big'"),
        (["a.npy", "--sizes", "2", "0"], "sizes: 0 is not >= 1"),
        (["a.npy", "--sizes", ""], "--sizes is empty"),
    ],
)
def test_a_bad_item_of_a_many_setting_is_a_one_line_error(argv, message, capsys) -> None:
    assert _many(argv) == (2, None)
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err


def test_print_config_shows_a_many_setting_as_a_list(capsys) -> None:
    assert _many(["a.npy", "b.npy", "--sizes", "2", "3", "--print-config"]) == (0, None)
    printed = tomllib.loads(capsys.readouterr().out)
    assert printed == {"paths": ["a.npy", "b.npy"], "sizes": [2, 3]}
