"""A picking arm that stops at the seedling tray: incomplete non-circular gears with a dwell.

The arm turns once per cycle on the driven gear of an external incomplete pair; the driver turns
at constant speed. For 60 deg of the driver (a sixth of the cycle: 0.25 s at 40 rpm) the arm
stands still at the tray while its needles close on a seedling — the locking arcs hold it —
then it swings round and back: a modified-sine rise over the other 300 deg, the driven's speed
jumping to 0.78 of the driver's as the first tooth meets it (the entry shock the manifest states)
and from the same speed back to rest at the tray.

The proof (``IncompletePairStudy``): the sectors, locks and relieved transitions meshed on the
re-read DXF and STL over the cycle; the dwell as made against the dwell asked (``dwells``: the
first tooth meets the held arm 0.1 deg of driver after the asked end; the arm is held within its
locking play of the tray angle).

**The design studio** (``transplanter design parts/picking_dwell.py``) opens :func:`problem` on this
pair: the law's free parameters — the dwell's span (centred on the tray at 180 deg of the driver),
the modified sine's amplitude — and the sector's teeth (the centre distance follows) as sliders.
The cost is the entry shock (the driven's speed jump per unit driver speed), plus ten times each
shortfall of the checks the pair family makes before it cuts (``incomplete_view.pair_checks``:
closure, the smallest ratio, the pitch curves' pressure deviation within seed 004's 30 deg,
the sectors' curvature against the shaper) and of the needles' 0.25 s at the tray; a law whose
locks or sectors do not fit at its size (``incomplete.check_fit``) is refused. The page draws the
quick checks at once and then (``later``) cuts the pair: its locking play and its first contact
after the dwell, as the build finds them before its meshing proof.
"""

import dataclasses

from transplanter.design.incomplete_view import incomplete_pair_view, limit_row, pair_checks
from transplanter.design.optimise import Problem
from transplanter.design.views import Kept
from transplanter.families import Family, Making
from transplanter.families.pairs.incomplete_pair import IncompletePairStudy
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.dwell_entry import TIP_BAND
from transplanter.geometry.pitch.intermittent import IntermittentLaw
from transplanter.shop.solids import Features

#: the pair as made: the dwell's span (deg of the driver, centred on the tray), the modified sine's
#: amplitude over the rest of the turn, and the driver's teeth on its sector (the centre distance
#: follows) — the design studio's variables (``VARIABLES``), whose "make parts" writes here
AS_MADE = (60.0, 0.35, 30)
#: the arm's cycle as first written: at the tray from 150 to 210 deg of the driver, a modified-sine
#: turn after it — the law of ``LAW_AT`` = (span, amplitude), which the family makes while
#: ``AS_MADE`` holds them (its angles in fractions of pi; :func:`law_text` writes degrees)
LAW = "150..210: dwell; 210..510: 2*pi*(phi - 7*pi/6)/(5*pi/3) - 0.35*sin(2*pi*(phi - 7*pi/6)/(5*pi/3))"
LAW_AT = (60.0, 0.35)
MODULE = 2.0  # mm
WIDTH = 12.0  # mm
#: the driven's play while it stands at the tray may not exceed this, deg
LOCKING_PLAY_DEG = 2.5


def picker(law: IntermittentLaw, teeth: int) -> IncompletePairStudy:
    """The picker's pair of ``law`` with ``teeth`` on the driver's sector, as the family makes it."""
    return IncompletePairStudy(
        "picker",
        law,
        MODULE,
        teeth=teeth,
        cutter=ShaperCutter(16),
        max_play_deg=LOCKING_PLAY_DEG,
        steps=360,
        # C45 quenched and tempered: the gears' material (transplanter.shop.catalogue), our choice
        making=tuple(Making(WIDTH, Features(12.0, keyway=False), material="C45") for _ in range(2)),
    )


def family() -> Family:
    span, amplitude, teeth = AS_MADE
    study = picker(_law(span, amplitude), int(teeth))
    return Family(
        "picking_dwell",
        f"A picking arm on incomplete non-circular gears: it stands at the tray for {span:g} deg of the driver "
        f"(module {MODULE:g} mm, {int(teeth)} teeth on the driver's sector), locking arcs over the dwell",
        (study,),
    )


# -- the design studio: the law's free parameters ------------------------------------------------

#: the driver's speed, r/min, and the time the needles take to close on a seedling at the tray, s
DRIVER_SPEED_RPM = 40.0
NEEDLES_CLOSE_S = 0.25
#: the pitch curves' pressure deviation may not exceed this, deg (seed 004's rule: the working
#: pressure angle stays within the cutter's 20 deg + 30 deg)
MAX_PRESSURE_DEVIATION_DEG = 30.0
#: the tray: the dwell is centred on this driver angle, deg
TRAY_DEG = 180.0
VARIABLES = (
    ("dwell_span_deg", 40.0, 120.0),
    ("amplitude", 0.0, 0.8),
    ("sector_teeth", 20.0, 40.999),
)
#: a shortfall's unit in the cost, by the row's unit
SHORTFALL_UNIT = {"rad": 1e-9, "": 0.05, "deg": 5.0, "1/mm": 0.01, "s": 0.05}


