"""A sweep's trial records: their identity (object, seed, settings), the fields the report
reads, and the chain defaults (``defaults.json``) their settings are relative to.

The log itself is the run engine's :class:`~simgrasp.runs.record_log.RecordLog`
(``trials.jsonl``); a line that is not a trial record (a JSON object with every field of
:data:`RECORD_FIELDS` the report reads, of its type) is an error naming the file and line.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from simgrasp.config.tree import build, diff, flatten
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.runs.identity import claim_identity
from simgrasp.runs.record_log import RecordLog
from simgrasp.scenes.render import select_backend
from simgrasp.scenes.views import VIEWS_BEFORE_RECORDED

TrialKey = tuple[str, int, str]
KEY_FIELDS = ("object", "seed")

_NUMBER = (int, float)
RECORD_FIELDS: dict[str, tuple[type, ...]] = {
    "object": (str,),
    "detector": (str,),
    "gripper": (str,),
    "noise": _NUMBER,
    "seed": (int,),
    "success": (bool, type(None)),
    "failure": (str, type(None)),
    "on_handle": (bool,),
    "detection_accuracy": (*_NUMBER, type(None)),
    "handle_recall": (bool, type(None)),
    "candidates": (int,),
    "handles": (int,),
    "timings_s": (dict,),
}
"""The fields the report reads from every record, with their JSON types (``bool`` is not taken
for a number)."""

NOISE_DIGITS = 9
"""Noise levels are compared after rounding to this many decimals."""

LEGACY_SETTINGS = {
    "detector": "detector.kind",
    "gripper": "gripper",
    "noise": "noise",
    "placement": "scene.placement",
    "views": "scene.num_views",
}
"""Top-level fields of records written before the ``settings`` field, and the settings they
name. Such a record without ``views`` was seen by two cameras, without ``placement`` placed
``"stable"``: then the only values."""


def trial_settings(config: ChainConfig) -> dict[str, Any]:
    """How ``config`` differs from the default chain config (dotted keys, plain values): with
    the object and seed, a sweep trial's identity. A new setting at its default changes no
    identity, so logs written before it existed still resume."""
    settings = diff(config, ChainConfig())
    if "noise" in settings:
        settings["noise"] = round(float(settings["noise"]), NOISE_DIGITS)
    return settings


DEFAULTS_FILE = "defaults.json"
"""The chain defaults (every setting, dotted keys) a sweep directory's ``settings`` fields are
relative to."""


def check_defaults(out_dir: Path) -> None:
    """Write ``out_dir/defaults.json``, or refuse a directory whose trials were recorded under
    other chain defaults: their identities (settings that differ from the defaults) would
    name other settings now, and a resume would mix them with new trials. Settings one of the
    two lacks (added or removed since) are not compared: a new setting starts at its default.
    The depth render backend is recorded with them (``render_backend``): GL and ray-cast depth
    differ slightly, and so do the trials seen through them."""
    claim_identity(
        Path(out_dir) / DEFAULTS_FILE,
        {**flatten(ChainConfig()), "render_backend": select_backend()},
        what="trials recorded under other chain defaults",
        hint=f"use another --out, or delete its trials.jsonl and {DEFAULTS_FILE} to rerun",
        shared_only=True,
        indent=1,
    )


MESHES_FILE = "meshes.json"
"""SHA-256 of each mesh file object's file the sweep's trials were run on (name -> digest),
and of each handle label file given for an object (``handles of NAME`` -> digest)."""


def check_meshes(out_dir: Path, objects: list[str]) -> None:
    """Record the contents of the mesh file objects among ``objects``, and of the handle label
    files given for them, in ``out_dir/meshes.json``, or refuse a directory whose trials of
    such an object were run on other contents (a file edited under its name: a resume would
    mix two meshes, or score ``on_handle`` on two labels). Objects new to the directory are
    added; YCB objects and generated tools have no mesh entry."""
    from simgrasp.runs.identity import object_file_digests

    digests = {}
    for name in objects:
        files = object_file_digests(name)
        if "mesh_sha256" in files:
            digests[name] = files["mesh_sha256"]
        if "handles_sha256" in files:
            digests[f"handles of {name}"] = files["handles_sha256"]
    if not digests:
        return
    path = Path(out_dir) / MESHES_FILE
    claim_identity(
        path,
        digests,
        what="trials of these objects run on other mesh or handle label file contents",
        hint="use another --out, or delete its trials.jsonl to rerun",
        shared_only=True,
    )
    earlier = json.loads(path.read_text(encoding="utf-8"))
    if set(digests) - set(earlier):
        path.write_text(json.dumps({**earlier, **digests}, indent=2) + "\n", encoding="utf-8")


def record_settings(record: dict[str, Any]) -> dict[str, Any]:
    """The settings a trial record was run with (see :func:`trial_settings`); records written
    before the ``settings`` field are read from their top-level fields."""
    if "settings" in record:
        given = record["settings"]
        if not isinstance(given, dict):
            raise SimgraspError(f"trial record with a bad settings field {given!r:.80}")
    else:
        given = {key: record[name] for name, key in LEGACY_SETTINGS.items() if name in record}
        given.setdefault("scene.num_views", VIEWS_BEFORE_RECORDED)
    return trial_settings(build(ChainConfig, given, source="trial record settings"))


def trial_key(record: Any) -> TrialKey:
    """The identity of a trial: (object, seed, its settings as canonical JSON)."""
    if not isinstance(record, dict):
        raise SimgraspError(f"a trial record is a JSON object, not {type(record).__name__}")
    missing = [name for name in KEY_FIELDS if name not in record]
    if missing:
        raise SimgraspError(f"trial record without {', '.join(missing)}: {record!r:.200}")
    seed = record["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise SimgraspError(f"trial record with a bad seed {seed!r}")
    settings = json.dumps(record_settings(record), sort_keys=True)
    return str(record["object"]), seed, settings


def check_record(record: Any) -> TrialKey:
    """The key of a whole trial record; a ValueError naming the missing fields of
    :data:`RECORD_FIELDS`, or the first mistyped one (or timing), otherwise."""
    key = trial_key(record)
    missing = [name for name in RECORD_FIELDS if name not in record]
    if missing:
        raise SimgraspError(f"trial record without {', '.join(missing)}, which the report needs")
    for name, types in RECORD_FIELDS.items():
        value = record[name]
        if not isinstance(value, types) or (isinstance(value, bool) and bool not in types):
            expected = " or ".join("null" if t is type(None) else t.__name__ for t in types)
            raise SimgraspError(f"trial record field {name!r} is {value!r:.60}, not {expected}")
    for stage, seconds in record["timings_s"].items():
        if isinstance(seconds, bool) or not isinstance(seconds, _NUMBER):
            raise SimgraspError(f"trial record timing {stage!r} is {seconds!r:.60}, not a number")
    return key


def trial_log(path: Path) -> RecordLog:
    """The record log of a sweep (``trials.jsonl``), its lines checked by :func:`check_record`."""
    return RecordLog(path, key=check_record)
