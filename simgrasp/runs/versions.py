"""Which library versions wrote a run's records: ``OUT/versions.json``.

A trial's outcome depends on more than its settings and seed: MuJoCo's solver, NumPy's
linear algebra, Open3D's normal estimation and trimesh's mesh processing change in the last
bits between releases, and a grasp on the edge of holding can tip either way. The records of a
run therefore say which versions made them, so a figure that no longer reproduces can be traced
to a library rather than to the code. A directory resumed under other versions lists each set
in the order it first wrote there; a run under a set already listed adds nothing.
"""

from __future__ import annotations

import json
import platform
from importlib import metadata
from pathlib import Path

VERSIONS_FILE = "versions.json"
LIBRARIES = ("simgrasp", "mujoco", "numpy", "scipy", "open3d", "trimesh", "coacd")
"""The distributions whose version is recorded (those not installed are left out)."""


def library_versions() -> dict[str, str]:
    """Python's version and each installed distribution of :data:`LIBRARIES` (name -> version)."""
    versions = {"python": platform.python_version()}
    for name in LIBRARIES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return versions


def record_versions(out_dir: Path) -> None:
    """Add this process's :func:`library_versions` to ``out_dir/versions.json`` (a JSON list
    of version sets) unless it lists them already. An unreadable file is replaced: it records
    provenance, never results."""
    path = Path(out_dir) / VERSIONS_FILE
    current = library_versions()
    try:
        seen = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(seen, list):
            seen = []
    except (OSError, ValueError):
        seen = []
    if current in seen:
        return
    path.write_text(json.dumps([*seen, current], indent=1) + "\n", encoding="utf-8")
