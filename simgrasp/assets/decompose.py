"""Convex decomposition of object meshes with CoACD, cached on disk (see ``cache.py``).

Hulls are in the same frame and units as the input mesh (object frame, meters).
"""

from __future__ import annotations

import sys
import threading
from dataclasses import asdict, dataclass
from typing import Literal

import numpy as np
import trimesh
from tqdm import tqdm

from simgrasp.assets import cache
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


def run_coacd(
    mesh: trimesh.Trimesh, config: DecompositionConfig, object_name: str
) -> tuple[trimesh.Trimesh, ...]:
    """Run CoACD once (no cache), with a spinner on stderr when it is a terminal."""
    global _coacd_calls
    _check_mesh(mesh, object_name)
    # Imported here, after trimesh has loaded scipy.spatial: a process that loads coacd's
    # library first cannot import open3d afterwards (ImportError: std::bad_cast).
    import coacd

    coacd.set_log_level("error")
    params = asdict(config)
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
        _coacd_calls += 1
        parts = coacd.run_coacd(coacd.Mesh(mesh.vertices, mesh.faces), **params)
    finally:
        done.set()
        spinner.join()
        bar.close()
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
    path = cache.entry_path(cache.cache_key(mesh, asdict(config)))
    hulls = cache.load_hulls(path)
    if hulls is None:
        hulls = run_coacd(mesh, config, object_name)
        cache.save_hulls(path, hulls)
    return hulls
