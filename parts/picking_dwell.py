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
"""

from transplanter.families import Family, Making
from transplanter.families.pairs.incomplete_pair import IncompletePairStudy
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pitch.intermittent import IntermittentLaw
from transplanter.shop.solids import Features

#: the arm's cycle: at the tray from 150 to 210 deg of the driver, a modified-sine turn after it
LAW = "150..210: dwell; 210..510: 2*pi*(phi - 7*pi/6)/(5*pi/3) - 0.35*sin(2*pi*(phi - 7*pi/6)/(5*pi/3))"
MODULE = 2.0  # mm
SECTOR_TEETH = 30  # driver teeth on its sector (the centre distance follows)
WIDTH = 12.0  # mm
#: the driven's play while it stands at the tray may not exceed this, deg
LOCKING_PLAY_DEG = 2.5


def family() -> Family:
    law = IntermittentLaw.parse(LAW)
    study = IncompletePairStudy(
        "picker",
        law,
        MODULE,
        teeth=SECTOR_TEETH,
        cutter=ShaperCutter(16),
        max_play_deg=LOCKING_PLAY_DEG,
        steps=360,
        # C45 quenched and tempered: the gears' material (transplanter.shop.catalogue), our choice
        making=tuple(Making(WIDTH, Features(12.0, keyway=False), material="C45") for _ in range(2)),
    )
    return Family(
        "picking_dwell",
        "A picking arm on incomplete non-circular gears: it stands at the tray for 60 deg of the driver "
        f"(module {MODULE:g} mm, {SECTOR_TEETH} teeth on the driver's sector), locking arcs over the dwell",
        (study,),
    )
