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

CHUNK = 1024
"""Neighborhoods fitted per vectorized step (keeps the working arrays in cache)."""

FLAT_TOL = 1e-12
"""A standardized neighborhood is collinear / coplanar when its second / smallest covariance
eigenvalue is below this (an RMS thickness below 1e-6 of the RMS radius)."""

CONDITION_LIMIT = 1e12
"""Largest accepted 1-norm condition number of the (equilibrated) fitting system, and the
smallest accepted ratio max/min of the eigen gap for the eigenvector methods."""

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
        raise ValueError(f"fit_quadrics: unknown method {method!r}; use one of {METHODS}")
    if method == "birdal" and normals is None:
        raise ValueError("fit_quadrics: method 'birdal' needs normals (one per point)")
    for name, value in (
        ("gradient_weight", gradient_weight),
        ("magnitude_weight", magnitude_weight),
    ):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"fit_quadrics: {name} must be > 0, got {value!r}")
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
    mw: float,
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

    coefficients = np.full((batch, 10), np.nan)
    centroids = np.zeros((batch, 3))
    for start in range(0, batch, CHUNK):
        chunk = slice(start, start + CHUNK)
        w = weights[chunk]
        chunk_pts = np.where(w[:, :, None] > 0, pts[chunk], 0.0)
        standard, standard_T_input, centroids[chunk] = _standardize(chunk_pts, w, count[chunk])
        spread = _spread(standard, count[chunk])
        flags = failure[chunk]  # a view: flags set here land in ``failure``
        flags[(flags == None) & ~(spread[:, 1] > FLAT_TOL)] = "collinear"  # noqa: E711
        flags[(flags == None) & ~(spread[:, 0] > FLAT_TOL)] = "coplanar"  # noqa: E711
        local = np.flatnonzero(flags == None)  # noqa: E711
        if len(local) == 0:
            continue
        idx = start + local
        fitted, ok = _fit_standard(standard[local], w[local], nrm, idx, method, weight, mw)
        world = _to_world(fitted, standard_T_input[local])
        ok &= np.all(np.isfinite(world), axis=1) & np.any(world[:, :6] != 0, axis=1)
        coefficients[idx[ok]] = world[ok]
        failure[idx[~ok]] = "ill_conditioned"
    valid_fit = failure == None  # noqa: E711
    return QuadricFit(coefficients, valid_fit, tuple(failure.tolist()), method, centroids)


