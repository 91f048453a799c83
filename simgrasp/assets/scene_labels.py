"""Handle labels of objects in real sensor scenes, in each scene's sensor frame (meters).

The shipped file ``models/handles/osd_learn_handles.json`` labels the side handles of the pot
in the osd-learn scenes: ``{"objects": {"learn33": {"object": 3, "regions": [...]}}}`` with the
regions of :mod:`simgrasp.labels` (boxes, capsules) in the sensor frame and ``object``
the pot's ground-truth object id (part labels ``10 object`` .. ``10 object + 9``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from simgrasp.errors import SimgraspError
from simgrasp.labels import HandleLabel
from simgrasp.resources import model_path

OSD_LABELS_FILE = ("handles", "osd_learn_handles.json")


@dataclass(frozen=True)
class SceneHandleLabel:
    """One labeled object of a real scene: its ground-truth object id and handle regions."""

    scene: str
    object_id: int
    label: HandleLabel
    """Regions in the scene's sensor frame (meters)."""


def load_scene_labels(path: Path | None = None) -> dict[str, SceneHandleLabel]:
    """The scene labels of ``path`` (default: the shipped osd-learn file), by scene name."""
    path = path or model_path(*OSD_LABELS_FILE)
    try:
        objects = json.loads(Path(path).read_text())["objects"]
    except (OSError, json.JSONDecodeError, KeyError, TypeError) as exc:
        raise SimgraspError(f"cannot read scene handle labels {path}: {exc}") from exc
    labels = {}
    for scene, entry in objects.items():
        if not isinstance(entry.get("object"), int):
            raise SimgraspError(f"scene handle labels {path}: {scene} has no integer 'object'")
        labels[scene] = SceneHandleLabel(
            scene, entry["object"], HandleLabel.from_json(scene, entry)
        )
    return labels
