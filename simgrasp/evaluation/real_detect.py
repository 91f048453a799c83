"""Handle detection on the real clouds of a manifest (:mod:`simgrasp.evaluation.real_manifest`):
per cloud, detector setting and seed, candidate accuracy (share of candidate centers inside a
labeled handle, the paper's Table I measure) and whether the top handle's center is on one;
summed per data set, per split (tune / holdout) and overall.

The settings compared are the detector presets of :mod:`simgrasp.handles.presets`, by name:
``default`` is what ``simgrasp detect`` runs (on a cloud measured to be one view, every real
capture, the single-view detector with the preset ``learned`` and its fallback), a
single-view preset (``learned``, ``standoff``) runs that detector alone, without the view test
or the fallback, and any other preset its detector on every cloud. Normals face the
manifest's viewpoint; nothing else about the capture is told to the detector.
"""

from __future__ import annotations

import csv
import hashlib
import json
import sys
import time
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.config.values import to_plain
from simgrasp.errors import SimgraspError
from simgrasp.evaluation.real_manifest import RealCloud, load_real_cloud, require_file
from simgrasp.handles import detect
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.detection import Detection
from simgrasp.handles.detector_config import DetectorName
from simgrasp.handles.presets import preset, single_view_preset
from simgrasp.handles.single_view.detector import SingleViewConfig, detect_single_view
from simgrasp.perception.depth_image import DEPTH_IMAGE_FORMATS
from simgrasp.runs.identity import claim_entries, claim_identity, file_digest


@dataclass(frozen=True)
class RealDetectRow:
    """One detection: cloud, setting, seed and its score (``top_on_handle`` False when no
    handle was found; ``detect_s`` wall seconds)."""

    cloud: str
    dataset: str
    split: str
    config: str
    seed: int
    points: int
    candidates: int
    on_handle: int
    handles: int
    top_on_handle: bool
    detect_s: float

    @property
    def accuracy(self) -> float:
        return self.on_handle / self.candidates if self.candidates else float("nan")


def setting_record(name: str, single_view: SingleViewConfig | None = None) -> dict[str, Any]:
    """What the rows of setting ``name`` depend on besides the clouds and the seed: its
    values, for ``default`` also the single-view settings it runs on a single view
    (``single_view``, as :func:`detect_named` takes it; None: the preset ``learned``),
    and the SHA-256 of the classifier file a single-view setting reads (a retrained model
    changes the rows as a changed setting does)."""
    config = preset(name)
    record: dict[str, Any] = {"detector": to_plain(config)}
    single = config
    if name == "default":
        single = single_view if single_view is not None else single_view_preset()
        record["single_view"] = to_plain(single)
    if isinstance(single, SingleViewConfig) and single.classifier:
        record["classifier_sha256"] = _digest(single.classifier_path(), f"setting {name}")
    return record


def detect_named(
    points: np.ndarray,
    name: str,
    seed: int,
    viewpoint: np.ndarray,
    single_view: SingleViewConfig | None = None,
) -> Detection:
    """Detect on a single view seen from ``viewpoint`` with the named setting; for
    ``default``, ``single_view`` replaces the preset ``learned`` (another trained
    classifier, ``scripts/compare_candidate_classifiers.py``)."""
    config = preset(name)
    if isinstance(config, SingleViewConfig):
        return detect_single_view(points, config, seed, viewpoint)
    kind: DetectorName = "tenpas" if isinstance(config, TenPasConfig) else "quadric"
    if name != "default":
        single_view = None
    elif single_view is None:
        single_view = single_view_preset()
    return detect(
        points, None, config, seed, detector=kind, viewpoint=viewpoint, single_view=single_view
    )


def score_cloud(
    cloud: RealCloud,
    points: np.ndarray,
    name: str,
    seed: int,
    single_view: SingleViewConfig | None = None,
) -> RealDetectRow:
    """Detect with setting ``name`` (``single_view`` as :func:`detect_named` takes it) and
    seed ``seed`` on ``points`` (the cloud as loaded)."""
    start = time.perf_counter()
    detection = detect_named(points, name, seed, cloud.viewpoint, single_view)
    elapsed = time.perf_counter() - start
    centers = detection.candidate_centers
    top = detection.handles[0].center[None] if detection.handles else np.zeros((0, 3))
    return RealDetectRow(
        cloud=cloud.name,
        dataset=cloud.dataset,
        split=cloud.split,
        config=name,
        seed=seed,
        points=len(points),
        candidates=len(centers),
        on_handle=int(cloud.label.contains(centers).sum()) if len(centers) else 0,
        handles=len(detection.handles),
        top_on_handle=bool(cloud.label.contains(top).any()),
        detect_s=elapsed,
    )


