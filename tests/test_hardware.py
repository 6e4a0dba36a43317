"""Generic hardware (machine.hardware): turned parts re-read from their drawings, bought parts'
judged sections, links mounted on links — no build."""

from __future__ import annotations

import dataclasses
import io
import math

import ezdxf
import numpy as np
import pytest

from transplanter.core.errors import SpecError
from transplanter.machine.bodies import Link, moving_links
from transplanter.machine.hardware import HIDDEN, TURN, Fitted, Turned, mounted, read_turned
from transplanter.shop import dxf
from transplanter.shop.catalogue import bearing_for, circlip_for_shaft, fit, key_for, screw


def _shaft() -> Turned:
    key, ring = key_for(10, 12), circlip_for_shaft(10)
    return Turned(
        "t.shaft",
        10.0,
        49.5,
        keyways=((13.8, key.length, key.b, key.t1, key.shaft_note(10)),),
        grooves=((0.6, ring.groove_width, ring.groove_diameter, ring.groove_note),),
        fits=((1.7, 9.7, fit(10, "k6").text),),
        quantity=3,
    )


def test_a_turned_part_is_its_drawing_and_its_exact_solid():
    shaft = _shaft()
    record, files = shaft.files()
    data = files["t.shaft.dxf"]
    doc = ezdxf.read(io.StringIO(data.decode()))
    layers = {e.dxf.layer for e in doc.modelspace()}
    assert dxf.CUT not in layers and TURN in layers  # a lathe part: nothing for the wire
    again = read_turned(data)
    assert again.same_as(shaft) and not again.same_as(Turned("x", 10.0, 49.5))
    # the exact volume: the cylinder less the keyseat (its rectangle less the sliver above the
    # circle) less the groove's ring
    key, ring = key_for(10, 12), circlip_for_shaft(10)
    r, w = 5.0, key.b / 2
    seg = r * r * math.acos(math.sqrt(r * r - w * w) / r) - w * math.sqrt(r * r - w * w)  # circle above the chord
    keyseat = (key.b * (key.t1 - (r - math.sqrt(r * r - w * w))) + seg) * key.length
    groove = math.pi * (r * r - (ring.groove_diameter / 2) ** 2) * ring.groove_width
    expected = math.pi * r * r * 49.5 - keyseat - groove
    assert record["solid_volume_mm3"] == pytest.approx(expected, rel=1e-9)
    assert record["stl"]["watertight"] and record["step"]["volume_rel_error"] < 1e-6
    assert shaft.section().area == pytest.approx(math.pi * r * r, rel=1e-4)  # its polygon, chords 0.25 µm
    text = data.decode()
    assert "make 3" in text and "k6" in text and "C45" in text


def test_a_bored_tube_reads_its_bore_from_the_hidden_lines():
    tube = Turned("t.tube", 12.0, 14.0, bore=5.5)
    data = tube.drawing()
    assert HIDDEN in {e.dxf.layer for e in ezdxf.read(io.StringIO(data.decode())).modelspace()}
    assert read_turned(data).bore == pytest.approx(5.5)
    assert tube.section().area == pytest.approx(math.pi / 4 * (144 - 5.5**2), rel=1e-4)


def test_bad_turned_parts_are_named():
    with pytest.raises(SpecError, match="keyway depth"):
        Turned("x", 10.0, 20.0, bore=7.0, keyways=((2.0, 8.0, 3.0, 1.8, ""),))
    with pytest.raises(SpecError, match="feature"):
        Turned("x", 10.0, 20.0, grooves=((19.5, 1.1, 9.6, ""),))
    with pytest.raises(SpecError, match="crosses the keyway"):
        Turned("x", 10.0, 20.0, keyways=((2.0, 8.0, 3.0, 1.8, ""),), grooves=((5.0, 1.1, 9.6, ""),))


