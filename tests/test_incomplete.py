"""Incomplete non-circular gears (issue 32): intermittent laws, toothed sectors with locking arcs,
and the proof of the made parts — the picking arm of ``parts/picking_dwell.py`` as built."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import shapely

from transplanter.app import cli
from transplanter.core.errors import GeometryError, SpecError
from transplanter.families.pairs.gear_pair import pair_family
from transplanter.families.pairs.incomplete_pair import IncompletePairStudy
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.pitch import PitchCurve
from transplanter.geometry.pitch.intermittent import Dwell, IncompletePair, IntermittentLaw, Motion, is_segmented
from transplanter.geometry.teeth import generate
from transplanter.shop.dxf import DxfPart, dxf_bytes
from transplanter.shop.machining import wire_violations

LAW = "0..60: dwell; 60..360: 2*pi*(phi - pi/3)/(5*pi/3) - 0.35*sin(2*pi*(phi - pi/3)/(5*pi/3))"


def test_a_law_of_segments_reads_and_states_its_jumps():
    law = IntermittentLaw.parse(LAW)
    assert law.turn_fraction == 1 and len(law.dwells) == 1 and is_segmented(LAW) and not is_segmented("phi")
    phi = np.radians([30.0, 60.0, 210.0, 359.999])
    assert np.allclose(law.psi(phi)[:2], 0.0) and law.psi(phi)[3] == pytest.approx(2 * math.pi, abs=1e-4)
    assert law.ratio(np.radians([30.0]))[0] == 0.0
    entry, exit_ = law.transitions()
    # the driven's speed jumps from 0 to 0.78 of the driver's as the motion starts, and back at its end
    assert entry.kind == "entry" and entry.speed_jump == pytest.approx(0.78, abs=1e-9)
    assert exit_.kind == "exit" and exit_.speed_jump == pytest.approx(-0.78, abs=1e-9)
    same = IntermittentLaw((Dwell(0, 60), Motion(60, 360, LAW.split(": ")[-1])))
    assert same.psi(phi) == pytest.approx(law.psi(phi), abs=1e-12)


def test_a_csv_marks_its_dwells_with_zero_rows():
    deg = np.arange(0.0, 360.0, 5.0)
    ratio = np.where(deg < 90, 0.0, 360 / 265)  # the motion rows span 90..355 deg: one driven turn
    rows = "".join(f"{a},{r}\n" for a, r in zip(deg, ratio, strict=True))
    law = IntermittentLaw.from_csv(b"phi_deg,ratio\n" + rows.encode())
    (dwell,) = law.dwells
    # the dwell spans from the last row of the motion to the first of the next
    assert (dwell.start % 360, dwell.end % 360) == (355.0, 90.0)
    assert law.turn_fraction == 1 and law.total_rise == pytest.approx(2 * math.pi, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "error", "words"),
    [
        ("0..60: dwell; 70..360: phi", SpecError, "follow each other"),
        ("0..60: dwell; 60..300: 1.2*phi", SpecError, "one driver turn"),
        ("0..360: 2*phi", SpecError, "at least one dwell"),
        ("0..60: dwell; 60..360: 1.1*(phi - pi/3)", SpecError, "does not close"),
        ("0..60: dwell; 60..360: 1.2*(phi-pi/3) - sin(1.2*(phi-pi/3))", GeometryError, "finite speed"),
        ("0..60: dwell; 60..360: __import__('os')", SpecError, "calls something other than"),
        ("0..60: dwell; 60..360 phi", SpecError, "A..B"),
    ],
)
def test_a_bad_law_is_refused_naming_what_is_wrong(text, error, words):
    with pytest.raises(error) as info:
        IntermittentLaw.parse(text)
    assert words in str(info.value)


def test_a_planet_driving_its_ring_needs_a_ratio_below_one():
    with pytest.raises(GeometryError, match="< 1"):
        IncompletePair(IntermittentLaw.parse(LAW), 50.0, "internal")


def test_a_toothed_sector_cuts_only_its_spaces():
    m = 2.0
    curve = PitchCurve.circle(30 * m / 2)  # 30 teeth' worth of pitch circle
    spaces = math.pi * m * np.arange(5, 12)
    gear = generate(curve, ShaperCutter(16, m), None, spaces=spaces)
    assert gear.teeth == len(spaces) and len(gear.spaces) == len(spaces)
    # the rest of the rim is the blank: uncut tip circle over the other 23 pitches
    r = np.linalg.norm(gear.toothed_contour, axis=1)
    assert np.isclose(r, curve.r(0.0) + m, atol=1e-3).mean() > 0.5
    assert gear.tip_lands[-1] == math.inf


def test_a_curved_sliver_thinner_than_the_tolerance_is_no_wire_violation():
    # a ring whose closing leaves a 2 µm crescent along 3 mm of a 74 mm arc: within the shop's tolerance
    ring = shapely.Point(0, 0).buffer(74.0, quad_segs=512)
    notch = shapely.Point(74.0 + 0.002 - 40.0, 0.0).buffer(40.0, quad_segs=2048)
    assert wire_violations(shapely.difference(ring, notch), 0.145).is_empty


def test_pair_family_makes_an_incomplete_pair_from_a_law_and_refuses_what_does_not_apply():
    fam = pair_family(LAW, module=3.0, teeth=30)
    (study,) = fam.parts
    assert isinstance(study, IncompletePairStudy) and study.making is not None
    assert "incomplete" in fam.description
    with pytest.raises(SpecError, match="shift does not apply"):
        pair_family(LAW, module=3.0, teeth=30, shift=0.2)
    with pytest.raises(SpecError, match="module and one of teeth"):
        pair_family(LAW, teeth=30, centre_distance=90.0)
    with pytest.raises(SpecError, match="lock_depth = 2.5 is out of range"):
        pair_family(LAW, module=3.0, teeth=30, lock_depth=2.5)  # past the working depth: into the roots
    with pytest.raises(SpecError, match="for incomplete pairs"):
        pair_family("phi - 0.08*sin(2*phi)", teeth=24, module=1.5, lock_clearance=0.05)


def test_pair_cli_refuses_an_option_of_full_pairs_for_a_law_with_dwells(tmp_path, capsys):
    argv = ["pair", LAW, "--module", "3", "--teeth", "30", "--shift", "0.1", "-o", str(tmp_path)]
    assert cli.main(argv) == 2
    assert "shift does not apply to an incomplete pair" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


def test_a_law_written_motion_first_starts_its_motion_in_a_transition():
    """Regression (issue 41, examples/dwells.csv): 60° comes back from radians as 59.99999999999999°,
    so the motion's first sample fell outside its transition window and was judged by the motion's
    backlash band — every law written motion-first (a ratio CSV starting at 0°, or this text) was
    refused with 0.7 mm of free play "at driver 60.00 deg"."""
    law = "60..360: 2*pi*(phi - pi/3)/(5*pi/3) - 0.35*sin(2*pi*(phi - pi/3)/(5*pi/3)); 360..420: dwell"
    (study,) = pair_family(law, module=3.0, centre_distance=100.0).parts
    motion = study.pair.law.motions[0]
    phi = np.radians([motion.start, motion.start + 0.5, 200.0, motion.end - 0.5])
    assert np.degrees(phi[0]) < motion.start  # the rounding this guards against
    assert study.phases(phi).tolist() == [2, 2, 0, 2]


#: a planet driving its ring: standing 60 deg of the planet, then half a ring turn at a ratio of 0.54-0.66
RING_LAW = "0..60: dwell; 60..360: pi*(phi - pi/3)/(5*pi/3) - 0.05*sin(2*pi*(phi - pi/3)/(5*pi/3))"


@pytest.fixture(scope="module")
def ring_pair():
    fam = pair_family(RING_LAW, internal=True, module=3.0, centre_distance=40.0)
    (study,) = fam.parts
    return dataclasses.replace(study, steps=90)


def test_an_internal_incomplete_pair_meshes_on_its_reread_dxf_and_its_locks_hold_the_ring(ring_pair):
    study = ring_pair
    g = study.gears
    assert g.driven.internal and study.lock_depth is None
    # the planet's arc stops 0.3 m short of its tips (1.5 m into the ring's with the ring's 0.8 m addendum)
    motion = study.pair.law.motions[0]
    r1 = float(study.pair.r1(np.radians([motion.start]), motion=motion)[0])
    assert g.locks[0].radius == pytest.approx(r1 + 0.7 * 3.0, abs=1e-6)
    files = {
        f"{study.name}.{role}.dxf": dxf_bytes(DxfPart(f"{study.name}.{role}", gear.polygon))
        for role, gear in zip(("driver", "driven"), g.gears, strict=True)
    }
    (report,) = study.meshed(files, sources=("dxf",)).values()
    res, problems = study.judge(report)
    assert problems == [] and res["max_penetration_mm2"] == 0.0
    # the ring stands within its locking play through the dwell, and through the transitions
    assert res["dwell"]["largest_play_deg"] < 1.0 and res["transition"]["largest_play_deg"] < 1.0
    assert res["dwell"]["free_play_mm"][0] >= study.band[0]
    (entry,) = study.entry_contacts(g.driver.polygon, g.driven.polygon)
    assert entry["touching"] == "a tooth of the sector" and not entry["tip_on_tip"]
    assert 0.0 <= entry["after_dwell_end_deg"] < 1.5


def test_a_planets_end_teeth_are_shortened_to_its_locking_arc(ring_pair):
    g, m = ring_pair.gears, ring_pair.module
    lock = g.locks[0]
    (start, end) = g.driver.sectors_deg[0]  # the sector's edge lines, through its outermost spaces
    pitch = math.degrees(math.pi * m / lock.radius)
    pts = np.asarray(g.driver.polygon.exterior.coords)
    r = np.linalg.norm(pts, axis=1)
    body = np.degrees(np.arctan2(pts[:, 1], pts[:, 0]))

    def tip(lo, hi):
        return float(r[np.mod(body - lo, 360.0) < np.mod(hi - lo, 360.0)].max())

    # the tooth either side of the dwell reaches no further than the arc; its neighbours keep their tips
    assert tip(end - pitch, end) <= lock.radius + 1e-6 and tip(start, start + pitch) <= lock.radius + 1e-6
    assert tip(end - 2 * pitch, end - pitch) > lock.radius + 0.25 * m
    assert tip(start + pitch, start + 2 * pitch) > lock.radius + 0.25 * m


@pytest.fixture(scope="module")
def picker(built):
    manifest = json.loads((built / "picking_dwell" / "manifest.json").read_text())
    rec = manifest["parts"]["picker"]
    assert "error" not in rec, rec.get("error")
    return rec


def test_the_picking_arm_meshes_on_its_reread_files_and_the_locks_hold_it(picker):
    res = picker["results"]
    play = picker["parameters"]["locking_play_deg"]
    for source in ("dxf", "stl"):
        m = res["meshing"][source]
        assert m["problems"] == [] and m["max_penetration_mm2"] == 0.0
        assert m["dwell"]["largest_play_deg"] <= play and m["transition"]["largest_play_deg"] <= play
        lo, hi = picker["parameters"]["backlash_band_mm"]
        assert lo <= m["motion"]["free_play_mm"][0] and m["motion"]["free_play_mm"][1] <= hi
        assert m["refined_samples"] > 0  # the extremes were refined between the samples
    assert {"driver.dxf", "driven.dxf", "driver.step", "driven.step", "assembly.3mf"} <= {
        f.split(".", 1)[1] for f in picker["files"]
    }


def test_the_picking_arm_dwells_where_and_as_long_as_asked(picker):
    res = picker["results"]
    (dwell,) = res["dwells"]
    (entry,) = res["entry"]
    # the first tooth meets the held arm a tenth of a degree after the asked end, on its flank
    assert 0 <= entry["after_dwell_end_deg"] < 0.5 and not entry["tip_on_tip"]
    assert entry["driver_radius_below_tip_m"] > 0.5
    assert abs(dwell["made_duration_deg"] - dwell["asked_duration_deg"]) < 0.5
    assert max(abs(v) for v in dwell["held_off_law_deg"]) < picker["parameters"]["locking_play_deg"] / 2
    (jump_in, jump_out) = res["transitions"]
    assert jump_in["speed_jump_w2_per_w1"] == pytest.approx(0.78, abs=1e-6)
    assert jump_out["speed_jump_w2_per_w1"] == pytest.approx(-0.78, abs=1e-6)


def test_the_command_line_says_an_incomplete_pairs_proof_per_phase(picker):
    # what `pair` and `check --run-script` print for each source (it raised KeyError before)
    line = cli._phases_line(picker["results"]["meshing"]["dxf"])
    assert line.startswith("overlap 0 mm², motion free play") and "dwell play <=" in line and "transition play" in line