RUN_FILE = "real_run.json"
"""What a ``--real`` output folder's rows were made from (:func:`run_identity`); not
``run.json``, which a run on object meshes keeps in the same folder (the default ``--out``)."""
SETTINGS_FILE = "real_settings.json"
"""The values each setting's rows in a ``--real`` output folder were made with
(:func:`setting_record`, by setting name): a rerun after a setting changed (its defaults, a
retrained classifier) is refused instead of keeping the old rows under the same name."""
COLUMNS = tuple(f.name for f in fields(RealDetectRow))
"""The columns of ``real_detect.csv``, in order (its header line)."""


def _digest(path: Path, what: str) -> str:
    """The SHA-256 of an input file (:func:`~simgrasp.runs.identity.file_digest`); one line
    naming ``what`` when it cannot be read."""
    try:
        return file_digest(path)
    except OSError as exc:
        raise SimgraspError(f"{what}: cannot read {path}: {exc.strerror or exc}") from exc


def _cloud_inputs(cloud: RealCloud) -> dict[str, str]:
    """SHA-256 of the cloud's file, its handle label (the label file's entry it uses) and,
    for a depth image read through it, the GraspNet ``meta.mat`` beside it."""
    what = f"cloud {cloud.name}"
    require_file(cloud)
    label = json.dumps(cloud.label.to_json(), sort_keys=True).encode()
    inputs = {"file": _digest(cloud.path, what), "label": hashlib.sha256(label).hexdigest()}
    meta = cloud.path.parent / "meta.mat"
    image = cloud.path.suffix.lower() in DEPTH_IMAGE_FORMATS
    if image and cloud.depth.intrinsics is None and meta.is_file():
        inputs["meta"] = _digest(meta, what)
    return inputs


def run_identity(manifest: Path, real_dir: Path, clouds: list[RealCloud]) -> dict[str, Any]:
    """What a run's rows depend on besides their setting and seed: the manifest's SHA-256,
    the real data folder (resolved) and each cloud's inputs (:func:`_cloud_inputs`)."""
    return {
        "manifest": _digest(manifest, "manifest"),
        "real_dir": str(Path(real_dir).expanduser().resolve()),
        "clouds": {cloud.name: _cloud_inputs(cloud) for cloud in clouds},
    }


def _parse_row(line: bytes) -> RealDetectRow:
    """The row on one CSV line; a ValueError saying what is wrong with it."""
    values = next(csv.reader([line.decode().rstrip("\r")]), [])
    if len(values) != len(COLUMNS):
        raise ValueError(f"{len(values)} fields, not {len(COLUMNS)}")
    raw = dict(zip(COLUMNS, values, strict=True))
    if raw["top_on_handle"] not in ("True", "False"):
        raise ValueError(f"top_on_handle is {raw['top_on_handle']!r}, not True or False")
    try:
        return RealDetectRow(
            cloud=raw["cloud"],
            dataset=raw["dataset"],
            split=raw["split"],
            config=raw["config"],
            seed=int(raw["seed"]),
            points=int(raw["points"]),
            candidates=int(raw["candidates"]),
            on_handle=int(raw["on_handle"]),
            handles=int(raw["handles"]),
            top_on_handle=raw["top_on_handle"] == "True",
            detect_s=float(raw["detect_s"]),
        )
    except ValueError as exc:
        raise ValueError(f"bad number ({exc})") from None


def _scan(path: Path) -> tuple[list[RealDetectRow], int, str]:
    """The rows of ``path`` (none when it is absent), where its torn last row starts (the
    file's size when none) and what is wrong with it. The last line is torn when it has no
    newline (a run killed mid-write) or is no row; a wrong header or another bad line is one
    error naming it."""
    if not path.is_file():
        return [], 0, ""
    data = path.read_bytes()
    *lines, rest = data.split(b"\n")  # rest: what follows the last newline
    if lines and lines[0].rstrip(b"\r") != ",".join(COLUMNS).encode():
        raise SimgraspError(f"{path}:1: not the header {','.join(COLUMNS)}")
    rows: list[RealDetectRow] = []
    start = len(lines[0]) + 1 if lines else 0
    for number, line in enumerate(lines[1:], start=2):
        try:
            if line.strip():
                rows.append(_parse_row(line))
        except ValueError as exc:  # UnicodeDecodeError included
            if number < len(lines) or rest:
                raise SimgraspError(
                    f"{path}:{number}: {exc}; the file is corrupt beyond a torn last row"
                ) from None
            return rows, start, str(exc)
        start += len(line) + 1
    return rows, start, "no newline"


