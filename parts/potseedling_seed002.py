"""Seed 002 (Sun et al. 2023): pot-seedling picking-and-planting mechanism from four exact poses.

Mechanism ③ of the paper, synthesised in ``_seed002.py`` with the intermediate points and the
cam follower our search chose (``OPTIMUM``): the four-pose synthesis, the two non-circular gear
stages (pitch curves, and their gears cut at module 1.5 by a 12-tooth shaper cutter) and the
swing cam with its oscillating roller follower.
"""

from _seed002 import CENTRE_DISTANCES, EXPONENT, OPTIMUM, chain, follower, swing

from transplanter.cutter import ShaperCutter
from transplanter.families import CamStudy, Family, Making, PitchPairStudy, SynthesisStudy, ToothedPairStudy
from transplanter.solids import Features

MODULE = 1.5  # mm, both gear stages
CUTTER_TEETH = 12  # shaper cutter
GEAR_WIDTH = 10.0  # mm
GEAR_BORE = 12.0  # mm, keyed (DIN 6885)
#: an oscillating follower's pressure angle cannot stay below about half its swing; the poses
#: force 83.9 deg of swing, and the optimum reaches 45.9 deg (the paper: 43 deg, follower unpublished)
CAM_PRESSURE_LIMIT_DEG = 46.0
CAM_WIDTH = 12.0  # mm
CAM_BORE = 30.0  # mm
#: where the synthesis may place centre and circle points (x ranges and the y range, mm)
FEASIBLE_BOXES = {"centre_x": (-60.0, 25.0), "circle_x": (30.0, 80.0), "y_range": (-100.0, 100.0)}


def family() -> Family:
    mechanism = chain(*OPTIMUM[:2])
    stages = mechanism.distribute(CENTRE_DISTANCES, exponent=EXPONENT)
    gears_23, sizing_23 = stages.stage23.sized(module=MODULE)
    gears_35, sizing_35 = stages.stage35.sized(module=MODULE)
    gear = Making(width=GEAR_WIDTH, features=Features(bore=GEAR_BORE))
    return Family(
        name="potseedling_seed002",
        description="Seed 002 pot-seedling mechanism: four-pose synthesis, non-circular gear stages and swing cam",
        parts=(
            SynthesisStudy("open_chain_3R", mechanism, boxes=FEASIBLE_BOXES),
            PitchPairStudy("stage_2_3", stages.stage23, module=MODULE),
            PitchPairStudy("stage_3_5", stages.stage35, module=MODULE),
            ToothedPairStudy(
                "gears_2_3", gears_23, ShaperCutter(CUTTER_TEETH), sizing_23.teeth[0], making=(gear, gear)
            ),
            ToothedPairStudy(
                "gears_3_5", gears_35, ShaperCutter(CUTTER_TEETH), sizing_35.teeth[0], making=(gear, gear)
            ),
            CamStudy(
                "swing_cam",
                swing(mechanism),
                follower(*OPTIMUM[2]),
                max_pressure_angle_deg=CAM_PRESSURE_LIMIT_DEG,
                making=Making(width=CAM_WIDTH, features=Features(bore=CAM_BORE)),
            ),
        ),
    )
