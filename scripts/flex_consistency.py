"""How well FleX's label of a nearby grasp predicts FleX's label, beside our agreement (issue 25).

For each grasp we labeled (a ``label-grasps`` data-set run of ACRONYM files), the nearest
other grasp of the same file within a pose tolerance (TCP position within ``mm``, rotation
within ``deg``, a half turn about the approach counting as the same grasp) is found among all
of the file's grasps. FleX's label of that neighbour, taken as a prediction of FleX's label of
the grasp, says how much FleX's own verdict changes under a pose change of that size: a
labeler whose physics differs from FleX's by about as much cannot be expected to agree with
FleX better. Our labels are scored on the same grasps. Rows per half of
``docs/results/acronym/halves.json`` and category; unscored grasps (``invalid``,
``sim_unstable``) are left out as ``compare-labels`` leaves them out. A second table gives,
per file, how often FleX's labels of all pairs of grasps within ``PAIR_TOLERANCE`` of each
other agree, beside our accuracy on the file, and how the two rank together.

    python scripts/flex_consistency.py --labels out/acronym/affordance \\
        --grasps $SIMGRASP_ACRONYM_DIR/affordance/grasps \\
        --out docs/results/acronym/flex-consistency.md
"""

from __future__ import annotations

import functools
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation
from scipy.stats import spearmanr

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.grasping.labeling.grasp_sets import FRANKA_T_TCP
from simgrasp.grasping.labeling.hdf5_files import open_hdf5
from simgrasp.grasping.labeling.label_compare import UNSCORED, load_labels
from simgrasp.grasping.labeling.reference_compare import compare_with_reference, labels_dir_of

HALVES = Path(__file__).resolve().parents[1] / "docs" / "results" / "acronym" / "halves.json"
TOLERANCES = ((3.0, 7.5), (5.0, 10.0), (8.0, 15.0))
"""(TCP distance in mm, rotation in degrees) of a neighbour."""
PAIR_TOLERANCE = (4.0, 10.0)
"""(mm, degrees) of the grasp pairs whose FleX labels are compared per file."""
CLOSE_PAIRS = (2.0, 5.0)
"""(mm, degrees) of the nearly equal grasp pairs counted over all files."""
HALF_TURN = np.diag([-1.0, -1.0, 1.0])
"""A parallel-jaw grasp turned half a turn about its approach (z) is the same grasp."""


@functools.cache
def tcp_poses(path: Path) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """(N, 3) TCP positions (m), (N, 3, 3) rotations and FleX labels of an ACRONYM file (read
    once)."""
    with open_hdf5(path) as handle:
        hand = np.asarray(handle["grasps/transforms"][()], float)
        flex = np.asarray(handle["grasps/qualities/flex/object_in_gripper"][()]).astype(bool)
    tcp = hand @ FRANKA_T_TCP
    return tcp[:, :3, 3], tcp[:, :3, :3], flex


