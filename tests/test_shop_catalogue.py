"""The bought parts' standard data and the bill of materials (issue 42): figures against spot values
of the standards and makers' catalogues, the selections (the smallest that carries the load; an
error naming the parameter when none does), ISO 281 against SKF's worked example, and the bill of
materials' stable item numbers and one-to-one check. Pure and fast: no build.
"""

from __future__ import annotations

import random

import pytest

from transplanter.core.errors import SpecError
from transplanter.shop.bom import HEADER, BoughtPart, MadePart, build_bom, numbers_from_csv
from transplanter.shop.catalogue import (
    bearing,
    bearing_for,
    bearings,
    bush_for,
    circlip_for_bore,
    circlip_for_shaft,
    fit,
    key_for,
    material,
    notes,
    nut,
    screw,
    table,
    washer,
)
from transplanter.shop.catalogue.bearings import SERIES, _check, equivalent_load, rating_life, rating_life_h
from transplanter.shop.catalogue.bushes import bushes
from transplanter.shop.catalogue.rings import circlips

TABLES = (
    "deep_groove_ball_bearings",
    "wrapped_bushes",
    "parallel_keys",
    "parallel_key_lengths",
    "retaining_rings_shafts",
    "retaining_rings_bores",
    "plain_washers",
    "socket_head_cap_screws",
    "socket_head_cap_screw_lengths",
    "hex_nuts",
    "shaft_and_hole_tolerances",
    "materials",
    "gear_materials",
)


@pytest.mark.parametrize("name", TABLES)
def test_every_row_cites_its_source_and_every_table_says_its_standard(name):
    rows = table(name)
    assert rows and all(r["source"].strip() for r in rows)
    said = " ".join(notes(name)) + " ".join(r["source"] for r in rows)
    assert any(s in said for s in ("ISO", "DIN", "EN")), name


# -- spot values from the standards and the makers' catalogues ------------------------------------


def test_6001_as_skf_lists_it():
    b = bearing("6001-2Z")
    assert (b.d, b.D, b.B, b.r_min) == (12, 28, 8, 0.3)
    assert (b.C_n, b.C0_n, b.f0) == (5400, 2360, 13)
    speeds = (b.reference_speed_rpm, b.limiting_speed_rpm, b.limiting_speed_2z_rpm)
    assert speeds == (60000, 38000, 30000) and b.mass_kg == 0.022
    assert bearing("6204").C_n == 13500 and bearing("61801").D == 21 and bearing("62/22").D == 50


def test_the_bearing_table_is_the_iso_15_plan_it_claims():
    """Bores 5-50 in the four series; within a series D and B grow with d (C need not: SKF rates
    618/9 above 61800); a 2Z bearing runs slower than the open one; catches a row read out of line."""
    rows = bearings()
    assert len(rows) == 64 and {b.series for b in rows} == set(SERIES)
    assert min(b.d for b in rows) == 5 and max(b.d for b in rows) == 50
    for s in SERIES:
        ser = sorted((b for b in rows if b.series == s), key=lambda b: b.d)
        assert all(x.D <= y.D and x.B <= y.B for x, y in zip(ser, ser[1:], strict=False)), s
    for b in rows:
        assert b.D > b.d and b.C0_n < b.C_n * 1.2 and b.limiting_speed_rpm < b.reference_speed_rpm
        assert b.limiting_speed_2z_rpm is None or b.limiting_speed_2z_rpm <= b.limiting_speed_rpm


def test_din_6885_for_a_12_mm_shaft():
    k = key_for(12, hub_length=16)
    assert (k.b, k.h, k.t1, k.t2, k.length) == (4, 4, 2.5, 1.8, 16)
    assert k.designation == "DIN 6885 A 4x4x16"
    assert k.shaft_note(12) == "keyway 4 N9 x 2.5 +0.1 deep (d - t1 = 9.5)"
    assert (key_for(12.01, 20).b, key_for(30, 40).b, key_for(30.5, 40).b) == (5, 8, 10)  # "over ... up to"


