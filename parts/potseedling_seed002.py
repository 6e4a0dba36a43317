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
import math

from _seed002 import (
    CAM_PRESSURE_LIMIT_DEG,
    CAM_SAMPLES,
    OPTIMUM,
    PLANTING_DEPTH,
    POSE_TOLERANCE,
    POT_DEPTH,
    TRAY,
    chain,
    cut_split,
    follower,
    problem,  # noqa: F401 (`transplanter design` and `optimise` read problem() from the part script)
    swing,
)

from transplanter.families import CamStudy, Family, Making, PitchPairStudy, SynthesisStudy, ToothedPairStudy
from transplanter.families.machines.carrier_machine import CarrierLayers, DoubleCarrierMachineStudy
from transplanter.families.machines.carrier_structure import CarrierStructure
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pitch import GearPair, Mesh, PitchCurve
from transplanter.shop.solids import Features

MODULE = 1.5  # mm, both gear stages
CUTTER_TEETH = 12  # shaper cutter
GEAR_WIDTH = 10.0  # mm
GEAR_BORE = 12.0  # mm, keyed (DIN 6885)
CAM_WIDTH = 12.0  # mm
CAM_BORE = 42.0  # mm: clears the Ø36 drive tube by the clearance (the cam sits on posts, not on a shaft)
#: where the synthesis may place centre and circle points (x ranges and the y range, mm)
FEASIBLE_BOXES = {"centre_x": (-60.0, 25.0), "circle_x": (30.0, 80.0), "y_range": (-100.0, 100.0)}
#: the sector gears 7-8 (ratio 1): the follower pivot is 152.2 mm from A0 and A_c 73.8 mm, so
#: they are at least 78.5 mm apart: 32 teeth of module 2.5 (80 mm)
SECTOR_MODULE, SECTOR_TEETH = 2.5, 32
#: the equal spur gears 9-10-11 on carrier 2 (A_c to Q is 75.55 mm): 26 teeth of module 1.5,
#: 39 mm apart, the idler 9.7 mm off the line A_c-Q
SPUR_TEETH = 26
#: two faces that move against each other keep this far apart, mm (issue 42: at least 0.5 mm unless a
#: thrust washer or bearing takes it): the worst stack of the plates' thickness (±0.1 mm each, ground
#: stock), flatness (0.1 mm) and a shaft's axial play in its bearings (≤ 0.2 mm) takes 0.6 mm of it
MIN_AXIAL_GAP = 1.0
#: the follower pivot's shaft end out of the lever's back face, towards the cam it passes over, mm:
#: the DIN 471 12 x 1 retaining ring that holds the lever, in its 1.1 mm groove, and the collar beyond
PIVOT_END = 2.0
#: the machine's planes, z mm from the cam's back face (back to front): the cam and the
#: follower lever beside it (the pivot's shaft end and MIN_AXIAL_GAP between them), carrier 1, the two
#: non-circular stages, the sectors, carrier 2, the spur gears, the arm and its claw — no shaft crosses
#: a plane where something could meet it, and planes that move against each other are >= MIN_AXIAL_GAP apart.
#: The gaps leave room for the structure (STRUCTURE): carrier 1's hub behind it (13-25, the lever beside
#: it), 2 mm between carrier 1 and stage 2-3 for the hub's screw heads and a shaft's spacer, carrier 1's
#: front plate at 59-67, 3 mm behind carrier 2 for the follower shaft's end, 4 mm in front of it for the
#: heads of sector 8's screws, carrier 2's front plate at 105-113
LAYERS = CarrierLayers(
    cam=(0.0, 12.0),
    lever=(18.0, 24.0),
    carrier1=(25.0, 33.0),
    stage23=(35.0, 45.0),
    stage35=(47.0, 57.0),
    sectors=(69.0, 79.0),
    carrier2=(82.0, 90.0),
    spurs=(94.0, 104.0),
    arm=(115.0, 123.0),
    claw=(123.0, 129.0),
    min_axial_gap=MIN_AXIAL_GAP,
    pivot_end=PIVOT_END,
)
#: what holds and drives the machine (families/machines/carrier_structure.py): the frame plate behind
#: the cam, carrier 1's hub keyed on the drive tube, the front plates of both carriers, z mm as LAYERS;
#: the cam's three posts (radius, deg in the cam's frame: its bolt holes), the standoffs (carrier 1's
#: and carrier 2's frames, clear of every gear's, sector's and the lever's sweep), the hub's screws.
#: Bearings and bushes are chosen for DESIGN_LOAD_N radial each at the shafts' largest speeds, carrier
#: 1 at seed 002's 60 r/min (§5.1). The load is ours (until the machine's forces are computed): three
#: times the seed's 100 N pushing-spring preload (§5.1), which reaches the bearings through the arm
#: and both carriers, covering the assembly's weight (~40 N) and its inertia at 60 r/min (~15 N)
DESIGN_LOAD_N = 300.0
STRUCTURE = CarrierStructure(
    frame=(-30.0, -18.0),
    hub=(13.0, 25.0),
    cover=(59.0, 67.0),
    front=(105.0, 113.0),
    posts=(56.0, (90.0, 210.0, 330.0)),
    standoffs_1=((40.0, 38.0), (110.0, -10.0), (-30.0, -40.0)),
    standoffs_2=((20.0, 40.0), (60.0, 40.0)),
    hub_bolts=(40.0, (90.0, 180.0, 270.0)),
    main_shaft=17.0,
    tube=36.0,
    shaft=12.0,
    load_n=DESIGN_LOAD_N,
    speed_rpm=60.0,
)
CLEARANCE = 3.0  # mm, between every two bodies that could meet
PLATE = 8.0  # mm, carriers and arm
#: materials (transplanter.shop.catalogue): seed 002 names none (its prototype is only "processed").
#: Ours: the gears, sectors, cam and follower lever in C45 quenched and tempered (teeth, cam track and
#: pin bore that wear), the carriers and the arm in S235JR plate, the claw, which grips moist pots,
#: in X5CrNi18-10 stainless steel
GEAR_STEEL, PLATE_STEEL, CLAW_STEEL = "C45", "S235JR", "X5CrNi18-10"


