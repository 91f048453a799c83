"""Batched classification and canonical geometry of quadrics (type, center, axes, semi-axes).

Classification is invariant to rigid motion, uniform space scaling and multiplying the equation
by any non-zero constant, with explicit relative tolerances:

1. Each coefficient row is divided by its largest magnitude (equation scale). q (3x3) is
   eigendecomposed; an eigenvalue counts as zero when ``|λ| <= rtol * max|λ|`` (rank q).
2. Center by the pseudo-inverse over the non-zero eigenvalues, ``x0 = -q⁺ g`` (g = [G, H, I]),
   which is the center of a central quadric and, when q is singular, the point of the center
   set (axis line, mid plane) nearest the origin — or nearest a given reference point, by
   first translating the coefficients so that the reference is the origin. The remaining
   constant is ``J' = J + gᵀx0`` and the linear part left in q's null space is ``g_n``.
3. ``J'`` is zero when ``|J'| <= rround * (|J| + |g| |x0|)``: its own floating-point rounding
   scale, with ``rround = min(rtol, ROUNDING_RTOL)``. A quadric has no intrinsic length other
   than the one ``J'`` defines, so only rounding can make ``J'`` zero; keeping this test at the
   rounding level (not at a loose ``rtol``) means a small cylinder far from the origin stays a
   cylinder.
4. ``g_n`` is zero when ``|g_n| <= sqrt(rtol * max|λ| |J'|) + rround * (|g| + max|λ| |x0|)``.
   The first term is the relative rank test of Q itself, made invariant: in the length unit
   ``ρ = sqrt(|J'| / max|λ|)`` (the quadric's own size) and with the equation divided by
   ``|J'|``, the canonical Q is ``diag(λᵢ / max|λ|, -1)`` plus the entry
   ``κ = |g_n| / sqrt(max|λ| |J'|)`` coupling the null direction to the constant, whose block
   ``[[0, κ], [κ, -1]]`` has the small eigenvalue ≈ -κ²; it counts as zero when
   ``κ² <= rtol``, like the eigenvalues of q. So a noisy fitted cylinder whose radius tapers a
   little along its axis is still a cylinder at a loose ``rtol``. The second term is the
   rounding floor that separates intersecting planes (J' = 0) from paraboloids.
5. The canonical form ``Σ λᵢ yᵢ² + 2 |g_n| t + J' = 0`` gives rank q, rank Q and the sign of
   det Q directly, and with them the type per Olmsted's table (see ``paper-notes.md``). When
   ``J' != 0`` and ``g_n = 0`` the equation is multiplied by ``-sign(J')`` so that ``J' < 0``:
   then a real ellipsoid / real cylinder / real parallel planes has all non-zero eigenvalues
   positive, a one-sheet hyperboloid has exactly one negative eigenvalue (its conjugate axis).

``DEFAULT_RTOL`` suits exact data; fitted (noisy) quadrics need a looser ``rtol`` (e.g. 1e-2)
so that a near-zero eigenvalue of a fitted cylinder counts as zero.

Geometry (all in the frame of the coefficients, same length units):

- ``axes`` rows are unit eigenvectors of q ordered by decreasing |λ| (so semi-axes increase,
  null directions last), each signed so its largest-magnitude component is positive.
  Paraboloids and parabolic cylinders use the direction of ``g_n`` as the first null axis.
- ``centers``: the center for ellipsoids, hyperboloids and cones (apex); the axis point
  nearest the reference (default: the origin) for cylinders and intersecting planes; the
  mid-plane point nearest the reference for parallel / coincident planes; the vertex for
  paraboloids; the point of the vertex line nearest the reference for parabolic cylinders.
- ``semi_axes``: ``sqrt(|J'/λᵢ|)`` aligned with ``axes`` (``inf`` along null directions) when
  ``J' != 0`` and ``g_n = 0``; NaN otherwise (cones, paraboloids, intersecting and coincident
  planes have no such length).
- ``handle_axes`` and ``transverse_semi_axes`` for the handle kinds only (NaN otherwise):
  cylinder axis / hyperboloid conjugate axis / ellipsoid longest axis, and the two other
  semi-axes sorted ascending.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.quadric.coefficients import (
    coefficients_to_matrix,
    matrix_to_coefficients,
    validate_coefficient_rows,
)
from simgrasp.quadric.kinds import QuadricKind

DEFAULT_RTOL = 1e-9
"""Relative tolerance for rank decisions on exact data."""

ROUNDING_RTOL = 1e-9
"""Upper bound on the tolerance of the rounding-level zero tests (constant J', and g_n when
J' = 0)."""

_KINDS = list(QuadricKind)
_KIND_LOOKUP = np.empty(len(_KINDS) + 1, dtype=object)
_KIND_LOOKUP[: len(_KINDS)] = _KINDS
_KIND_LOOKUP[len(_KINDS)] = None
_NO_KIND = len(_KINDS)
_CODE = {kind: i for i, kind in enumerate(_KINDS)}


@dataclass(frozen=True, eq=False)
class QuadricAnalysis:
    """Canonical geometry of B quadrics (coefficient frame and units; see module docstring).

    Attributes:
        kinds: (B,) object array of :class:`QuadricKind`; ``None`` for rows that are not a
            quadric (non-finite coefficients or a zero quadratic part).
        centers: (B, 3) center points (NaN for rows without a kind).
        axes: (B, 3, 3) principal directions, rows unit vectors.
        semi_axes: (B, 3) semi-axis lengths aligned with ``axes`` rows (inf: unbounded,
            NaN: undefined).
        handle_axes: (B, 3) handle direction for handle kinds, NaN otherwise.
        transverse_semi_axes: (B, 2) the two semi-axes across the handle, ascending; NaN for
            non-handle kinds.
        eigenvalues: (B, 3) eigenvalues of q aligned with ``axes``, after the equation is
            scaled by its largest coefficient magnitude and signed so that ``J' <= 0``
            (zeroed where they count as zero).
    """

    kinds: NDArray[np.object_]
    centers: NDArray[np.float64]
    axes: NDArray[np.float64]
    semi_axes: NDArray[np.float64]
    handle_axes: NDArray[np.float64]
    transverse_semi_axes: NDArray[np.float64]
    eigenvalues: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.kinds)