def _cut_torn_row(path: Path, start: int, problem: str) -> None:
    """Cut ``path`` (if there) at byte ``start``, where a torn last row begins, with a line on
    stderr saying what was cut (it runs again): the next row starts on a fresh line."""
    if not path.is_file() or start >= path.stat().st_size:
        return
    with path.open("rb+") as handle:
        handle.seek(start)
        cut = handle.read()
        handle.truncate(start)
    sys.stderr.write(
        f"{path}: cut a torn last row ({len(cut)} bytes, {problem}): "
        f"{cut[:60].decode(errors='replace')!r}...; it runs again\n"
    )


def _claim(out_dir: Path, identity: dict[str, Any], has_rows: bool) -> None:
    """Record ``identity`` in ``out_dir``'s :data:`RUN_FILE`, or refuse a folder with rows of
    other inputs; a folder without rows yet (a run stopped by a bad input) takes the new one."""
    if not has_rows:
        (out_dir / RUN_FILE).unlink(missing_ok=True)
    claim_identity(out_dir / RUN_FILE, identity, what="real detections of other inputs")


def run_real_detect(
    clouds: list[RealCloud],
    configs: Iterable[str],
    seeds: range,
    out_csv: Path,
    identity: dict[str, Any],
) -> list[RealDetectRow]:
    """Every cloud x setting x seed, appended to ``out_csv`` as it finishes; rows already
    there are kept and not redone when ``identity`` (:func:`run_identity`) is the one recorded
    beside them, and refused in one line naming what changed otherwise."""
    configs = tuple(configs)
    records = {name: setting_record(name) for name in configs}  # an unknown name: one line
    done, torn, problem = _scan(out_csv)
    _claim(out_csv.parent, identity, bool(done))  # before the file is changed
    claim_entries(
        out_csv.parent / SETTINGS_FILE,
        records,
        {r.config for r in done},
        what="detector setting",
        hint="delete that setting's rows from the CSV to rerun them, or use another --out",
    )
    _cut_torn_row(out_csv, torn, problem)
    have = {(r.cloud, r.config, r.seed) for r in done}
    new_file = not out_csv.is_file() or out_csv.stat().st_size == 0
    with out_csv.open("a", newline="") as handle:
        writer = csv.DictWriter(handle, COLUMNS)
        if new_file:
            writer.writeheader()
        for cloud in clouds:
            todo = [(c, s) for c in configs for s in seeds if (cloud.name, c, s) not in have]
            if not todo:
                continue
            points = load_real_cloud(cloud)
            for name, seed in todo:
                row = score_cloud(cloud, points, name, seed)
                writer.writerow(asdict(row))
                handle.flush()
                done.append(row)
    wanted = {c.name for c in clouds}
    return [r for r in done if r.cloud in wanted and r.config in configs and r.seed in seeds]


def pooled_score(rows: list[RealDetectRow]) -> tuple[float, int, int]:
    """Pooled candidate accuracy, seeds with the top handle on a handle, and runs."""
    candidates = sum(r.candidates for r in rows)
    pooled = sum(r.on_handle for r in rows) / candidates if candidates else 0.0
    return pooled, sum(r.top_on_handle for r in rows), len(rows)


def _cell(rows: list[RealDetectRow]) -> str:
    accuracy, top, runs = pooled_score(rows)
    return f"{accuracy:.2f} ({top}/{runs})"


def tables(rows: list[RealDetectRow]) -> str:
    """Markdown: per cloud, per data set, per split and overall, one column per setting;
    a cell is the pooled candidate accuracy and (runs with the top handle on a handle / runs)."""
    configs = list(dict.fromkeys(r.config for r in rows))
    groups: list[tuple[str, Callable[[RealDetectRow], str]]] = [
        ("cloud", lambda r: f"{r.cloud} ({r.split})"),
        ("data set", lambda r: f"{r.dataset} ({r.split})"),
        ("split", lambda r: r.split),
        ("all", lambda r: "all"),
    ]
    parts = []
    for title, key in groups:
        names = list(dict.fromkeys(key(r) for r in rows))
        lines = [f"| {title} | " + " | ".join(configs) + " |"]
        lines.append("|---" * (len(configs) + 1) + "|")
        for name in names:
            cells = [_cell([r for r in rows if key(r) == name and r.config == c]) for c in configs]
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
        parts.append("\n".join(lines))
    return "\n\n".join(parts)
