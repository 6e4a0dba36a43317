"""Seed 004 (Zhou et al. 2022): differential internal-engagement non-circular planetary train.

Two designs, both from ``_seed004.py`` (the paper's data, our reading of it, the design problem):

* **The published reading, as a finding.** At the paper's module the 3 mm corners of the
  pitch curves admit no shaper cutter; at m = 0.406 mm (560/140 teeth, 8-tooth cutter) the
  teeth can be cut and mesh exactly at the pitch point, but the meshing check finds them
  *fouling* 5-12 mm from it: where the ring's radius changes by 20 mm within 7.5 deg, the
  pitch curves stay within the teeth's reach over ±15 mm while the ratio changes too fast for
  the teeth there to follow. Finer modules, stub teeth and flattened radii reduce but do not
  remove it before the trajectory is lost (see README); the toothed pair is reported and its
  DXF/STL are withheld.
* **The optimised train, made** — the nearest design that can be built: the paper's layout
  (4:1 lobes, three planets) with the ratio law, carrier radius and arm ``_seed004.made_design()``
  picks — the Pareto front's coarsest design that keeps issue 27's rules (ring tips >= 0.6 m,
  mean contact ratio >= 1.4) with every objective met; the front has none at m >= 2.5 mm, so it is
  ``OPTIMUM`` cut as before (ring tips 0.43 m, 3.33 mm), which the study's front and table show
  beside the best the search found under those rules. Either way the pair is held to the ISO/TR
  10064-2 backlash at every position. Its ring, planets (make three) and carrier plate are made.
"""

import math

from _seed004 import (
    MARGINS_UNDER_PLAY,
    PLANET_BORE,
    PLANT_SPACING,
    PLANTING_DEPTH,
    PUBLISHED,
    PUBLISHED_MODULE,
    RING_ADDENDUM_MIN,
    SEEDLING_BOX,
    SITE,
    VARIANTS,
    design_train,
    front_design,
    front_points,
    made_design,
    problem,  # noqa: F401 (the studio and the optimiser find problem() here)
    train,
)

from transplanter.families import (
    Family,
    Layers,
    Making,
    PitchPairStudy,
    PlanetaryMachineStudy,
    PlanetaryStudy,
    ToothedPairStudy,
    TrainProof,
)
from transplanter.families.machines.planetary_structure import Structure
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.proportions import CUTTER_ADDENDUM, RING_RIM
from transplanter.shop.solids import Features

# -- the published reading ---------------------------------------------------------------
RING_TEETH = 80  # 20 on the planet, the paper's module
# The pair's 3.0 mm convex corners admit a cutter of pitch radius < 3.0 mm: at the paper's
# module that is impossible, so the teeth are cut at m = 0.406 mm (560/140 teeth) by an
# 8-tooth cutter, the coarsest pitch with no undercut and no secondary cutting.
FINE_RING_TEETH = 560
FINE_CUTTER_TEETH = 8
FACE_WIDTH = 12.0  # mm, not published
WIRE = (0.05, 0.01)  # mm, wire and spark gap: reaches the 0.04 mm root fillets of the fine teeth
PLANET_SHAFT = 5.0  # mm: the planet's pitch curve passes 3.84 mm from its axis, so no keyway

# -- the optimised train -----------------------------------------------------------------
WIDTH = 12.0  # mm, face width of ring, planets and carrier
RING_BOLTS = 8  # M3 clearance holes in the middle of the ring's rim, half a pitch off the +x timing notch
BOLT_HOLE = 3.4  # mm
CARRIER_BORE = 20.0  # mm, carrier shaft with a DIN 6885 key
CARRIER_MARGIN = 12.0  # mm of plate beyond the planet-shaft holes
# Planet tips shortened from the screen's 1.0 m: at 1.0 m a planet tip passes the ring 12.4 µm
# away at mid-play (driver 258°, 2-3 pitches from the pitch point), under the 14.3 µm half
# tolerance budget; at 0.94 m the smallest mid-play clearance is 18.6 µm and the smallest
# free play 0.097 mm (was 0.074 mm), contact ratio 1.28 (was 1.29).
PLANET_ADDENDUM = 0.94  # modules
# Cut for more than the ISO/TR 10064-2 minimum (0.1416 mm at this module and centre distance): cut
# for that figure the free play dips to 0.0988 mm where a planet tip passes a ring flank near its
# tip; the proof asks at least 0.191 mm for the floor at every position (min_backlash="iso"), and
# 0.193 leaves the DXF and STL their 1-2 µm of difference from the outlines.
BACKLASH = 0.193  # mm

