"""Named tolerances, each with the reason for its value.

Tests and library code import these names instead of scattering literals.
"""

from __future__ import annotations

__all__ = [
    "LOOP_CLOSURE_MM",
    "ASSEMBLY_MARGIN",
    "DERIVATIVE_REL",
    "ANGLE_ROOT_RAD",
    "PITCH_CLOSURE_RAD",
    "PITCH_REFERENCE",
]

#: A four-bar loop solved in closed form closes to round-off: links of up to a few
#: metres in float64 leave ~1e-12 mm; 1e-9 mm leaves three decades of margin.
LOOP_CLOSURE_MM = 1e-9

#: Relative margin by which a triangle inequality must hold for a linkage to count
#: as assemblable at a crank angle. Below it the transmission angle is within
#: ~1e-4 rad of a toggle and velocities blow up, so the design is rejected.
ASSEMBLY_MARGIN = 1e-9

#: Analytic velocity/acceleration vs a 5-point central difference of the analytic
#: position with h = 1e-4 rad: truncation O(h^4) ~ 1e-16, round-off ~ eps/h ~ 1e-12,
#: so 1e-7 relative to the largest magnitude is a safe, still-sharp bound.
DERIVATIVE_REL = 1e-7

#: Crank angles of soil entry/exit and speed extremes are refined with scipy root
#: finders to this tolerance (1e-10 rad is 1e-8 mm of tip travel at 100 mm radius).
ANGLE_ROOT_RAD = 1e-10

#: A conjugate pitch curve must close: the driven rotation over one driver lobe may miss
#: 2π/n2 by at most this. The Gauss-Legendre integral is exact to ~1e-14 rad and brentq
#: solves the centre distance to ~1e-14 relative, so 1e-9 rad (1e-7 mm of pitch arc at
#: 100 mm) leaves five decades of margin and still rejects any real non-closing input.
PITCH_CLOSURE_RAD = 1e-9

#: Computed conjugates against closed forms or adaptive-quadrature references (mm, rad,
#: dimensionless ratio): both sides are round-off exact, so 1e-9 is a sharp bound.
PITCH_REFERENCE = 1e-9