def law_text(span_deg: float, amplitude: float) -> str:
    """``LAW`` with a dwell of ``span_deg`` centred on the tray and a modified sine of ``amplitude``
    over the rest of the turn (``LAW_AT`` gives ``LAW``'s law, written with its angles in degrees)."""
    start, end = TRAY_DEG - span_deg / 2, TRAY_DEG + span_deg / 2
    u = f"2*pi*(phi - {end!r}*pi/180)/({360.0 - span_deg!r}*pi/180)"
    return f"{start!r}..{end!r}: dwell; {end!r}..{start + 360.0!r}: {u} - {amplitude!r}*sin({u})"


_LAWS = Kept(16)


def _law(span_deg: float, amplitude: float) -> IntermittentLaw:
    """The law of ``law_text`` (kept); at ``LAW_AT``, ``LAW`` itself (its angles written in fractions
    of pi differ from ``law_text``'s by round-off: the family makes it as first written)."""
    text = LAW if (span_deg, amplitude) == LAW_AT else law_text(span_deg, amplitude)
    return _LAWS.get(text, lambda: IntermittentLaw.parse(text))


def entry_shock_of_law() -> float:
    """The driven's speed jump as its first tooth meets it (ω2/ω1), ``LAW`` as first written (kept):
    the bar a design's entry shock is held to."""
    return _LAWS.get(("shock", LAW), lambda: IntermittentLaw.parse(LAW).transitions()[0].speed_jump)


def design_study(x) -> IncompletePairStudy:
    """The picker's pair of design ``x`` (``VARIABLES`` order), sized (a TransplanterError where
    its sector cannot carry the teeth)."""
    study = picker(_law(float(x[0]), float(x[1])), int(x[2]))
    study.pair  # noqa: B018 - sized here, so a law that cannot carry the teeth is said by the view
    return study


def quick_rows(study: IncompletePairStudy):
    """The checks the pair family makes before it cuts (``pair_checks``), the entry shock against
    ``LAW``'s, and the time at the tray against the needles'."""
    pair = study.pair
    rows = pair_checks(pair, study.tool.pitch_radius, MAX_PRESSURE_DEVIATION_DEG)
    jump = pair.law.transitions()[0].speed_jump
    dwell = pair.law.dwells[0]
    at_tray = (dwell.end - dwell.start) / 360.0 * 60.0 / DRIVER_SPEED_RPM
    return rows + (
        limit_row("entry shock: speed jump w2/w1", jump, "", entry_shock_of_law(), True, "LAW's pair"),
        limit_row("time at the tray", at_tray, "s", NEEDLES_CLOSE_S, False, "the needles close"),
    )


def cut_rows(study: IncompletePairStudy):
    """The pair cut (seconds): its lock's locking play in all against the study's, and each
    first tooth contact after a dwell off both tips and not before the dwell's end."""
    study.fit()
    gears = study.gears
    rows = []
    for lock in gears.locks:
        rows.append(
            limit_row("lock: nominal locking play in all", 2 * lock.nominal_play_deg, "deg", study.max_play_deg, True)
        )
    for e in study.entry_contacts(gears.driver.polygon, gears.driven.polygon):
        below = max(e["driver_radius_below_tip_m"], e["driven_radius_from_tip_m"])
        rows.append(limit_row("first contact: below a tip by", below, "m", TIP_BAND, False, "not tip on tip"))
        rows.append(limit_row("first contact after the dwell's end", e["after_dwell_end_deg"], "deg", 0.0, False))
    return tuple(rows)


def cost_of(rows) -> float:
    """The entry shock (ω2/ω1) and ten times each check's shortfall in ``SHORTFALL_UNIT`` s."""
    shock = next(r.value for r in rows if r.name.startswith("entry shock"))
    short = sum(max(0.0, -r.margin) / SHORTFALL_UNIT[r.unit] for r in rows if not r.name.startswith("entry shock"))
    return shock + 10.0 * short


def view(x):
    """What ``transplanter design`` draws of the picker's pair of design ``x``; its cut (``later``)."""
    study = design_study(x)
    rows = quick_rows(study)
    pair = study.pair
    notes = (
        f"{pair.law.describe()}; module {MODULE:g} mm, {int(x[2])} teeth on the driver's sector, "
        f"a = {pair.centre_distance:.4f} mm; cost {cost_of(rows):.6g}",
    )
    shown = incomplete_pair_view(pair, rows, MAX_PRESSURE_DEVIATION_DEG, notes=notes)
    return dataclasses.replace(
        shown, later=lambda: cut_rows(study), later_title="the pair cut: its lock and first contact"
    )


def describe(x) -> dict[str, str]:
    """Each quick check of design ``x``, with its margin."""
    return {r.name: f"{r.value:.4g} {r.unit} (margin {r.margin:+.3g})" for r in quick_rows(design_study(x))}


def problem() -> Problem:
    """The law's dwell span and amplitude and the sector's teeth for the smallest entry shock that
    passes the family's checks (module docstring)."""

    def cost(x):
        study = design_study(x)
        study.fit()
        return cost_of(quick_rows(study))

    return Problem(
        "picking_dwell law",
        VARIABLES,
        cost,
        infeasible=1e3,
        x0=AS_MADE,
        optimum="AS_MADE",  # make parts (the studio) and `optimise --write` record a design there
        choices=("sector_teeth",),
        describe=describe,
        view=view,
    )