# -- the machine ---------------------------------------------------------------------------
# Two faces that move against each other are kept MIN_AXIAL_GAP apart (issue 42: at least 0.5 mm
# unless a thrust washer or bearing takes it). 1 mm: the worst stack of what sets a face's place —
# each plate's thickness (±0.1 mm, ground stock), its flatness (0.1 mm) and a shaft's axial play in
# its deep-groove bearings (≤ 0.2 mm) — takes 0.6 mm of it, the rest keeps soil grit from wedging
# between a turning face and its neighbour.
MIN_AXIAL_GAP = 1.0  # mm
# Planes across the machine, mm from the ring's back face: the ring and planets, the front carrier
# plate (the planet shafts' front bearings in it) 1 mm in front of them, the arm plates on the
# shafts' ends 1 mm in front of the carrier, and the needles bolted to the plates' outer faces over
# 3 mm spacers: each arm plate is held on its shaft by a DIN 471 circlip on its outer face, and the
# shaft's end stands 1.7 mm out of the plate (the circlip's groove, n_min from the end) — the other
# arms' needles pass over it, so they keep the minimum gap beyond it (the structure checks it).
# Drawn in one plane an arm plate crosses another arm's needle (the build says by how much), so
# plates and needles sit in two planes: a needle passes over the other arms' plates; the needles
# all share one plane, as seed 004's objective i has them. The structure's planes (the rear carrier
# plate behind the gears, the ring's spacer and flange, the frame) follow from these
# (families/machines/planetary_structure.py).
LAYERS = Layers(
    gears=(0.0, WIDTH),
    carrier=(WIDTH + MIN_AXIAL_GAP, 2 * WIDTH + MIN_AXIAL_GAP),
    plates=(26.0, 34.0),
    needles=(37.0, 43.0),
    min_axial_gap=MIN_AXIAL_GAP,
)
CLEARANCE = 3.0  # mm, between any two bodies that could meet (moving parts, box, soil)
# Materials (transplanter.shop.catalogue). Seed 004 names none; it says only that the non-circular
# internal gear "can be manufactured by wire cutting or powder metallurgy". Ours: the gears in C45
# quenched and tempered (a wire-EDM blank that holds its shape when cut), the carrier plates in
# S235JR plate, the arm plates in C45+QT plate (the hub of the planet shaft's 3x3 key: S235's yield
# leaves that key short at the needle force below), the needles — in wet paddy soil — in
# X5CrNi18-10 stainless steel.
GEAR_STEEL, PLATE_STEEL, NEEDLE_STEEL = "C45", "S235JR", "X5CrNi18-10"
ARM_PLATE = Making(width=8.0, material=GEAR_STEEL)  # mm thick; bore, key and needle holes set by the study
NEEDLE = Making(width=6.0, material=NEEDLE_STEEL)  # mm thick flat needle, 6 mm wide
# What holds and drives the train (issue 42), stated: the design load — 30 N at the needle tip,
# against its motion (seed 004 gives no force; the one measurement of the kind we found is a rice
# transplanter finger's: mean tangential force 3.1-5.3 N, one-millisecond peaks of the resultant
# 28.3-29.7 N, Kumar & Thomas, AgricEngInt: CIGR Journal 17(1):30-43, 2015 — its peak, rounded up,
# taken as acting all the way through the soil; the mesh reaction it causes at the planet's least
# pitch radius, whole on every support, sizes the bearings), 1 mm running clearance between two pieces of hardware that
# turn against each other (a sleeve passing a bore circlip, the carrier shaft in the hollow ring
# shaft), the carrier shaft in the carrier's Ø20 keyed bore, tie tubes at R70 between the planets
# (their Ø12 17 mm from the planets' tips), a 20 mm gap between the frame plates, 25 mm hub seats for the two
# prime movers' sprockets, and the seedling box: 280 mm wide (a standard rice mat), 2 mm sheet, the
# door's lip 25 mm up from the floor (the mat's 20 mm soil block and 5 over it). Plates in S235JR,
# the ring's spacer in 6061-T6 (light; its tapped holes engage 2 d), the ring flange — the hub of
# the ring drive's key, short in aluminium under 30 N at the needles — and the shafts in C45.
STRUCTURE = Structure(
    needle_force_n=30.0,
    running_clearance=1.0,
    carrier_shaft=CARRIER_BORE,
    tie_radius=70.0,
    frame_gap=20.0,
    drive_hub=25.0,
    box_width=280.0,
    sheet=2.0,
    door_lip=25.0,
    plate_material=PLATE_STEEL,
    light_material="6061-T6",
    flange_material=GEAR_STEEL,
    shaft_material=GEAR_STEEL,
)


def ring_bolt_holes(pair, module: float) -> tuple:
    """M3 clearance holes on the middle of the ring's rim, half a pitch off the +x timing notch."""
    rim = pair.driver.max_radius().value + (CUTTER_ADDENDUM + RING_RIM / 2) * module
    bolts = [2 * math.pi * (k + 0.5) / RING_BOLTS for k in range(RING_BOLTS)]
    return tuple((rim * math.cos(t), rim * math.sin(t), BOLT_HOLE) for t in bolts)


