"""Conversions between the 10 quadric coefficients and the symmetric 4x4 matrix Q.

f(x, y, z) = Ax² + By² + Cz² + 2Dxy + 2Exz + 2Fyz + 2Gx + 2Hy + 2Iz + J = [x 1] Q [x 1]ᵀ with
``Q = [[A, D, E, G], [D, B, F, H], [E, F, C, I], [G, H, I, J]]``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError

# Position in Q (row, col) of coefficients A..J (upper triangle).
_ROWS = np.array([0, 1, 2, 0, 0, 1, 0, 1, 2, 3])
_COLS = np.array([0, 1, 2, 1, 2, 2, 3, 3, 3, 3])


def coefficients_to_matrix(coefficients: ArrayLike) -> NDArray[np.float64]:
    """(..., 10) coefficients -> (..., 4, 4) symmetric matrices Q."""
    c = np.asarray(coefficients, dtype=np.float64)
    matrix = np.empty(c.shape[:-1] + (4, 4))
    matrix[..., _ROWS, _COLS] = c
    matrix[..., _COLS, _ROWS] = c
    return matrix


def matrix_to_coefficients(matrix: ArrayLike) -> NDArray[np.float64]:
    """(..., 4, 4) matrices Q -> (..., 10) coefficients, symmetrizing Q first."""
    m = np.asarray(matrix, dtype=np.float64)
    return 0.5 * (m[..., _ROWS, _COLS] + m[..., _COLS, _ROWS])


def validate_coefficient_rows(coefficients: ArrayLike, name: str = "coefficients") -> np.ndarray:
    """Return a (B, 10) float array or raise ValueError naming the wrong shape."""
    try:
        c = np.asarray(coefficients, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise SimgraspError(f"{name} must be numbers, shape (B, 10): {error}") from None
    if c.ndim != 2 or c.shape[1] != 10:
        raise SimgraspError(f"{name} must have shape (B, 10) [A..J], got {c.shape}")
    return c
