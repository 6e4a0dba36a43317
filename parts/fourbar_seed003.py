"""Seed 003 (Yamashita, Ichikawa & Mori): shaking force and balancing of planting fingers.

Table 3 gives two fingers, type I and type II: pair distances a (frame), b (crank),
c (coupler), d (rocker) in mm, centres of mass (g1, g2) in each link's frame, link weights
in gf, mounting angle phi (the frame link points at -phi from the horizontal) and the crank
speed. The moments of inertia are not published, so the torque here is the part due to the
translation of the link masses and gravity; give ``inertia`` to include rotation.
"""

import math

from transplanter.families import BalancingStudy, Family
from transplanter.linkage.dynamics import LinkMass, MassModel
from transplanter.linkage.fourbar import FourBar

# name: (a, b, c, d, (gb1, gb2), (gc1, gc2), (gd1, gd2), mb, mc, md [kg], phi [deg], rpm)
TABLE_3 = {
    "type_I": (88.0, 33.5, 71.5, 80.0, (12.0, 0.0), (-50.0, -20.0), (32.0, 0.0), 0.199, 0.687, 0.259, 83.0, 193.0),
    "type_II": (85.0, 40.0, 70.0, 80.0, (17.0, 0.0), (-45.0, -20.0), (12.0, 0.0), 0.226, 0.761, 0.226, 100.0, 200.0),
}


def study(name: str) -> BalancingStudy:
    a, b, c, d, gb, gc, gd, mb, mc, md, phi, rpm = TABLE_3[name]
    linkage = FourBar(ground=a, crank=b, coupler=c, rocker=d, ground_angle=-math.radians(phi), branch=+1)
    masses = MassModel(crank=LinkMass(mb, gb), coupler=LinkMass(mc, gc), rocker=LinkMass(md, gd))
    return BalancingStudy(name, linkage, masses, crank_speed=2 * math.pi * rpm / 60)


def family() -> Family:
    return Family(
        name="fourbar_seed003",
        description="Seed 003 planting fingers type I and II (Table 3): shaking force, torque, balancing",
        parts=tuple(study(name) for name in TABLE_3),
    )