def analyze_quadrics(
    coefficients: ArrayLike,
    rtol: float = DEFAULT_RTOL,
    reference_points: ArrayLike | None = None,
) -> QuadricAnalysis:
    """Classify B quadrics and recover their canonical geometry, vectorized.

    Args:
        coefficients: (B, 10) rows ``[A, B, C, D, E, F, G, H, I, J]``.
        rtol: relative tolerance for every rank / zero decision (module docstring).
        reference_points: (B, 3) or (3,) points (coefficient frame) where a quadric whose q is
            singular within ``rtol`` is read: the constant ``J'`` and the null-space linear
            term are evaluated at the point of the center set nearest the reference, which is
            also the reported center of cylinders and planes. Default: the origin. For a
            fitted neighborhood pass its centroid (:attr:`QuadricFit.centroids`): a noisy
            cylinder fit is a long ellipsoid or hyperboloid whose cross-section must be read
            near the data, not near a far-away origin. Exact quadrics give the same result for
            any reference.

    Returns:
        A :class:`QuadricAnalysis`. Rows with non-finite coefficients, a zero quadratic part
        or a quadratic part so small that the center overflows get kind ``None`` and NaN
        geometry; this function never raises for such rows.
    """
    c = validate_coefficient_rows(coefficients)
    if not (np.isfinite(rtol) and 0 < rtol < 1):
        raise SimgraspError(f"rtol must be in (0, 1), got {rtol!r}")
    reference = np.zeros((len(c), 3))
    if reference_points is not None:
        try:
            reference = np.broadcast_to(
                np.asarray(reference_points, dtype=np.float64), (len(c), 3)
            ).copy()
        except ValueError:
            raise SimgraspError(
                f"reference_points must be (3,) or ({len(c)}, 3), got {np.shape(reference_points)}"
            ) from None
        if not np.all(np.isfinite(reference)):
            raise SimgraspError("reference_points must be finite")
    rround = min(rtol, ROUNDING_RTOL)
    with np.errstate(all="ignore"):
        analysis = _analyze(_translated(c, reference), rtol, rround)
    analysis.centers[...] += reference
    return analysis


