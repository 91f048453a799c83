"""A grasping method written outside simgrasp, as a benchmark user would write one: it reads
only the folders of ``simgrasp bench export`` (json and numpy) and writes one answer file per
scene. Its grasp: straight down at the target cloud's center, the jaws across the cloud's
narrower horizontal extent, as low as the table allows.

    python tests/bench_method.py EXPORT_DIR GRASPS_DIR

The same method in process: ``simgrasp bench run SUITE --method bench_method:propose``.
"""

import json
import sys
from pathlib import Path

import numpy as np


def top_down(cloud: np.ndarray, table_top_z: float, pad_reach: float) -> dict:
    """The answer for a target cloud (N x 3, world frame, meters)."""
    if len(cloud) < 10:
        return {"grasps": []}
    center = cloud.mean(axis=0)
    _, axes = np.linalg.eigh(np.cov((cloud[:, :2] - center[:2]).T))
    closing = np.array([axes[0, 0], axes[1, 0], 0.0])  # the narrower horizontal direction
    approach = np.array([0.0, 0.0, -1.0])
    lowest = table_top_z + pad_reach + 0.01
    position = np.array([center[0], center[1], max(cloud[:, 2].max() - 0.02, lowest)])
    world_T_tcp = np.eye(4)
    world_T_tcp[:3, :3] = np.column_stack([np.cross(closing, approach), closing, approach])
    world_T_tcp[:3, 3] = position
    return {"grasps": [{"world_T_tcp": world_T_tcp.tolist(), "width": None}]}


def answer(folder: Path) -> dict:
    """The answer for the scene exported in ``folder``."""
    observation = json.loads((folder / "observation.json").read_text())
    cloud = np.load(folder / observation["cloud"])
    return top_down(cloud, observation["table_top_z"], observation["gripper"]["pad_reach"])


def propose(observation) -> dict:  # noqa: ANN001 (a BenchObservation; simgrasp not imported)
    """The same method in process (``--method bench_method:propose``)."""
    pad_reach = observation.gripper["pad_reach"]
    return top_down(observation.cloud, observation.table_top_z, pad_reach)


def main(export_dir: str, grasps_dir: str) -> None:
    out = Path(grasps_dir)
    out.mkdir(parents=True, exist_ok=True)
    for folder in sorted(p for p in Path(export_dir).iterdir() if p.is_dir()):
        (out / f"{folder.name}.json").write_text(json.dumps(answer(folder)))


if __name__ == "__main__":
    main(*sys.argv[1:3])
