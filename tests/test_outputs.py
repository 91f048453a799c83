"""Every path a command writes is proved writable before its work starts: one clear line
naming the flag and the path, no traceback, and no minutes of work lost at the end."""

from __future__ import annotations

import typing
from pathlib import Path

import pytest

from simgrasp.cli import COMMANDS, command_module, main
from simgrasp.config.schema import leaves

READ_OR_CLAIMED = {
    ("detect", "cloud"),
    ("segment", "scene"),
    ("detect-eval", "real"),
    ("detect-eval", "real_dir"),
    ("labels", "manifest"),
    ("trial", "handles"),
    ("evaluate", "handles"),
    ("label-grasps", "handles"),
    ("object", "handles"),
    ("sample-grasps", "handles"),
    ("scenes", "handles"),
    ("label-grasps", "grasps"),
    ("label-grasps", "mesh_root"),
    ("compare-labels", "reference"),
    ("compare-labels", "other"),
    ("compare-labels", "reference_file"),
    ("view", "path"),
    # run folders, each checked and locked by runs.out_dir.claim_out_dir
    ("demo", "out"),
    ("detect-eval", "out"),
    ("evaluate", "out"),
    ("label-grasps", "out"),
    # a file (show) or a folder (export) by the action: checked in its run
    ("object", "out"),
    # read (score's grasp files) or a run folder (export's, claimed by claim_out_dir)
    ("bench", "path"),
}
"""Path settings that are read, or written under a run's own check."""


def test_every_path_setting_is_read_or_marked_as_an_output() -> None:
    """A new path setting must say which it is: read, or ``setting(output=...)``."""
    for command in COMMANDS:
        for leaf in leaves(command_module(command).Options):
            if leaf.annotation is Path or Path in typing.get_args(leaf.annotation):
                known = (command, leaf.key) in READ_OR_CLAIMED
                assert known != (leaf.spec.output is not None), (command, leaf.key)


@pytest.mark.parametrize(
    ("args", "flag"),
    [
        (["label-handles", "gen_mug", "--out", "{blocked}/h.json"], "--out"),
        (["label-handles", "gen_mug", "--plot", "{blocked}/h.png"], "--plot"),
        (["sample-grasps", "gen_mug", "--n", "5", "--out", "{blocked}/g.npz"], "--out"),
        (["detect", "{cloud}", "--plot", "{blocked}/d.png"], "--plot"),
        (["segment", "{cloud}", "--labels", "{blocked}/l.npy"], "--labels"),
        (["trial", "gen_mug", "--render", "{blocked}/t.png"], "--render"),
        (["scenes", "export", "--out", "{blocked}/scenes"], "--out"),
        (["labels", "--out", "{blocked}/labels"], "--out"),
        (["object", "show", "gen_mug", "--out", "{blocked}/m.png"], "--out"),
        (["object", "export", "gen_mug", "--out", "{blocked}/m"], "--out"),
        (["view", "{cloud}", "--export", "{blocked}/v.html"], "--export"),
    ],
)
def test_an_output_under_a_file_is_one_line_before_any_work(
    args: list[str], flag: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    blocked = tmp_path / "a_file"
    blocked.write_text("not a folder")
    cloud = tmp_path / "cloud.npy"
    cloud.write_bytes(b"")
    filled = [a.format(blocked=blocked, cloud=cloud) for a in args]
    assert main(filled) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and flag in err and "a_file is a file" in err, err


@pytest.mark.parametrize(
    "args",
    [
        ["detect", "{cloud}", "--plot", "{folder}/d.txt"],
        ["segment", "{cloud}", "--plot", "{folder}/s"],
        ["label-handles", "gen_mug", "--plot", "{folder}/h.json"],
        ["compare-labels", "{folder}", "--reference", "{cloud}", "--plot", "{folder}/c.csv"],
    ],
)
def test_a_picture_matplotlib_cannot_write_is_refused_before_any_work(
    args: list[str], tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    cloud = tmp_path / "cloud.npy"
    cloud.write_bytes(b"")
    assert main([a.format(folder=tmp_path, cloud=cloud) for a in args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--plot" in err and "a picture needs" in err, err


@pytest.mark.parametrize(
    ("args", "flag", "wanted"),
    [
        (["label-handles", "gen_mug", "--out", "{folder}/h.txt"], "--out", ".json"),
        (["view", "{folder}", "--export", "{folder}/v.txt"], "--export", ".html or .htm"),
        (["sample-grasps", "gen_mug", "--n", "2", "--out", "{folder}/g.json"], "--out", ".npz"),
        (["segment", "{cloud}", "--labels", "{folder}/l.csv"], "--labels", ".npy"),
    ],
)
def test_an_output_file_of_another_kind_is_refused_before_any_work(
    args: list[str], flag: str, wanted: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    """An output named with a suffix its format never has (a label written to ``h.txt``, a
    page to ``v.txt``) is one line before the run, and nothing is written."""
    cloud = tmp_path / "cloud.npy"
    cloud.write_bytes(b"")
    filled = [a.format(folder=tmp_path, cloud=cloud) for a in args]
    assert main(filled) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"{flag} {filled[-1]}: expected a {wanted} file" in err
    assert not Path(filled[-1]).exists()


def test_a_run_refused_after_the_check_leaves_no_empty_folders(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    """The check makes an output's folders; a run that then fails (an unknown object) takes
    back those it made and left empty, and leaves the folders that were there."""
    out = tmp_path / "new" / "deeper" / "h.json"
    assert main(["label-handles", "no_such_object", "--out", str(out)]) == 2
    assert "no_such_object" in capsys.readouterr().err
    assert not (tmp_path / "new").exists() and tmp_path.is_dir()
