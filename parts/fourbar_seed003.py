"""Seed 003 (Yamashita, Ichikawa & Mori): shaking force and balancing of planting fingers.

Table 3 gives two fingers, type I and type II: pair distances a (frame), b (crank),
c (coupler), d (rocker) in mm, centres of mass (g1, g2) in each link's frame, link weights
in gf, mounting angle phi (the frame link points at -phi from the horizontal) and the crank
speed. The moments of inertia are not published, so the torque here is the part due to the
translation of the link masses and gravity; give ``inertia`` to include rotation.

The paper gives no finger tip. Reading: the coupler is a plate of one section — the bar B->C
and a straight finger from B — so the finger's tip follows from the published coupler centre
of mass (``finger_for_centre_of_mass``): type I (-168.90, -56.07) mm, type II (-157.06,
-56.77) mm in the coupler frame. The paper puts ball bearings at the coupler joints: 626
(6 x 19 x 6) in 19 mm housings at B, C and O4, 6 mm plates (the bearing's width), a Ø12
drive shaft keyed to the crank; finger nose radius 5 mm.
"""

import math

from transplanter.design.linkage.dynamics import LinkMass, MassModel
from transplanter.design.linkage.fourbar import FourBar
from transplanter.design.linkage.planting import PlantingArm
from transplanter.families import BalancingStudy, Family, Joint, LinkPlatesStudy, Making
from transplanter.families.mechanisms.plates import finger_for_centre_of_mass

# name: (a, b, c, d, (gb1, gb2), (gc1, gc2), (gd1, gd2), mb, mc, md [kg], phi [deg], rpm)
TABLE_3 = {
    "type_I": (88.0, 33.5, 71.5, 80.0, (12.0, 0.0), (-50.0, -20.0), (32.0, 0.0), 0.199, 0.687, 0.259, 83.0, 193.0),
    "type_II": (85.0, 40.0, 70.0, 80.0, (17.0, 0.0), (-45.0, -20.0), (12.0, 0.0), 0.226, 0.761, 0.226, 100.0, 200.0),
}


BEARING = Joint("626 ball bearing 6x19x6 in an N7 housing", hole=19.0, boss=28.0)  # mm
SHAFT = Joint("drive shaft 12 h7, DIN 6885-1 key 4x4", hole=12.05, boss=28.0)  # mm
PLATE = 6.0  # mm
#: the plates' material (transplanter.shop.catalogue): seed 003 names none; S235JR steel plate, our choice
PLATES = Making(width=PLATE, material="S235JR")
NOSE = 5.0  # mm, finger tip radius


def study(name: str) -> BalancingStudy:
    a, b, c, d, gb, gc, gd, mb, mc, md, phi, rpm = TABLE_3[name]
    linkage = FourBar(ground=a, crank=b, coupler=c, rocker=d, ground_angle=-math.radians(phi), branch=+1)
    masses = MassModel(crank=LinkMass(mb, gb), coupler=LinkMass(mc, gc), rocker=LinkMass(md, gd))
    return BalancingStudy(name, linkage, masses, crank_speed=2 * math.pi * rpm / 60)


def plates(name: str) -> LinkPlatesStudy:
    s = study(name)
    tip = finger_for_centre_of_mass(s.linkage.coupler, s.masses.coupler.com)
    arm = PlantingArm(s.linkage, tip, s.crank_speed, name=name)
    return LinkPlatesStudy(f"{name}_plates", arm, BEARING, SHAFT, PLATE, NOSE, making=PLATES)


def family() -> Family:
    return Family(
        name="fourbar_seed003",
        description="Seed 003 planting fingers type I and II (Table 3): shaking force, torque, balancing, plates",
        parts=(*(study(name) for name in TABLE_3), *(plates(name) for name in TABLE_3)),
    )
