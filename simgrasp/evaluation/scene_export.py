"""What a ``simgrasp scenes export`` folder holds, so a killed or repeated export resumes
without mixing settings.

The folder's ``run.json`` records what its views were made with (:func:`export_identity`): the
object (a mesh file's SHA-256 too), the scene and the sensor model. A later export into it with
other settings is refused (:func:`claim_export_dir`); one with the same settings skips the
seeds whose every camera file is there (:func:`finished_seeds`). Each view is written under a
temporary name and renamed into place (:func:`write_whole`), so a file under its final name is
always complete.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from dataclasses import asdict
from pathlib import Path
from typing import Any

from simgrasp.errors import SimgraspError
from simgrasp.perception.sensors.settings import SensorSettings
from simgrasp.scenes.config import SceneConfig

RUN_FILE = "run.json"
COMMAND = "scenes"
PARTIAL_GLOB = ".*.pcd.*.part"
"""Temporary names of views being written (:func:`write_whole`)."""


def export_identity(
    name: str, asset_name: str, scene: SceneConfig, sensor: SensorSettings
) -> dict[str, Any]:
    """What ``run.json`` holds: the object ``name`` (with its mesh file's SHA-256), the scene
    settings, the distractor pool they resolve to (with clutter: ``all`` depends on
    ``$SIMGRASP_YCB_DIR``), and the sensor kind with its model's parameters."""
    from simgrasp.runs.identity import object_file_digests
    from simgrasp.scenes.clutter_sets import distractor_pool

    identity: dict[str, Any] = {"object": name}
    if (mesh := object_file_digests(name).get("mesh_sha256")) is not None:
        identity["mesh_sha256"] = mesh
    identity["scene"] = asdict(scene)
    if scene.clutter:
        identity["clutter_pool"] = distractor_pool(scene.clutter_objects, asset_name)
    identity["sensor"] = {"kind": sensor.kind, "model": asdict(sensor.model())}
    return identity


def refuse_other_command(out: Path, last_command: str | None) -> None:
    """Refuse ``out`` when another command (its lock file names it) wrote it last."""
    if last_command not in (None, COMMAND):
        raise SimgraspError(
            f"--out {out} holds the output of `simgrasp {last_command}`; use another --out"
        )


def claim_export_dir(out: Path, identity: dict[str, Any]) -> None:
    """Record ``identity`` in ``out``'s ``run.json``, or refuse a folder that holds views of
    other settings (named) or views with no record, and remove the temporary files of a
    killed export. Call it while holding ``out`` (:func:`~simgrasp.runs.out_dir.claim_out_dir`)."""
    from simgrasp.runs.identity import claim_identity

    if not (out / RUN_FILE).exists() and any(out.glob("*.pcd")):
        raise SimgraspError(
            f"--out {out} holds PCD files with no {RUN_FILE} saying what made them; "
            "use another --out"
        )
    claim_identity(out / RUN_FILE, identity, what="views of other settings")
    for partial in out.glob(PARTIAL_GLOB):
        partial.unlink(missing_ok=True)


def camera_names(scene: SceneConfig) -> tuple[str, ...]:
    """The cameras a scene of ``scene``'s settings has: its explicit ones, else the default
    viewpoints' names."""
    import numpy as np

    from simgrasp.scenes.camera import default_viewpoints

    cameras = scene.cameras or default_viewpoints(np.zeros(3), n=scene.num_views)
    return tuple(camera.name for camera in cameras)


def view_path(out: Path, stem: str, seed: int, camera: str) -> Path:
    """Where the view of ``camera`` of seed ``seed``'s scene is written."""
    return out / f"{stem}_s{seed}_{camera}.pcd"


def finished_seeds(out: Path, stem: str, seeds: int, cameras: tuple[str, ...]) -> list[int]:
    """The seeds of ``0..seeds-1`` whose every camera's view is already in ``out``."""
    return [
        seed
        for seed in range(seeds)
        if all(view_path(out, stem, seed, camera).is_file() for camera in cameras)
    ]


def write_whole(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file renamed into place: a killed write
    leaves no partial file under ``path``'s name."""
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
    try:
        with os.fdopen(handle, "wb") as file:
            file.write(data)
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise


def spans(seeds: list[int]) -> str:
    """``seeds`` (ascending) as runs: ``0-13, 15``."""
    runs: list[list[int]] = []
    for seed in seeds:
        if runs and seed == runs[-1][-1] + 1:
            runs[-1].append(seed)
        else:
            runs.append([seed])
    return ", ".join(str(run[0]) if len(run) == 1 else f"{run[0]}-{run[-1]}" for run in runs)
