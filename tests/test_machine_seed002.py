"""The whole seed-002 machine (issue 29): both carriers, the sector and spur gears, the arm and
its claw as parts, posed from the made parts; the claw through the four poses, the gearbox above
the soil; the kinematics against the synthesised chain."""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import sys

import numpy as np
import pytest

from transplanter.core.errors import GeometryError, SpecError
from transplanter.families.machines.carrier_machine import GEARBOX_ABOVE_SOIL_MM, CarrierLayers
from transplanter.geometry.pitch import GearPair, Mesh, PitchCurve
from transplanter.machine.bodies import MOTION_POSITIONS
from transplanter.machine.carriers import CarrierLayout, DoubleCarrierMachine, MadeMesh, pair_pose


def _machine(built):
    folder = built / "potseedling_seed002"
    return folder, json.loads((folder / "manifest.json").read_text())["parts"]["machine"]


@pytest.fixture(scope="module")
def seed002(parts_dir):
    sys.path.insert(0, str(parts_dir))
    try:
        import _seed002
        import potseedling_seed002

        yield _seed002, potseedling_seed002
    finally:
        sys.path.remove(str(parts_dir))


def test_the_seed002_machine_ships_every_part_and_its_record(built):
    folder, rec = _machine(built)
    machine = rec["results"]["machine"]
    names = set(machine["bodies"])
    assert names == {
        "carrier_1", "carrier_2", "cam", "lever", "roller", "sun", "gear_3", "gear_4", "gear_5",
        "sector_7", "sector_8", "gear_9", "gear_10", "gear_11", "arm", "claw", "soil",
    }  # fmt: skip
    # carriers, sectors, the lever, the arm and the claw ship as parts (the part the machine is
    # posed from): DXF, STL, STEP
    parts = json.loads((folder / "manifest.json").read_text())["parts"]["carriers"]
    assert "carriers" in rec["parameters"]["uses"]
    for part in ("carrier_1", "carrier_2", "sector_7", "sector_8", "lever", "arm", "claw"):
        for ext in (".dxf", ".stl", ".step"):
            assert f"carriers.{part}{ext}" in parts["files"]
        assert b"make 1" in (folder / f"carriers.{part}.dxf").read_bytes()
    assert parts["results"]["keys_deg"] == machine["keys_deg"]  # cut as the machine is posed
    # the sector pair's full gears are the teeth's proof, not parts: their notes say so
    assert b"do not cut this drawing" in (folder / "gears_7_8.driver.dxf").read_bytes()
    assert b"make 2" in (folder / "gears_9_10.driver.dxf").read_bytes()  # gears 9 and 11
    rows = list(csv.DictReader(io.StringIO((folder / machine["motion"]).read_text())))
    assert len(rows) == MOTION_POSITIONS >= 720
    assert {f"{n}.{c}" for n in names for c in ("x_mm", "y_mm", "angle_deg")} | {"driver_deg"} == set(rows[0])
    # stage 2-3 and the spur gears are seen from their backs: mounted face down
    assert {n for n, b in machine["bodies"].items() if b.get("mirrored")} == {
        "sun", "gear_3", "gear_9", "gear_10", "gear_11",
    }  # fmt: skip
    assert rec["results"]["assembly"]["bodies"] == 16 and rec["results"]["assembly"]["max_overlap_mm3"] <= 1e-6
    from PIL import Image

    with Image.open(folder / machine["animation"]) as im:
        assert (folder / machine["animation"]).stat().st_size <= 2_000_000 and im.n_frames >= 72


def test_the_claw_passes_the_four_poses_and_the_gearbox_clears_the_soil(built):
    """Posed from the made meshes and the follower on the re-read cam, the claw meets Table 1's
    four poses within the stated tolerance, every gearbox body stays >= 40 mm above the soil
    (seed 002 requirement 7), and only the claw's tines enter the soil."""
    _, rec = _machine(built)
    machine = rec["results"]["machine"]
    poses = machine["poses"]
    assert [p["pose"] for p in poses] == [1, 2, 3, 4]
    for p in poses:
        pos, att = p["tolerance"]
        assert p["pass"] and p["tip_off_mm"] <= pos and abs(p["attitude_off_deg"]) <= att
        # the keys are cut as designed: what the made meshes cost at the poses is the gears' play
        assert 0.0 < p["tip_off_mm"] < 1.0 and 0.0 < abs(p["attitude_off_deg"]) < 0.5
    low = machine["gearbox_above_soil"]
    assert low["required_mm"] == GEARBOX_ABOVE_SOIL_MM and low["min_mm"] >= 40.0
    assert low["margin_mm"] == pytest.approx(low["min_mm"] - 40.0, abs=1e-6)
    by_pair = {frozenset(r["bodies"]): r for r in machine["clearances"]}
    for name in ("carrier_1", "carrier_2", "sector_7", "gear_11", "lever"):
        row = by_pair[frozenset((name, "soil"))]
        assert row["required_mm"] == 40.0 and row["pass"] and row["min_mm"] >= low["min_mm"] - 1e-9
    claw = by_pair[frozenset(("claw", "soil"))]
    depth = claw["enters_from_tip_mm"]
    assert "working" in claw and 30.0 <= depth["deepest_from_tip_mm"] <= depth["at_most_mm"] < 44.0
    assert by_pair[frozenset(("arm", "soil"))]["min_mm"] >= 3.0  # the arm plate stays out
    assert by_pair[frozenset(("gear_9", "gear_11"))]["min_mm"] > 30.0  # 9 and 11 never meet


