"""Seed 000 (Kim & Chung): crank-rocker planting mechanisms A, B and C of rice transplanters.

Table 1 gives each mechanism in the Denavit-Hartenberg convention (lengths in cm, converted
to mm here): frame a1, crank a2, coupler a3, rocker a4, the fork apex (X3P, Y3P) in the
rocker-pin frame and the frame rotation phi. The crank turns at 8 pi rad/s (240 rpm) and the
machine advances at 60 cm/s; the planting depth is 4 cm.

The paper does not say which way each crank turns nor which assembly it uses; its own
Table 2 settles both: assembly branch +1 for all three, A counter-clockwise ("backward
relative to the wheels") and B and C clockwise (B "in the same direction as the wheels").

The paper gives no parts; the plates are our stated choice: 6 mm steel plate, ISO 2338 Ø8 pins
at B, C and O4 in 8.05 mm holes (a running fit), a Ø12 drive shaft keyed to the crank
(DIN 6885-1 key 4 × 4) running in the frame plate, bosses of twice and more the hole, and
a finger nose of radius 5 mm centred on the fork apex.

**The design studio** (``transplanter design parts/fourbar_seed000.py``) opens :func:`problem` on
arm B as the family makes it (``MADE_B``, as published until a design is recorded there): its
Table 1 dimensions as sliders (±30 %, the frame's rotation ±30 deg), its
Table 2 metrics as the family states them (``PlantingArm.metrics``, what ``ArmStudy`` records)
judged against the published arm B itself — the paper sets no targets, it compares A, B and C and
prefers B's short path through the soil (less friction) — with the hole width of seed 004
(``objectives.HOLE_WIDTH_MAX_MM``) and the designers' 40-140 deg transmission angle
(``FourBar.transmission_angle``). The cost is the path length in the soil (cm), plus ten times
each shortfall in units of 0.5 cm, 0.1 m/s, 5 m/s^2 or 5 deg; a design whose link plates cannot
be made (``LinkPlatesStudy``) or whose crank does not turn fully is refused.
"""

import math

import numpy as np

from transplanter.design.arm_view import planting_arm_view
from transplanter.design.linkage.dh import DHFourBar
from transplanter.design.linkage.planting import PlantingArm
from transplanter.design.objectives import HOLE_WIDTH_MAX_MM
from transplanter.design.optimise import Problem
from transplanter.design.views import Kept, Row
from transplanter.families import ArmStudy, Family, Joint, LinkPlatesStudy, Making

CRANK_SPEED = 8 * math.pi  # rad/s, 240 rpm
FORWARD_SPEED = 600.0  # mm/s
PLANTING_DEPTH = 40.0  # mm

PIN = Joint("ISO 2338 pin 8 m6, running fit", hole=8.05, boss=20.0)  # mm
SHAFT = Joint("drive shaft 12 h7, DIN 6885-1 key 4x4", hole=12.05, boss=28.0)  # mm
PLATE = 6.0  # mm
#: the plates' material (transplanter.shop.catalogue): seed 000 names none; S235JR steel plate, our choice
PLATES = Making(width=PLATE, material="S235JR")
NOSE = 5.0  # mm, finger tip radius

# name: (a1, a2, a3, a4, X3P, Y3P [mm], phi [deg], sense of crank rotation)
TABLE_1 = {
    "mechanism_A": (75.0, 35.0, 75.0, 80.0, -237.8, -101.7, 90.0, +1),
    "mechanism_B": (125.0, 40.0, 100.0, 85.0, -273.8, 63.3, 322.0, -1),
    "mechanism_C": (120.0, 38.0, 103.0, 75.0, -345.1, -100.3, 282.0, -1),
}


def arm(name: str) -> PlantingArm:
    a1, a2, a3, a4, x3, y3, phi, sense = TABLE_1[name]
    linkage = DHFourBar(a1=a1, a2=a2, a3=a3, a4=a4, phi=math.radians(phi), branch=+1)
    return PlantingArm.from_dh(linkage, x3, y3, sense * CRANK_SPEED, FORWARD_SPEED, name=name)


def made_arm(name: str) -> PlantingArm:
    """The arm the family makes: A and C as Table 1 gives them, B with the dimensions ``MADE_B``."""
    return arm_b(MADE_B) if name == "mechanism_B" else arm(name)


def family() -> Family:
    arms = [made_arm(name) for name in TABLE_1]
    return Family(
        name="fourbar_seed000",
        description="Seed 000 crank-rocker planting mechanisms A, B, C (Table 1): Table 2 metrics and link plates",
        parts=(
            *(ArmStudy(a, PLANTING_DEPTH) for a in arms),
            *(LinkPlatesStudy(f"{a.name}_plates", a, PIN, SHAFT, PLATE, NOSE, making=PLATES) for a in arms),
        ),
    )


# -- the design studio: arm B around its published design ----------------------------------------

#: arm B's design vector: Table 1's a1..a4, X3P, Y3P (mm, ±30 %) and phi (deg, ±30 deg)
VARIABLES_B = (
    ("a1_frame_mm", 87.5, 162.5),
    ("a2_crank_mm", 28.0, 52.0),
    ("a3_coupler_mm", 70.0, 130.0),
    ("a4_rocker_mm", 59.5, 110.5),
    ("x3p_fork_mm", -355.94, -191.66),
    ("y3p_fork_mm", 44.31, 82.29),
    ("phi_frame_deg", 292.0, 352.0),
)
#: arm B as published (``VARIABLES_B`` order): the bar of its rows and where a search starts
PUBLISHED_B = TABLE_1["mechanism_B"][:7]
#: arm B as the family makes it (``VARIABLES_B`` order; as published until a design is recorded
#: here: the studio's "make parts" and ``transplanter optimise --write`` write it)
MADE_B = (125.0, 40.0, 100.0, 85.0, -273.8, 63.3, 322.0)
#: the transmission angle at the rocker pin stays within these, deg (the designers' rule that
#: ``FourBar.transmission_angle`` states)
TRANSMISSION_ANGLE_DEG = (40.0, 140.0)
#: a shortfall's unit in the cost, by the row's unit
SHORTFALL_UNIT = {"cm": 0.5, "m/s": 0.1, "m/s^2": 5.0, "deg": 5.0}


