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
    "WIRE_EDM_TOLERANCE",
    "DXF_INSET_MM",
    "DXF_ARC_TOLERANCE_MM",
    "DXF_READBACK_MM",
    "SHOP_OVERLAP_MM2",
    "MESH_REFERENCE_MM",
    "SOLID_VOLUME_REL",
    "PENETRATION_TOL",
    "AREA_ROUND_OFF_MM2",
    "CONTACT_TOL_MM",
    "ONE_SIDED_MM",
    "READBACK_FLATTEN_MM",
    "ASSEMBLY_OVERLAP_MM3",
    "TIP_PATH_TOL_MM",
    "FOLLOWER_TOL",
    "CHORD_TOLERANCE",
    "MIN_CONTOUR_AREA",
    "FLAT_ARC_RADIUS_MM",
    "SPIKE_LENGTH",
    "ARC_RADIUS_MM",
    "REFINE_MM",
    "REFINE_RAD",
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

#: Default manufacturing tolerance of a made surface, ± mm normal to it: a wire-EDM shop
#: holds ±2-5 µm on contour (one skim cut); the larger value is the safe default. The
#: backlash of a shipped pair must survive it (``backlash.tolerance_budget``).
WIRE_EDM_TOLERANCE = 5e-3

#: The DXF arc fit is one-sided: every contour is first moved this far into the material
#: (mm), then fitted within DXF_ARC_TOLERANCE_MM, so the arcs lie 0.05-0.55 µm inside the
#: generated outline and never add material to it (where the outline is convex, as on the
#: flanks, its chords are already inside the exact envelope, so the arcs are inside that too).
DXF_INSET_MM = 0.3e-3

#: Arc-fit tolerance about the inset contour, mm (0.05 µm under the inset, for the sagitta of an arc
#: between the checked vertices and chord midpoints: the arcs stay 0.05-0.55 µm inside the source).
DXF_ARC_TOLERANCE_MM = 0.25e-3

#: A re-read DXF contour may lie at most this far from its source (both ways), mm: the 1 µm
#: flank budget.
DXF_READBACK_MM = 1e-3

#: Overlap (mm²) of a shipped pair's re-read parts at any meshing step: with designed
#: backlash the teeth never touch on both flanks, so anything above the polygon Booleans'
#: round-off (~1e-12 mm²) is interference.
SHOP_OVERLAP_MM2 = 1e-9

#: The closed-form meshing check (``validate.mesh_check``) against the root-finding one it
#: replaced (``tests/reference_meshing.py``), on contact arcs and backlash, mm: the new one is
#: exact for the polygons, the old one stopped its ``brentq`` at 1e-8 mm, so they differ by at
#: most about that (measured up to 9.3e-9 mm); 2e-8 mm is a sharp bound.
MESH_REFERENCE_MM = 2e-8

#: A made solid (STL mesh, STEP solid, 3MF body) must enclose its section's area × width within
#: this, relative: the STL's float32 vertices move a 100 mm part's surface by ~4e-6 mm, which
#: changes its volume by ~1e-7 relative; the STEP solid is exact to ~1e-12.
SOLID_VOLUME_REL = 1e-6

#: overlap (mm²) of two polygons reported as 0: the round-off of GEOS's Booleans on outlines of
#: ~100 mm (coordinates exact to ~1e-14 mm, areas to ~1e-12 mm²)
AREA_ROUND_OFF_MM2 = 1e-12

#: gap (mm) at which two flanks count as in contact in the meshing check: 2 µm — under the
#: wire-EDM tolerance, and eight chord tolerances, so the chords of one contact count once
CONTACT_TOL_MM = 2e-3

#: overlap area (mm²) that counts as interference: the outlines are exact to 0.25 µm chords,
#: so a zero-backlash pair overlaps by ~1e-4 mm² over a few teeth; real interference of a
#: module-0.4 tooth tip 10 µm deep is already ~3e-3 mm²
PENETRATION_TOL = 1e-3

#: re-read DXF points outside the part by more than this (mm) count as added material: float
#: round-off of the arc reconstruction is ~1e-12 mm
ONE_SIDED_MM = 1e-9

#: arcs of the re-read DXF are sampled to this chord (mm): what ``dxf.read_section`` uses for the
#: meshing check, a tenth of the arc fit's tolerance; the samples lie on the arcs exactly, so the
#: one-sided check is unaffected, and the read-back deviation is overstated by at most this
READBACK_FLATTEN_MM = 5e-5

#: Two parts of an assembly may share at most this volume (mm³): the meshes are exact to float
#: round-off, and the closest designed gap (backlash, ≥ 10 µm) leaves none at all.
ASSEMBLY_OVERLAP_MM3 = 1e-6

#: the tip path of the four-bar rebuilt from the plates' files may leave the designed one by
#: this much, mm: the 1 µm flank budget; the arcs re-read each centre to ~1e-9 mm
TIP_PATH_TOL_MM = 1e-3

#: largest follower error on the made cam, mm at the roller: what the shop may be off by
#: (``WIRE_EDM_TOLERANCE``), five times the profile's own chord and arc-fitting error (≲ 1 µm)
FOLLOWER_TOL = WIRE_EDM_TOLERANCE

#: Largest chord error of the generated outline against the exact envelope, mm (0.25 µm:
#: a quarter of the 1 µm flank budget, the rest is margin for the DXF arc fit).
CHORD_TOLERANCE = 0.25e-3

#: a closed contour enclosing less than this (mm²) is a degenerate sliver, not something to cut
MIN_CONTOUR_AREA = 1e-6

#: an arc of a larger radius (mm) — a nearly straight one the arc fit left — is written as the
#: exact rational B-spline of the arc: STEP files carry 13 significant digits, so such a circle's
#: centre would move by R·1e-13 (1 µm at 1e7 mm) and the arc's sagitta with it
FLAT_ARC_RADIUS_MM = 1e5

#: a back-turn (> 90°) on segments shorter than this (mm) is an envelope artefact where two pieces
#: meet (1.5 µm on a 20-tooth ellipse pair, 7.6 µm at a 17-tooth planet's root, 17 µm where an
#: 18-tooth shaper's fold undercuts a 12-tooth gear — kept, that needle hid the undercut and the
#: DXF's arcs could not follow it within 1 µm): a real tooth outline cannot turn back within
#: 25 µm (its smallest fillet radius is tens of µm; a pointed tooth is refused by its tip land)
SPIKE_LENGTH = 100 * CHORD_TOLERANCE

#: a DXF arc draws a hole or the nose when its radius is theirs within this, mm: the arcs are
#: inset 0.3 µm and fitted within 0.25 µm (``tolerances.DXF_INSET_MM``), the blends between the
#: nose and the finger's flanks differ by tens of µm
ARC_RADIUS_MM = 2e-3

#: The meshing proof refines every extreme of the free play and the clearance until the values
#: at the ends of the intervals beside it differ by less than this (mm): half the 1 µm to which a
#: stated backlash or clearance must be the true extreme.
REFINE_MM = 0.5e-3

#: ... or until those intervals are narrower than this (rad of driver turn): where the free play
#: jumps (a tip leaving a corner), its floor is taken from the continuous side, whose slope on
#: the shipped pairs is at most ~5 mm/rad, so 1e-5 rad leaves it within 0.05 µm.
REFINE_RAD = 1e-5