def _fit_standard(
    std_pts: np.ndarray,
    w: np.ndarray,
    nrm: np.ndarray | None,
    idx: np.ndarray,
    method: str,
    weight: float,
    magnitude_weight: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Fit one chunk of standardized neighborhoods: (coefficients, ok) in the standard frame."""
    if method == "taubin":
        return _taubin(std_pts, w)
    if method == "algebraic":
        return _algebraic(std_pts, w)
    n = np.where(w[:, :, None] > 0, nrm[idx], 0.0)
    length = np.sqrt(np.einsum("bki,bki->bk", n, n))
    has_normal = length > 0
    n /= np.where(has_normal, length, 1.0)[:, :, None]
    return _birdal(std_pts, n, w, w * has_normal, weight, magnitude_weight)


def _standardize(
    pts: np.ndarray, weights: np.ndarray, count: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points in each neighborhood's standard frame (centroid 0, RMS radius 1), the (B, 4, 4)
    transform T mapping input coordinates to standard ones (x' = T x) and the (B, 3)
    centroids in input coordinates."""
    safe_count = np.maximum(count, 1)
    magnitude = np.max(np.abs(pts), axis=(1, 2), initial=0.0)
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


def _spread(standard: np.ndarray, count: np.ndarray) -> np.ndarray:
    """(B, 3) ascending eigenvalues of the standardized covariance (they sum to 1)."""
    cov = np.matmul(np.swapaxes(standard, 1, 2), standard) / np.maximum(count, 1)[:, None, None]
    cov = np.where(np.isfinite(cov), cov, 0.0)
    return np.linalg.eigvalsh(cov)


def _monomials(p: np.ndarray) -> np.ndarray:
    """(B, K, 10) rows v(p) with f(p) = v(p) · [A..J]."""
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    v = np.empty(p.shape[:-1] + (10,))
    np.multiply(x, x, out=v[..., 0])
    np.multiply(y, y, out=v[..., 1])
    np.multiply(z, z, out=v[..., 2])
    np.multiply(2 * x, y, out=v[..., 3])
    np.multiply(2 * x, z, out=v[..., 4])
    np.multiply(2 * y, z, out=v[..., 5])
    np.multiply(2, p, out=v[..., 6:9])
    v[..., 9] = 1.0
    return v


def _normal_rows(p: np.ndarray, n: np.ndarray) -> np.ndarray:
    """(B, K, 10) rows r(p) = G(p)ᵀ n with nᵀ∇f(p) = r(p) · [A..J]."""
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    nx, ny, nz = n[..., 0], n[..., 1], n[..., 2]
    r = np.empty(p.shape[:-1] + (10,))
    np.multiply(2 * x, nx, out=r[..., 0])
    np.multiply(2 * y, ny, out=r[..., 1])
    np.multiply(2 * z, nz, out=r[..., 2])
    r[..., 3] = 2 * (y * nx + x * ny)
    r[..., 4] = 2 * (z * nx + x * nz)
    r[..., 5] = 2 * (z * ny + y * nz)
    np.multiply(2, n, out=r[..., 6:9])
    r[..., 9] = 0.0
    return r


# ∂f/∂x_d = 2 Σ_a p̃_a c[_GRAD_INDEX[d, a]] with p̃ = [x, y, z, 1] (G(p) = ∂(∇f)/∂c).
_GRAD_INDEX = np.array([[0, 3, 4, 6], [3, 1, 5, 7], [4, 5, 2, 8]])


def _gradient_operators() -> tuple[np.ndarray, np.ndarray]:
    """Linear maps from second moments S = Σ p̃ p̃ᵀ (16) to Σ GᵀG (100), and from the cross
    moments C = Σ p̃ nᵀ (12) to Σ Gᵀn (10)."""
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
    """M = Σ w v vᵀ (B,10,10), N = Σ w_g GᵀG (B,10,10) and the weighted p̃ w_g (B,K,4)."""
    v = _monomials(p) * np.sqrt(w)[:, :, None]
    M = np.matmul(np.swapaxes(v, 1, 2), v)
    ph = _homogeneous(p)
    ph_weighted = ph * w_grad[:, :, None]
    S = np.matmul(np.swapaxes(ph_weighted, 1, 2), ph)
    N = (S.reshape(-1, 16) @ _TO_NORMAL).reshape(-1, 10, 10)
    return M, N, ph_weighted


def _birdal(
    p: np.ndarray,
    n: np.ndarray,
    w: np.ndarray,
    w_grad: np.ndarray,
    weight: float,
    magnitude_weight: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Normal equations of Σ (v·c)² + w Σ |P_t G c|² + w m Σ (nᵀG c - 1)² (P_t = I - n nᵀ).

    With r_p = Gᵀn: Σ |P_t G c|² = cᵀ(N - Σ r rᵀ)c and Σ (nᵀGc - 1)² = cᵀ(Σ r rᵀ)c - 2 cᵀΣ r + K,
    so for m = 1 (plain ∇f = n) the Σ r rᵀ terms cancel.
    """
    M, N, ph_weighted = _moments(p, w, w_grad)
    A = M + weight * N
    if magnitude_weight != 1.0:
        r = _normal_rows(p, n) * np.sqrt(w_grad)[:, :, None]
        A += weight * (magnitude_weight - 1) * np.matmul(np.swapaxes(r, 1, 2), r)
    C = np.matmul(np.swapaxes(ph_weighted, 1, 2), n)
    rhs = weight * magnitude_weight * (C.reshape(-1, 12) @ _TO_RHS)
    return _solve_spd(A, rhs)


def _solve_spd(A: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve batched symmetric positive (semi)definite systems with Jacobi equilibration.

    A system is ill-conditioned when a Cholesky pivot of the equilibrated matrix (unit
    diagonal) is below 1 / CONDITION_LIMIT, or the factorization fails.
    """
    diag = np.einsum("bii->bi", A)
    ok = np.all(diag > 0, axis=1) & np.all(np.isfinite(A), axis=(1, 2))
    d = 1.0 / np.sqrt(np.where(ok[:, None], diag, 1.0))
    A_eq = A * d[:, :, None] * d[:, None, :]
    A_eq[~ok] = np.eye(A.shape[1])
    factor = _batched_cholesky(A_eq, ok)
    pivots = np.einsum("bii->bi", factor) ** 2
    ok &= np.min(pivots, axis=1) * CONDITION_LIMIT > 1.0
    A_eq[~ok] = np.eye(A.shape[1])
    solution = d * np.linalg.solve(A_eq, (d * rhs)[:, :, None])[:, :, 0]
    return solution, ok


def _batched_cholesky(A: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """Cholesky factors; matrices that are not positive definite (rare) are marked not ok."""
    try:
        return np.linalg.cholesky(A)
    except np.linalg.LinAlgError:
        factor = np.empty_like(A)
        for i, matrix in enumerate(A):
            try:
                factor[i] = np.linalg.cholesky(matrix)
            except np.linalg.LinAlgError:
                factor[i] = np.eye(len(matrix))
                ok[i] = False
        return factor


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
