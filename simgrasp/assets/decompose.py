"""Convex decomposition of object meshes with CoACD, cached on disk (see ``cache.py``).

Hulls are in the same frame and units as the input mesh (object frame, meters). CoACD runs in
a child process (:mod:`simgrasp.assets.coacd_child`): its triangulation loops forever on a few
meshes of overlapping closed parts (some generated kettles), and such a run is stopped after
``DecompositionConfig.time_limit`` and redone on CoACD's remeshed manifold (:func:`remeshed`).
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import threading
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Literal

import numpy as np
import trimesh
from tqdm import tqdm

from simgrasp.assets import cache, coacd_child
from simgrasp.errors import SimgraspError

MIN_HULL_VOLUME = 1e-10  # m^3 (0.1 mm^3): flatter hulls are dropped, MuJoCo rejects them


@dataclass(frozen=True)
class DecompositionConfig:
    """CoACD parameters (names as in ``coacd.run_coacd``).

    The defaults decompose each of the 20 YCB test meshes in at most ~10 s on one core here
    (most in under 2 s) while hulls still follow handles and cavities (the mug decomposes
    into about a dozen hulls). ``threshold`` is CoACD's concavity tolerance (lower: more,
    tighter hulls); ``max_convex_hull`` caps the hull count (-1: no cap); ``max_ch_vertex``
    caps vertices per hull.
    """

    threshold: float = 0.1
    max_convex_hull: int = 12
    preprocess_mode: Literal["auto", "on", "off"] = "auto"
    preprocess_resolution: int = 25
    resolution: int = 500
    mcts_nodes: int = 10
    mcts_iterations: int = 40
    mcts_max_depth: int = 2
    pca: bool = False
    merge: bool = True
    max_ch_vertex: int = 64
    seed: int = 0
    time_limit: float = 180.0
    """Seconds one CoACD run may take before it is stopped and redone on the remeshed manifold
    (:func:`remeshed`); runs here take 1-30 s. It decides only when a run is given up, so it
    is neither a CoACD parameter nor part of the cache key (:meth:`coacd_params`)."""

    def __post_init__(self) -> None:
        if not 0.01 <= self.threshold <= 1.0:
            raise SimgraspError(
                f"DecompositionConfig.threshold must be in [0.01, 1], got {self.threshold}"
            )
        if self.max_convex_hull == 0 or self.max_convex_hull < -1:
            raise SimgraspError(
                "DecompositionConfig.max_convex_hull must be -1 or positive, "
                f"got {self.max_convex_hull}"
            )
        if self.preprocess_mode not in ("auto", "on", "off"):
            raise SimgraspError(
                "DecompositionConfig.preprocess_mode must be 'auto', 'on' or 'off', "
                f"got {self.preprocess_mode!r}"
            )
        for name in ("preprocess_resolution", "resolution", "mcts_nodes", "mcts_iterations"):
            if getattr(self, name) < 1:
                raise SimgraspError(f"DecompositionConfig.{name} must be positive")
        if self.max_ch_vertex < 4:
            raise SimgraspError("DecompositionConfig.max_ch_vertex must be at least 4")
        if not self.time_limit > 0:
            raise SimgraspError(
                f"DecompositionConfig.time_limit must be positive (s), got {self.time_limit}"
            )

    def coacd_params(self) -> dict[str, object]:
        """``coacd.run_coacd``'s keywords, also the cache key's settings: every field but
        ``time_limit``."""
        params = asdict(self)
        del params["time_limit"]
        return params


REMESH_RESOLUTION = 50
"""CoACD's voxel resolution (per bounding-box side) for :func:`remeshed`: fine enough that a
remeshed thin part thickens by about 2 % of the object's size."""


def remeshed(config: DecompositionConfig) -> DecompositionConfig:
    """``config`` with CoACD's voxel remeshing on, at :data:`REMESH_RESOLUTION` or finer: the
    settings a run that did not finish is redone with (a manifold surface, no overlapping
    parts for the triangulation to loop on)."""
    resolution = max(REMESH_RESOLUTION, config.preprocess_resolution)
    return replace(config, preprocess_mode="on", preprocess_resolution=resolution)


_coacd_calls = 0


def coacd_calls() -> int:
    """How many times this process has run CoACD (a cache hit runs it zero times)."""
    return _coacd_calls


def _check_mesh(mesh: trimesh.Trimesh, object_name: str) -> None:
    if len(mesh.faces) == 0 or len(mesh.vertices) < 4:
        raise SimgraspError(f"object {object_name!r}: mesh is empty, cannot decompose it")
    if not np.all(np.isfinite(mesh.vertices)):
        raise SimgraspError(f"object {object_name!r}: mesh has non-finite vertices")
    if np.any(mesh.faces >= len(mesh.vertices)) or np.any(mesh.faces < 0):
        raise SimgraspError(f"object {object_name!r}: mesh faces index missing vertices")