def test_the_joined_bodies_touch_and_never_overlap(built):
    """Posed from the motion table, the DXF bodies read with ezdxf alone (mirrored where the record
    says): every mesh and the roller on the cam are in contact and never overlap — the poses are
    the made parts' own, at their driving flanks. Within the judge's 5 µm outlines: found 4-6.4 µm
    apart at most (a mesh at the middle of its play would be ~45 µm off), overlaps under 4e-4 mm²
    (chords of the simplified circles)."""
    import shapely

    from test_machine import _relative, _section

    folder, rec = _machine(built)
    machine = rec["results"]["machine"]
    bodies = machine["bodies"]
    table = np.loadtxt(folder / machine["motion"], delimiter=",", skiprows=1)
    cols = (folder / machine["motion"]).read_text().splitlines()[0].split(",")
    sections = {}
    for name in ("cam", "roller", "sun", "gear_3", "gear_4", "gear_5", "sector_7", "sector_8", "gear_9", "gear_10",
                 "gear_11"):  # fmt: skip
        sections[name] = _section((folder / bodies[name]["dxf"]).read_bytes())
        if bodies[name].get("mirrored"):
            sections[name] = shapely.affinity.scale(sections[name], 1.0, -1.0, origin=(0, 0))

    def pose(name, row):
        i = cols.index(f"{name}.x_mm")
        return [table[row, i + k] for k in range(3)]

    for a, b in (("cam", "roller"), ("sun", "gear_3"), ("gear_4", "gear_5"), ("sector_7", "sector_8"),
                 ("gear_9", "gear_10"), ("gear_10", "gear_11")):  # fmt: skip
        for row in range(0, len(table), 60):  # every 15 deg of the driver
            moved = _relative(sections[a], pose(a, row), pose(b, row))
            assert shapely.distance(moved, sections[b]) < 0.015, (a, b, row)
            assert shapely.intersection(moved, sections[b]).area < 1e-3, (a, b, row)


def test_parts_on_one_shaft_turn_together_and_their_keys_are_stated(built):
    """From the motion table: the parts keyed on one shaft keep their angle to each other over the
    whole cycle, and the record's keyway angles are those of the parts' +y (a part mounted face
    down shows its keyway at -y)."""
    folder, rec = _machine(built)
    machine = rec["results"]["machine"]
    table = np.loadtxt(folder / machine["motion"], delimiter=",", skiprows=1)
    cols = (folder / machine["motion"]).read_text().splitlines()[0].split(",")

    def keyway(name):
        turn = -90.0 if machine["bodies"][name].get("mirrored") else 90.0
        return table[:, cols.index(f"{name}.angle_deg")] + turn

    for a, b, key in (
        ("gear_4", "gear_3", "gear_4_keyway_from_gear_3s"),
        ("gear_9", "gear_5", "gear_9_keyway_from_gear_5s"),
        ("sector_7", "lever", "sector_7_keyway_from_the_levers"),
        ("arm", "gear_11", "arm_keyway_from_gear_11s"),
    ):
        apart = (keyway(a) - keyway(b) + 180.0) % 360.0 - 180.0
        assert np.ptp(apart) < 1e-5, (a, b)  # keyed: they turn together
        assert apart[0] == pytest.approx(machine["keys_deg"][key], abs=1e-3)