def test_bought_parts_are_judged_by_what_stands_out_of_their_hosts():
    pick = bearing_for(10, 60, 1200)
    section, z = Fitted("b", pick, "carrier", 16.0).judged()
    assert pick.designation == "6000-2Z" and z == (16.0, 24.0)
    assert section.area == pytest.approx(math.pi / 4 * (26**2 - 10**2), rel=1e-4)
    head, z = Fitted("s", screw("M3", 20), "ring", 12.0, flip=True).judged()
    assert z == (12.0, 15.0)  # put in from the front: its head in front of z = 12
    assert Fitted("s", screw("M5", 35), "carrier", -13.0).judged()[1] == (-18.0, -13.0)
    assert Fitted("k", key_for(20, 12), "carrier", 0.0).judged() is None  # inside its hub


def test_a_mounted_link_is_rigid_to_its_base_and_bounds_its_speed():
    base = Link("carrier", lambda t: (0 * np.asarray(t), 0 * np.asarray(t), -np.asarray(t)), 0.0, 1.0)
    tube = mounted(base, "carrier@tie_1", 70.0, 0.0)
    theta = np.linspace(0.0, 2 * math.pi, 90, endpoint=False)
    x, y, _ = tube.pose(theta)
    assert np.allclose(np.hypot(x, y), 70.0) and tube.speed == pytest.approx(70.0)
    moving = moving_links({"carrier": base, tube.name: tube, "fixed": Link.fixed()}, theta)
    assert not moving("carrier", tube.name) and moving("fixed", tube.name)


def test_a_planet_bearing_leaves_its_sleeve_a_wall_whatever_the_load():
    """Under a light load the thinnest bearing that carries it (a 61800 on Ø10) has a bore circlip
    whose lugs leave no sleeve: the structure takes the next that does (61900); under seed 004's
    former 100 N (1 153 N on each support) the 6000; a load nothing carries names the parameter."""
    from transplanter.families.machines.planetary_structure import Structure, _planet_bearing
    from transplanter.shop.catalogue import bearing_for

    light, heavy = Structure(needle_force_n=30.0), Structure(needle_force_n=100.0)
    assert bearing_for(10.0, 60.0, 345.8).designation.startswith("61800")
    assert _planet_bearing(10.0, 60.0, 345.8, light).designation.startswith("61900")
    assert _planet_bearing(10.0, 60.0, 1152.8, heavy).designation.startswith("6000")
    with pytest.raises(SpecError, match="no planet bearing for Ø10 at needle_force_n = 5000 N: ") as e:
        _planet_bearing(10.0, 60.0, 5e4, Structure(needle_force_n=5000.0))
    assert len(str(e.value)) < 400


def test_a_turned_part_lists_its_operations_and_one_drawn_for_reference_ships_its_drawing_only():
    """Issue 42: the lathe's work as a numbered routing (turn with the seats' fits, the grooves, the
    keyways, then the part's own operations); quantity 0 ships the drawing, no STL or STEP."""
    from transplanter.shop import formats

    post = Turned(
        "p.post",
        16.0,
        18.0,
        grooves=((1.0, 1.1, 15.2, "DIN 471 16x1"),),
        keyways=((5.0, 8.0, 5.0, 3.0, "key 5x5"),),
        operations=("drill Ø4.2 and tap M5 10 deep at each end",),
        material="S235JR",
    )
    assert [line for line in post.operation_lines() if line.startswith("op ")] == [
        "op 10: turn Ø16 x 18",
        "op 20: turn the circlip grooves",
        "op 30: mill the keyways",
        "op 40: drill Ø4.2 and tap M5 10 deep at each end",
    ]
    record, files = post.files()
    assert set(files) == {"p.post.dxf", "p.post.stl", "p.post.step"} and record["operations"][-1].startswith("op 40")
    drawn = dataclasses.replace(post, quantity=0)
    record, files = drawn.files()
    assert set(files) == {"p.post.dxf"} and record["shipped"] == formats.REFERENCE_ONLY
    assert b"do not make: drawn for reference" in files["p.post.dxf"]
