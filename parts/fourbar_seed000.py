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
"""

import math

from transplanter.design.linkage.dh import DHFourBar
from transplanter.design.linkage.planting import PlantingArm
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


def family() -> Family:
    return Family(
        name="fourbar_seed000",
        description="Seed 000 crank-rocker planting mechanisms A, B, C (Table 1): Table 2 metrics and link plates",
        parts=(
            *(ArmStudy(arm(name), PLANTING_DEPTH) for name in TABLE_1),
            *(LinkPlatesStudy(f"{name}_plates", arm(name), PIN, SHAFT, PLATE, NOSE, making=PLATES) for name in TABLE_1),
        ),
    )
