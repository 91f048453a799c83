"""Detect handles in a point cloud saved as a ``.npy`` file (N x 3, meters).

    python examples/detect_npy.py [CLOUD.npy]

Without an argument, a cloud of the generated mug's surface is written to ``mug.npy`` first.
"""

import sys

import numpy as np
import trimesh

import simgrasp

if len(sys.argv) > 1:
    path = sys.argv[1]
else:
    mug = simgrasp.load_object("gen_mug")
    points, _ = trimesh.sample.sample_surface(mug.mesh, 20_000, seed=0)
    path = "mug.npy"
    np.save(path, points)

detection = simgrasp.detect_handles(np.load(path), seed=0)
print(f"{len(detection.candidates)} handle-like neighborhoods, {len(detection.handles)} handles")
for handle in detection.handles:
    center = np.round(handle.center, 3)
    print(f"  center {center} m, width {handle.width:.3f} m, score {handle.score:.2f}")
