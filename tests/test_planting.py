"""Planting metrics and ground path."""

import math

import numpy as np
import pytest

from transplanter.core.errors import AssemblyError, GeometryError, SpecError
from transplanter.design.linkage.fourbar import FourBar
from transplanter.design.linkage.planting import PlantingArm


def test_mechanism_b_in_a_few_lines():
    from transplanter.design.linkage.dh import DHFourBar

    arm = PlantingArm.from_dh(DHFourBar(125, 40, 100, 85, math.radians(322)), -273.8, 63.3, -8 * math.pi, 600)
    m = arm.metrics(planting_depth=40)
    assert abs(m.loop_height - 222.65) < 0.01


def test_ground_path_is_frame_path_plus_travel(seed000_arms):
    arm = seed000_arms["C"]
    t = np.linspace(0, 2 * arm.period, 50)
    g = arm.ground_path(t)
    f = arm.tip_motion(arm.angle_reference + arm.crank_speed * t).position
    np.testing.assert_allclose(g[:, 0] - f[:, 0], arm.forward_speed * t, atol=1e-9)
    np.testing.assert_allclose(g[:, 1], f[:, 1], atol=0)


def test_path_length_in_soil_matches_polyline(seed000_arms):
    """quad over the analytic speed vs a 20 000-segment polyline (error ~ L h^2 / 24 < 1e-6 mm)."""
    arm = seed000_arms["A"]
    m = arm.metrics(planting_depth=40.0)
    t_in = arm.angle_reference + m.entry.crank_angle
    t_out = arm.angle_reference + m.exit.crank_angle
    theta = np.linspace(t_in, t_out, 20001)
    p = arm.tip_motion(theta).position
    p[:, 0] += arm.forward_speed * (theta - t_in) / arm.crank_speed
    assert abs(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)) - m.path_length_in_soil) < 1e-4


def test_soil_level_and_depth_are_equivalent(seed000_arms):
    arm = seed000_arms["B"]
    by_depth = arm.metrics(planting_depth=40.0)
    by_level = arm.metrics(soil_level=by_depth.soil_level)
    assert by_level.entry.crank_angle == pytest.approx(by_depth.entry.crank_angle, abs=1e-9)
    assert by_level.planting_depth == pytest.approx(40.0, abs=1e-9)


def test_events_lie_on_the_soil_line(seed000_arms):
    for arm in seed000_arms.values():
        m = arm.metrics(planting_depth=40.0)
        assert m.entry.position[1] == pytest.approx(m.soil_level, abs=1e-6)
        assert m.exit.position[1] == pytest.approx(m.soil_level, abs=1e-6)
        assert m.entry.velocity[1] < 0 < m.exit.velocity[1]
        assert abs(m.lowest.velocity[1]) < 1e-3


@pytest.mark.parametrize(
    "kwargs, err, match",
    [
        ({"planting_depth": 40.0, "soil_level": 0.0}, SpecError, "exactly one"),
        ({"planting_depth": -1.0}, SpecError, "planting_depth = -1.0 is out of range"),
        ({"planting_depth": float("nan")}, SpecError, "planting_depth = nan"),
        ({"soil_level": -1e6}, GeometryError, "never enters the soil"),
        ({"planting_depth": 1e4}, GeometryError, "planting_depth must be < loop height"),
    ],
)
def test_bad_metric_inputs(seed000_arms, kwargs, err, match):
    with pytest.raises(err, match=match):
        seed000_arms["A"].metrics(**kwargs)


def test_bad_arm_inputs():
    fb = FourBar(125, 40, 100, 85)
    with pytest.raises(SpecError, match="crank_speed = 0.0"):
        PlantingArm(fb, (0.0, 0.0), 0.0)
    with pytest.raises(SpecError, match="forward_speed = -1"):
        PlantingArm(fb, (0.0, 0.0), 1.0, -1)
    with pytest.raises(SpecError, match="tip = "):
        PlantingArm(fb, (float("nan"), 0.0), 1.0)
    with pytest.raises(AssemblyError, match="crank cannot turn fully"):
        PlantingArm(FourBar(100, 65, 70, 90), (0.0, 0.0), 1.0)
