"""Features of single-view handle candidates and the shipped boosted-tree classifier over them: the
paper's "further restrictions", learned from simulated views with exact handle labels instead
of chosen by hand (``scripts/train_candidate_classifier.py`` fits it with scikit-learn; here
it is applied with numpy alone).

Every feature is measured on the cloud itself, relative to its own point spacing or the
candidate's fitted width where a length would depend on the capture: the finger slots' shares
of the strip's points (:mod:`simgrasp.handles.single_view.standoff`), the fitted width in meters
and in point spacings, how far the fitted axis lies from the seen surface point (in half widths),
how end-on the axis is seen, the surface variation of the 1 cm patch (noise and curvature),
the patch's point count in expected points, the distance to the cloud's centroid in RMS
radii and the quadric kind.

Lengths are meters, in the cloud's frame (sensor at ``eye``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.errors import SimgraspError
from simgrasp.handles.core.detection import Candidate
from simgrasp.handles.single_view.standoff import StandoffConfig, slot_shares

FEATURES = (
    "slot_max",
    "slot_min",
    "width",
    "width_spacings",
    "axis_offset",
    "axis_cosine",
    "variation",
    "density",
    "centrality",
    "ellipsoid",
    "hyperboloid",
    "cylinder",
)
"""The feature names, in column order."""

PATCH_RADIUS = 0.01
"""Radius (m) of the patch whose surface variation and point count are features."""


def _patch(near: NDArray[np.float64], spacing: float) -> tuple[float, float]:
    """Surface variation (smallest over summed covariance eigenvalue) of a patch and its point
    count over the count a flat patch sampled at ``spacing`` would hold."""
    if len(near) < 4:
        return 0.0, 0.0
    eigenvalues = np.linalg.eigvalsh(np.cov((near - near.mean(axis=0)).T))
    variation = float(eigenvalues[0] / max(eigenvalues.sum(), 1e-12))
    expected = np.pi * PATCH_RADIUS**2 / max(spacing, 1e-4) ** 2
    return variation, len(near) / expected


def candidate_features(
    candidates: tuple[Candidate, ...],
    points: NDArray[np.float64],
    eye: NDArray[np.float64],
    spacing: float,
    standoff: StandoffConfig | None = None,
) -> NDArray[np.float64]:
    """(M, len(FEATURES)) features of ``candidates`` in the cloud ``points`` (N, 3) seen from
    ``eye``, whose median point spacing is ``spacing`` (m)."""
    standoff = standoff or StandoffConfig()
    tree = cKDTree(points)
    centroid = points.mean(axis=0)
    rms = float(np.sqrt(((points - centroid) ** 2).sum(axis=1).mean())) or 1.0
    rows = []
    for c in candidates:
        reach = c.width / 2 + standoff.gap + standoff.finger + standoff.half_length
        near = points[tree.query_ball_point(c.handle_point, reach)]
        shares = slot_shares(near, c, eye, standoff)
        ray = c.handle_point - eye
        axis = c.axis / np.linalg.norm(c.axis)
        half = max(c.width / 2, 1e-4)
        variation, density = _patch(points[tree.query_ball_point(c.center, PATCH_RADIUS)], spacing)
        rows.append(
            [
                max(shares),
                min(shares),
                c.width,
                c.width / max(spacing, 1e-4),
                float(np.linalg.norm(c.handle_point - c.center)) / half,
                abs(float(axis @ ray)) / max(float(np.linalg.norm(ray)), 1e-9),
                variation,
                density,
                float(np.linalg.norm(c.center - centroid)) / rms,
                float("ellipsoid" in c.kind),
                float("hyperboloid" in c.kind),
                float("cylinder" in c.kind),
            ]
        )
    return np.array(rows, dtype=float).reshape(len(candidates), len(FEATURES))


@dataclass(frozen=True)
class TreeClassifier:
    """Boosted regression trees on the raw features (scikit-learn's gradient boosting with a
    zero initial guess): p = sigmoid(rate x the sum of each tree's leaf value + ``shift``).
    Each tree is (feature, threshold, left, right, value) arrays over its nodes; a leaf has
    feature -1. ``shift`` moves the model's threshold within an ensemble (0 alone)."""

    trees: tuple[tuple[NDArray[np.float64], ...], ...]
    rate: float
    shift: float = 0.0

    @classmethod
    def parse(cls, raw: dict, source: Path) -> TreeClassifier:
        """The model of the JSON object ``raw`` written by
        ``scripts/train_candidate_classifier.py`` (``source`` names it in errors)."""
        if tuple(raw["features"]) != FEATURES:
            raise SimgraspError(f"{source}: its features {raw['features']} are not {FEATURES}")
        keys = ("feature", "threshold", "left", "right", "value")
        trees = tuple(tuple(np.array(tree[k]) for k in keys) for tree in raw["trees"])
        return cls(trees, float(raw["learning_rate"]), float(raw.get("shift", 0.0)))

    def probability(self, features: NDArray[np.float64]) -> NDArray[np.float64]:
        """(M,) the probability that each row's candidate is on a handle."""
        logit = np.full(len(features), self.shift)
        rows = np.arange(len(features))
        for feature, threshold, left, right, value in self.trees:
            node = np.zeros(len(features), dtype=int)
            while (inner := feature[node] >= 0).any():
                at = node[inner]
                goes_left = features[rows[inner], feature[at].astype(int)] <= threshold[at]
                node[inner] = np.where(goes_left, left[at], right[at]).astype(int)
            logit += self.rate * value[node]
        return 1.0 / (1.0 + np.exp(-logit))


@dataclass(frozen=True)
class MaxEnsemble:
    """Models trained on different object sets, each with its own threshold moved onto a
    common one by its ``shift``: a candidate's probability is the largest of theirs, so it
    passes where any member keeps it."""

    members: tuple[TreeClassifier, ...]

    def probability(self, features: NDArray[np.float64]) -> NDArray[np.float64]:
        """(M,) the members' largest probability that each row's candidate is on a handle."""
        return np.max([m.probability(features) for m in self.members], axis=0)


def read_classifier(path: Path) -> TreeClassifier | MaxEnsemble:
    """The classifier file written by ``scripts/train_candidate_classifier.py``: one model, or
    an ensemble (``{"members": [model, ...]}``, each model with its ``shift``)."""
    if not path.is_file():
        raise SimgraspError(f"{path}: no such candidate classifier file")
    try:
        raw = json.loads(path.read_text())
        if "members" in raw:
            return MaxEnsemble(tuple(TreeClassifier.parse(m, path) for m in raw["members"]))
        return TreeClassifier.parse(raw, path)
    except (ValueError, KeyError, TypeError) as exc:
        raise SimgraspError(f"{path}: not a candidate classifier file ({exc!r})") from exc