def arm_b(x) -> PlantingArm:
    """Arm B with the dimensions ``x`` (``VARIABLES_B`` order), turning and moving as published."""
    a1, a2, a3, a4, x3, y3, phi = (float(v) for v in x)
    sense = TABLE_1["mechanism_B"][7]
    linkage = DHFourBar(a1=a1, a2=a2, a3=a3, a4=a4, phi=math.radians(phi), branch=+1)
    return PlantingArm.from_dh(linkage, x3, y3, sense * CRANK_SPEED, FORWARD_SPEED, name="mechanism_B")


def transmission_angles(arm: PlantingArm) -> tuple[float, float]:
    """(least, largest) transmission angle over a crank turn, deg, as ``ArmStudy`` records them."""
    fb = arm.linkage
    mu = fb.transmission_angle(fb.solve(np.linspace(0, 2 * math.pi, 721)))
    return math.degrees(float(mu.min())), math.degrees(float(mu.max()))


def arm_b_figures(arm: PlantingArm):
    """(metrics at the planting depth, {quantity: value} in Table 2's units with the transmission
    angles): what the family states of the arm."""
    m = arm.metrics(planting_depth=PLANTING_DEPTH)
    table = {label: value for label, value, _ in m.table()}
    table["transmission angle min"], table["transmission angle max"] = transmission_angles(arm)
    table["in-soil acceleration"] = max(table[f"{k} acceleration"] for k in ("entry", "lowest", "exit"))
    return m, table


_PUBLISHED = Kept(1)


def published_b() -> dict[str, float]:
    """Arm B's figures as published (:func:`arm_b_figures` of Table 1's arm B), kept."""
    return _PUBLISHED.get((), lambda: arm_b_figures(arm("mechanism_B"))[1])


def arm_b_rows(table: dict[str, float]) -> tuple[Row, ...]:
    """Arm B's objectives: each of its figures ``table`` against its limit."""
    ref = published_b()
    low_mu, high_mu = TRANSMISSION_ANGLE_DEG
    asked = (
        # (quantity, row name, unit, limit, at most, why)
        ("path length in soil (ground)", "path length in soil (ground)", "cm", ref, True, "arm B as published"),
        ("entry-exit distance (ground)", "entry-exit distance (ground)", "cm", ref, True, "arm B as published"),
        ("hole width (ground)", "hole width (ground)", "cm", HOLE_WIDTH_MAX_MM / 10, True, "seed 004's hole"),
        ("loop height", "loop height (reaches the seedling board)", "cm", ref, False, "arm B as published"),
        ("entry speed", "speed entering the soil", "m/s", ref, True, "arm B as published"),
        ("in-soil acceleration", "acceleration at entry, lowest, exit", "m/s^2", ref, True, "arm B as published"),
        ("transmission angle min", "transmission angle min", "deg", low_mu, False, "designers' rule"),
        ("transmission angle max", "transmission angle max", "deg", high_mu, True, "designers' rule"),
    )
    rows = []
    for quantity, name, unit, limit, at_most, why in asked:
        value = table[quantity]
        bound = limit[quantity] if isinstance(limit, dict) else limit
        margin = bound - value if at_most else value - bound
        said = f"{'<=' if at_most else '>='} {bound:.4g} {unit} ({why})"
        rows.append(Row(name, value, unit, said, margin, margin >= 0.0))
    return tuple(rows)


def arm_b_judged(x):
    """(arm, its metrics, its rows) of design ``x``; a TransplanterError where it cannot be built
    (the crank does not turn fully, the link plates have no room for their holes)."""
    built = arm_b(x)
    LinkPlatesStudy("mechanism_B_plates", built, PIN, SHAFT, PLATE, NOSE, making=PLATES)  # refuses no-room plates
    m, table = arm_b_figures(built)
    return built, m, arm_b_rows(table)


def cost_of(rows: tuple[Row, ...]) -> float:
    """The path length in the soil (cm) and ten times each shortfall in ``SHORTFALL_UNIT`` s."""
    short = sum(max(0.0, -r.margin) / SHORTFALL_UNIT[r.unit] for r in rows)
    return rows[0].value + 10.0 * short


def view(x):
    """What ``transplanter design`` draws of arm B with dimensions ``x``."""
    built, m, rows = arm_b_judged(x)
    paper = "the paper's Table 2 for B: loop 22.3 x 9.8 cm, path in soil 9.2 cm, entry-exit 2 cm, 119 deg in soil"
    return planting_arm_view(built, m, rows, notes=(f"cost {cost_of(rows):.6g}", paper))


def describe(x) -> dict[str, str]:
    """Each objective of arm B's design ``x``, with its margin."""
    return {r.name: f"{r.value:.4g} {r.unit} (margin {r.margin:+.3g})" for r in arm_b_judged(x)[2]}


def problem() -> Problem:
    """Arm B's dimensions for the shortest path through the soil, no worse than published on the
    rest (module docstring)."""
    return Problem(
        "seed000 arm B",
        VARIABLES_B,
        lambda x: cost_of(arm_b_judged(x)[2]),
        infeasible=1e3,
        x0=PUBLISHED_B,
        describe=describe,
        view=view,
        optimum="MADE_B",
        design=MADE_B,
    )