def _spin(bar: tqdm, done: threading.Event) -> None:
    while not done.wait(0.25):
        bar.refresh()


def _coacd_parts(
    mesh: trimesh.Trimesh, config: DecompositionConfig, object_name: str
) -> list[tuple[np.ndarray, np.ndarray]] | None:
    """CoACD's parts of ``mesh`` as (vertices, faces), from one run in a child process; None
    when it did not finish within ``config.time_limit``."""
    global _coacd_calls
    with tempfile.TemporaryDirectory(prefix="simgrasp-coacd-") as folder:
        job = Path(folder) / "job.npz"
        params = json.dumps(config.coacd_params())
        np.savez(job, vertices=mesh.vertices, faces=mesh.faces, params=np.array(params))
        _coacd_calls += 1
        child = subprocess.Popen(
            [sys.executable, coacd_child.__file__, str(job)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
        )
        try:
            _, errors = child.communicate(timeout=config.time_limit)
        except BaseException as stopped:  # past the limit, or interrupted: leave no CoACD behind
            child.kill()
            child.communicate()
            if isinstance(stopped, subprocess.TimeoutExpired):
                return None
            raise
        if child.returncode != 0:
            last = (errors.strip().splitlines() or [f"exit status {child.returncode}"])[-1]
            raise SimgraspError(f"object {object_name!r}: CoACD failed: {last}")
        with np.load(coacd_child.parts_path(job)) as found:
            vertices, faces, counts = found["vertices"], found["faces"], found["counts"]
    ends = np.cumsum(counts, axis=0)
    starts = ends - counts
    return [
        (vertices[v0:v1], faces[f0:f1])
        for (v0, f0), (v1, f1) in zip(starts.tolist(), ends.tolist(), strict=True)
    ]


def _spun(
    mesh: trimesh.Trimesh, config: DecompositionConfig, object_name: str
) -> list[tuple[np.ndarray, np.ndarray]] | None:
    """:func:`_coacd_parts` with a spinner on stderr when it is a terminal."""
    done = threading.Event()
    bar = tqdm(
        desc=f"decomposing {object_name} (CoACD)",
        bar_format="{desc}: {elapsed}",
        file=sys.stderr,
        disable=None,
        leave=False,
    )
    spinner = threading.Thread(target=_spin, args=(bar, done), daemon=True)
    spinner.start()
    try:
        return _coacd_parts(mesh, config, object_name)
    finally:
        done.set()
        spinner.join()
        bar.close()


def run_coacd(
    mesh: trimesh.Trimesh, config: DecompositionConfig, object_name: str
) -> tuple[trimesh.Trimesh, ...]:
    """Run CoACD (no cache); a run that does not finish within ``config.time_limit`` is
    redone once with :func:`remeshed` settings, and said so on stderr."""
    _check_mesh(mesh, object_name)
    parts = _spun(mesh, config, object_name)
    if parts is None:
        print(
            f"decomposing {object_name}: CoACD did not finish in {config.time_limit:g} s; "
            "redoing it on its remeshed manifold",
            file=sys.stderr,
        )
        parts = _spun(mesh, remeshed(config), object_name)
    if parts is None:
        raise SimgraspError(
            f"object {object_name!r}: CoACD did not finish in {config.time_limit:g} s, nor on "
            "its remeshed manifold; set other DecompositionConfig settings"
        )
    hulls = tuple(
        hull
        for hull in (trimesh.Trimesh(v, f).convex_hull for v, f in parts)
        if hull.volume > MIN_HULL_VOLUME
    )
    if not hulls:
        hulls = (mesh.convex_hull,)
    if hulls[0].volume <= MIN_HULL_VOLUME:
        raise SimgraspError(
            f"object {object_name!r}: mesh has no volume, cannot build collision hulls"
        )
    return hulls


def decompose(
    mesh: trimesh.Trimesh,
    config: DecompositionConfig,
    object_name: str,
    *,
    use_cache: bool = True,
) -> tuple[trimesh.Trimesh, ...]:
    """Convex hulls covering ``mesh`` (its frame and units), from the cache when possible."""
    if not use_cache:
        return run_coacd(mesh, config, object_name)
    path = cache.entry_path(cache.cache_key(mesh, config.coacd_params()))
    hulls = cache.load_hulls(path)
    if hulls is None:
        hulls = run_coacd(mesh, config, object_name)
        cache.save_hulls(path, hulls)
    return hulls
