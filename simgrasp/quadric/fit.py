"""Batched quadric fitting to point neighborhoods: Birdal (normals), Taubin, algebraic.

Every method first standardizes each neighborhood (subtract its centroid, divide by its RMS
radius) and maps the fitted coefficients back exactly, Q = Tᵀ Q' T with T the standardizing
transform, so results do not depend on the cloud's units or position. With the monomial row
v(p) = [x², y², z², 2xy, 2xz, 2yz, 2x, 2y, 2z, 1] (f(p) = v(p)·c) and the gradient rows
∇f(p) = G(p) c:

- ``"birdal"`` (Birdal et al., CVPR 2018): linear least squares on f(p) = 0 and
  ∇f(p) = n for every point, minimizing Σ (v·c)² + w Σ |G c - n|², with ``w =
  gradient_weight`` (default 1: in standardized units a unit residual in f and a unit error in
  the unit normal weigh the same). Normals fix the scale, so there is no trivial solution.
  The normal rows split into a tangential part (∇f ∥ n) and a magnitude part (nᵀ∇f = 1);
  ``magnitude_weight`` m scales the latter: m = 1 (default) is Birdal's plain ∇f = n, which
  is biased where |∇f| varies over the patch (elliptic sections: about 20-100 % error in the
  smaller semi-axis on noise-free 70° patches); m -> 0 keeps only ∇f ∥ n plus the scale and
  is exact on exact data but less robust to noise.
- ``"taubin"``: minimize Σ (v·c)² / Σ |G c|², the generalized eigenproblem M c = λ N c with
  the smallest λ (J eliminated by its Schur complement because N does not involve J).
- ``"algebraic"``: minimize Σ (v·c)² subject to |c| = 1, the smallest eigenvector of M.

The sums the methods need are batched BLAS products of per-point feature rows, one small
matrix per neighborhood: the Gram matrix Σ u uᵀ of u = [x², y², z², xy, xz, yz, x, y, z, 1]
holds every moment of the standardized points up to degree 4, and with normals come Σ p̃ nᵀ
and Σ p̃ p̃ᵀ over the points with a normal (p̃ = [x, y, z, 1]). The small systems are then
assembled and solved vectorized over neighborhoods. A degenerate neighborhood never raises:
its row is NaN, ``valid`` is False and ``failure`` says why (``"non_finite"``,
``"too_few_points"``, ``"collinear"``, ``"coplanar"``, ``"ill_conditioned"``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.quadric.fit_systems import (
    algebraic,
    birdal_system,
    features,
    flatness,
    point_sums,
    solve_spd,
    taubin,
    to_world,
)

FitMethod = Literal["birdal", "taubin", "algebraic"]
METHODS: tuple[FitMethod, ...] = ("birdal", "taubin", "algebraic")

MIN_POINTS = {"birdal": 3, "taubin": 9, "algebraic": 9}
"""Fewest points per neighborhood: 9 determine a quadric; with normals each point gives 4
equations."""

CHUNK = 1024
"""Neighborhoods fitted per vectorized step (keeps the working arrays in cache)."""

MAGNITUDE_WEIGHT = 1.0
"""Default weight of the nᵀ∇f = 1 rows relative to the ∇f ∥ n rows (1: Birdal's ∇f = n)."""

FAILURES = ("non_finite", "too_few_points", "collinear", "coplanar", "ill_conditioned")


@dataclass(frozen=True, eq=False)
class QuadricFit:
    """B fitted quadrics, one per neighborhood, in the input frame and units.

    Behaves as its (B, 10) coefficient array: ``len(fit)``, ``fit.shape``, ``fit[i]`` (a row)
    and ``np.asarray(fit)``.

    Attributes:
        coefficients: (B, 10) ``[A..J]`` rows, NaN where the fit failed.
        valid: (B,) True where the fit succeeded.
        failure: per neighborhood ``None`` or one of :data:`FAILURES`.
        method: the fitting method used.
        centroids: (B, 3) centroid of each neighborhood's (finite, unmasked) points, input
            frame (zeros for empty ones): the reference point to analyse the fits at
            (``analyze_quadrics(fit.coefficients, rtol, reference_points=fit.centroids)``).
    """

    coefficients: NDArray[np.float64]
    valid: NDArray[np.bool_]
    failure: tuple[str | None, ...]
    method: str
    centroids: NDArray[np.float64]

    @property
    def shape(self) -> tuple[int, int]:
        return self.coefficients.shape

    def __len__(self) -> int:
        return len(self.coefficients)

    def __getitem__(self, index: int) -> NDArray[np.float64]:
        return self.coefficients[index]

    def __array__(self, dtype: np.dtype | None = None, copy: bool | None = None) -> np.ndarray:
        if dtype is None and not copy:
            return self.coefficients
        return np.array(self.coefficients, dtype=dtype, copy=True)


def fit_quadrics(
    points: ArrayLike | Sequence[ArrayLike],
    normals: ArrayLike | Sequence[ArrayLike] | None = None,
    method: FitMethod = "birdal",
    mask: ArrayLike | None = None,
    *,
    gradient_weight: float = 1.0,
    magnitude_weight: float = MAGNITUDE_WEIGHT,
) -> QuadricFit:
    """Fit one quadric per neighborhood.

    Args:
        points: (B, K, 3) equal-size neighborhoods, or a list of (K_i, 3) arrays (padded
            internally). Any frame and length unit.
        normals: unit surface normals like ``points`` (required for ``"birdal"``, ignored
            otherwise); they are renormalized, and a zero normal only contributes f(p) = 0.
        method: ``"birdal"``, ``"taubin"`` or ``"algebraic"`` (module docstring).
        mask: (B, K) bool, True for real points (only with dense ``points``); masked-out
            entries are ignored whatever their value.
        gradient_weight: weight w of the normal rows against the f rows (``"birdal"``).
        magnitude_weight: relative weight of the unit-gradient-magnitude part of the normal
            rows (``"birdal"``; module docstring).

    Returns:
        A :class:`QuadricFit` in the frame and units of ``points``.

    Raises:
        ValueError: unknown method, missing normals for ``"birdal"``, or argument shapes that
            do not match (not 3 columns, points/normals/mask mismatch).
    """
    if method not in METHODS:
        raise SimgraspError(f"fit_quadrics: unknown method {method!r}; use one of {METHODS}")
    if method == "birdal" and normals is None:
        raise SimgraspError("fit_quadrics: method 'birdal' needs normals (one per point)")
    for name, value in (
        ("gradient_weight", gradient_weight),
        ("magnitude_weight", magnitude_weight),
    ):
        if not (np.isfinite(value) and value > 0):
            raise SimgraspError(f"fit_quadrics: {name} must be > 0, got {value!r}")
    pts, nrm, valid_point = _dense_inputs(points, normals if method == "birdal" else None, mask)
    with np.errstate(all="ignore"):
        return _fit(pts, nrm, valid_point, method, gradient_weight, magnitude_weight)


def _dense_inputs(
    points: ArrayLike | Sequence[ArrayLike],
    normals: ArrayLike | Sequence[ArrayLike] | None,
    mask: ArrayLike | None,
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """Validate shapes and return dense (B, K, 3) points, normals or None, (B, K) mask."""
    if isinstance(points, list | tuple):
        if mask is not None:
            raise SimgraspError("fit_quadrics: mask is only for dense (B, K, 3) points, not a list")
        pts, valid = _pad(points, "points")
        nrm = None
        if normals is not None:
            if not isinstance(normals, list | tuple) or len(normals) != len(points):
                raise SimgraspError("fit_quadrics: normals must be a list matching the points list")
            nrm, valid_n = _pad(normals, "normals")
            if nrm.shape != pts.shape or not np.array_equal(valid, valid_n):
                raise SimgraspError("fit_quadrics: each normals array must match its points array")
        return pts, nrm, valid
    pts = _as_float(points, "points")
    if pts.ndim != 3 or pts.shape[2] != 3:
        raise SimgraspError(
            f"fit_quadrics: points must be (B, K, 3) or a list of (K_i, 3) arrays, got "
            f"shape {pts.shape}"
        )
    nrm = None
    if normals is not None:
        nrm = _as_float(normals, "normals")
        if nrm.shape != pts.shape:
            raise SimgraspError(
                f"fit_quadrics: normals shape {nrm.shape} does not match points {pts.shape}"
            )
    if mask is None:
        valid = np.ones(pts.shape[:2], dtype=bool)
    else:
        valid = np.asarray(mask)
        if valid.shape != pts.shape[:2] or valid.dtype != np.bool_:
            raise SimgraspError(
                f"fit_quadrics: mask must be bool of shape {pts.shape[:2]}, got "
                f"{valid.dtype} {valid.shape}"
            )
    return pts, nrm, valid


def _as_float(values: ArrayLike | Sequence[ArrayLike], name: str) -> np.ndarray:
    try:
        return np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise SimgraspError(f"fit_quadrics: {name} must be numeric: {error}") from None


def _pad(arrays: Sequence[ArrayLike], name: str) -> tuple[np.ndarray, np.ndarray]:
    items = [_as_float(a, name) for a in arrays]
    for i, item in enumerate(items):
        if item.ndim != 2 or item.shape[1] != 3:
            raise SimgraspError(
                f"fit_quadrics: {name}[{i}] must have shape (K, 3), got {item.shape}"
            )
    width = max((len(item) for item in items), default=0)
    dense = np.zeros((len(items), width, 3))
    valid = np.zeros((len(items), width), dtype=bool)
    for i, item in enumerate(items):
        dense[i, : len(item)] = item
        valid[i, : len(item)] = True
    return dense, valid


def _fit(
    pts: np.ndarray,
    nrm: np.ndarray | None,
    valid: np.ndarray,
    method: str,
    weight: float,
    mw: float,
) -> QuadricFit:
    batch = len(pts)
    coefficients = np.empty((batch, 10))
    failure = np.empty(batch, dtype=np.intp)
    centroids = np.empty((batch, 3))
    for start in range(0, batch, CHUNK):
        chunk = slice(start, start + CHUNK)
        chunk_nrm = None if nrm is None else nrm[chunk]
        coefficients[chunk], failure[chunk], centroids[chunk] = _fit_chunk(
            pts[chunk], chunk_nrm, valid[chunk], method, weight, mw
        )
    names = np.array((None, *FAILURES), dtype=object)[failure]
    return QuadricFit(coefficients, failure == 0, tuple(names.tolist()), method, centroids)


def _fit_chunk(
    pts: np.ndarray,
    nrm: np.ndarray | None,
    valid: np.ndarray,
    method: str,
    weight: float,
    mw: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fit one chunk of neighborhoods: (B, 10) coefficients (NaN where the fit failed), (B,)
    failure codes (0: fitted, i: ``FAILURES[i - 1]``) and (B, 3) centroids."""
    finite = _finite_points(pts)
    if nrm is not None:
        finite &= _finite_points(nrm)
    use = valid & finite
    count = np.count_nonzero(use, axis=1).astype(np.float64)
    failure = np.zeros(len(pts), dtype=np.intp)
    failure[count < MIN_POINTS[method]] = _code("too_few_points")
    failure[np.any(valid & ~finite, axis=1)] = _code("non_finite")
    phi, standard_T_input, centroids = features(pts, nrm, use, count)
    gram = point_sums(phi[:10], phi[:10])  # Σ u uᵀ
    collinear, coplanar = flatness(gram, count)
    failure[(failure == 0) & collinear] = _code("collinear")
    failure[(failure == 0) & coplanar] = _code("coplanar")
    coefficients = np.full((len(pts), 10), np.nan)
    local = np.flatnonzero(failure == 0)
    if len(local) == 0:
        return coefficients, failure, centroids
    if method == "birdal":
        A, rhs = birdal_system(gram, phi, weight, mw)
        fitted, ok = solve_spd(A[local], rhs[local])
    elif method == "taubin":
        fitted, ok = taubin(gram[local])
    else:
        fitted, ok = algebraic(gram[local])
    world = to_world(fitted, standard_T_input[local])
    ok &= np.all(np.isfinite(world), axis=1) & np.any(world[:, :6] != 0, axis=1)
    coefficients[local[ok]] = world[ok]
    failure[local[~ok]] = _code("ill_conditioned")
    return coefficients, failure, centroids


def _code(failure: str) -> int:
    """Integer code of a failure name (0 is success)."""
    return FAILURES.index(failure) + 1


def _finite_points(values: np.ndarray) -> np.ndarray:
    """(B, K) True where all three coordinates of the (B, K, 3) ``values`` are finite."""
    finite = np.isfinite(values)
    return finite[:, :, 0] & finite[:, :, 1] & finite[:, :, 2]
