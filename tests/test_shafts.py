"""Keys and shafts under load (issue 44): the beam, the key's pressure, the fatigue check, refusals."""

import math

import numpy as np
import pytest

from transplanter.core.errors import GeometryError, SpecError
from transplanter.families.machines.shafts import _safety, bending_moment, hub_torque, key_pressure, strength
from transplanter.machine.bodies import Link
from transplanter.machine.dynamics import Drive, Lump, Machine, Pin, solve


def test_a_beam_on_two_supports_has_the_textbook_moment():
    # P = 1000 N at a = 30 mm of a 100 mm span: supports P b / L and P a / L, M_max = P a b / L
    p, a, span = 1000.0, 30.0, 100.0
    up = lambda v: np.array([[0.0, v]])  # noqa: E731
    forces = [(0.0, up(p * (span - a) / span)), (a, up(-p)), (span, up(p * a / span))]
    m = bending_moment(np.array([a, 50.0, span]), forces)[0]
    assert m[0, 1] == pytest.approx(p * a * (span - a) / span * 1e-3, rel=1e-12)  # 21 N·m
    assert m[1, 1] == pytest.approx(p * a / span * (span - 50.0) * 1e-3, rel=1e-12)
    assert abs(m[2, 1]) < 1e-12
    mid = bending_moment(np.array([50.0]), [(0.0, up(500.0)), (50.0, up(-1000.0)), (100.0, up(500.0))])
    assert mid[0, 0, 1] == pytest.approx(1000.0 * 100.0 / 4 * 1e-3)  # P L / 4


def test_a_key_pressure_by_hand():
    # T = 10 N·m on Ø20, key 6x6x12 form A (t1 3.5): l_tr = 12 - 6, p = 2 T / (d (h - t1) l_tr)
    assert key_pressure(10.0, 20.0, 6.0, 3.5, 6.0) == pytest.approx(2 * 10e3 / (20 * 2.5 * 6))


def test_strengths_by_ruling_section_cite_their_source():
    thin, thick = strength("C45", 10.0), strength("C45", 20.0)
    assert (thin["re_mpa"], thin["rm_mpa"], thick["re_mpa"], thick["rm_mpa"]) == (490, 700, 430, 650)
    assert "683-1" in thin["source"] and strength("S235JR", 12.0)["re_mpa"] == 235


def test_rotating_bending_alone_gives_the_endurance_limit_over_the_stress():
    # a fixed moment on a turning shaft: fully reversed at every fibre, sigma_a = K_t 32 M / (pi d^3)
    theta = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    mvec = np.tile([0.0, 5.0], (theta.size, 1))
    n_f, n_y, sa, sm, se = _safety(mvec, theta, np.zeros_like(theta), "shoulder", 5.0, 0.0, 700.0, 490.0)
    sigma = 2.7 * 32 * 5e3 / (math.pi * 10.0**3)
    assert sa == pytest.approx(sigma, rel=1e-3) and sm == pytest.approx(0.0, abs=1e-6 * sigma)
    assert n_f == pytest.approx(se / sa, rel=1e-9) and n_y == pytest.approx(490.0 / sigma, rel=1e-3)
    ka, kb = 4.51 * 700.0**-0.265, 1.24 * 10.0**-0.107  # Shigley 9th ed. Table 6-2, eq. 6-20
    assert se == pytest.approx(ka * kb * 0.814 * 350.0)


def test_a_hub_on_a_drive_takes_the_drive_torque():
    bar = Link("bar", lambda t: (np.zeros_like(t), np.zeros_like(t), np.asarray(t, dtype=float)))
    lumps = (Lump(1.0, (100.0, 0.0, 0.0), 0.0),)
    m = Machine(
        {"bar": bar}, {"bar": lumps}, pins=(Pin("O", "fixed", "bar", (-10.0, 10.0)),), drives=(Drive("motor", "bar"),)
    )
    loads = solve(m, np.array([0.0, 0.3, np.pi / 2]), speed=2.0)
    assert hub_torque(m, loads, "bar", lumps, ()) == pytest.approx(loads.torque[:, 0], abs=1e-9)