def published_parts(published) -> tuple:
    """The paper's pair, its fine-module teeth as a finding (no shop files), and its train."""
    return (
        PitchPairStudy("ring_planet_pitch", published.pair, teeth=RING_TEETH),
        ToothedPairStudy(
            "ring_planet_teeth",
            published.pair,
            ShaperCutter(FINE_CUTTER_TEETH, tip_fillet=0.1),
            teeth=FINE_RING_TEETH,
            making=(
                Making(width=FACE_WIDTH, wire=WIRE, material=GEAR_STEEL),
                Making(
                    width=FACE_WIDTH,
                    features=Features(bore=PLANET_SHAFT, keyway=False),
                    wire=WIRE,
                    material=GEAR_STEEL,
                ),
            ),
            # a finding (see above): no shop files; standard teeth are kept (trimming the
            # ring's tips to the closed-form limit, 0.35 m, loses the contact)
            must_mesh=False,
            trim_ring_tips=False,
            train=TrainProof(published),
            rejected=(
                ("paper module (80/20 teeth, 12-tooth cutter)", RING_TEETH, ShaperCutter(12, tip_fillet=0.1)),
                ("m = 0.71 mm (320/80 teeth, 8-tooth cutter)", 320, ShaperCutter(8, tip_fillet=0.1)),
            ),
        ),
        PlanetaryStudy(
            "transplanting_train",
            published,
            seedling_box=SEEDLING_BOX,
            plant_spacing=PLANT_SPACING,
            planting_depth=PLANTING_DEPTH,
            gearbox_radius=published.pair.driver.max_radius().value + 10.0,
            reference=PUBLISHED,
            variants=tuple((label, train(*args)) for label, args in VARIANTS),
        ),
    )


def made_parts(published) -> tuple:
    """The optimised train at the coarsest module that cuts and meshes: ring, planets, carrier."""
    # the front's coarsest design with ring tips >= 0.6 m, a mean contact ratio >= 1.4 and every
    # objective met — or, where the front has none, OPTIMUM as cut before issue 27 (_seed004)
    made, cut = made_design()
    optimised = design_train(made)
    pair = optimised.pair
    best, best_module = front_design(2.5)  # the best the search found with 0.6 m ring tips
    planet_shafts = Features.bolt_circle(3, pair.centre_distance, PLANET_BORE, bore=CARRIER_BORE)
    gears = ToothedPairStudy(
        "optimised_ring_planet",
        pair,
        ShaperCutter(cut.cutter_teeth),
        teeth=cut.teeth[0],
        making=(
            Making(width=WIDTH, features=Features(holes=ring_bolt_holes(pair, cut.module)), material=GEAR_STEEL),
            Making(width=WIDTH, features=Features(bore=PLANET_BORE), material=GEAR_STEEL),
        ),
        addendum=(cut.ring_addendum, min(cut.pinion_addendum, PLANET_ADDENDUM)),
        trim_ring_tips=False,
        backlash=BACKLASH,
        min_backlash="iso",  # the ISO/TR 10064-2 minimum at every position, the dips included
        train=TrainProof(optimised, SITE, keep=tuple(MARGINS_UNDER_PLAY.items())),
    )
    return (
        PitchPairStudy("optimised_pitch", pair, teeth=cut.teeth[0]),  # ν, curvature, convexity
        gears,
        PlanetaryStudy(
            "optimised_train",
            optimised,
            seedling_box=SEEDLING_BOX,
            plant_spacing=PLANT_SPACING,
            planting_depth=PLANTING_DEPTH,
            reference=PUBLISHED + (("module", PUBLISHED_MODULE, "mm"),),
            site=SITE,
            module=cut.module,
            compare=(
                ("published reading", published, 0.0),
                ("best with 0.6 m ring tips, m >= 2.5", design_train(best), best_module),
            ),
            must_meet=True,
            # the planet layout, drawn not cut (quantity 0): the machine cuts its two carrier plates
            # to it, with bearing seats, tie-screw holes and the shaft's keyed bore
            carrier=(
                pair.centre_distance + PLANET_BORE / 2 + CARRIER_MARGIN,
                Making(width=WIDTH, features=planet_shafts, material=PLATE_STEEL, quantity=0),
            ),
            front=front_points(made, cut.module),  # module against the smallest objective margin
            min_ring_addendum=RING_ADDENDUM_MIN,
        ),
        # the whole machine, posed from the gears' and the carrier's files: the arms as parts
        PlanetaryMachineStudy(
            "machine",
            optimised,
            gears,
            carrier="optimised_train",
            site=SITE,
            layers=LAYERS,
            clearance=CLEARANCE,
            plate=ARM_PLATE,
            needle=NEEDLE,
            structure=STRUCTURE,
        ),
    )


def family() -> Family:
    published = train()
    return Family(
        name="planetary_seed004",
        description="Seed 004 differential internal non-circular planetary train: the published reading as a "
        "finding, and the optimised train whose ring, planets and carrier are made",
        parts=(*published_parts(published), *made_parts(published)),
    )
