"""A method's answer for one scene: ``GRASPS/SCENE.json``, read and checked.

The file holds ``{"grasps": [{"world_T_tcp": 4x4 nested list (world frame, meters),
"width": meters or null}, ...]}``, best first (``width`` null: the gripper's widest opening).
An in-process method returns the same table (or its list, or
:class:`~simgrasp.grasping.grasp.Grasp` objects). A missing file, a file that is no such
table, or a grasp that is not a finite rigid transform with a width in (0, max opening] is a
:class:`AnswerProblem`: the scene's record names it as its failure, and the run goes on.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.errors import SimgraspError
from simgrasp.grasping.grasp import Grasp

MAX_GRASPS = 1000
"""Grasps read from one answer at most (the rest are never executed anyway)."""


@dataclass(frozen=True)
class AnswerProblem:
    """Why a scene's answer cannot be executed: ``failure`` (``missing_grasp_file``,
    ``invalid_grasp_file`` or ``method_error``) and a one-line ``detail``."""

    failure: str
    detail: str


def grasp_file(grasps_dir: Path, scene_id: str) -> Path:
    """Where the answer for ``scene_id`` lies: ``GRASPS/SCENE.json``."""
    return Path(grasps_dir) / f"{scene_id}.json"


def read_answer(path: Path, max_opening: float, source: str) -> list[Grasp] | AnswerProblem:
    """The grasps of the answer file ``path`` (best first), or the problem with it."""
    if not path.is_file():
        return AnswerProblem("missing_grasp_file", f"{path} does not exist")
    try:
        payload = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        return AnswerProblem("invalid_grasp_file", f"{path}: not JSON ({error})")
    return answer_grasps(payload, max_opening, source, str(path))


def answer_grasps(
    payload: Any, max_opening: float, source: str, where: str
) -> list[Grasp] | AnswerProblem:
    """The grasps of an answer (the file's table, its list of grasps, or ``Grasp`` objects),
    or the problem with it; ``where`` names it in the detail."""
    if isinstance(payload, dict):
        if "grasps" not in payload:
            return AnswerProblem("invalid_grasp_file", f'{where}: no "grasps" list')
        payload = payload["grasps"]
    if not isinstance(payload, list | tuple):
        return AnswerProblem("invalid_grasp_file", f'{where}: "grasps" is not a list')
    grasps = []
    for index, item in enumerate(payload[:MAX_GRASPS]):
        try:
            grasps.append(_grasp(item, max_opening, source))
        except SimgraspError as error:
            return AnswerProblem("invalid_grasp_file", f"{where}: grasp {index}: {error}")
    return grasps


def _grasp(item: Any, max_opening: float, source: str) -> Grasp:
    """One answer item as a grasp; an error naming what is wrong with it."""
    if isinstance(item, Grasp):
        item = {"world_T_tcp": item.world_T_tcp, "width": item.width}
    if not isinstance(item, dict) or "world_T_tcp" not in item:
        raise SimgraspError('is not a table with "world_T_tcp"')
    try:
        width = float(max_opening if item.get("width") is None else item["width"])
        if not 0 < width <= max_opening:
            raise SimgraspError(f"width {width} m is not in (0, {max_opening}] m")
        return Grasp(_matrix(item["world_T_tcp"]), width, source=source)
    except (TypeError, ValueError) as error:
        raise SimgraspError(str(error)) from None


def _matrix(value: Any) -> Any:
    """``value`` as a float array (an error when it is not numbers)."""
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise SimgraspError("world_T_tcp is not a 4x4 list of numbers") from None
