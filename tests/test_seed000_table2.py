"""Seed 000 Table 2 (Kim & Chung), mechanisms A, B, C.

Tolerances, and why:

* Inputs were measured with a scale and a protractor (Table 1: lengths to 1 mm, angles to
  ~0.5 deg); the fork apex is 259-359 mm from the rocker pin, so its position is uncertain by
  about +-3 mm. Lengths (loop height/width, path length): 5 %.
* The paper evaluated its equations every 10 deg of crank angle (some rows interpolated to
  0.5 deg), so a published extreme is the best grid value: crank angles of events and extremes
  within 10 deg; magnitudes are compared with our value *at the published crank angle*.
* Magnitudes: 5 % plus an absolute part from the +-3 mm tip uncertainty times the coupler's
  angular rates (|w3| <= 23 rad/s, |alpha3| <= ~600 rad/s^2): 0.07 m/s and 3.5 m/s^2.

Rows that still fall outside are listed in DISCREPANCIES with the figures measured; the test
asserts they *are* outside (so the list stays true) and every other row inside.
"""

import math

import numpy as np
import pytest

CM, MS, MS2 = 10.0, 1000.0, 1000.0  # mm per cm, mm/s per m/s, mm/s^2 per m/s^2
TOL_LEN_REL = 0.05
TOL_ANGLE_DEG = 10.0
TOL_REL = 0.05
TOL_V = 0.07 * MS
TOL_A = 3.5 * MS2

# Table 2: (crank angle deg, magnitude, direction deg) for the extremes
EXTREMES = {
    "A": {
        "max_speed": (190, 4.43, 93.58),
        "min_speed": (150, 0.298, 66.36),
        "max_acceleration": (170, 189.91, 100.07),
        "min_acceleration": (85, 44.85, 22.09),
    },
    "B": {
        "max_speed": (195, 3.24, 75.44),
        "min_speed": (300, 0.914, 160.13),
        "max_acceleration": (150, 106.67, -82.24),
        "min_acceleration": (190, 8.85, -119.4),
    },
    "C": {
        "max_speed": (190, 3.68, 63.73),
        "min_speed": (135, 0.858, -30.56),
        "max_acceleration": (140, 133.43, -92.17),
        "min_acceleration": (190, 21.03, 116.56),
    },
}
# height, width (cm), crank angle in soil (deg), path in soil (cm), entry-exit distance (cm)
LOOP = {"A": (25.0, 7.4, 75.0, 10.6, 5.0), "B": (22.3, 9.8, 119.0, 9.2, 2.0), "C": (25.0, 12.7, 112.5, 9.8, 2.7)}
# events: crank angle (deg), speed (m/s), acceleration (m/s^2)
EVENTS = {
    "A": {"entry": (104, 2.7, 49.6), "exit": (179, 3.94, 146.1), "lowest": (150, 0.28, 167.8)},
    "B": {"entry": (7.5, 2.33, 49.7), "exit": (248.5, 1.8, 50.0), "lowest": (310, 0.97, 48.2)},
    "C": {"entry": (16.5, 2.95, 61.8), "exit": (264, 1.36, 50.0), "lowest": (320, 1.09, 61.0)},
}
# (mechanism, row) -> what we measured; these do not reproduce within the tolerances above
DISCREPANCIES = {
    ("C", "exit speed"): "1.735 m/s at our exit (262.7 deg) vs 1.36; our exit v = (0.44, 1.68) vs (-0.32, 1.32)",
}


def _close(ours, paper, rel, abs_):
    return abs(ours - paper) <= rel * abs(paper) + abs_


def _check(results, key, ok, detail):
    results.append((key, ok, detail))


def _angle_diff(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


@pytest.fixture(scope="module")
def table(seed000_arms):
    return {k: (arm, arm.metrics(planting_depth=40.0)) for k, arm in seed000_arms.items()}


@pytest.mark.parametrize("mech", ["A", "B", "C"])
def test_table2(mech, table):
    arm, m = table[mech]
    results = []
    h, w, soil_deg, path, dist = LOOP[mech]
    _check(results, (mech, "height"), _close(m.loop_height, h * CM, TOL_LEN_REL, 0), m.loop_height)
    _check(results, (mech, "width"), _close(m.loop_width, w * CM, TOL_LEN_REL, 0), m.loop_width)
    _check(
        results,
        (mech, "crank angle in soil"),
        abs(math.degrees(m.crank_angle_in_soil) - soil_deg) < 5.0,
        math.degrees(m.crank_angle_in_soil),
    )
    _check(
        results, (mech, "path in soil"), _close(m.path_length_in_soil, path * CM, TOL_LEN_REL, 0), m.path_length_in_soil
    )
    _check(results, (mech, "entry-exit distance"), abs(m.entry_exit_distance - dist * CM) < 3.0, m.entry_exit_distance)
    for name, (ang, speed, acc) in EVENTS[mech].items():
        st = getattr(m, name)
        _check(
            results,
            (mech, f"{name} angle"),
            _angle_diff(math.degrees(st.crank_angle), ang) <= TOL_ANGLE_DEG,
            math.degrees(st.crank_angle),
        )
        _check(results, (mech, f"{name} speed"), _close(st.speed, speed * MS, TOL_REL, TOL_V), st.speed)
        _check(
            results,
            (mech, f"{name} acceleration"),
            _close(st.acceleration_magnitude, acc * MS2, TOL_REL, TOL_A),
            st.acceleration_magnitude,
        )
    for name, (ang, mag, _direction) in EXTREMES[mech].items():
        ex = getattr(m, name)
        _check(
            results,
            (mech, f"{name} angle"),
            _angle_diff(math.degrees(ex.crank_angle), ang) <= TOL_ANGLE_DEG,
            math.degrees(ex.crank_angle),
        )
        pm = arm.tip_motion(arm.angle_reference + math.radians(ang))
        ours = pm.speed[0] if "speed" in name else pm.acceleration_magnitude[0]
        tol_abs = TOL_V if "speed" in name else TOL_A
        _check(results, (mech, name), _close(ours, mag * MS, TOL_REL, tol_abs), ours)
    unexpected = [(k, d) for k, ok, d in results if not ok and k not in DISCREPANCIES]
    stale = [k for k, ok, _ in results if ok and k in DISCREPANCIES]
    assert not unexpected, f"rows outside tolerance: {unexpected}"
    assert not stale, f"rows listed as discrepancies now reproduce; update DISCREPANCIES: {stale}"


@pytest.mark.parametrize("mech", ["A", "B", "C"])
def test_max_speed_direction(mech, table):
    """The direction of the fastest tip motion fixes the sense of crank rotation (5 deg)."""
    arm, m = table[mech]
    ang, _, direction = EXTREMES[mech]["max_speed"]
    v = arm.tip_motion(arm.angle_reference + math.radians(ang)).velocity[0]
    assert _angle_diff(math.degrees(math.atan2(v[1], v[0])), direction) < 5.0


def test_entry_velocity_components_of_b(table):
    """Mechanism B's entry row reproduces to the paper's two digits: (-1.2, -2.0) m/s."""
    _, m = table["B"]
    np.testing.assert_allclose(np.array(m.entry.velocity) / MS, (-1.2, -2.0), atol=0.05)
    np.testing.assert_allclose(np.array(m.lowest.acceleration) / MS2, (15.5, 45.7), atol=0.5)
