"""Closed non-circular pitch curves and conjugate gear pairs (external and internal).

Maths only (numpy/scipy): no shapely, manifold3d or ezdxf here.
"""

from transplanter.geometry.pitch.curve import CurvatureExtreme, PitchCurve
from transplanter.geometry.pitch.pair import ConvexityIndex, GearPair, Mesh, ToothSizing, driven_axis, driven_turn
from transplanter.geometry.pitch.periodic import (
    Constant,
    EccentricCircle,
    FocalEllipse,
    FourierSeries,
    Periodic,
    PeriodicIntegral,
    PeriodicSpline,
)

__all__ = [
    "PitchCurve",
    "CurvatureExtreme",
    "GearPair",
    "Mesh",
    "ToothSizing",
    "ConvexityIndex",
    "Periodic",
    "Constant",
    "FourierSeries",
    "PeriodicSpline",
    "FocalEllipse",
    "EccentricCircle",
    "PeriodicIntegral",
    "driven_axis",
    "driven_turn",
]
