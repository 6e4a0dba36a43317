"""Interference of internal (ring/pinion) pairs from the closed-form limits of circular gear theory.

A ring gear meshing with a pinion (a planet) can fail in ways the pitch curves do not show,
all known in closed form for circular gears (e.g. KHK's Gear Technical Reference, Colbourne
ch. 9, Litvin & Fuentes §10):

- **fillet interference** — the ring's tips reach below the pinion's *form circle*, the
  lowest point of its involute that the shaper cutter generated (below it is the trochoid
  fillet); the classic involute interference (tips past the pinion's base-circle tangency
  point N1) is its limit for a sharp, infinitely small cutter;
- **the pinion's tips in the ring's fillet** — the same at the other end of the path of contact;
- **trochoid interference** — the pinion's tip corner, moving on a trochoid relative to the
  ring, cuts the ring's tips as it leaves the mesh (small tooth-count differences):
  ``θ1 z1/z2 + inv α_w − inv α_a2 − θ2 ≥ 0``;
- **trimming interference** — a pinion pushed in *radially* trims the ring's teeth:
  ``θ1 + inv α_a1 − inv α_w − (z2/z1)(θ2 + inv α_a2 − inv α_w) ≥ 0``; an axially assembled
  pair does not care, so this one is reported as an assembly constraint;
- **ring tips trimmed by the cutter** — the ring's tip beyond the cutter's base-circle
  tangency N0 is cut by the cutter's non-involute flank (a standard ring z = 60 cut by a
  z0 = 20 cutter sits at this limit: 58.02 mm against a 58 mm tip);
- a **contact ratio** below 1 (the teeth would let go).

**Along a non-circular pitch curve** each meshing position is an equivalent circular pair:
the ring's and the pinion's pitch radii are the radii of curvature of their pitch curves at
the contact (equivalent tooth counts ``z = 2ρ/m``), the pressure angle is the cutter's (the
teeth are involutes of the local equivalent base circles), and the cutter is circular. The
checks run at every position; where the ring's pitch curve is locally straight or concave
the pair is locally external (or a rack) and the internal limits do not apply there.

The remedy these limits give in closed form is **ring-tip trimming**: the largest ring
addendum that keeps the ring's tips above the pinion's form point and inside the cutter's
involute at every position (then trochoid interference and the contact ratio are checked
with it); or a **cutter with fewer teeth**, whose shallower form circle frees the pinion's
flank.

numpy only (no shapely), so the optimiser can screen designs with it.

Examples
--------
A standard ring z = 60 and pinion z = 30, both cut by a 20-tooth shaper (m = 2): the ring's
tips reach into the pinion's fillet, and a ring addendum of 0.785 m clears it.

>>> import math
>>> from transplanter.geometry.interference import circular_internal
>>> lim = circular_internal(60, 30, 2.0, cutter_teeth=20)
>>> lim.problems()[0].startswith("fillet interference")
True
>>> round(lim.max_ring_addendum, 3)
0.785
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.ndimage import maximum_filter1d

from transplanter.core.errors import GeometryError, SpecError
from transplanter.geometry.cutter import ShaperCutter

__all__ = [
    "InternalLimits",
    "internal_limits",
    "circular_internal",
    "pair_limits",
    "screen_module",
    "fouling_screen",
    "ScreenResult",
    "MIN_CONTACT_RATIO",
    "TRIM_MARGIN",
    "trimmed_addendum",
]

#: a contact ratio below this leaves moments with a single tooth pair barely in contact; 1.1 is
#: the usual design floor for spur gears (below 1 the teeth let go)
MIN_CONTACT_RATIO = 1.1
#: ring tips are trimmed this far (modules) under the closed-form limit: the limits are exact for
#: the equivalent circular pairs, the margin covers the curvature sampled between positions
TRIM_MARGIN = 0.02


def _inv(a):
    return np.tan(a) - a


@dataclass(frozen=True)
class InternalLimits:
    """Margins of the closed-form limits at each evaluated meshing position (arrays).

    Lengths are along the line of action (mm); a margin < 0 is a violation. Positions where
    the pair is not locally internal carry NaN and are ignored.
    """

    driver_angle: np.ndarray = field(repr=False)
    #: ring tip above the pinion's form point (fillet interference), mm
    fillet: np.ndarray = field(repr=False)
    #: pinion tip below the ring's form point, mm
    pinion_tip: np.ndarray = field(repr=False)
    #: ring tip inside the cutter's involute (N0), mm
    cutter_trim: np.ndarray = field(repr=False)
    #: trochoid interference, rad
    trochoid: np.ndarray = field(repr=False)
    #: trimming interference on radial assembly, rad
    trimming: np.ndarray = field(repr=False)
    contact_ratio: np.ndarray = field(repr=False)
    #: largest ring addendum (modules) clearing fillet and cutter-trim limits at each position
    ring_addendum_limit: np.ndarray = field(repr=False)
    #: largest pinion addendum (modules) keeping its tips off the ring's fillet
    pinion_addendum_limit: np.ndarray = field(repr=False)
    ring_addendum: float = 1.0
    pinion_addendum: float = 1.0
    module: float = 1.0

    @property
    def max_ring_addendum(self) -> float:
        return float(np.nanmin(self.ring_addendum_limit))

    @property
    def max_pinion_addendum(self) -> float:
        return float(np.nanmin(self.pinion_addendum_limit))

    @property
    def min_contact_ratio(self) -> float:
        return float(np.nanmin(self.contact_ratio))

    @property
    def radial_assembly(self) -> bool:
        """True if the pinion can be put into the ring radially everywhere (no trimming)."""
        return bool(np.nanmin(self.trimming) >= 0)

    def _worst(self, values) -> tuple[float, float]:
        """The least value and the driver angle (deg) where it first occurs: values tied to within
        rounding (once per lobe) are one tie — ``nanargmin`` took whichever the last ulp favoured,
        which differs between processors (seed 004's ring: 88° on one, 178° on another)."""
        values = np.asarray(values, dtype=float)
        least = float(np.nanmin(values))
        k = int(np.flatnonzero(values <= least + 1e-12 * max(1.0, abs(least)))[0])
        return float(values[k]), math.degrees(float(self.driver_angle[k]))

    def problems(
        self,
        names: tuple[str, str] = ("ring", "pinion"),
        min_contact_ratio: float = MIN_CONTACT_RATIO,
        trochoid: bool = True,
    ) -> list[str]:
        """What interferes, where, and the remedy, in words (empty when clear).

        Radial-assembly trimming is not a problem here (see :attr:`radial_assembly`); a contact
        ratio below ``min_contact_ratio`` is (1: only where the teeth let go). ``trochoid`` False
        leaves out the trochoid limit (exact for circular gears; along non-circular curves the
        screen leaves it to the full check, see :func:`fouling_screen`).
        """
        ring, pinion = names
        m = self.module
        out = []
        v, at = self._worst(self.fillet)
        if v < 0:
            out.append(
                f"fillet interference: the {ring}'s tooth tips reach {-v:.3g} mm (along the line of action) below the "
                f"{pinion}'s form circle at driver angle {at:.1f} deg; ring addendum {self.ring_addendum:g} m must be "
                f"<= {self.max_ring_addendum:.3f} m (ring-tip trimming)"
            )
        v, at = self._worst(self.cutter_trim)
        if v < 0 and not out:
            out.append(
                f"the {ring}'s tips lie {-v:.3g} mm beyond the cutter's involute at driver angle {at:.1f} deg (the "
                f"cutter trims them); ring addendum must be <= {self.max_ring_addendum:.3f} m"
            )
        v, at = self._worst(self.pinion_tip)
        if v < 0:
            out.append(
                f"the {pinion}'s tips reach {-v:.3g} mm into the {ring}'s fillet at driver angle {at:.1f} deg; "
                f"{pinion} addendum {self.pinion_addendum:g} m must be <= {self.max_pinion_addendum:.3f} m"
            )
        v, at = self._worst(self.trochoid)
        if v < 0 and trochoid:
            out.append(
                f"trochoid interference: the {pinion}'s tip corners cut the {ring}'s tips when leaving mesh "
                f"(margin {v:.3g} rad at driver angle {at:.1f} deg); the tooth-count difference is too small for "
                "these addenda — shorten the ring's tips further or increase the difference"
            )
        v, at = self._worst(self.contact_ratio)
        if v < min_contact_ratio:
            out.append(
                f"contact ratio {v:.3f} at driver angle {at:.1f} deg is below {min_contact_ratio:g} (limit): the teeth "
                f"are too short for this mesh ({ring} addendum {self.ring_addendum:g} m, {pinion} "
                f"{self.pinion_addendum:g} m, m = {m:g} mm)"
            )
        return out


def internal_limits(
    ring_radius,
    pinion_radius,
    module: float,
    *,
    pressure_angle: float = math.radians(20.0),
    ring_addendum: float = 1.0,
    pinion_addendum: float = 1.0,
    cutter_radius: float,
    cutter_roll: float,
    ring_shift: float = 0.0,
    pinion_shift: float = 0.0,
    driver_angle=None,
) -> InternalLimits:
    """Closed-form limits of internal pairs with pitch radii ``ring_radius`` > ``pinion_radius``
    (arrays, mm: circular gears, or the local radii of curvature of non-circular pitch curves).

    Both gears are cut by a shaper cutter of pitch radius ``cutter_radius`` whose involute ends
    ``cutter_roll`` mm of roll from its base circle (``ShaperCutter.involute_end_roll``);
    addenda and shifts in modules; a ring's tips are ``(ring_addendum + ring_shift) m`` inside
    its pitch circle.
    """
    m = float(module)
    alpha = float(pressure_angle)
    r2 = np.atleast_1d(np.asarray(ring_radius, dtype=float))
    r1 = np.broadcast_to(np.asarray(pinion_radius, dtype=float), r2.shape).astype(float)
    ok = np.isfinite(r2) & np.isfinite(r1) & (r2 > r1) & (r1 > 0)
    r2 = np.where(ok, r2, np.nan)
    r1 = np.where(ok, r1, np.nan)
    ca, sa = math.cos(alpha), math.sin(alpha)
    rb1, rb2, rb0 = r1 * ca, r2 * ca, cutter_radius * ca
    a = r2 - r1
    # cutting the pinion (external mesh with the cutter, moved out by the shift)
    a01 = r1 + cutter_radius + pinion_shift * m
    aw01 = np.arccos(np.clip((rb1 + rb0) / a01, -1, 1))
    form1 = np.maximum(a01 * np.sin(aw01) - cutter_roll, 0.0)  # pinion form point from N1
    # cutting the ring (cutter inside, moved towards the ring's centre by the shift)
    a02 = r2 - cutter_radius - ring_shift * m
    aw02 = np.arccos(np.clip((rb2 - rb0) / a02, -1, 1))
    n0 = a02 * np.sin(aw02)  # N0 from N2
    form2 = n0 + cutter_roll  # ring form point from N2
    # the pair (its base circles are r cos α whatever the shifts: the pitch curves roll)
    ra2 = r2 - (ring_addendum + ring_shift) * m
    ra1 = r1 + (pinion_addendum + pinion_shift) * m
    rho_a2 = np.sqrt(np.maximum(ra2**2 - rb2**2, 0.0))  # ring tip from N2
    rho_a1 = np.sqrt(np.maximum(ra1**2 - rb1**2, 0.0))  # pinion tip from N1
    n1 = a * sa  # N1 from N2
    fillet = rho_a2 - (n1 + form1)
    pinion_tip = form2 - (n1 + rho_a1)
    cutter_trim = rho_a2 - n0
    contact = (n1 + rho_a1 - rho_a2) / (math.pi * m * ca)
    need = np.maximum(n1 + form1, n0)  # the ring tip's roll distance from N2 must reach this
    ring_limit = (r2 - np.sqrt(rb2**2 + need**2)) / m - ring_shift
    pinion_limit = (np.sqrt(rb1**2 + np.maximum(form2 - n1, 0.0) ** 2) - r1) / m - pinion_shift
    # trochoid and trimming (KHK), with tooth counts in proportion to the radii
    aa1 = np.arccos(np.clip(rb1 / ra1, -1, 1))
    aa2 = np.arccos(np.clip(rb2 / ra2, -1, 1))
    inv_w = float(_inv(alpha))
    th1 = np.arccos(np.clip((ra2**2 - ra1**2 - a**2) / (2 * a * ra1), -1, 1)) + _inv(aa1) - inv_w
    th2 = np.arccos(np.clip((a**2 + ra2**2 - ra1**2) / (2 * a * ra2), -1, 1))
    trochoid = th1 * r1 / r2 + inv_w - _inv(aa2) - th2
    k = r1 / r2
    with np.errstate(invalid="ignore", divide="ignore"):
        t1 = np.arcsin(np.sqrt(np.clip((1 - (np.cos(aa1) / np.cos(aa2)) ** 2) / (1 - k**2), 0, 1)))
        t2 = np.arcsin(np.sqrt(np.clip(((np.cos(aa2) / np.cos(aa1)) ** 2 - 1) / (1 / k**2 - 1), 0, 1)))
    trimming = t1 + _inv(aa1) - inv_w - (t2 + _inv(aa2) - inv_w) / k
    angle = np.zeros(r2.shape) if driver_angle is None else np.asarray(driver_angle, dtype=float)
    return InternalLimits(
        angle,
        fillet,
        pinion_tip,
        cutter_trim,
        trochoid,
        trimming,
        contact,
        ring_limit,
        pinion_limit,
        float(ring_addendum),
        float(pinion_addendum),
        m,
    )


def circular_internal(
    ring_teeth: int,
    pinion_teeth: int,
    module: float,
    *,
    cutter_teeth: int,
    ring_addendum: float = 1.0,
    pinion_addendum: float = 1.0,
    **cutter_options,
) -> InternalLimits:
    """:func:`internal_limits` of circular gears with these tooth counts, cut by a
    ``ShaperCutter(cutter_teeth, module, **cutter_options)``."""
    from transplanter.geometry.cutter import ShaperCutter

    if not pinion_teeth < ring_teeth:
        raise SpecError.out_of_range("pinion teeth", pinion_teeth, f"< ring teeth {ring_teeth}")
    c = ShaperCutter(cutter_teeth, module, **cutter_options)
    return internal_limits(
        module * ring_teeth / 2,
        module * pinion_teeth / 2,
        module,
        pressure_angle=c.pressure_angle,
        ring_addendum=ring_addendum,
        pinion_addendum=pinion_addendum,
        cutter_radius=c.pitch_radius,
        cutter_roll=c.involute_end_roll,
    )


def pair_limits(
    pair,
    cutter,
    *,
    ring_addendum: float = 1.0,
    pinion_addendum: float = 1.0,
    ring_shift: float = 0.0,
    pinion_shift: float = 0.0,
    n: int = 720,
) -> InternalLimits:
    """:func:`internal_limits` along a sized internal ``pitch.GearPair`` (either gear driving):
    at ``n`` driver angles, the equivalent circular pair of the pitch curves' radii of
    curvature at the contact (see the module docstring)."""
    if pair.ring is None:
        raise GeometryError("pair_limits is for internal pairs; this pair is external")
    phi1 = 2 * math.pi * np.arange(n) / n
    k1 = pair.driver.curvature(phi1)
    k2 = pair.driven.curvature(pair.driven_contact_angle(phi1))
    k_ring, k_pin = (k1, k2) if pair.ring == "driver" else (k2, k1)
    return _curvature_limits(
        k_ring, k_pin, cutter, phi1, ring_addendum, pinion_addendum, ring_shift=ring_shift, pinion_shift=pinion_shift
    )


def _curvature_limits(
    k_ring, k_pin, cutter, driver_angle, ring_addendum, pinion_addendum, ring_shift=0.0, pinion_shift=0.0
) -> InternalLimits:
    """:func:`internal_limits` of the equivalent circular pairs of curvatures ``k_ring``,
    ``k_pin`` (1/mm) cut by ``cutter``; locally straight or concave positions (not internal) NaN."""
    with np.errstate(divide="ignore"):
        rho_ring = np.where(k_ring > 0, 1.0 / k_ring, np.nan)
        rho_pin = np.where(k_pin > 0, 1.0 / k_pin, np.nan)
    return internal_limits(
        rho_ring,
        rho_pin,
        cutter.module,
        pressure_angle=cutter.pressure_angle,
        ring_addendum=ring_addendum,
        pinion_addendum=pinion_addendum,
        cutter_radius=cutter.pitch_radius,
        cutter_roll=cutter.involute_end_roll,
        ring_shift=ring_shift,
        pinion_shift=pinion_shift,
        driver_angle=driver_angle,
    )


#: Half-width of the window (pitches) over which the screen takes each pitch curve's sharpest
#: convex curvature: the teeth in mesh span about 1.5 pitches either side of the contact, and a
#: tooth's tip reaches the mate's flank up to 2-3 pitches away where the curvature changes fast
#: (what made the published seed-004 pair foul 12.8 mm = 2.5 pitches from the contact).
SCREEN_WINDOW_PITCHES = 3.0
#: Shaper cutters the screen tries, teeth: fewer teeth free the ring's tips (see above); 12 is
#: about the fewest a disc cutter is made with at these modules.
SCREEN_CUTTERS = (12, 14, 16, 18, 20, 24)


@dataclass(frozen=True)
class ScreenResult:
    """The coarsest tooth count at which an internal pair passes :func:`screen_module`."""

    module: float
    teeth: tuple[int, int]
    cutter_teeth: int
    ring_addendum: float
    pinion_addendum: float
    contact_ratio: float
    #: smallest convex radii of curvature (ring, pinion) of the pitch curves, mm
    min_radius_of_curvature: tuple[float, float]


@dataclass(frozen=True)
class _Rolled:
    """Curvatures of ring and pinion at their contact on a uniform grid of rolled arc length
    over one driver lobe (both curves roll the same length): driver angles, grid step (mm)."""

    ring: np.ndarray
    pinion: np.ndarray
    driver_angle: np.ndarray
    step: float


def _window_curvature(pair, n: int = 2048) -> _Rolled:
    length = pair.driver.perimeter / pair.driver.lobes
    phi1 = pair.driver.angle_at_arc_length(length * np.arange(n) / n)
    k1 = pair.driver.curvature(phi1)
    k2 = pair.driven.curvature(pair.driven_contact_angle(phi1))
    return _Rolled(*((k1, k2) if pair.ring == "driver" else (k2, k1)), phi1, length / n)


def fouling_screen(
    pair,
    cutter,
    *,
    ring_addendum: float | None = None,
    pinion_addendum: float = 1.0,
    window: float = SCREEN_WINDOW_PITCHES,
) -> InternalLimits:
    """:func:`internal_limits` of a sized internal ``pair`` cut by ``cutter`` (a ``ShaperCutter``)
    with each pitch curve's radius of curvature taken as the smallest within ``window`` pitches
    of the contact (on a uniform grid of rolled arc length over one driver lobe): the screen
    for fouling a few pitches away from the contact, where the curvature changes fast. Its
    verdict is ``problems(trochoid=False)``: along non-circular curves KHK's trochoid formula
    refused pairs that the full meshing check found clear (``tests/test_screen.py``), so tip
    fouling is judged by the fillet and pinion-tip limits on the windowed radii, and the cut
    teeth's own checks (secondary cutting, undercut) by ``teeth.generate``. ``ring_addendum`` None trims the
    ring's tips to the fillet/cutter limit less 0.02 m (at most 1), as :func:`screen_module` and
    ``pair_gate.generate_pair(trim_ring_tips=True)`` do. Its ``problems()`` are empty when the cut
    teeth are expected to mesh; concave stretches (the pair locally external) carry NaN."""
    if pair.ring is None:
        raise GeometryError("fouling_screen is for internal pairs; this pair is external")
    rolled = _window_curvature(pair)
    if ring_addendum is None:
        ring_addendum = _trimmed(_windowed_limits(rolled, cutter, 1.0, pinion_addendum, window))
    return _windowed_limits(rolled, cutter, ring_addendum, pinion_addendum, window)


def trimmed_addendum(limit: float) -> float:
    """Ring-tip trimming: the addendum (modules) ``TRIM_MARGIN`` under ``limit``, rounded down to
    0.01 m (``pair_gate.generate_pair(trim_ring_tips=True)`` and the screen both cut to it)."""
    return math.floor((limit - TRIM_MARGIN) * 100) / 100


def _trimmed(full: InternalLimits) -> float:
    """The ring addendum trimmed to the fillet/cutter limit, at most a full addendum."""
    return min(1.0, trimmed_addendum(full.max_ring_addendum))


def _windowed_limits(rolled: _Rolled, cutter, ring_addendum, pinion_addendum, window) -> InternalLimits:
    size = 2 * math.ceil(window * math.pi * cutter.module / rolled.step) + 1
    k_ring = maximum_filter1d(rolled.ring, size, mode="wrap")
    k_pin = maximum_filter1d(rolled.pinion, size, mode="wrap")
    return _curvature_limits(k_ring, k_pin, cutter, rolled.driver_angle, ring_addendum, pinion_addendum)


def screen_module(
    pair,
    *,
    max_module: float = 8.0,
    min_module: float = 0.5,
    cutters: tuple[int, ...] = SCREEN_CUTTERS,
    pressure_angle: float = math.radians(20.0),
    window: float = SCREEN_WINDOW_PITCHES,
    pinion_addenda: tuple[float, ...] = (1.0, 0.8),
    min_ring_addendum: float = 0.3,
    min_contact_ratio: float = MIN_CONTACT_RATIO,
) -> ScreenResult | None:
    """The largest module (coarsest whole tooth count) at which an internal ``pair`` is expected
    to mesh: the fast fouling screen of a design search (numpy only, a few ms).

    From the coarsest tooth count down, for each cutter in ``cutters`` (tooth counts) and each
    pinion addendum in ``pinion_addenda`` (full, then stub): the ring's tips are trimmed to the
    fillet/cutter limit (at most a full addendum, at least ``min_ring_addendum`` — the least
    ``pair_gate.generate_pair`` trims to), then the limits of :func:`internal_limits` (a contact
    ratio of at least ``min_contact_ratio`` among them) must hold with each curve's
    radius of curvature taken as the *smallest* within ``window`` pitches of the contact — so a
    curvature that changes fast, which fouls a few pitches away from the contact, counts — and
    the cutter must roll inside the ring's sharpest convex corner. The pinion's pitch curve must
    be convex; where the ring's is concave the pair is locally external and these limits do not
    apply. None if no module >= ``min_module`` passes. Its verdict is validated against the full
    meshing check of the cut teeth in ``tests/test_screen.py``.
    """
    if pair.ring is None:
        raise GeometryError("screen_module is for internal pairs; this pair is external")
    rolled = _window_curvature(pair)
    if rolled.pinion.min() <= 0 or rolled.ring.max() <= 0:
        return None
    n_ring, n_pin = pair.lobes if pair.ring == "driver" else pair.lobes[::-1]
    lobe_length = pair.driver.perimeter / pair.driver.lobes  # one ring lobe rolls one pinion lobe
    k_first = max(1, math.ceil(lobe_length / (math.pi * max_module)))
    k_last = math.floor(lobe_length / (math.pi * min_module))
    sharpest = 1.0 / rolled.ring.max()
    for k in range(k_first, k_last + 1):
        m = lobe_length / (k * math.pi)
        for z0, pinion_addendum in itertools.product(cutters, pinion_addenda):
            cutter = ShaperCutter(z0, m, pressure_angle=pressure_angle)
            if cutter.pitch_radius >= sharpest:
                continue
            ring_add = _trimmed(_windowed_limits(rolled, cutter, 1.0, pinion_addendum, window))
            if ring_add < min_ring_addendum:
                continue
            lim = _windowed_limits(rolled, cutter, ring_add, pinion_addendum, window)
            if lim.problems(trochoid=False, min_contact_ratio=min_contact_ratio):
                continue
            return ScreenResult(
                m,
                (k * n_ring, k * n_pin),
                z0,
                ring_add,
                pinion_addendum,
                lim.min_contact_ratio,
                (float(sharpest), float(1 / rolled.pinion.max())),
            )
    return None
