"""Seed 001 (Kumar & Thomas): four-bar of a power-tiller 8-row rice transplanter.

Table 1: crank 6.0 cm, coupler 20.0 cm, follower 21.3 cm, fixed link 33.0 cm at 37.4 deg to
the horizontal, coupler extension 25.3 cm; crank at 125 rpm, forward speed 1.5 km/h.

Reading: the fixed link runs from the crank pivot to the follower pivot at 37.4 deg and the
assembly is branch -1; with it the paper's coupler angle range (-18.1 to +19.4 deg) and
follower angle range (54.1 to 89.4 deg, direction rocker pin -> follower pivot) reproduce.
The finger is taken on the coupler line 25.3 cm beyond the rocker pin (20 + 25.3 cm from the
crank pin). The paper's velocity and acceleration figures (280.32 cm/s, 3866.5 cm/s^2) do
not follow from these dimensions under any reading of the finger position (see README).
The planting depth is not given; 40 mm is assumed.

The plates are our stated choice: 8 mm steel plate, ISO 2338 Ø10 pins at B, C and O4 in
10.05 mm holes (a running fit), a Ø20 drive shaft keyed to the crank (DIN 6885-1 key 6 × 6),
a finger nose of radius 6 mm at the finger position.
"""

import math

from transplanter.design.linkage.fourbar import FourBar
from transplanter.design.linkage.planting import PlantingArm
from transplanter.families import ArmStudy, Family, Joint, LinkPlatesStudy, Making

LINKAGE = FourBar(ground=330.0, crank=60.0, coupler=200.0, rocker=213.0, ground_angle=math.radians(37.4), branch=-1)
CRANK_SPEED = 2 * math.pi * 125 / 60  # rad/s
FORWARD_SPEED = 1500.0 / 3.6  # mm/s (1.5 km/h)
FINGER = (200.0 + 253.0, 0.0)  # mm in the coupler frame

PIN = Joint("ISO 2338 pin 10 m6, running fit", hole=10.05, boss=24.0)  # mm
SHAFT = Joint("drive shaft 20 h7, DIN 6885-1 key 6x6", hole=20.05, boss=40.0)  # mm
PLATE = 8.0  # mm
#: the plates' material (transplanter.shop.catalogue): seed 001 names none; S235JR steel plate, our choice
PLATES = Making(width=PLATE, material="S235JR")
NOSE = 6.0  # mm, finger tip radius


def family() -> Family:
    arm = PlantingArm(LINKAGE, FINGER, CRANK_SPEED, FORWARD_SPEED, name="eight_row_arm")
    return Family(
        name="fourbar_seed001",
        description="Seed 001 four-bar of an 8-row power-tiller transplanter (Table 1) and its link plates",
        parts=(
            ArmStudy(arm, planting_depth=40.0),
            LinkPlatesStudy("eight_row_arm_plates", arm, PIN, SHAFT, PLATE, NOSE, making=PLATES),
        ),
    )