def family() -> Family:
    mechanism = chain(*OPTIMUM[:2])
    stages = cut_split(mechanism)  # at EXPONENT, as the studio's page judges it
    gears_23, sizing_23 = stages.stage23.sized(module=MODULE)
    gears_35, sizing_35 = stages.stage35.sized(module=MODULE)
    gear = Making(width=GEAR_WIDTH, features=Features(bore=GEAR_BORE), material=GEAR_STEEL)
    cutter = ShaperCutter(CUTTER_TEETH)
    keys = "the shaft's keyways: machine.machine.json keys_deg"
    # the sun is keyed on the fixed shaft (STRUCTURE.main_shaft), gear 3 on its own
    sun = dataclasses.replace(gear, features=Features(bore=STRUCTURE.main_shaft))
    stage_23 = ToothedPairStudy(
        "gears_2_3",
        gears_23,
        cutter,
        sizing_23.teeth[0],
        making=(sun, gear),
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
        making=(
            Making(width=GEAR_WIDTH, features=Features(bore=GEAR_BORE), quantity=0, step=False, material=GEAR_STEEL),
        )
        * 2,
        notes=("the teeth of sector gears 7 and 8: the shop cuts carriers.sector_7.dxf and carriers.sector_8.dxf",),
    )
    spur_pair = GearPair.from_driver(PitchCurve.circle(MODULE * SPUR_TEETH / 2), Mesh.EXTERNAL, 1)
    spur = Making(width=GEAR_WIDTH, features=Features(bore=GEAR_BORE), material=GEAR_STEEL)
    spurs = ToothedPairStudy(
        "gears_9_10",
        spur_pair,
        cutter,
        SPUR_TEETH,
        making=(dataclasses.replace(spur, quantity=2), spur),
        notes=(f"gears 9 and 11 are the driver (make 2), the idler 10 the driven; all three mount face down; {keys}",),
    )
    radius, angles = STRUCTURE.posts
    posts = tuple(
        (radius * math.cos(math.radians(a)), radius * math.sin(math.radians(a)), STRUCTURE.screws["posts"][1])
        for a in angles
    )
    cam = CamStudy(
        "swing_cam",
        swing(mechanism),
        follower(*OPTIMUM[2]),
        n=CAM_SAMPLES,
        max_pressure_angle_deg=CAM_PRESSURE_LIMIT_DEG,
        making=Making(width=CAM_WIDTH, features=Features(holes=((0.0, 0.0, CAM_BORE), *posts)), material=GEAR_STEEL),
    )
    plate = Making(width=PLATE, material=PLATE_STEEL)
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
        lever=Making(width=6.0, material=GEAR_STEEL),
        sector=Making(width=GEAR_WIDTH, material=GEAR_STEEL),
        arm=plate,
        claw=Making(width=6.0, material=CLAW_STEEL),
        structure=STRUCTURE,
        tray=TRAY,
        pot_depth=POT_DEPTH,
        planting_depth=PLANTING_DEPTH,
        pose_tolerance=POSE_TOLERANCE,
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
