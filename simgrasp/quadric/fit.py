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
- ``"taubin"``: minimize Σ (v·c)² / Σ |G c|², the generalized eigenproblem M c = λ N c with
  the smallest λ (J eliminated by its Schur complement because N does not involve J).
- ``"algebraic"``: minimize Σ (v·c)² subject to |c| = 1, the smallest eigenvector of M.

All sums are built from batched matrix products and the small systems solved batched. A
degenerate neighborhood never raises: its row is NaN, ``valid`` is False and ``failure`` says
why (``"non_finite"``, ``"too_few_points"``, ``"collinear"``, ``"coplanar"``,
``"ill_conditioned"``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.quadric.coefficients import coefficients_to_matrix, matrix_to_coefficients

FitMethod = Literal["birdal", "taubin", "algebraic"]
METHODS: tuple[str, ...] = ("birdal", "taubin", "algebraic")

MIN_POINTS = {"birdal": 3, "taubin": 9, "algebraic": 9}
"""Fewest points per neighborhood: 9 determine a quadric; with normals each point gives 4
equations."""

FLAT_TOL = 1e-12
"""A standardized neighborhood is collinear / coplanar when its second / smallest covariance
eigenvalue is below this (an RMS thickness below 1e-6 of the RMS radius)."""

CONDITION_LIMIT = 1e12
"""Largest accepted 1-norm condition number of the (equilibrated) fitting system, and the
smallest accepted ratio max/min of the eigen gap for the eigenvector methods."""

MAGNITUDE_WEIGHT = 1.0

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

    Returns:
        A :class:`QuadricFit` in the frame and units of ``points``.

    Raises:
        ValueError: unknown method, missing normals for ``"birdal"``, or argument shapes that
            do not match (not 3 columns, points/normals/mask mismatch).
    """
    if method not in METHODS:
        raise ValueError(f"fit_quadrics: unknown method {method!r}; use one of {METHODS}")
    if method == "birdal" and normals is None:
        raise ValueError("fit_quadrics: method 'birdal' needs normals (one per point)")
    if not (np.isfinite(gradient_weight) and gradient_weight > 0):
        raise ValueError(f"fit_quadrics: gradient_weight must be > 0, got {gradient_weight!r}")
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
            raise ValueError("fit_quadrics: mask is only for dense (B, K, 3) points, not a list")
        pts, valid = _pad(points, "points")
        nrm = None
        if normals is not None:
            if not isinstance(normals, list | tuple) or len(normals) != len(points):
                raise ValueError("fit_quadrics: normals must be a list matching the points list")
            nrm, valid_n = _pad(normals, "normals")
            if nrm.shape != pts.shape or not np.array_equal(valid, valid_n):
                raise ValueError("fit_quadrics: each normals array must match its points array")
        return pts, nrm, valid
    pts = _as_float(points, "points")
    if pts.ndim != 3 or pts.shape[2] != 3:
        raise ValueError(
            f"fit_quadrics: points must be (B, K, 3) or a list of (K_i, 3) arrays, got "
            f"shape {pts.shape}"
        )
    nrm = None
    if normals is not None:
        nrm = _as_float(normals, "normals")
        if nrm.shape != pts.shape:
            raise ValueError(
                f"fit_quadrics: normals shape {nrm.shape} does not match points {pts.shape}"
            )
    if mask is None:
        valid = np.ones(pts.shape[:2], dtype=bool)
    else:
        valid = np.asarray(mask)
        if valid.shape != pts.shape[:2] or valid.dtype != np.bool_:
            raise ValueError(
                f"fit_quadrics: mask must be bool of shape {pts.shape[:2]}, got "
                f"{valid.dtype} {valid.shape}"
            )
    return pts, nrm, valid


def _as_float(values: ArrayLike, name: str) -> np.ndarray:
    try:
        return np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f"fit_quadrics: {name} must be numeric: {error}") from None


def _pad(arrays: Sequence[ArrayLike], name: str) -> tuple[np.ndarray, np.ndarray]:
    items = [_as_float(a, name) for a in arrays]
    for i, item in enumerate(items):
        if item.ndim != 2 or item.shape[1] != 3:
            raise ValueError(f"fit_quadrics: {name}[{i}] must have shape (K, 3), got {item.shape}")
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
    magnitude_weight: float,
) -> QuadricFit:
    batch = len(pts)
    failure = np.full(batch, None, dtype=object)
    finite = np.isfinite(pts).all(axis=2)
    if nrm is not None:
        finite &= np.isfinite(nrm).all(axis=2)
    bad_value = np.any(valid & ~finite, axis=1)
    failure[bad_value] = "non_finite"
    weights = (valid & finite).astype(np.float64)
    count = weights.sum(axis=1)
    failure[(failure == None) & (count < MIN_POINTS[method])] = "too_few_points"  # noqa: E711

    pts = np.where(weights[:, :, None] > 0, pts, 0.0)
    standard, standard_T_input, centroids = _standardize(pts, weights, count)
    spread = _spread(standard, weights, count)
    open_ = failure == None  # noqa: E711
    failure[open_ & ~(spread[:, 1] > FLAT_TOL)] = "collinear"
    open_ = failure == None  # noqa: E711
    failure[open_ & ~(spread[:, 0] > FLAT_TOL)] = "coplanar"

    active = failure == None  # noqa: E711
    coefficients = np.full((batch, 10), np.nan)
    if np.any(active):
        idx = np.flatnonzero(active)
        std_pts, w = standard[idx], weights[idx]
        if method == "birdal":
            n = np.where(w[:, :, None] > 0, nrm[idx], 0.0)
            length = np.linalg.norm(n, axis=2)
            n = np.where(length[:, :, None] > 0, n / np.where(length > 0, length, 1)[:, :, None], 0)
            fitted, ok = _birdal(std_pts, n, w, w * (length > 0), weight, magnitude_weight)
        elif method == "taubin":
            fitted, ok = _taubin(std_pts, w)
        else:
            fitted, ok = _algebraic(std_pts, w)
        world = _to_world(fitted, standard_T_input[idx])
        ok &= np.all(np.isfinite(world), axis=1) & np.any(world[:, :6] != 0, axis=1)
        coefficients[idx[ok]] = world[ok]
        failure[idx[~ok]] = "ill_conditioned"
    valid_fit = failure == None  # noqa: E711
    return QuadricFit(coefficients, valid_fit, tuple(failure.tolist()), method, centroids)


def _standardize(
    pts: np.ndarray, weights: np.ndarray, count: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points in each neighborhood's standard frame (centroid 0, RMS radius 1), the (B, 4, 4)
    transform T mapping input coordinates to standard ones (x' = T x) and the (B, 3)
    centroids in input coordinates."""
    safe_count = np.maximum(count, 1)
    magnitude = np.max(np.abs(pts), axis=(1, 2))
    magnitude = np.where(magnitude > 0, magnitude, 1.0)
    scaled = pts / magnitude[:, None, None]
    centroid = np.einsum("bk,bki->bi", weights, scaled) / safe_count[:, None]
    centered = (scaled - centroid[:, None, :]) * weights[:, :, None]
    rms = np.sqrt(np.einsum("bki,bki->b", centered, centered) / safe_count)
    rms = np.where(rms > 0, rms, 1.0)
    standard = centered / rms[:, None, None]
    scale = 1.0 / (magnitude * rms)
    transform = np.zeros((len(pts), 4, 4))
    transform[:, [0, 1, 2], [0, 1, 2]] = scale[:, None]
    transform[:, :3, 3] = -centroid / rms[:, None]
    transform[:, 3, 3] = 1.0
    return standard, transform, centroid * magnitude[:, None]


def _spread(standard: np.ndarray, weights: np.ndarray, count: np.ndarray) -> np.ndarray:
    """(B, 3) ascending eigenvalues of the standardized covariance (they sum to 1)."""
    cov = np.einsum("bki,bkj->bij", standard, standard) / np.maximum(count, 1)[:, None, None]
    cov = np.where(np.isfinite(cov), cov, 0.0)
    return np.linalg.eigvalsh(cov)


def _monomials(p: np.ndarray) -> np.ndarray:
    """(B, K, 10) rows v(p) with f(p) = v(p) · [A..J]."""
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    return np.stack(
        [
            x * x,
            y * y,
            z * z,
            2 * x * y,
            2 * x * z,
            2 * y * z,
            2 * x,
            2 * y,
            2 * z,
            np.ones_like(x),
        ],
        axis=-1,
    )


# ∂f/∂x_d = 2 Σ_a p̃_a c[_GRAD_INDEX[d, a]] with p̃ = [x, y, z, 1].
_GRAD_INDEX = np.array([[0, 3, 4, 6], [3, 1, 5, 7], [4, 5, 2, 8]])


def _gradient_operators() -> tuple[np.ndarray, np.ndarray]:
    """Linear maps from second moments S = Σ p̃ p̃ᵀ (16) to Σ GᵀG (100), and from the cross
    moments C = Σ p̃ nᵀ (12) to Σ Gᵀ n (10)."""
    to_normal = np.zeros((4, 4, 10, 10))
    to_rhs = np.zeros((4, 3, 10))
    for d in range(3):
        for a in range(4):
            to_rhs[a, d, _GRAD_INDEX[d, a]] += 2.0
            for b in range(4):
                to_normal[a, b, _GRAD_INDEX[d, a], _GRAD_INDEX[d, b]] += 4.0
    return to_normal.reshape(16, 100), to_rhs.reshape(12, 10)


_TO_NORMAL, _TO_RHS = _gradient_operators()


def _homogeneous(p: np.ndarray) -> np.ndarray:
    return np.concatenate([p, np.ones(p.shape[:-1] + (1,))], axis=-1)


def _moments(
    p: np.ndarray, w: np.ndarray, w_grad: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M = Σ w v vᵀ (B,10,10), N = Σ w_g GᵀG (B,10,10) and p̃ (B,K,4)."""
    v = _monomials(p)
    M = np.matmul(np.swapaxes(v * w[:, :, None], 1, 2), v)
    ph = _homogeneous(p)
    S = np.matmul(np.swapaxes(ph * w_grad[:, :, None], 1, 2), ph)
    N = (S.reshape(-1, 16) @ _TO_NORMAL).reshape(-1, 10, 10)
    return M, N, ph


def _birdal(
    p: np.ndarray,
    n: np.ndarray,
    w: np.ndarray,
    w_grad: np.ndarray,
    weight: float,
    magnitude_weight: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Normal equations of Σ (v·c)² + w Σ |P_t G c|² + w m Σ (nᵀG c - 1)² (P_t = I - n nᵀ).

    With r_p = Gᵀn: Σ |P_t G c|² = cᵀ(N - Σ r rᵀ)c and Σ (nᵀGc - 1)² = cᵀ(Σ r rᵀ)c - 2 cᵀΣ r + K.
    """
    M, N, ph = _moments(p, w, w_grad)
    outer = (ph[:, :, :, None] * n[:, :, None, :]).reshape(*n.shape[:2], 12)
    r = (outer @ _TO_RHS) * np.sqrt(w_grad)[:, :, None]
    R = np.matmul(np.swapaxes(r, 1, 2), r)
    A = M + weight * N + weight * (magnitude_weight - 1) * R
    rhs = weight * magnitude_weight * r.sum(axis=1)
    return _solve_spd(A, rhs)


def _solve_spd(A: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve batched symmetric systems with Jacobi equilibration; flag ill-conditioned ones."""
    diag = np.einsum("bii->bi", A)
    ok = np.all(diag > 0, axis=1) & np.all(np.isfinite(A), axis=(1, 2))
    d = 1.0 / np.sqrt(np.where(ok[:, None], diag, 1.0))
    A_eq = A * d[:, :, None] * d[:, None, :]
    A_eq[~ok] = np.eye(A.shape[1])
    inverse = _batched_inverse(A_eq, ok)
    cond = np.abs(A_eq).sum(axis=1).max(axis=1) * np.abs(inverse).sum(axis=1).max(axis=1)
    ok &= cond < CONDITION_LIMIT
    solution = d * np.einsum("bij,bj->bi", inverse, d * rhs)
    return solution, ok


def _batched_inverse(A: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """Inverse of each matrix; exactly singular ones (rare) are marked not ok, not raised."""
    try:
        return np.linalg.inv(A)
    except np.linalg.LinAlgError:
        inverse = np.empty_like(A)
        for i, matrix in enumerate(A):
            try:
                inverse[i] = np.linalg.inv(matrix)
            except np.linalg.LinAlgError:
                inverse[i] = np.eye(len(matrix))
                ok[i] = False
        return inverse


def _smallest_eigenvector(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit eigenvector of the smallest eigenvalue of each symmetric matrix, and whether it is
    well separated from the second smallest (a unique solution)."""
    ok = np.all(np.isfinite(A), axis=(1, 2))
    A = np.where(ok[:, None, None], A, np.eye(A.shape[1]))
    lam, vec = np.linalg.eigh(A)
    top = np.max(np.abs(lam), axis=1)
    ok &= (lam[:, 1] - lam[:, 0]) * CONDITION_LIMIT > top
    return vec[:, :, 0], ok


def _algebraic(p: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    M = np.matmul(np.swapaxes(_monomials(p) * w[:, :, None], 1, 2), _monomials(p))
    return _smallest_eigenvector(M)


def _taubin(p: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    M, N, _ = _moments(p, w, w)
    m12, m22 = M[:, :9, 9], M[:, 9, 9]
    reduced = M[:, :9, :9] - m12[:, :, None] * m12[:, None, :] / m22[:, None, None]
    lam_n, vec_n = np.linalg.eigh(N[:, :9, :9])
    ok = lam_n[:, 0] * CONDITION_LIMIT > lam_n[:, -1]
    whiten = vec_n / np.sqrt(np.where(ok[:, None], np.maximum(lam_n, 1e-300), 1.0))[:, None, :]
    A = np.swapaxes(whiten, 1, 2) @ reduced @ whiten
    A = 0.5 * (A + np.swapaxes(A, 1, 2))
    y, unique = _smallest_eigenvector(A)
    c9 = np.einsum("bij,bj->bi", whiten, y)
    j = -np.einsum("bi,bi->b", m12, c9) / m22
    return np.concatenate([c9, j[:, None]], axis=1), ok & unique


def _to_world(coefficients: np.ndarray, transform: np.ndarray) -> np.ndarray:
    """Standard-frame coefficients -> input frame: Q = Tᵀ Q' T with x' = T x."""
    Q_standard = coefficients_to_matrix(coefficients)
    return matrix_to_coefficients(np.swapaxes(transform, 1, 2) @ Q_standard @ transform)