def test_din_471_and_472_for_12_mm():
    c = circlip_for_shaft(12)
    assert (c.s, c.groove_diameter, c.groove_width, c.n_min) == (1, 11.5, 1.1, 0.8)
    assert (c.groove_upper, c.groove_lower) == (0, -0.11)
    r = circlip_for_bore(12)
    assert (r.s, r.groove_diameter, r.groove_width) == (1, 12.5, 1.1)
    assert circlip_for_bore(28).groove_diameter == 29.4  # FreeCAD Fasteners' 20.4 is a typo
    for c in circlips("DIN 471"):
        assert c.groove_diameter < c.nominal and c.groove_width > c.s
    for c in circlips("DIN 472"):
        assert c.groove_diameter > c.nominal and c.groove_width > c.s


def test_iso_286_limits_for_the_bearing_seats():
    assert (fit(12, "h6").upper, fit(12, "h6").lower) == (0, -0.011)
    assert fit(12, "k6").text == "Ø12 k6 (+0.012/+0.001)"
    assert fit(12, "j6").text == "Ø12 j6 (+0.008/-0.003)"
    assert fit(28, "H7").text == "Ø28 H7 (+0.021/0)"
    assert fit(10, "k6").text == "Ø10 k6 (+0.010/+0.001)"  # 10 is in "over 6 up to 10"
    assert fit(18, "h6").limits == (18.0, 17.989)


def test_screws_nuts_washers():
    s = screw("M4", 12)
    assert (s.head_diameter, s.head_height, s.socket, s.thread_ref) == (7, 4, 3, 20)
    assert s.designation == "ISO 4762 M4x12" and s.thread_min == 12
    assert screw(8, 40).thread_min == 28
    n = nut("M8")
    assert (n.height, n.across_flats) == (6.8, 13)
    w = washer("M8")
    assert (w.inner, w.outer, w.thickness) == (8.4, 16, 1.6)
    assert washer("M8", "ISO 7090").designation == "ISO 7090 8"


def test_masses_are_plausible():
    """Catalogue masses as listed; estimated ones from the nominal solid of steel."""
    assert screw("M6", 20).mass_kg == pytest.approx(0.0067, rel=0.15)  # a DIN 912 M6x20 weighs ~6.5 g
    assert washer("M8").mass_kg == pytest.approx(7850e-9 * 3.14159 / 4 * (16**2 - 8.4**2) * 1.6, rel=1e-6)
    assert circlip_for_shaft(12).mass_kg == pytest.approx(0.0005)
    assert bush_for(12, 12, 100).mass_kg == pytest.approx(0.0024)


def test_bushes_carry_the_makers_specific_loads():
    """C = K d B and C0 = 250 N/mm2 d B to within the chamfers (SKF p. 11): a row read out of line
    would be off by far more."""
    for b in bushes():
        K = 80 if b.variant == "E" else 120
        assert b.C_n == pytest.approx(K * b.d * b.B, rel=0.1), b.designation
        assert b.C0_n == pytest.approx(250 * b.d * b.B, rel=0.1), b.designation
        assert b.designation.startswith(f"PCM {b.d:02.0f}{b.D:02.0f}{b.B:02.0f} ")


# -- selections -----------------------------------------------------------------------------------


@pytest.mark.parametrize(("radial", "expected"), [(300, "61801-2Z"), (800, "6001-2Z"), (2000, "6201-2Z")])
def test_bearing_for_takes_the_smallest_that_carries_the_load(radial, expected):
    pick = bearing_for(12, speed_rpm=60, radial_n=radial)
    assert pick.designation == expected
    assert pick.static_safety >= 1.5 and pick.life_h >= 3000
    smaller = [b for b in bearings() if b.d == 12 and b.D < pick.bearing.D]
    assert all(_check(b, True, 60, radial, 0, 3000, 1.5)[0] is None for b in smaller)


def test_bearing_for_refuses_by_name():
    with pytest.raises(SpecError, match=r"bore_mm = 11 .* expected one of 5, 6, 7"):
        bearing_for(11, 60, 100)
    with pytest.raises(SpecError, match=r"radial_n = 5000 N.*static safety"):
        bearing_for(12, 60, 5000)
    with pytest.raises(SpecError, match=r"limiting speed"):
        bearing_for(12, 50000, 10)
    with pytest.raises(SpecError, match=r"L10h"):
        bearing_for(12, 3000, 1500, life_h=20000)
    with pytest.raises(SpecError, match="series"):
        bearing_for(12, 60, 10, series=("63",))
    with pytest.raises(SpecError, match="speed_rpm"):
        bearing_for(12, -1, 10)


