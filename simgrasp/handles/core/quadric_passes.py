"""The quadric detector's passes and their clustering: the accepted neighborhoods of a pass
(:class:`Accepted`, :class:`Pass`) and the handles clustered from every pass's candidates
(:func:`cluster_passes`), for :func:`simgrasp.handles.core.quadric_detector.detect_quadric_handles`.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.handles.core.cluster import Ranked, best_first, cluster_handles
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.core.detection import Candidate, Handle
from simgrasp.quadric import Quadric, QuadricAnalysis, QuadricFit


@dataclass(frozen=True)
class Accepted:
    """The accepted neighborhoods of one or more passes, (M, ...) arrays: neighborhood
    centers, handle points on the axes, handle axes, smaller transverse semi-axes, quadric
    coefficients (a plate's: its two faces) and the points they are expressed about, kinds
    (``QuadricKind``, or ``"plate"`` for the plate test's)."""

    centers: NDArray[np.float64]
    on_axis: NDArray[np.float64]
    axes: NDArray[np.float64]
    half_widths: NDArray[np.float64]
    coefficients: NDArray[np.float64]
    centroids: NDArray[np.float64]
    kinds: NDArray[np.object_]

    @classmethod
    def none(cls) -> Accepted:
        vectors = np.zeros((0, 3))
        return cls(
            vectors, vectors, vectors, np.zeros(0), np.zeros((0, 10)), vectors, np.zeros(0, object)
        )

    @classmethod
    def joined(cls, parts: list[Accepted]) -> Accepted:
        return cls(*(joined([getattr(p, f.name) for p in parts]) for f in fields(cls)))

    @classmethod
    def of(
        cls,
        centers: NDArray[np.float64],
        analysis: QuadricAnalysis,
        on_axis: NDArray[np.float64],
        fit: QuadricFit,
    ) -> Accepted:
        """Every fitted neighborhood as a row (copies: the plate test overwrites rows)."""
        return cls(
            centers,
            on_axis.copy(),
            analysis.handle_axes.copy(),
            analysis.transverse_semi_axes[:, 0].copy(),
            fit.coefficients.copy(),
            fit.centroids.copy(),
            analysis.kinds.astype(object),
        )

    def rows(self, index: NDArray[np.int64]) -> Accepted:
        return type(self)(*(getattr(self, f.name)[index] for f in fields(self)))


@dataclass(frozen=True)
class Pass:
    """One pass's accepted neighborhoods, all its sampled centers (m) and whether it had
    any neighborhood to fit."""

    accepted: Accepted
    sampled_centers: NDArray[np.float64]
    fitted: bool


def cluster_passes(
    pts: NDArray[np.float64], passes: list[Pass], config: QuadricDetectorConfig
) -> tuple[tuple[Handle, ...], tuple[Candidate, ...]]:
    """Handles clustered from each pass's accepted candidates on their own (single linkage
    would chain a dense fine pass's candidates with the first pass's into one blob over a
    handle and the body next to it), ranked together by score, and the candidates
    supporting the handles kept. A later pass's handle counts only where the earlier passes
    found none (:func:`_elsewhere`). A handle's score is its support share of all passes'
    accepted candidates, as one pass's is of its own (:func:`_pass_weights`)."""
    centroid = pts.mean(axis=0)
    rms_radius = float(np.sqrt(((pts - centroid) ** 2).sum(axis=1).mean()))
    joined = Accepted.joined([p.accepted for p in passes])
    found: list[Ranked] = []
    offset = 0
    for weight, accepted in zip(_pass_weights(passes), (p.accepted for p in passes), strict=True):
        ranked = cluster_handles(
            accepted.on_axis,
            accepted.axes,
            2 * accepted.half_widths,
            distance=config.cluster_distance,
            min_support=config.min_support,
            object_center=centroid if config.prefer_central else None,
            centrality_length=max(
                config.centrality_min_length, config.centrality_scale * rms_radius
            ),
            centrality_measure=config.centrality_measure,
            max_opening=config.gripper_max_opening if config.prefer_clearance else None,
            min_relative_score=config.min_relative_score,
            anchors=accepted.centers if config.handle_anchor == "surface" else None,
        )
        kept = [r.scaled(weight, offset) for r in ranked]
        found += _elsewhere(kept, found, joined.on_axis, config.cluster_distance)
        offset += len(accepted.centers)
    kept = best_first(found, config.min_relative_score)
    return tuple(r.handle for r in kept), _candidates(
        joined, tuple(r.members for r in kept), config
    )


def _pass_weights(passes: list[Pass]) -> list[float]:
    """Each pass's share of all passes' accepted candidates (1 for a single pass): the factor
    from a handle's support share within its pass to its share of all candidates. Within its
    pass, a fine handle of two candidates on a chips can, the fine pass's only ones, had the
    score of a sole handle and outranked the first pass's handle of 27."""
    counts = [len(p.accepted.centers) for p in passes]
    total = sum(counts)
    return [count / total if total > 0 else 1.0 for count in counts]


def _elsewhere(
    new: list[Ranked],
    earlier: list[Ranked],
    on_axis: NDArray[np.float64],
    distance: float,
) -> list[Ranked]:
    """The ``new`` handles none of whose candidates' handle points (rows of ``on_axis``)
    lies within ``distance`` (m) of an ``earlier`` handle's: a part the first pass holds
    keeps the first pass's handle, and so its grasp (a fork's or spatula's handle, found by
    the fine pass too, narrower and placed elsewhere along it)."""
    if not earlier or not new:
        return new
    tree = cKDTree(on_axis[np.concatenate([r.members for r in earlier])])
    return [
        r
        for r in new
        if np.isinf(tree.query(on_axis[r.members], distance_upper_bound=distance)[0]).all()
    ]


def _candidates(
    accepted: Accepted, members: tuple[NDArray[np.int64], ...], config: QuadricDetectorConfig
) -> tuple[Candidate, ...]:
    """The accepted neighborhoods in ``members`` (row indices) as candidates, in row order."""
    supporting = np.sort(np.concatenate(list(members) or [np.zeros(0, int)]))
    quadrics = Quadric.batch(
        accepted.coefficients[supporting], config.kind_rtol, accepted.centroids[supporting]
    )
    return tuple(
        Candidate(
            center=accepted.centers[i],
            quadric=quadric,
            kind=str(accepted.kinds[i]),
            axis=accepted.axes[i],
            width=float(2 * accepted.half_widths[i]),
            handle_point=accepted.on_axis[i],
        )
        for i, quadric in zip(supporting, quadrics, strict=True)
    )


def joined(arrays: list[NDArray]) -> NDArray:
    """The per-scale batches concatenated along the batch axis (a single scale: not copied)."""
    return arrays[0] if len(arrays) == 1 else np.concatenate(arrays)