def turn_degrees(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Angle (degrees) between the grasp rotations ``a`` and ``b`` ((3, 3) or (N, 3, 3) each),
    a half turn about the approach counting as no turn."""
    relative = np.swapaxes(a, -1, -2) @ b
    return np.minimum(
        np.degrees(Rotation.from_matrix(relative).magnitude()),
        np.degrees(Rotation.from_matrix(relative @ HALF_TURN).magnitude()),
    )


@functools.cache
def scored_labels(labels_dir: Path) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """(our success, scored) of a label directory (read once); unscored as compare-labels."""
    ours = load_labels(labels_dir)
    return ours["success"].astype(bool), ~np.isin(ours["failure"], UNSCORED)


def nearest_neighbour(
    i: int,
    positions: NDArray[np.float64],
    rotations: NDArray[np.float64],
    tree: cKDTree,
    mm: float,
    deg: float,
) -> int | None:
    """The grasp nearest grasp ``i`` (distance / mm + angle / deg) within both tolerances."""
    others = np.array([j for j in tree.query_ball_point(positions[i], mm / 1000) if j != i])
    if others.size == 0:
        return None
    angle = turn_degrees(rotations[i], rotations[others])
    near = angle < deg
    if not near.any():
        return None
    distance = np.linalg.norm(positions[others] - positions[i], axis=1) * 1000 / mm + angle / deg
    return int(others[near][np.argmin(distance[near])])


def file_counts(path: Path, labels_dir: Path, mm: float, deg: float) -> tuple[int, int, int]:
    """(grasps with a neighbour, FleX's neighbour right, ours right) over a file's scored grasps."""
    positions, rotations, flex = tcp_poses(path)
    success, scored = scored_labels(labels_dir)
    tree = cKDTree(positions)
    counts = [0, 0, 0]
    for i in np.flatnonzero(scored):
        j = nearest_neighbour(int(i), positions, rotations, tree, mm, deg)
        if j is None:
            continue
        counts[0] += 1
        counts[1] += int(flex[j] == flex[i])
        counts[2] += int(success[i] == flex[i])
    return counts[0], counts[1], counts[2]


def pair_agreement(path: Path, mm: float, deg: float) -> tuple[int, float]:
    """(pairs, share with equal FleX labels) of all pairs of a file's grasps within both
    tolerances of each other."""
    positions, rotations, flex = tcp_poses(path)
    pairs = cKDTree(positions).query_pairs(mm / 1000, output_type="ndarray")
    if len(pairs) == 0:
        return 0, float("nan")
    near = pairs[turn_degrees(rotations[pairs[:, 0]], rotations[pairs[:, 1]]) < deg]
    return len(near), float(np.mean(flex[near[:, 0]] == flex[near[:, 1]])) if len(near) else 0.0


def per_file(labels: Path, grasps: Path) -> str:
    """Per file: FleX's agreement between grasp pairs within ``PAIR_TOLERANCE`` and our
    accuracy; then Spearman's rank correlation of the two over the mugs and over all files."""
    halves = json.loads(HALVES.read_text())
    mm, deg = PAIR_TOLERANCE
    lines = [
        f"| file | half | pairs within {mm:g} mm, {deg:g} deg | FleX agrees with itself "
        "| our accuracy (all scored grasps) |",
        "|---|---|---|---|---|",
    ]
    rows: list[tuple[str, float, float]] = []
    close = [0, 0]
    for half in ("tune", "held_out"):
        for name in halves[f"{half}/files"]:
            path = grasps / name
            count, agree = pair_agreement(path, mm, deg)
            accuracy = compare_with_reference(labels, [path])["files"][0]["accuracy"]
            rows.append((name, agree, accuracy))
            pairs, equal = pair_agreement(path, *CLOSE_PAIRS)
            close = [close[0] + pairs, close[1] + round(equal * pairs)]
            label = half.replace("_", "-")
            lines.append(f"| {name[:13]} | {label} | {count} | {agree:.3f} | {accuracy:.3f} |")
    for category in ("Mug", ""):
        chosen = [r for r in rows if r[0].startswith(category)]
        rho = spearmanr([r[1] for r in chosen], [r[2] for r in chosen]).statistic
        lines.append(
            f"\nSpearman's rank correlation, {category.lower() + 's' if category else 'all files'} "
            f"({len(chosen)}): {rho:.2f}"
        )
    lines.append(
        f"\nNearly equal grasps (within {CLOSE_PAIRS[0]:g} mm, {CLOSE_PAIRS[1]:g} deg) over all "
        f"files: {close[0]} pairs, FleX agrees with itself on {close[1] / close[0]:.3f}"
    )
    return "\n".join(lines) + "\n"


def table(labels: Path, grasps: Path) -> str:
    """The markdown table of every tolerance, half and category."""
    halves = json.loads(HALVES.read_text())
    lines = [
        "| neighbour within | half | category | grasps with a neighbour "
        "| FleX's label of the neighbour agrees | ours agrees |",
        "|---|---|---|---|---|---|",
    ]
    for mm, deg in TOLERANCES:
        for half in ("tune", "held_out"):
            pooled: dict[str, list[int]] = {}
            for name in halves[f"{half}/files"]:
                path = grasps / name
                counts = file_counts(path, labels_dir_of(labels, path), mm, deg)
                for key in (name.split("_", 1)[0], "all"):
                    total = pooled.setdefault(key, [0, 0, 0])
                    total[:] = [a + b for a, b in zip(total, counts, strict=True)]
            for key in sorted(pooled, key=lambda k: (k == "all", k)):
                n, flex_right, ours_right = pooled[key]
                lines.append(
                    f"| {mm:g} mm, {deg:g} deg | {half.replace('_', '-')} | {key} | {n} "
                    f"| {flex_right / n:.3f} | {ours_right / n:.3f} |"
                )
    return "\n".join(lines) + "\n"


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    labels: Path
    """A label-grasps data-set run of the ACRONYM files."""
    grasps: Path
    """The ACRONYM files' folder."""
    out: Path
    """The markdown table to write."""


def run(options: Options) -> None:
    """Both tables, written to ``out`` and printed."""
    if not options.grasps.is_dir():
        raise SystemExit(f"no such folder: {options.grasps} (set SIMGRASP_ACRONYM_DIR)")
    options.out.write_text(
        table(options.labels, options.grasps) + "\n" + per_file(options.labels, options.grasps)
    )
    print(options.out.read_text(), end="")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
