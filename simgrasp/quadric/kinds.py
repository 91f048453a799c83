"""The 17 quadric types (Olmsted's invariant classification) and the handle-shaped ones."""

from __future__ import annotations

from enum import StrEnum


class QuadricKind(StrEnum):
    """Type of a quadric surface f(x) = 0 (real or imaginary, proper or degenerate); a str."""

    REAL_ELLIPSOID = "real_ellipsoid"
    IMAGINARY_ELLIPSOID = "imaginary_ellipsoid"
    HYPERBOLOID_ONE_SHEET = "hyperboloid_one_sheet"
    HYPERBOLOID_TWO_SHEETS = "hyperboloid_two_sheets"
    REAL_CONE = "real_cone"
    IMAGINARY_CONE = "imaginary_cone"
    ELLIPTIC_PARABOLOID = "elliptic_paraboloid"
    HYPERBOLIC_PARABOLOID = "hyperbolic_paraboloid"
    REAL_ELLIPTIC_CYLINDER = "real_elliptic_cylinder"
    IMAGINARY_ELLIPTIC_CYLINDER = "imaginary_elliptic_cylinder"
    HYPERBOLIC_CYLINDER = "hyperbolic_cylinder"
    REAL_INTERSECTING_PLANES = "real_intersecting_planes"
    IMAGINARY_INTERSECTING_PLANES = "imaginary_intersecting_planes"
    PARABOLIC_CYLINDER = "parabolic_cylinder"
    REAL_PARALLEL_PLANES = "real_parallel_planes"
    IMAGINARY_PARALLEL_PLANES = "imaginary_parallel_planes"
    COINCIDENT_PLANES = "coincident_planes"


HANDLE_KINDS: frozenset[QuadricKind] = frozenset(
    {
        QuadricKind.REAL_ELLIPSOID,
        QuadricKind.HYPERBOLOID_ONE_SHEET,
        QuadricKind.REAL_ELLIPTIC_CYLINDER,
    }
)
"""Kinds that can describe a graspable handle (paper criterion (a))."""

CYLINDER_KINDS: frozenset[QuadricKind] = frozenset(
    {
        QuadricKind.REAL_ELLIPTIC_CYLINDER,
        QuadricKind.IMAGINARY_ELLIPTIC_CYLINDER,
        QuadricKind.HYPERBOLIC_CYLINDER,
    }
)
"""Kinds whose centers form a line (the axis) rather than a point."""
