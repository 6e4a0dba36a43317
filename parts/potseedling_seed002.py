"""Seed 002 (Sun et al. 2023): pot-seedling picking-and-planting mechanism from four exact poses.

Mechanism ③ of the paper, synthesised in ``_seed002.py`` with the intermediate points and the
cam follower our search chose (``OPTIMUM``): the four-pose synthesis, the two non-circular gear
stages (pitch curves, and their gears cut at module 1.5 by a 12-tooth shaper cutter), the
swing cam with its oscillating roller follower, and the whole machine (Fig. 10): the sector
gears 7-8 (ratio 1) that turn carrier 2 with the follower, the equal spur gears 9-10-11 on
carrier 2, both carriers, the arm and its claw, posed from the made parts and judged over the
cycle.
"""

import dataclasses

from _seed002 import CENTRE_DISTANCES, EXPONENT, OPTIMUM, chain, follower, swing

from transplanter.families import CamStudy, Family, Making, PitchPairStudy, SynthesisStudy, ToothedPairStudy
from transplanter.families.machines.carrier_machine import CarrierLayers, DoubleCarrierMachineStudy
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pitch import GearPair, Mesh, PitchCurve
from transplanter.shop.solids import Features

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
#: the sector gears 7-8 (ratio 1): the follower pivot is 152.2 mm from A0 and A_c 73.8 mm, so
#: they are at least 78.5 mm apart: 32 teeth of module 2.5 (80 mm)
SECTOR_MODULE, SECTOR_TEETH = 2.5, 32
#: the equal spur gears 9-10-11 on carrier 2 (A_c to Q is 75.55 mm): 26 teeth of module 1.5,
#: 39 mm apart, the idler 9.7 mm off the line A_c-Q
SPUR_TEETH = 26
#: the machine's planes, z mm from the cam's back face (back to front): the cam and the
#: follower lever beside it, carrier 1, the two non-circular stages, the sectors, carrier 2, the spur gears,
#: the arm and its claw — no shaft crosses a plane where something could meet it
LAYERS = CarrierLayers(
    cam=(0.0, 12.0),
    lever=(13.0, 19.0),
    carrier1=(20.0, 28.0),
    stage23=(30.0, 40.0),
    stage35=(42.0, 52.0),
    sectors=(54.0, 64.0),
    carrier2=(66.0, 74.0),
    spurs=(76.0, 86.0),
    arm=(88.0, 96.0),
    claw=(96.0, 102.0),
)
CLEARANCE = 3.0  # mm, between every two bodies that could meet
PLATE = 8.0  # mm, carriers and arm


def family() -> Family:
    mechanism = chain(*OPTIMUM[:2])
    stages = mechanism.distribute(CENTRE_DISTANCES, exponent=EXPONENT)
    gears_23, sizing_23 = stages.stage23.sized(module=MODULE)
    gears_35, sizing_35 = stages.stage35.sized(module=MODULE)
    gear = Making(width=GEAR_WIDTH, features=Features(bore=GEAR_BORE))
    cutter = ShaperCutter(CUTTER_TEETH)
    keys = "the shaft's keyways: machine.machine.json keys_deg"
    stage_23 = ToothedPairStudy(
        "gears_2_3",
        gears_23,
        cutter,
        sizing_23.teeth[0],
        making=(gear, gear),
        notes=(f"the sun 2 (driver, fixed) and gear 3 (driven, on gear 4's shaft) mount face down; {keys}",),
    )
    stage_35 = ToothedPairStudy(
        "gears_3_5",
        gears_35,
        cutter,
        sizing_35.teeth[0],
        making=(gear, gear),
        notes=(f"gear 4 (driver) on gear 3's shaft, gear 5 (driven) on gear 9's; {keys}",),
    )
    sector_pair = GearPair.from_driver(PitchCurve.circle(SECTOR_MODULE * SECTOR_TEETH / 2), Mesh.EXTERNAL, 1)
    sectors = ToothedPairStudy(
        "gears_7_8",
        sector_pair,
        cutter,
        SECTOR_TEETH,
        making=(Making(width=GEAR_WIDTH, features=Features(bore=GEAR_BORE), quantity=0, step=False),) * 2,
        notes=("the teeth of sector gears 7 and 8: the shop cuts carriers.sector_7.dxf and carriers.sector_8.dxf",),
    )
    spur_pair = GearPair.from_driver(PitchCurve.circle(MODULE * SPUR_TEETH / 2), Mesh.EXTERNAL, 1)
    spur = Making(width=GEAR_WIDTH, features=Features(bore=GEAR_BORE))
    spurs = ToothedPairStudy(
        "gears_9_10",
        spur_pair,
        cutter,
        SPUR_TEETH,
        making=(dataclasses.replace(spur, quantity=2), spur),
        notes=(f"gears 9 and 11 are the driver (make 2), the idler 10 the driven; all three mount face down; {keys}",),
    )
    cam = CamStudy(
        "swing_cam",
        swing(mechanism),
        follower(*OPTIMUM[2]),
        max_pressure_angle_deg=CAM_PRESSURE_LIMIT_DEG,
        making=Making(width=CAM_WIDTH, features=Features(bore=CAM_BORE)),
    )
    plate = Making(width=PLATE)
    machine = DoubleCarrierMachineStudy(
        "machine",
        mechanism,
        stage_23,
        stage_35,
        sectors,
        spurs,
        cam,
        LAYERS,
        CLEARANCE,
        plate=plate,
        lever=Making(width=6.0),
        sector=Making(width=GEAR_WIDTH),
        arm=plate,
        claw=Making(width=6.0),
    )
    return Family(
        name="potseedling_seed002",
        description="Seed 002 pot-seedling mechanism: four-pose synthesis, non-circular gear stages and swing cam",
        parts=(
            SynthesisStudy("open_chain_3R", mechanism, boxes=FEASIBLE_BOXES),
            PitchPairStudy("stage_2_3", stages.stage23, module=MODULE),
            PitchPairStudy("stage_3_5", stages.stage35, module=MODULE),
            stage_23,
            stage_35,
            sectors,
            spurs,
            cam,
            machine.parts_study(),
            machine,
        ),
    )
