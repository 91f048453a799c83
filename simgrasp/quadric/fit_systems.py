"""The numerical core of :func:`simgrasp.quadric.fit.fit_quadrics`, vectorized over one chunk of
neighborhoods: per-point feature rows of the standardized points, the moment sums, the flatness
tests, each method's small system and its batched solver, and the map back to the input frame
(the method is described in :mod:`simgrasp.quadric.fit`).
"""

from __future__ import annotations

import numpy as np

from simgrasp.quadric.coefficients import coefficients_to_matrix, matrix_to_coefficients

FLAT_TOL = 1e-12
"""A standardized neighborhood is collinear / coplanar when its second / smallest covariance
eigenvalue is below this (an RMS thickness below 1e-6 of the RMS radius)."""

CONDITION_LIMIT = 1e12
"""Largest accepted 1-norm condition number of the (equilibrated) fitting system, and the
smallest accepted ratio max/min of the eigen gap for the eigenvector methods."""


# Per-point features φ, one (B, K) plane each: u = [x², y², z², xy, xz, yz, x, y, z, 1] of the
# standardized point (0 at unused points; the monomial row is v = _MONOMIAL_SCALE u, and
# p̃ = [x, y, z, 1] the rows _X to _X + 3), then with normals ("birdal") the unit normal n (0
# where there is none) and the gradient-row weight w_n (1 at used points with a normal).
_X, _ONE, _NORMAL, _NORMAL_WEIGHT = 6, 9, 10, 13
_MONOMIAL_SCALE = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 1.0])