def test_open_bearings_and_those_without_2z():
    assert bearing_for(20, 100, 200).designation == "6004-2Z"  # 61804/61904 have no 2Z variant
    assert bearing_for(20, 100, 200, shielded=False).designation == "61804"


def test_iso_281_life_against_skf_worked_example():
    """SKF General Catalogue p. 78, example 1: 6309, C = 55.3 kN, Fr = 10 kN, 3 000 r/min:
    L10 = 169 million revolutions, 940 operating hours."""
    assert rating_life(55300, 10000) == pytest.approx(169, abs=0.5)
    assert rating_life_h(55300, 10000, 3000) == pytest.approx(940, abs=1)


def test_equivalent_load_follows_the_iso_281_table():
    b = bearing("6204")  # f0 13, C0 6550 N
    Fa = 1.03 * b.C0_n / b.f0  # a table point: e 0.28, Y 1.55
    P, X, Y, e = equivalent_load(b, 1000, Fa)
    assert (X, Y, e) == (0.56, pytest.approx(1.55), pytest.approx(0.28))
    assert P == pytest.approx(0.56 * 1000 + 1.55 * Fa)
    assert equivalent_load(b, 1000, 0.2 * 1000)[:3] == (1000, 1.0, 0.0)  # Fa/Fr = 0.2 <= e = 0.226: P = Fr
    mid = equivalent_load(b, 100, (0.345 + 0.689) / 2 * b.C0_n / b.f0)
    assert mid[2] == pytest.approx((1.99 + 1.71) / 2)  # linear between two points


def test_bush_for():
    b = bush_for(12, 12, 2000, speed_rpm=30)
    assert b.designation == "PCM 121408 E" and b.pressure_n_mm2 == pytest.approx(80 * 2000 / 7650)
    assert bush_for(12, 12, 9000).designation == "PCM 121410 E"  # the 8 mm one carries 7.65 kN
    with pytest.raises(SpecError, match="radial_n"):
        bush_for(12, 12, 50000)
    with pytest.raises(SpecError, match="length_mm"):
        bush_for(12, 5, 10)
    with pytest.raises(SpecError, match="speed_rpm"):
        bush_for(12, 12, 10, speed_rpm=5000)


def test_refusals_name_the_parameter():
    for call, words in (
        (lambda: key_for(60, 40), "shaft_d = 60"),
        (lambda: key_for(12, 4), "hub_length = 4"),
        (lambda: circlip_for_shaft(23), r"d = 23 .*nearest: 22, 24"),
        (lambda: circlip_for_bore(200), "D = 200"),
        (lambda: screw("M4", 13), r"length = 13 .*expected one of 6, 8"),
        (lambda: screw("M4", 45), "length = 45"),
        (lambda: screw("M14", 20), "M = 'M14'"),
        (lambda: fit(200, "k6"), "nominal = 200"),
        (lambda: fit(12, "p6"), "tolerance_class = 'p6'"),
        (lambda: fit(4, "H7"), "nominal = 4"),
        (lambda: washer("M3", "ISO 7090"), "ISO 7090"),
    ):
        with pytest.raises(SpecError, match=words):
            call()


# -- the bill of materials ------------------------------------------------------------------------


def _parts():
    made = [
        MadePart("sun_gear", ("sun_gear.dxf", "sun_gear.step", "sun_gear.stl"), 1, "C45", 12000.0),
        MadePart("Carrier", ("Carrier.dxf",), 2, "6061-T6", 30000.0),
        MadePart("arm", ("arm.dxf", "arm.stl"), 4, "S235JR", 8000.0),
    ]
    bought = [
        BoughtPart.of(bearing_for(12, 100, 300), 8),
        BoughtPart.of(key_for(12, 16), 2),
        BoughtPart.of(screw("M4", 12), 12, "8.8 steel"),
        BoughtPart.of(circlip_for_shaft(12), 8),
    ]
    return made, bought


FILES = ["Carrier.dxf", "arm.dxf", "arm.stl", "sun_gear.dxf", "sun_gear.step", "sun_gear.stl"]


def test_the_order_is_stable_and_documented():
    made, bought = _parts()
    bom = build_bom(made, bought)
    assert [(i.item, i.name if i.made else i.designation) for i in bom.items] == [
        (1, "arm"),
        (2, "Carrier"),
        (3, "sun_gear"),
        (4, "DIN 471 12x1"),
        (5, "DIN 6885 A 4x4x16"),
        (6, "61801-2Z"),
        (7, "ISO 4762 M4x12"),
    ]
    for seed in range(5):  # the same parts in any order: the same list, byte for byte
        m, b = made[:], bought[:]
        random.Random(seed).shuffle(m)
        random.Random(seed).shuffle(b)
        assert build_bom(m, b).csv() == bom.csv()
    assert bom.csv().decode().splitlines()[0] == ",".join(HEADER)


