"""Handle labels: regions of an object, in the object's own mesh frame, that count as its handle.

A label is a union of primitive regions (capsules and oriented boxes), or the whole object
(chips can, lemon: the entire object is graspable as a handle), or empty (no handle).
Units are meters; frames are the object's mesh frame (``points_object``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.resources import model_path


def _vec3(value: ArrayLike, what: str) -> NDArray[np.float64]:
    arr = np.asarray(value, dtype=float)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise SimgraspError(f"{what} must be 3 finite numbers, got {value!r}")
    return arr


@dataclass(frozen=True)
class Capsule:
    """All points within ``radius`` of the segment ``p0``-``p1`` (object frame, meters)."""

    p0: NDArray[np.float64]
    p1: NDArray[np.float64]
    radius: float

    def contains(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        seg = self.p1 - self.p0
        length2 = float(seg @ seg)
        t = np.zeros(len(points)) if length2 == 0 else (points - self.p0) @ seg / length2
        closest = self.p0 + np.clip(t, 0.0, 1.0)[:, None] * seg
        return np.linalg.norm(points - closest, axis=1) <= self.radius

    @property
    def axis(self) -> NDArray[np.float64]:
        """Unit direction from ``p0`` to ``p1`` (object frame)."""
        seg = self.p1 - self.p0
        return seg / np.linalg.norm(seg)

    def to_json(self) -> dict[str, Any]:
        return {
            "type": "capsule",
            "p0": self.p0.tolist(),
            "p1": self.p1.tolist(),
            "radius": self.radius,
        }


@dataclass(frozen=True)
class Box:
    """An oriented box: ``center``, rotation ``object_R_box`` (columns = box axes), half extents."""

    center: NDArray[np.float64]
    object_R_box: NDArray[np.float64]
    half_extents: NDArray[np.float64]

    def contains(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        points_box = (points - self.center) @ self.object_R_box
        return np.all(np.abs(points_box) <= self.half_extents, axis=1)

    @property
    def axis(self) -> NDArray[np.float64]:
        """The box's longest axis (object frame)."""
        return self.object_R_box[:, int(np.argmax(self.half_extents))]

    def to_json(self) -> dict[str, Any]:
        return {
            "type": "box",
            "center": self.center.tolist(),
            "rotation": self.object_R_box.tolist(),
            "half_extents": self.half_extents.tolist(),
        }


Region = Capsule | Box


@dataclass(frozen=True)
class HandleLabel:
    """The labeled handle of one object, in its mesh frame.

    ``whole_object`` marks objects that are graspable as a handle everywhere (every point of
    the object counts); an empty ``regions`` tuple with ``whole_object`` False means no handle.
    """

    object_name: str
    regions: tuple[Region, ...] = field(default_factory=tuple)
    whole_object: bool = False

    @property
    def has_handle(self) -> bool:
        return self.whole_object or bool(self.regions)

    def contains(self, points_object: ArrayLike) -> NDArray[np.bool_]:
        """Which points (N x 3, object frame, meters) lie in the handle region."""
        pts = np.asarray(points_object, dtype=float).reshape(-1, 3)
        if self.whole_object:
            return np.ones(len(pts), dtype=bool)
        inside = np.zeros(len(pts), dtype=bool)
        for region in self.regions:
            inside |= region.contains(pts)
        return inside

    def to_json(self) -> dict[str, Any]:
        return {
            "whole_object": self.whole_object,
            "regions": [r.to_json() for r in self.regions],
        }

    @staticmethod
    def from_json(object_name: str, data: dict[str, Any]) -> HandleLabel:
        """Parse one object's label; errors name the object and the offending field."""
        try:
            regions = tuple(_region_from_json(r) for r in data.get("regions", []))
        except (KeyError, ValueError, TypeError) as exc:
            raise SimgraspError(f"bad handle label for object {object_name!r}: {exc}") from exc
        return HandleLabel(object_name, regions, bool(data.get("whole_object", False)))


def _region_from_json(data: dict[str, Any]) -> Region:
    kind = data.get("type")
    if kind == "capsule":
        radius = float(data["radius"])
        if not radius > 0:
            raise SimgraspError(f"capsule radius must be positive, got {radius}")
        return Capsule(_vec3(data["p0"], "capsule p0"), _vec3(data["p1"], "capsule p1"), radius)
    if kind == "box":
        rotation = np.asarray(data.get("rotation", np.eye(3)), dtype=float)
        if rotation.shape != (3, 3) or not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-6):
            raise SimgraspError("box rotation must be a 3x3 rotation matrix")
        half = _vec3(data["half_extents"], "box half_extents")
        if np.any(half <= 0):
            raise SimgraspError(f"box half_extents must be positive, got {half.tolist()}")
        return Box(_vec3(data["center"], "box center"), rotation, half)
    raise SimgraspError(f"unknown region type {kind!r} (expected 'capsule' or 'box')")


YCB_LABELS_FILE = ("handles", "ycb_handles.json")


def load_label_file(path: Path) -> dict[str, HandleLabel]:
    """Read a label file: ``{"objects": {name: {"whole_object": bool, "regions": [...]}}}``."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise SimgraspError(f"cannot read handle label file {path}: {exc}") from exc
    objects = data.get("objects")
    if not isinstance(objects, dict):
        raise SimgraspError(f"handle label file {path} has no 'objects' mapping")
    return {name: HandleLabel.from_json(name, entry) for name, entry in objects.items()}


def ycb_handle_label(object_id: str) -> HandleLabel:
    """The shipped handle label of a YCB object (e.g. ``"033_spatula"``); empty if unlabeled."""
    labels = load_label_file(model_path(*YCB_LABELS_FILE))
    return labels.get(object_id, HandleLabel(object_id))


def load_handle_label(path: Path, object_name: str | None = None) -> HandleLabel:
    """One object's label from a label file (``simgrasp label-handles --out``): the object
    named ``object_name``, or the file's only object when no name is given."""
    labels = load_label_file(path)
    if object_name is not None:
        if object_name not in labels:
            raise SimgraspError(f"handle label file {path} has no object {object_name!r}")
        return labels[object_name]
    if len(labels) != 1:
        names = ", ".join(sorted(labels)) or "none"
        raise SimgraspError(
            f"handle label file {path} holds {len(labels)} objects ({names}); name one"
        )
    return next(iter(labels.values()))


def write_label_file(path: Path, labels: dict[str, HandleLabel], description: str) -> Path:
    """Write ``labels`` in the format :func:`load_label_file` reads."""
    data = {"description": description, "objects": {n: h.to_json() for n, h in labels.items()}}
    Path(path).write_text(json.dumps(data, indent=1) + "\n")
    return Path(path)
