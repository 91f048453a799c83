"""What kind of PATH ``simgrasp view`` was given, and the page builder of each kind.

One :class:`Kind` per page: a cheap test of the path (no plotly, no MuJoCo) and the function
that builds the page's HTML. Adding a kind of page is one row of :data:`KINDS`.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from simgrasp.errors import SimgraspError


@dataclass(frozen=True)
class Kind:
    """One kind of PATH: ``what`` it is (for the error listing the kinds), ``matches`` the
    test of a path, ``page`` the builder (``page(path, ycb_dir) -> HTML``)."""

    what: str
    matches: Callable[[Path], bool]
    page: Callable[[Path, str | None], str]


def is_label_dir(path: Path) -> bool:
    return path.is_dir() and (path / "run.json").is_file() and (path / "labels.jsonl").is_file()


def is_trial_record(path: Path) -> bool:
    """A ``trial --json`` output: one JSON object naming its object, gripper and failure."""
    if not (path.is_file() and path.suffix.lower() == ".json"):
        return False
    try:
        record = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError):
        return False
    return isinstance(record, dict) and {"object", "gripper", "failure"} <= record.keys()


def _grasp_page(path: Path, ycb_dir: str | None) -> str:
    from simgrasp.viewer.grasp_page import grasp_page

    return grasp_page(path, ycb_dir)


def _trial_page(path: Path, ycb_dir: str | None) -> str:
    from simgrasp.viewer.trial_page import trial_page

    return trial_page(path, ycb_dir)


def is_detection_json(path: Path) -> bool:
    """A ``detect --json`` output (``--segment`` too): its detector, handles and candidates."""
    if not (path.is_file() and path.suffix.lower() == ".json"):
        return False
    try:
        report = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError):
        return False
    return isinstance(report, dict) and {"detector", "handles", "candidates"} <= report.keys()


def is_eval_dir(path: Path) -> bool:
    return path.is_dir() and (path / "trials.jsonl").is_file() and (path / "report.md").is_file()


def _detect_page(path: Path, ycb_dir: str | None) -> str:
    from simgrasp.viewer.detect_page import detect_page

    return detect_page(path)


def _report_page(path: Path, ycb_dir: str | None) -> str:
    from simgrasp.viewer.report_page import report_page

    return report_page(path, ycb_dir)


KINDS = (
    Kind("a label-grasps output folder (run.json, labels.jsonl)", is_label_dir, _grasp_page),
    Kind("a trial record (trial --record --json > t.json)", is_trial_record, _trial_page),
    Kind("a detection (detect --json > d.json)", is_detection_json, _detect_page),
    Kind("an evaluate or demo output folder (trials.jsonl, report.md)", is_eval_dir, _report_page),
)
"""Every kind of PATH, tried in order."""


def kind_of(path: Path) -> Kind:
    """The kind of ``path``; a one-line error listing the kinds accepted when none matches."""
    if not path.exists():
        raise SimgraspError(f"{path}: no such file or folder")
    for kind in KINDS:
        if kind.matches(path):
            return kind
    folders = data_set_folders(path)
    if folders:
        raise SimgraspError(
            f"{path} is a label-grasps data set of {len(folders)} grasp files: view one file's "
            f"folder, e.g. simgrasp view {path / folders[0]}"
        )
    accepted = "; ".join(kind.what for kind in KINDS)
    raise SimgraspError(f"{path}: not a path simgrasp view shows; it shows {accepted}")


def data_set_folders(path: Path) -> list[str]:
    """The per-file label folders of a ``label-grasps --grasps GLOB|DIR`` output (its
    ``summary.json`` lists them); empty for any other path."""
    try:
        files = json.loads((path / "summary.json").read_text())["files"]
        return [str(f["dir"]) for f in files if is_label_dir(path / str(f["dir"]))]
    except (OSError, ValueError, KeyError, TypeError):
        return []
