"""Quadric core: the 17 quadric types, batched classification and geometry, batched fitting
(Birdal normals-based, Taubin, algebraic) and surface meshes for plots."""

from simgrasp.quadric.analysis import DEFAULT_RTOL, QuadricAnalysis, analyze_quadrics
from simgrasp.quadric.fit import FAILURES, METHODS, QuadricFit, fit_quadrics
from simgrasp.quadric.kinds import HANDLE_KINDS, QuadricKind
from simgrasp.quadric.mesh import surface_mesh
from simgrasp.quadric.quadric import Quadric

__all__ = [
    "DEFAULT_RTOL",
    "FAILURES",
    "HANDLE_KINDS",
    "METHODS",
    "Quadric",
    "QuadricAnalysis",
    "QuadricFit",
    "QuadricKind",
    "analyze_quadrics",
    "fit_quadrics",
    "surface_mesh",
]