def test_adding_a_part_keeps_every_number_and_appends():
    made, bought = _parts()
    first = build_bom(made, bought)
    more = [*made, MadePart("bracket", ("bracket.dxf",), 1, "S235JR", 1000.0)]
    more_bought = [*bought, BoughtPart.of(nut("M4"), 12)]
    second = build_bom(more, more_bought, previous=numbers_from_csv(first.csv()))
    kept = second.numbers()
    assert all(kept[k] == n for k, n in first.numbers().items())
    assert kept["made:bracket"] == 8 and kept["bought:ISO 4032:ISO 4032 M4"] == 9
    # a dropped part's number is not given to another
    third = build_bom([p for p in more if p.name != "arm"], more_bought, previous=second)
    assert "made:arm" not in third.numbers() and 1 not in third.numbers().values()
    kept = [p for p in more if p.name != "arm"]
    fourth = build_bom([*kept, MadePart("pin", ("pin.dxf",), 1, "C45", 100.0)], more_bought, previous=third)
    assert fourth.numbers()["made:pin"] == 10


def test_masses_and_duplicates():
    made, bought = _parts()
    bom = build_bom(made, [*bought, BoughtPart.of(circlip_for_shaft(12), 2)])
    ring = next(i for i in bom.items if i.designation == "DIN 471 12x1")
    assert ring.quantity == 10  # one designation, one item
    arm = next(i for i in bom.items if i.name == "arm")
    assert arm.mass_kg == pytest.approx(material("S235JR").density_kg_m3 * 8000e-9)
    assert bom.total_mass_kg == pytest.approx(sum(i.mass_kg * i.quantity for i in bom.items))
    with pytest.raises(SpecError, match="listed twice"):
        build_bom([*made, made[0]], bought)
    with pytest.raises(SpecError, match="material = 'brass'"):
        MadePart("x", ("x.dxf",), 1, "brass", 1.0)
    with pytest.raises(SpecError, match="stem"):
        MadePart("x", ("y.dxf",), 1, "C45", 1.0)


def test_the_made_mass_is_the_solids_volume_times_the_density():
    manifold3d = pytest.importorskip("manifold3d")
    cube = manifold3d.Manifold.cube((10.0, 20.0, 5.0))
    part = MadePart.from_solid("block", ["block.stl"], 1, "C45", cube)
    assert part.mass_kg == pytest.approx(7850 * 1000e-9)


def test_one_to_one_with_the_files():
    made, bought = _parts()
    bom = build_bom(made, bought)
    assert bom.problems(FILES) == ()
    bom.check(FILES)
    missing = [f for f in FILES if f != "arm.stl"]
    assert bom.problems(missing) == ("item 1 (arm): file arm.stl is missing",)
    with pytest.raises(SpecError, match="arm.stl is missing"):
        bom.check(missing)
    assert bom.problems([*FILES, "frame.dxf"]) == ("file frame.dxf is in no item",)
    assert bom.problems([*FILES, "arm.step"]) == ("file arm.step is not listed in item 1 (arm)",)


def test_the_report_table_and_the_csv():
    made, bought = _parts()
    bom = build_bom(made, bought)
    rows = bom.rows()
    assert rows[0] == HEADER and len(rows) == 1 + len(bom.items)
    assert rows[1][:5] == ["1", "arm", "4", "made", "S235JR"] and rows[1][5] == "7850"
    bearing_row = next(r for r in rows if r[6] == "61801-2Z")
    md = bom.markdown().splitlines()  # the README's table: one line per item, the summary in one line
    assert len(md) == 2 + len(bom.items) and md[2].startswith("| 1 | arm | 4 | made | S235JR |")
    assert any("| bought | 61801-2Z |" in line for line in md)
    assert bom.summary().startswith(f"{len(bom.items)} items: ")
    assert bearing_row[3:5] == ["bought", ""] and bearing_row[7] == "ISO 15" and bearing_row[9] == ""
    assert numbers_from_csv(bom.csv()) == bom.numbers()
