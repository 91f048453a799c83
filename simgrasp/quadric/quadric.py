"""One quadric surface f(x) = 0 with its type and canonical geometry.

The geometry comes from :func:`simgrasp.quadric.analysis.analyze_quadrics` with B = 1, so a
single quadric and a batch are analysed by the same code. Lengths are in the units of the frame
the coefficients are expressed in.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.quadric.analysis import DEFAULT_RTOL, QuadricAnalysis, analyze_quadrics
from simgrasp.quadric.coefficients import (
    coefficients_to_matrix,
    matrix_to_coefficients,
    validate_coefficient_rows,
)
from simgrasp.quadric.kinds import CYLINDER_KINDS, HANDLE_KINDS, QuadricKind
from simgrasp.transforms import invert_transform

RIGID_TOLERANCE = 1e-6
"""Tolerance on RᵀR = I, det R = 1 and the last row [0, 0, 0, 1] of a rigid transform."""


@lru_cache(maxsize=16)
def _rigid_inverse(transform: bytes) -> NDArray[np.float64]:
    """The inverse of the finite 4x4 transform given as its float64 bytes (row-major), read
    only; a one-line error when it is not rigid. Cached, so that the checks run once per
    transform when one moves many quadrics (every candidate of a detection)."""
    T = np.frombuffer(transform, dtype=np.float64).reshape(4, 4)
    R = T[:3, :3]
    rigid = (
        np.allclose(R.T @ R, np.eye(3), atol=RIGID_TOLERANCE)
        and abs(np.linalg.det(R) - 1) <= RIGID_TOLERANCE
        and np.allclose(T[3], [0, 0, 0, 1], atol=RIGID_TOLERANCE)
    )
    if not rigid:
        raise SimgraspError(
            "transform must be rigid (orthonormal rotation with det +1, last row 0 0 0 1)"
        )
    inverse = invert_transform(T)
    inverse.setflags(write=False)
    return inverse


@dataclass(frozen=True, eq=False)
class Quadric:
    """f(x, y, z) = Ax² + By² + Cz² + 2Dxy + 2Exz + 2Fyz + 2Gx + 2Hy + 2Iz + J.

    Attributes:
        coefficients: (10,) ``[A, B, C, D, E, F, G, H, I, J]`` (read-only float array).
        rtol: relative tolerance for every rank / zero decision of the classification
            (see :mod:`simgrasp.quadric.analysis`); loosen it (e.g. 1e-2) for fitted quadrics.
        reference_point: (3,) point where a quadric singular within ``rtol`` is read (its
            cylinder cross-section and reported axis point), or None for the origin; for a
            fitted neighborhood use its centroid. Irrelevant for exact quadrics.
    """

    coefficients: NDArray[np.float64]
    rtol: float = DEFAULT_RTOL
    reference_point: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        try:
            c = np.array(self.coefficients, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError) as error:
            raise SimgraspError(f"quadric coefficients must be 10 numbers: {error}") from None
        if c.shape != (10,):
            raise SimgraspError(f"quadric coefficients must be 10 numbers [A..J], got {c.size}")
        if not np.all(np.isfinite(c)):
            raise SimgraspError(f"quadric coefficients must be finite, got {c.tolist()}")
        if not np.any(c[:6]):
            raise SimgraspError(
                "quadric coefficients: the quadratic part A..F is all zero (a plane, not a quadric)"
            )
        if not (np.isfinite(self.rtol) and 0 < self.rtol < 1):
            raise SimgraspError(f"quadric rtol must be in (0, 1), got {self.rtol!r}")
        c.setflags(write=False)
        object.__setattr__(self, "coefficients", c)
        if self.reference_point is not None:
            reference = np.array(self.reference_point, dtype=np.float64)
            if reference.shape != (3,) or not np.all(np.isfinite(reference)):
                raise SimgraspError(
                    f"quadric reference_point must be one finite 3-D point, got {reference!r}"
                )
            reference.setflags(write=False)
            object.__setattr__(self, "reference_point", reference)

    @classmethod
    def from_coefficients(
        cls,
        coefficients: ArrayLike,
        rtol: float = DEFAULT_RTOL,
        reference_point: ArrayLike | None = None,
    ) -> Quadric:
        """Validated quadric from ``[A..J]`` (ValueError on wrong count, non-finite values or an
        all-zero quadratic part)."""
        return cls(
            np.asarray(coefficients), rtol=rtol, reference_point=_point_or_none(reference_point)
        )

    @classmethod
    def batch(
        cls,
        coefficients: ArrayLike,
        rtol: float = DEFAULT_RTOL,
        reference_points: ArrayLike | None = None,
    ) -> tuple[Quadric, ...]:
        """One quadric per row of (B, 10) ``coefficients``, with the (B, 3)
        ``reference_points`` if given: the constructor's checks run once on the whole batch
        (ValueError naming the first bad row), so a detector's hundreds of fits cost no more
        than one array copy each."""
        rows = validate_coefficient_rows(coefficients).copy()
        references = None
        if reference_points is not None:
            references = np.array(reference_points, dtype=np.float64)
            if references.shape != (len(rows), 3):
                raise SimgraspError(
                    f"reference_points must have shape ({len(rows)}, 3), got {references.shape}"
                )
            references.setflags(write=False)
        bad = ~np.isfinite(rows).all(axis=1) | ~rows[:, :6].any(axis=1)
        if references is not None:
            bad |= ~np.isfinite(references).all(axis=1)
        if len(rows):
            first = int(np.argmax(bad))  # the first bad row, or row 0 (then only rtol is checked)
            try:
                cls(rows[first], rtol, None if references is None else references[first])
            except ValueError as error:
                raise SimgraspError(f"row {first}: {error}") from None
        rows.setflags(write=False)
        quadrics = []
        for row in range(len(rows)):
            quadric = object.__new__(cls)
            object.__setattr__(quadric, "coefficients", rows[row])
            object.__setattr__(quadric, "rtol", rtol)
            object.__setattr__(
                quadric, "reference_point", None if references is None else references[row]
            )
            quadrics.append(quadric)
        return tuple(quadrics)

    @classmethod
    def from_matrix(
        cls,
        matrix: ArrayLike,
        rtol: float = DEFAULT_RTOL,
        reference_point: ArrayLike | None = None,
    ) -> Quadric:
        """Quadric from a 4x4 matrix Q with f(x) = [x 1] Q [x 1]ᵀ (symmetrized)."""
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape != (4, 4):
            raise SimgraspError(f"quadric matrix must be 4x4, got shape {m.shape}")
        return cls(
            matrix_to_coefficients(m), rtol=rtol, reference_point=_point_or_none(reference_point)
        )

    @property
    def Q(self) -> NDArray[np.float64]:  # noqa: N802 - the standard symbol
        """The symmetric 4x4 matrix with f(x) = [x 1] Q [x 1]ᵀ."""
        return coefficients_to_matrix(self.coefficients)

    @property
    def q(self) -> NDArray[np.float64]:
        """The 3x3 quadratic part."""
        return self.Q[:3, :3]

    def evaluate(self, points: ArrayLike) -> NDArray[np.float64] | float:
        """f at (N, 3) points -> (N,), or at one (3,) point -> float (algebraic residual)."""
        pts, single = _points(points, "evaluate")
        Q = self.Q
        values = np.einsum("ni,ij,nj->n", pts, Q[:3, :3], pts) + 2 * pts @ Q[:3, 3] + Q[3, 3]
        return float(values[0]) if single else values

    def gradient(self, points: ArrayLike) -> NDArray[np.float64]:
        """∇f = 2 (q x + g) at (N, 3) points -> (N, 3), or at one (3,) point -> (3,)."""
        pts, single = _points(points, "gradient")
        Q = self.Q
        grads = 2 * (pts @ Q[:3, :3] + Q[:3, 3])
        return grads[0] if single else grads

    def transformed(self, transform: ArrayLike) -> Quadric:
        """The quadric moved by the rigid 4x4 ``transform`` T (new_T_old).

        If f(x) = 0 then the result g satisfies g(T x) = 0: Q' = T⁻ᵀ Q T⁻¹. The reference
        point, if any, moves with T.
        """
        T = np.asarray(transform, dtype=np.float64)
        if T.shape != (4, 4) or not np.all(np.isfinite(T)):
            raise SimgraspError(f"transform must be a finite 4x4 matrix, got shape {T.shape}")
        R = T[:3, :3]
        inverse = _rigid_inverse(np.ascontiguousarray(T).tobytes())
        reference = None
        if self.reference_point is not None:
            reference = R @ self.reference_point + T[:3, 3]
        return Quadric.from_matrix(
            inverse.T @ self.Q @ inverse, rtol=self.rtol, reference_point=reference
        )

    @cached_property
    def _analysis(self) -> QuadricAnalysis:
        return analyze_quadrics(
            self.coefficients[None], rtol=self.rtol, reference_points=self.reference_point
        )

    @property
    def kind(self) -> QuadricKind:
        """The quadric's type (Olmsted's 17-type table)."""
        return self._analysis.kinds[0]

    @property
    def center(self) -> NDArray[np.float64]:
        """(3,) center; for cylinders the axis point nearest the reference point (default: the
        origin), for paraboloids the vertex (see :mod:`simgrasp.quadric.analysis`)."""
        return self._analysis.centers[0].copy()

    @property
    def axes(self) -> NDArray[np.float64]:
        """(3, 3) principal directions as unit rows, by decreasing |eigenvalue| of q."""
        return self._analysis.axes[0].copy()

    @property
    def semi_axes(self) -> NDArray[np.float64]:
        """(3,) semi-axes aligned with ``axes`` rows; inf where unbounded, NaN if undefined."""
        return self._analysis.semi_axes[0].copy()

    @property
    def eigenvalues(self) -> NDArray[np.float64]:
        """(3,) eigenvalues of q aligned with ``axes`` (equation scaled so max |coef| = 1 and
        signed so that the canonical constant is <= 0; zero where counted as zero)."""
        return self._analysis.eigenvalues[0].copy()

    @property
    def handle_axis(self) -> NDArray[np.float64]:
        """(3,) unit handle direction: cylinder axis, hyperboloid conjugate axis, ellipsoid
        longest axis. ValueError for other kinds."""
        self._require_handle("handle_axis")
        return self._analysis.handle_axes[0].copy()

    @property
    def transverse_semi_axes(self) -> NDArray[np.float64]:
        """(2,) the semi-axes perpendicular to ``handle_axis``, ascending (handle kinds)."""
        self._require_handle("transverse_semi_axes")
        return self._analysis.transverse_semi_axes[0].copy()

    def distance_to_center(self, point: ArrayLike) -> float:
        """Distance from ``point`` (3,) to the center; for cylinder kinds, to the axis line."""
        p = np.asarray(point, dtype=np.float64)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise SimgraspError(f"distance_to_center needs one finite 3-D point, got {p!r}")
        offset = p - self.center
        if self.kind in CYLINDER_KINDS:
            axis = self.axes[2]
            offset = offset - (offset @ axis) * axis
        return float(np.linalg.norm(offset))

    def _require_handle(self, name: str) -> None:
        if self.kind not in HANDLE_KINDS:
            raise SimgraspError(
                f"{name} is defined for handle kinds "
                f"({', '.join(sorted(k.value for k in HANDLE_KINDS))}), not {self.kind.value}"
            )

    def __repr__(self) -> str:
        coefficients = np.array2string(self.coefficients, precision=4, separator=", ")
        return f"Quadric({coefficients}, rtol={self.rtol:g})"


def _points(points: ArrayLike, name: str) -> tuple[np.ndarray, bool]:
    pts = np.asarray(points, dtype=np.float64)
    single = pts.shape == (3,)
    pts = pts.reshape(1, 3) if single else pts
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise SimgraspError(f"{name}: points must have shape (N, 3) or (3,), got {pts.shape}")
    return pts, single


def _point_or_none(point: ArrayLike | None) -> NDArray[np.float64] | None:
    return None if point is None else np.asarray(point, dtype=np.float64)
