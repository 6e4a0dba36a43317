"""Meshing of the generated parts themselves: penetration, transmission error, contact.

Tolerances: overlap 1e-3 mm² (zero-backlash teeth overlap only by the outlines' chord error,
measured ~1e-4 mm² over a window); transmission error 1 µm for zero backlash (the envelope is
exact to 0.25 µm per outline); backlash band 0.09..0.12 mm for 0.05 mm thinning per gear (the
circumferential backlash varies with the pitch curve's pressure angle).
"""

import dataclasses

import pytest

from transplanter.cutter import ShaperCutter
from transplanter.pitch import GearPair, PitchCurve
from transplanter.teeth import generate, generate_pair
from transplanter.validate import mesh_check


@pytest.fixture(scope="module")
def ellipse_pair():
    return GearPair.from_driver(PitchCurve.ellipse(40.0, 0.2, 2), "external", 2).sized(module=2.0)


def test_generated_pair_meshes_without_backlash(ellipse_pair):
    pair, sizing = ellipse_pair
    g1, g2 = generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth)
    r = mesh_check(pair, g1.polygon, g2.polygon, 2.0, steps=48)
    assert r.problems() == []
    assert r.max_penetration < 1e-3
    assert r.max_transmission_error < 1e-3
    assert r.min_contacts >= 1 and r.contact_ratio > 2  # both flanks touch


def test_backlash_pair_stays_in_its_band(ellipse_pair):
    pair, sizing = ellipse_pair
    g1, g2 = generate_pair(pair, ShaperCutter(20, 2.0, thickening=0.05), sizing.teeth)
    r = mesh_check(pair, g1.polygon, g2.polygon, 2.0, steps=48)
    assert r.problems(backlash=(0.09, 0.12)) == []
    assert r.offset == pytest.approx(-0.05, abs=0.01)  # half the backlash on each side
    assert r.max_transmission_error < 0.02 and 1.5 < r.contact_ratio < 2.5


def test_broken_pairs_are_caught(ellipse_pair):
    pair, sizing = ellipse_pair
    g1, g2 = generate_pair(pair, ShaperCutter(20, 2.0), sizing.teeth)
    close = dataclasses.replace(pair, centre_distance=pair.centre_distance - 0.3)
    r = mesh_check(close, g1.polygon, g2.polygon, 2.0, steps=24)
    assert any("teeth interfere" in p for p in r.problems())
    # a driven gear with one tooth more, cut on its own curve, placed as the design pair
    bigger, s2 = pair.sized(teeth=sizing.teeth[0] + 2)  # the 2-lobe gear: one more tooth per lobe
    wrong = generate(bigger.driven.scaled(sizing.module / s2.module), ShaperCutter(20, 2.0), s2.teeth[1], phase=0.5)
    r = mesh_check(pair, g1.polygon, wrong.polygon, 2.0, steps=24)
    assert any("teeth interfere" in p for p in r.problems())