def test_the_claw_tip_envelope_under_the_meshes_play(built):
    """Every mesh anywhere within its measured play: the arm turns by at most the sum of the
    plays (stage 2-3's carried through 4-5's ratio), carrier 2 by the sectors'; the tip's envelope
    is what those turns can move it — no more than L2 and L3 times them."""
    folder, rec = _machine(built)
    under = rec["results"]["machine"]["tip_under_play"]
    plays = under["plays_deg"]
    for pair, record in (("stage23", "gears_2_3"), ("sectors", "gears_7_8"), ("spurs", "gears_9_10")):
        teeth = json.loads((folder / f"{record}.teeth.json").read_text())["results"]["assembly"]
        assert 0.0 < plays[pair] and teeth["backlash_mm"]["max"] > 0.0
    assert under["arm_turn_max_deg"] >= plays["stage35"] + 2 * plays["spurs"]
    assert under["carrier_2_turn_deg"] >= plays["sectors"]
    bound = 75.56 * math.radians(under["carrier_2_turn_deg"]) + 125.0 * math.radians(under["arm_turn_max_deg"])
    assert 0.1 < under["max_mm"] <= bound + 1e-6
    assert 0.0 < under["picking_max_mm"] <= under["max_mm"] and 0.0 < under["planting_max_mm"] <= under["max_mm"]


def test_the_gear_and_cam_routes_reproduce_the_chain(seed002):
    """With design meshes (no measured error) and the cam's law, the carriers, gears and arm
    posed by DoubleCarrierMachine put the tip where the open chain does (to 0.02 mm: the swing
    interpolated between 1440 positions), the sun and the cam stand still, the arm turns once
    relative to carrier 1 per cycle."""
    s, _ = seed002
    ch = s.chain(*s.OPTIMUM[:2])
    d = ch.distribute(s.CENTRE_DISTANCES, exponent=s.EXPONENT)
    g23, _ = d.stage23.sized(module=1.5)
    g35, _ = d.stage35.sized(module=1.5)
    f = s.follower(*s.OPTIMUM[2])
    sec = GearPair.from_driver(PitchCurve.circle(40.0), Mesh.EXTERNAL, 1)
    spur = GearPair.from_driver(PitchCurve.circle(19.5), Mesh.EXTERNAL, 1)
    l1, l2, _ = ch.link_lengths
    lay = CarrierLayout.solve(l1, l2, g23.centre_distance, g35.centre_distance, f.pivot_distance, 80.0, 39.0)
    tau = 2 * math.pi * np.arange(1440) / 1440
    m = DoubleCarrierMachine(
        ch, lay, MadeMesh(g23), MadeMesh(g35), MadeMesh(sec), MadeMesh(spur), f, tau, s.swing(ch)(tau)
    )
    t = np.linspace(0.0, 2 * math.pi, 997)
    assert np.abs(m.tip(t) - m.to_machine(ch.state(t).tip)).max() < 0.02
    poses = m.poses(t)
    assert np.ptp(poses["sun"][2]) < 1e-9 and np.ptp(poses["carrier1"][0]) == 0.0
    rel = np.unwrap(poses["arm"][2] - poses["carrier1"][2])
    assert rel[-1] - rel[0] == pytest.approx(2 * math.pi, abs=1e-6)
    # the shafts keep their distances on carrier 1 and 2
    assert math.dist(lay.s3, (0, 0)) == pytest.approx(g23.centre_distance)
    assert math.dist(lay.pivot, (l1, 0)) == pytest.approx(80.0)
    assert math.dist(lay.idler, (l2, 0)) == pytest.approx(39.0)
    # a mirrored pair turns its driver the other way
    assert pair_pose(0.0, 0.1, 0.2, True)[0] == pytest.approx(0.1)
    assert pair_pose(0.0, 0.1, 0.2, False)[0] == pytest.approx(-0.1)


def test_bad_seed002_machine_input_is_named(seed002):
    _, script = seed002
    fam = script.family()
    study = fam.parts[-1]
    with pytest.raises(SpecError, match="layers.spurs"):
        dataclasses.replace(study, layers=dataclasses.replace(study.layers, spurs=(76.0, 90.0)))
    with pytest.raises(SpecError, match="layers.cam"):
        CarrierLayers(**{**dataclasses.asdict(study.layers), "cam": (12.0, 0.0)})
    with pytest.raises(SpecError, match="pose_tolerance"):
        dataclasses.replace(study, pose_tolerance=(0.0, 0.5))
    with pytest.raises(SpecError, match="clearance"):
        dataclasses.replace(study, clearance=-1.0)
    with pytest.raises(GeometryError, match=r"the follower pivot \(.*\) cannot be placed: 152.2 and 60 mm"):
        CarrierLayout.solve(73.8, 75.5, 45.0, 45.0, 152.2, 60.0, 39.0)  # sectors closer than 152.2 - 73.8
    with pytest.raises(GeometryError, match="gears_2_3.dxf_meshing.csv"):
        study.build_using(None, {})