@pytest.mark.parametrize(
    ("call", "error", "words"),
    [
        (lambda: key_pressure(10.0, 20.0, 3.0, 3.5, 6.0), SpecError, "h - t1"),
        (lambda: key_pressure(10.0, float("nan"), 6.0, 3.5, 6.0), SpecError, "key d"),
        (lambda: strength("brass", 10.0), SpecError, "brass"),
        (lambda: strength("C45", 250.0), SpecError, "250"),
        (lambda: bending_moment(np.array([1.0]), [(0.0, np.array([[0.0, 1.0]]))]), GeometryError, "balance"),
    ],
)
def test_bad_inputs_are_refused_by_name(call, error, words):
    with pytest.raises(error, match=words):
        call()


def test_every_strength_row_cites_a_standard():
    from transplanter.shop.catalogue import materials, notes, table

    rows = table("material_strengths")
    assert rows and all(r["source"].strip() and any(s in r["source"] for s in ("ISO", "EN ")) for r in rows)
    assert {r["name"] for r in rows} <= set(materials()) and notes("material_strengths")


def test_a_finding_names_each_remedy_once_with_the_elements_it_is_for():
    """Three arms' keys short for one reason read as one remedy; a shaft short at two sections
    names the larger diameter; every element that passes stays out."""
    from transplanter.families.machines.shafts import finding

    hub = "a longer hub (8 mm now) or a second key"
    keys = [{"key": f"key_arm_{k}", "pass": False, "resize": hub} for k in (3, 1, 2)]
    keys.append({"key": "key_planet_1", "pass": True})
    shafts = [
        {"shaft": "planet_shaft_1", "pass": False, "resize_to_mm": 14},
        {"shaft": "planet_shaft_1", "pass": False, "resize_to_mm": 16},
        {"shaft": "ring_shaft", "pass": True},
    ]
    rec = {
        "pass": False,
        "keys": keys,
        "shafts": shafts,
        "smallest_key_safety": {"key": "key_arm_1", "safety": 0.42},
        "smallest_shaft_safety": {"shaft": "planet_shaft_1", "section": "keyseat", "fatigue_safety": 0.5},
        "needle_force_capacity": {"n": 21.5, "limited_by": "key_arm_1"},
    }
    text = finding(rec, "100 N")
    assert text is not None and text.startswith("under 100 N 3 keys and 2 shaft sections fall short")
    assert text.endswith(f"to carry it: key_arm_1, key_arm_2, key_arm_3: {hub}; planet_shaft_1: Ø16")
    assert "carries 21.5 N" in text and "key_planet_1" not in text and "ring_shaft" not in text
    assert finding({**rec, "pass": True}, "100 N") is None


def test_a_cantilever_bends_as_the_textbook_says():
    """Issue 42: the fixed shaft built into the frame is rated as a cantilever. Point loads
    superposed against Roark's closed forms (deflection and slope at the free end, and between the
    clamp and a load), vector loads at right angles adding as vectors; Shigley's Table 7-2 limits."""
    from transplanter.families.machines.cantilever import E_STEEL_MPA, deflection_and_slope, gear_deflection_limit_mm

    d = 20.0
    ei = E_STEEL_MPA * math.pi * d**4 / 64
    # two loads, 300 N at 40 mm and -100 N at 15 mm, seen at the free end 60 mm out
    dev, tilt = deflection_and_slope(np.array([[300.0, -100.0]]), np.array([40.0, 15.0]), np.array([60.0]), d)
    want = 300 * 40**2 * (3 * 60 - 40) / (6 * ei) - 100 * 15**2 * (3 * 60 - 15) / (6 * ei)
    assert dev == pytest.approx(abs(want), rel=1e-12)
    assert tilt == pytest.approx(abs(300 * 40**2 / (2 * ei) - 100 * 15**2 / (2 * ei)), rel=1e-12)
    # between the clamp and the load: F x² (3a - x) / 6EI, slope F x (2a - x) / 2EI
    dev, tilt = deflection_and_slope(np.array([[300.0]]), np.array([40.0]), np.array([10.0]), d)
    assert (dev, tilt) == (pytest.approx(300 * 100 * 110 / (6 * ei)), pytest.approx(300 * 10 * 70 / (2 * ei)))
    # at right angles: the deflections add as vectors; the largest over the rows is taken
    rows = np.array([[[3.0, 0.0], [0.0, 4.0]], [[1.0, 0.0], [0.0, 1.0]]]) * 100
    dev, _ = deflection_and_slope(rows, np.array([30.0, 30.0]), np.array([30.0]), d)
    assert dev == pytest.approx(500 * 30**3 / (3 * ei))
    assert [gear_deflection_limit_mm(m) for m in (3.0, 1.5, 1.0)] == [0.254, 0.127, 0.0762]
