"""CoACD in a child process, so that a run that never ends can be stopped.

``python coacd_child.py JOB`` reads ``vertices`` (V x 3, the mesh's frame and units), ``faces``
(F x 3) and ``params`` (``coacd.run_coacd``'s keywords, as JSON) from the ``.npz`` file JOB,
and writes CoACD's parts to JOB with the suffix ``.parts.npz``: ``vertices`` and ``faces`` of
every part concatenated, each part's faces indexing its own vertices, and ``counts`` (P x 2),
each part's vertex and face count. The file appears whole or not at all.
:func:`simgrasp.assets.decompose.run_coacd` runs it as a script: it imports nothing of
simgrasp, only NumPy and CoACD.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np


def parts_path(job: Path) -> Path:
    """Where the child writes the parts of ``job``."""
    return job.with_suffix(".parts.npz")


def main(job: Path) -> None:
    """Decompose the mesh of ``job`` and write its parts (:func:`parts_path`)."""
    with np.load(job) as given:
        vertices, faces = given["vertices"], given["faces"]
        params = json.loads(str(given["params"]))
    import coacd

    coacd.set_log_level("error")
    parts = coacd.run_coacd(coacd.Mesh(vertices, faces), **params)
    counts = np.array([(len(v), len(f)) for v, f in parts], dtype=np.int64).reshape(-1, 2)
    partial = job.with_suffix(".partial.npz")
    np.savez(
        partial,
        vertices=np.concatenate([np.zeros((0, 3)), *(np.asarray(v, float) for v, _ in parts)]),
        faces=np.concatenate([np.zeros((0, 3), int), *(np.asarray(f, int) for _, f in parts)]),
        counts=counts,
    )
    partial.replace(parts_path(job))


if __name__ == "__main__":
    main(Path(sys.argv[1]))