def features(
    pts: np.ndarray, nrm: np.ndarray | None, use: np.ndarray, count: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The (F, B, K) features φ of (B, K, 3) neighborhoods (F = 10, or 14 with normals), the
    (B, 4, 4) transforms T mapping input coordinates to standard ones (x' = T x) and the
    (B, 3) centroids in input coordinates. ``use`` (B, K) marks the points to fit, ``count``
    their number per neighborhood."""
    phi = np.empty((10 if nrm is None else 14,) + use.shape)
    transform, centroids = _standardize(pts, use, count, phi[_X : _X + 3])
    x, y, z = phi[_X : _X + 3]
    for row, (a, b) in enumerate(((x, x), (y, y), (z, z), (x, y), (x, z), (y, z))):
        np.multiply(a, b, out=phi[row])
    phi[_ONE] = use
    if nrm is not None:
        phi[_NORMAL_WEIGHT] = _unit_normals(nrm, use, phi[_NORMAL : _NORMAL + 3])
    return phi, transform, centroids


def _standardize(
    pts: np.ndarray, use: np.ndarray, count: np.ndarray, out: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Write the standard coordinates of (B, K, 3) neighborhoods (centroid 0 and RMS radius 1
    over the points in ``use``, 0 at the others) to ``out`` (3, B, K).

    Returns the (B, 4, 4) transform T mapping input coordinates to standard ones (x' = T x)
    and the (B, 3) centroids in input coordinates.
    """
    unused = ~use
    safe_count = np.maximum(count, 1)
    centered = pts.copy()
    centered[unused] = 0.0
    magnitude = np.max(np.abs(centered), axis=(1, 2), initial=0.0)
    magnitude = np.where(magnitude > 0, magnitude, 1.0)
    centered /= magnitude[:, None, None]
    centroid = np.einsum("bk,bki->bi", use.astype(np.float64), centered) / safe_count[:, None]
    centered -= centroid[:, None, :]
    centered[unused] = 0.0
    rms = np.sqrt(np.einsum("bki,bki->b", centered, centered) / safe_count)
    rms = np.where(rms > 0, rms, 1.0)
    np.divide(centered.transpose(2, 0, 1), rms[:, None], out=out)
    scale = 1.0 / (magnitude * rms)
    transform = np.zeros((len(pts), 4, 4))
    transform[:, [0, 1, 2], [0, 1, 2]] = scale[:, None]
    transform[:, :3, 3] = -centroid / rms[:, None]
    transform[:, 3, 3] = 1.0
    return transform, centroid * magnitude[:, None]


def _unit_normals(nrm: np.ndarray, use: np.ndarray, out: np.ndarray) -> np.ndarray:
    """Write the (B, K, 3) normals, made unit, to ``out`` (3, B, K) (0 at points not in ``use``
    and where a normal's length is 0 in floating point); return where there is a normal."""
    length = np.sqrt(np.einsum("bki,bki->bk", nrm, nrm))
    has_normal = use & (length > 0)
    np.copyto(out, nrm.transpose(2, 0, 1))
    out[:, ~use] = 0.0
    out /= np.where(has_normal, length, np.inf)
    return has_normal


def point_sums(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(B, F, G) sums Σ_k a_k b_kᵀ over each neighborhood's points of the per-point rows
    a (F, B, K) and b (G, B, K), one BLAS product per neighborhood."""
    return np.matmul(a.transpose(1, 0, 2), b.transpose(1, 2, 0))


def _normal_second_moments(gram: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(B, 4, 4) second moments Σ w_n p̃ p̃ᵀ over the points with a normal: the Gram matrices'
    Σ p̃ p̃ᵀ block where every used point has one."""
    w_n = phi[_NORMAL_WEIGHT]
    if np.array_equal(w_n, phi[_ONE]):
        return gram[:, _X : _X + 4, _X : _X + 4]
    # Per-point rows (B, K, 4): BLAS then sums in the Gram block's order, to the last bit.
    homogeneous = np.ascontiguousarray(phi[_X : _X + 4].transpose(1, 2, 0))
    weighted = homogeneous * w_n[:, :, None]
    return np.matmul(weighted.transpose(0, 2, 1), homogeneous)


_COVARIANCE_ROUNDOFF = 1e-14
"""Bound on the round-off of e2 and det computed from a covariance of trace 1 (entries at most
1 in magnitude)."""


def flatness(gram: np.ndarray, count: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(collinear, coplanar): whether the second smallest / smallest eigenvalue of each
    standardized covariance (its eigenvalues sum to 1) is not above FLAT_TOL.

    The eigenvalues λ0 ≤ λ1 ≤ λ2 are only computed where cheap lower bounds (less
    ``_COVARIANCE_ROUNDOFF``) do not already put both above 10 FLAT_TOL, far enough that
    computing them could not flag the neighborhood: with e2 = λ0λ1 + λ0λ2 + λ1λ2 (between
    λ1λ2 and 3 λ1λ2) and det = λ0λ1λ2, λ1 ≥ e2 / (3 trace) and λ0 ≥ det / e2.
    """
    cov = gram[:, _X : _X + 3, _X : _X + 3] / np.maximum(count, 1)[:, None, None]
    cov = np.where(np.isfinite(cov), cov, 0.0)
    (a, d, e), (_, b, f), (_, _, c) = cov.transpose(1, 2, 0)
    minor_a = b * c - f * f
    e2 = minor_a + (a * c - e * e) + (a * b - d * d)
    det = a * minor_a - d * (d * c - e * f) + e * (d * f - b * e)
    bound, error = 10 * FLAT_TOL, _COVARIANCE_ROUNDOFF
    clear = (e2 - error > 3 * bound * (a + b + c)) & (det - error > bound * (e2 + error))
    smallest = np.full((len(cov), 2), np.inf)
    smallest[~clear] = np.linalg.eigvalsh(cov[~clear])[:, :2]
    return ~(smallest[:, 1] > FLAT_TOL), ~(smallest[:, 0] > FLAT_TOL)


def _algebraic_matrix(gram: np.ndarray) -> np.ndarray:
    """M = Σ w v vᵀ (B, 10, 10) with f(p) = v(p) · [A..J]."""
    return gram[:, :10, :10] * (_MONOMIAL_SCALE[:, None] * _MONOMIAL_SCALE)


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


def _gradient_matrix(second_moments: np.ndarray) -> np.ndarray:
    """N = Σ w_g GᵀG (B, 10, 10) from the (B, 4, 4) second moments S = Σ w_g p̃ p̃ᵀ."""
    return (second_moments.reshape(-1, 16) @ _TO_NORMAL).reshape(-1, 10, 10)


def _normal_rows(phi: np.ndarray) -> np.ndarray:
    """(10, B, K) rows r(p) = G(p)ᵀ n (nᵀ∇f(p) = r(p) · [A..J]) of the standard coordinates
    and unit normals in the features ``phi`` (r = 0 where there is no normal)."""
    x, y, z = phi[_X : _X + 3]
    n = phi[_NORMAL : _NORMAL + 3]
    nx, ny, nz = n
    r = np.empty((10,) + x.shape)
    np.multiply(2 * x, nx, out=r[0])
    np.multiply(2 * y, ny, out=r[1])
    np.multiply(2 * z, nz, out=r[2])
    r[3] = 2 * (y * nx + x * ny)
    r[4] = 2 * (z * nx + x * nz)
    r[5] = 2 * (z * ny + y * nz)
    np.multiply(2, n, out=r[6:9])
    r[9] = 0.0
    return r


def birdal_system(
    gram: np.ndarray, phi: np.ndarray, weight: float, magnitude_weight: float
) -> tuple[np.ndarray, np.ndarray]:
    """Normal equations A c = rhs, (B, 10, 10) and (B, 10), of
    Σ (v·c)² + w Σ |P_t G c|² + w m Σ (nᵀG c - 1)² (P_t = I - n nᵀ).

    With r_p = Gᵀn: Σ |P_t G c|² = cᵀ(N - Σ r rᵀ)c and Σ (nᵀGc - 1)² = cᵀ(Σ r rᵀ)c - 2 cᵀΣ r + K,
    so for m = 1 (plain ∇f = n) the Σ r rᵀ terms cancel. Σ r = Σ Gᵀn is linear in Σ p̃ nᵀ.
    """
    A = _algebraic_matrix(gram) + weight * _gradient_matrix(_normal_second_moments(gram, phi))
    if magnitude_weight != 1.0:
        r = _normal_rows(phi)
        A += weight * (magnitude_weight - 1) * point_sums(r, r)
    C = point_sums(phi[_X : _X + 4], phi[_NORMAL : _NORMAL + 3])  # Σ p̃ nᵀ
    return A, weight * magnitude_weight * (C.reshape(-1, 12) @ _TO_RHS)


def solve_spd(A: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
    # Batch last, so that the substitution steps run over contiguous rows.
    solution = _cholesky_solve(np.ascontiguousarray(factor.transpose(1, 2, 0)), (d * rhs).T)
    return d * solution.T, ok


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


def _cholesky_solve(L: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve L Lᵀ x = rhs for batch-last lower-triangular L (n, n, B) and rhs (n, B)."""
    x = rhs.copy()
    n = len(L)
    for j in range(n):
        x[j] /= L[j, j]
        x[j + 1 :] -= L[j + 1 :, j] * x[j]
    for j in range(n - 1, -1, -1):
        x[j] /= L[j, j]
        x[:j] -= L[j, :j] * x[j]
    return x


def _smallest_eigenvector(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit eigenvector of the smallest eigenvalue of each symmetric matrix, and whether it is
    well separated from the second smallest (a unique solution)."""
    ok = np.all(np.isfinite(A), axis=(1, 2))
    A = np.where(ok[:, None, None], A, np.eye(A.shape[1]))
    lam, vec = np.linalg.eigh(A)
    top = np.max(np.abs(lam), axis=1)
    ok &= (lam[:, 1] - lam[:, 0]) * CONDITION_LIMIT > top
    return vec[:, :, 0], ok


def algebraic(gram: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return _smallest_eigenvector(_algebraic_matrix(gram))


def taubin(gram: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    M = _algebraic_matrix(gram)
    N = _gradient_matrix(gram[:, _X : _X + 4, _X : _X + 4])  # from Σ w p̃ p̃ᵀ
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


def to_world(coefficients: np.ndarray, transform: np.ndarray) -> np.ndarray:
    """Standard-frame coefficients -> input frame: Q = Tᵀ Q' T with x' = T x."""
    Q_standard = coefficients_to_matrix(coefficients)
    return matrix_to_coefficients(np.swapaxes(transform, 1, 2) @ Q_standard @ transform)
