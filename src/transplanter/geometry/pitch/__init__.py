"""Closed non-circular pitch curves and conjugate gear pairs (external and internal).

:mod:`~transplanter.geometry.pitch.periodic` (periodic functions: Fourier series, splines, the
named curves), :mod:`~transplanter.geometry.pitch.curve` (a closed curve r(φ) and its tangent,
curvature, arc length, pressure angle), :mod:`~transplanter.geometry.pitch.pair` (the conjugate
curve, centre distance, tooth sizing), :mod:`~transplanter.geometry.pitch.arcframe` (a curve by
arc length, the frame cutters roll in), :mod:`~transplanter.geometry.pitch.transmission` (a pair
from an expression, ratio samples or a named curve) and
:mod:`~transplanter.geometry.pitch.intermittent` (laws of dwells and motions, incomplete pairs).

Takes
    radii in mm, angles in rad, ratios ω2/ω1.
Gives
    frozen curves and pairs, evaluated from their exact definition (no polylines).
May import
    :mod:`transplanter.core` only. Maths only (numpy/scipy): no shapely, manifold3d or ezdxf here.
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