def _translated(c: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Coefficients of f(y + p), i.e. the same surface with the reference p as origin."""
    if not np.any(reference):
        return c
    transform = np.broadcast_to(np.eye(4), (len(c), 4, 4)).copy()
    transform[:, :3, 3] = reference
    matrix = coefficients_to_matrix(c)
    with np.errstate(all="ignore"):
        return matrix_to_coefficients(np.swapaxes(transform, 1, 2) @ matrix @ transform)


def _analyze(c: np.ndarray, rtol: float, rround: float) -> QuadricAnalysis:
    finite = np.all(np.isfinite(c), axis=1)
    scale = np.max(np.abs(np.where(finite[:, None], c, 0.0)), axis=1)
    usable = finite & (scale > 0)
    c = np.where(usable[:, None], c / np.where(usable, scale, 1.0)[:, None], 0.0)
    matrix = coefficients_to_matrix(c)
    q, g, constant = matrix[:, :3, :3], matrix[:, :3, 3], matrix[:, 3, 3]

    lam, vec = np.linalg.eigh(q)  # columns of vec are eigenvectors
    lam_max = np.max(np.abs(lam), axis=1)
    usable &= lam_max > 0
    nonzero = np.abs(lam) > rtol * lam_max[:, None]
    rank = nonzero.sum(axis=1)

    g_eig = np.einsum("bji,bj->bi", vec, g)
    y0 = np.where(nonzero, -g_eig / np.where(nonzero, lam, 1.0), 0.0)
    x0 = np.einsum("bij,bj->bi", vec, y0)
    j_prime = constant + np.einsum("bi,bi->b", g_eig, y0)
    g_null = np.where(nonzero, 0.0, g_eig)
    g_null_norm = np.linalg.norm(g_null, axis=1)
    g_norm = np.linalg.norm(g, axis=1)
    x0_norm = np.linalg.norm(x0, axis=1)

    j_zero = np.abs(j_prime) <= rround * (np.abs(constant) + g_norm * x0_norm)
    j_kept = np.where(j_zero, 0.0, j_prime)
    g_zero = g_null_norm <= (
        np.sqrt(rtol * lam_max * np.abs(j_kept)) + rround * (g_norm + lam_max * x0_norm)
    )
    central = g_zero & ~j_zero
    sign = np.where(central, -np.sign(j_kept), 1.0)
    lam_signed = np.where(nonzero, lam * sign[:, None], 0.0)
    positive = (lam_signed > 0).sum(axis=1)
    negative = rank - positive
    same_sign = (positive == 0) | (negative == 0)

    code = _classify(rank, central, j_zero, g_zero, positive, same_sign)
    code = np.where(usable, code, _NO_KIND)

    # Order eigenpairs by decreasing |λ| (zero-classified last).
    order = np.argsort(-np.abs(lam_signed), axis=1, kind="stable")
    lam_sorted = np.take_along_axis(lam_signed, order, axis=1)
    axes = np.take_along_axis(np.swapaxes(vec, 1, 2), order[:, :, None], axis=1)
    centers = x0.copy()

    _orient_parabolic(axes, centers, vec, g_null, g_null_norm, j_prime, rank, g_zero)
    axes *= _canonical_signs(axes)[:, :, None]

    return _analysis(code, axes, centers, lam_sorted, j_kept, central)


def _analysis(
    code: np.ndarray,
    axes: np.ndarray,
    centers: np.ndarray,
    lam_sorted: np.ndarray,
    j_kept: np.ndarray,
    central: np.ndarray,
) -> QuadricAnalysis:
    """Semi-axes, handle geometry and the result of :func:`_analyze`; a quadric with no kind
    or an overflowed center gets NaN geometry (``axes``, ``centers``, ``lam_sorted`` are
    modified in place)."""
    semi = np.where(
        lam_sorted != 0,
        np.sqrt(np.abs(j_kept[:, None] / np.where(lam_sorted != 0, lam_sorted, 1))),
        np.inf,
    )
    semi = np.where(central[:, None], semi, np.nan)
    invalid = (code == _NO_KIND) | ~np.all(np.isfinite(centers), axis=1)  # overflowed centers
    code = np.where(invalid, _NO_KIND, code)
    handle_axes, transverse = _handle_geometry(code, axes, semi, lam_sorted)
    centers[invalid] = np.nan
    axes[invalid] = np.nan
    semi[invalid] = np.nan
    lam_sorted[invalid] = np.nan
    return QuadricAnalysis(
        kinds=_KIND_LOOKUP[code],
        centers=centers,
        axes=axes,
        semi_axes=semi,
        handle_axes=handle_axes,
        transverse_semi_axes=transverse,
        eigenvalues=lam_sorted,
    )


def _classify(
    rank: np.ndarray,
    central: np.ndarray,
    j_zero: np.ndarray,
    g_zero: np.ndarray,
    positive: np.ndarray,
    same_sign: np.ndarray,
) -> np.ndarray:
    """Integer kind codes from the canonical-form invariants (``J' < 0`` when central)."""
    k = _CODE
    no_constant = g_zero & j_zero
    conditions = [
        (rank == 3) & central & (positive == 3),
        (rank == 3) & central & (positive == 0),
        (rank == 3) & central & (positive == 2),
        (rank == 3) & central & (positive == 1),
        (rank == 3) & j_zero & ~same_sign,
        (rank == 3) & j_zero & same_sign,
        (rank == 2) & ~g_zero & same_sign,
        (rank == 2) & ~g_zero & ~same_sign,
        (rank == 2) & central & (positive == 2),
        (rank == 2) & central & (positive == 0),
        (rank == 2) & central & (positive == 1),
        (rank == 2) & no_constant & ~same_sign,
        (rank == 2) & no_constant & same_sign,
        (rank == 1) & ~g_zero,
        (rank == 1) & central & (positive == 1),
        (rank == 1) & central & (positive == 0),
        (rank == 1) & no_constant,
    ]
    choices = [
        k[QuadricKind.REAL_ELLIPSOID],
        k[QuadricKind.IMAGINARY_ELLIPSOID],
        k[QuadricKind.HYPERBOLOID_ONE_SHEET],
        k[QuadricKind.HYPERBOLOID_TWO_SHEETS],
        k[QuadricKind.REAL_CONE],
        k[QuadricKind.IMAGINARY_CONE],
        k[QuadricKind.ELLIPTIC_PARABOLOID],
        k[QuadricKind.HYPERBOLIC_PARABOLOID],
        k[QuadricKind.REAL_ELLIPTIC_CYLINDER],
        k[QuadricKind.IMAGINARY_ELLIPTIC_CYLINDER],
        k[QuadricKind.HYPERBOLIC_CYLINDER],
        k[QuadricKind.REAL_INTERSECTING_PLANES],
        k[QuadricKind.IMAGINARY_INTERSECTING_PLANES],
        k[QuadricKind.PARABOLIC_CYLINDER],
        k[QuadricKind.REAL_PARALLEL_PLANES],
        k[QuadricKind.IMAGINARY_PARALLEL_PLANES],
        k[QuadricKind.COINCIDENT_PLANES],
    ]
    return np.select(conditions, choices, default=_NO_KIND)


def _orient_parabolic(
    axes: np.ndarray,
    centers: np.ndarray,
    vec: np.ndarray,
    g_null: np.ndarray,
    g_null_norm: np.ndarray,
    j_prime: np.ndarray,
    rank: np.ndarray,
    g_zero: np.ndarray,
) -> None:
    """Paraboloids / parabolic cylinders: first null axis along g_n, center at the vertex."""
    parabolic = ~g_zero & (rank < 3)
    if not np.any(parabolic):
        return
    idx = np.flatnonzero(parabolic)
    gamma = g_null_norm[idx]
    direction = np.einsum("bij,bj->bi", vec[idx], g_null[idx]) / gamma[:, None]
    centers[idx] += (-j_prime[idx] / (2 * gamma))[:, None] * direction
    first_null = rank[idx]  # rows 0..rank-1 are the non-zero eigen directions
    axes[idx, first_null] = direction
    cyl = first_null == 1
    if np.any(cyl):
        line = np.cross(axes[idx[cyl], 0], direction[cyl])
        axes[idx[cyl], 2] = line / np.linalg.norm(line, axis=1)[:, None]


def _canonical_signs(axes: np.ndarray) -> np.ndarray:
    """(B, 3) signs making each axis row's largest-magnitude component positive."""
    largest = np.argmax(np.abs(axes), axis=2)
    component = np.take_along_axis(axes, largest[:, :, None], axis=2)[:, :, 0]
    return np.where(component < 0, -1.0, 1.0)


def _handle_geometry(
    code: np.ndarray, axes: np.ndarray, semi: np.ndarray, lam_sorted: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Handle axis and sorted transverse semi-axes for the three handle kinds (NaN elsewhere).

    Ellipsoid: longest axis (smallest |λ|, last row); cylinder: null axis (last row);
    one-sheet hyperboloid: the axis of the single negative eigenvalue (``J' < 0`` convention).
    """
    count = len(code)
    handle_row = np.full(count, 2)
    hyperboloid = code == _CODE[QuadricKind.HYPERBOLOID_ONE_SHEET]
    handle_row[hyperboloid] = np.argmin(lam_sorted[hyperboloid], axis=1)
    is_handle = (
        hyperboloid
        | (code == _CODE[QuadricKind.REAL_ELLIPSOID])
        | (code == _CODE[QuadricKind.REAL_ELLIPTIC_CYLINDER])
    )
    rows = np.arange(count)
    handle_axes = np.where(is_handle[:, None], axes[rows, handle_row], np.nan)
    others = np.ones((count, 3), dtype=bool)
    others[rows, handle_row] = False
    transverse = np.sort(semi[others].reshape(count, 2), axis=1)
    transverse = np.where(is_handle[:, None], transverse, np.nan)
    return handle_axes, transverse
