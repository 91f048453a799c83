"""Ground-truth objects of an organized real frame drawn by hand (polygons, circles or seed
pixels on the frame's height image; ``models/handles/graspnet_objects.json`` describes the
recipe), turned into per-pixel part labels that :func:`~simgrasp.evaluation.segment_eval.
part_ious` scores a segmentation against: object ``i`` (in file order) gets part label
``10 (i + 2)``, every other pixel 0.

Lengths are meters in the frame's camera frame; pixels are (column x, row y) of its grid.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw
from scipy import ndimage

from simgrasp.errors import SimgraspError

Pixel = tuple[int, int]


@dataclass(frozen=True)
class DrawnObject:
    """One object: exactly one of a ``polygon`` (pixel vertices), a ``circle`` (x, y,
    radius in pixels) or a ``seed`` pixel whose connected above-table pixels it is."""

    name: str
    polygon: tuple[Pixel, ...] = ()
    circle: tuple[int, int, int] | None = None
    seed: Pixel | None = None


@dataclass(frozen=True)
class FrameObjects:
    """A frame's drawn objects (in precedence order) and its table: a least-squares plane
    of the valid points inside ``table_polygon``, refit once on those within
    ``refit_distance`` (m); objects are pixels more than ``min_height`` (m) above it."""

    objects: tuple[DrawnObject, ...]
    table_polygon: tuple[Pixel, ...]
    refit_distance: float
    min_height: float


def read_frame_objects(path: Path) -> FrameObjects:
    """The annotation file at ``path``; one line naming the file and the entry when it is
    malformed."""
    try:
        raw = json.loads(path.read_text())
        table = raw["table"]
        objects = tuple(_drawn(entry) for entry in raw["objects"])
        return FrameObjects(
            objects,
            tuple((int(x), int(y)) for x, y in table["polygon"]),
            float(table["refit_distance"]),
            float(table["min_height"]),
        )
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise SimgraspError(f"{path}: not a frame-objects annotation ({exc!r})") from exc


def _drawn(entry: dict) -> DrawnObject:
    """One ``objects`` entry of the file: a name and exactly one shape."""
    name = str(entry["name"])
    shapes = [key for key in ("polygon", "circle", "seed") if key in entry]
    if len(shapes) != 1:
        raise ValueError(f"object {name!r} needs exactly one of polygon, circle, seed")
    if "circle" in entry:
        x, y, radius = entry["circle"]
        return DrawnObject(name, circle=(int(x), int(y), int(radius)))
    if "seed" in entry:
        x, y = entry["seed"]
        return DrawnObject(name, seed=(int(x), int(y)))
    polygon = tuple((int(x), int(y)) for x, y in entry["polygon"])
    if len(polygon) < 3:
        raise ValueError(f"object {name!r}: a polygon needs at least 3 vertices")
    return DrawnObject(name, polygon=polygon)


def _drawn_mask(
    shape: tuple[int, int], polygon: tuple[Pixel, ...], circle: tuple[int, ...] | None
) -> NDArray[np.bool_]:
    """(H, W) pixels inside a polygon or circle, rasterized by PIL (edges included)."""
    canvas = Image.new("1", (shape[1], shape[0]), 0)
    draw = ImageDraw.Draw(canvas)
    if circle is not None:
        x, y, r = circle
        draw.ellipse([x - r, y - r, x + r, y + r], fill=1)
    else:
        draw.polygon(list(polygon), fill=1)
    return np.asarray(canvas, dtype=bool)


def table_heights(grid: NDArray[np.floating], annotation: FrameObjects) -> NDArray[np.float64]:
    """(H, W) height (m) of each pixel above the annotation's table plane (NaN where the
    frame has no point), the plane's normal turned toward the sensor at the origin."""
    points = grid.reshape(-1, 3).astype(np.float64)
    inside = _drawn_mask(grid.shape[:2], annotation.table_polygon, None).reshape(-1)
    table = points[inside & np.isfinite(points).all(axis=1)]
    if len(table) < 3:
        raise SimgraspError("the table polygon holds fewer than 3 valid points")
    normal, offset = _plane(table)
    table = table[np.abs(table @ normal + offset) <= annotation.refit_distance]
    normal, offset = _plane(table)
    if offset < 0:  # the sensor (origin) on the positive side
        normal, offset = -normal, -offset
    return (points @ normal + offset).reshape(grid.shape[:2])


def _plane(points: NDArray[np.float64]) -> tuple[NDArray[np.float64], float]:
    """Unit normal and offset of the least-squares plane of ``points`` (N, 3)."""
    center = points.mean(axis=0)
    normal = np.linalg.svd(points - center, full_matrices=False)[2][-1]
    return normal, float(-normal @ center)


def truth_labels(grid: NDArray[np.floating], annotation: FrameObjects) -> NDArray[np.int32]:
    """(H W,) part labels of the frame ``grid`` (H, W, 3): ``10 (i + 2)`` for the pixels of
    the i-th object, 0 elsewhere; an object with no pixel, or a seed off the objects, is an
    error naming it."""
    shape = grid.shape[:2]
    with np.errstate(invalid="ignore"):
        free = table_heights(grid, annotation) > annotation.min_height
    labels = np.zeros(shape, dtype=np.int32)
    for index, drawn in enumerate(annotation.objects):
        if drawn.seed is not None:
            components, _ = ndimage.label(free)
            x, y = drawn.seed
            if not (0 <= y < shape[0] and 0 <= x < shape[1] and free[y, x]):
                raise SimgraspError(
                    f"object {drawn.name!r}: its seed {drawn.seed} is not on an object"
                )
            mine = components == components[y, x]
        else:
            mine = free & _drawn_mask(shape, drawn.polygon, drawn.circle)
        if not mine.any():
            raise SimgraspError(f"object {drawn.name!r} holds no pixel above the table")
        labels[mine] = 10 * (index + 2)
        free &= ~mine
    return labels.reshape(-1)
