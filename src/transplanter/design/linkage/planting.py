"""A four-bar planting arm: tip path relative to the frame and to the ground, planting metrics.

The machine travels along +x at ``forward_speed``; relative to the ground the tip is at
(seed 000 eq. 11) ``x_g = x + v t``, ``y_g = y`` with ``t`` the time since the start of the
cycle, so the crank angle is ``theta2(t) = start + crank_speed * t``.

Planting metrics follow seed 000 Table 2. The soil surface is the horizontal line
``planting_depth`` above the lowest point of the tip path (or an explicit ``soil_level``).
The tip *enters* where it crosses that line downwards and *exits* where it crosses it upwards,
in the order the crank actually turns; the in-soil interval is the one holding the lowest point.
Velocities and accelerations in the table are relative to the machine frame (seed 000
Figs 14-19); path length in soil, entry-to-exit distance and hole width are relative to the
ground. Crank angles are reported from ``angle_reference`` (seed 000 measures them from its
frame axis X1, i.e. ``angle_reference = phi``).

Examples
--------
>>> import numpy as np
>>> from transplanter.design.linkage.dh import DHFourBar
>>> from transplanter.design.linkage.planting import PlantingArm
>>> arm = PlantingArm.from_dh(
...     DHFourBar(a1=125.0, a2=40.0, a3=100.0, a4=85.0, phi=np.radians(322.0)),
...     x3=-273.8, y3=63.3, crank_speed=-8 * np.pi, forward_speed=600.0)
>>> m = arm.metrics(planting_depth=40.0)
>>> round(m.loop_height / 10, 1), round(m.loop_width / 10, 1)  # cm, Table 2: 22.3, 9.8
(22.3, 9.5)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import integrate, optimize

from transplanter.core.errors import MAX_MAGNITUDE, GeometryError, SpecError, check_number
from transplanter.core.extrema import refine_extreme
from transplanter.core.tolerances import ANGLE_ROOT_RAD
from transplanter.design.linkage.dh import DHFourBar
from transplanter.design.linkage.fourbar import FourBar, Link, PointMotion

__all__ = ["PlantingArm", "Cycle", "TipState", "Extreme", "PlantingMetrics"]


@dataclass(frozen=True)
class Cycle:
    """One crank revolution sampled uniformly in time.

    Attributes
    ----------
    theta2 : (n,) float
        Absolute crank angles, rad, in the order the crank turns.
    time : (n,) float
        s since the start of the cycle.
    frame : PointMotion
        Tip relative to the machine frame.
    ground_position, ground_velocity : (n, 2) float
        Tip relative to the ground, mm and mm/s.
    """

    theta2: np.ndarray
    time: np.ndarray
    frame: PointMotion
    ground_position: np.ndarray
    ground_velocity: np.ndarray


@dataclass(frozen=True)
class TipState:
    """Tip state at one crank angle (frame-relative), mm, mm/s, mm/s^2; angle in rad."""

    crank_angle: float
    position: tuple[float, float]
    velocity: tuple[float, float]
    acceleration: tuple[float, float]

    @property
    def speed(self) -> float:
        return math.hypot(*self.velocity)

    @property
    def acceleration_magnitude(self) -> float:
        return math.hypot(*self.acceleration)


@dataclass(frozen=True)
class Extreme:
    """An extreme of speed or acceleration: crank angle (rad), magnitude, direction (rad)."""

    crank_angle: float
    magnitude: float
    direction: float


@dataclass(frozen=True)
class PlantingMetrics:
    """Seed 000 Table 2 quantities for one arm (mm, mm/s, mm/s^2, rad).

    Crank angles are measured from the arm's ``angle_reference`` and wrapped to [0, 2 pi).
    """

    soil_level: float
    planting_depth: float
    loop_height: float
    loop_width: float
    crank_angle_in_soil: float
    path_length_in_soil: float
    entry_exit_distance: float
    hole_width: float
    entry: TipState
    exit: TipState
    lowest: TipState
    max_speed: Extreme
    min_speed: Extreme
    max_acceleration: Extreme
    min_acceleration: Extreme

    def table(self) -> list[tuple[str, float, str]]:
        """Rows (quantity, value, unit) in the units of seed 000 Table 2 (cm, m/s, deg)."""
        deg = math.degrees
        rows: list[tuple[str, float, str]] = [
            ("planting depth", self.planting_depth / 10, "cm"),
            ("loop height", self.loop_height / 10, "cm"),
            ("loop width", self.loop_width / 10, "cm"),
            ("crank angle in soil", deg(self.crank_angle_in_soil), "deg"),
            ("path length in soil (ground)", self.path_length_in_soil / 10, "cm"),
            ("entry-exit distance (ground)", self.entry_exit_distance / 10, "cm"),
            ("hole width (ground)", self.hole_width / 10, "cm"),
        ]
        for label, st in (("entry", self.entry), ("exit", self.exit), ("lowest", self.lowest)):
            rows += [
                (f"{label} crank angle", deg(st.crank_angle), "deg"),
                (f"{label} velocity x", st.velocity[0] / 1000, "m/s"),
                (f"{label} velocity y", st.velocity[1] / 1000, "m/s"),
                (f"{label} speed", st.speed / 1000, "m/s"),
                (f"{label} acceleration x", st.acceleration[0] / 1000, "m/s^2"),
                (f"{label} acceleration y", st.acceleration[1] / 1000, "m/s^2"),
                (f"{label} acceleration", st.acceleration_magnitude / 1000, "m/s^2"),
            ]
        for label, ex, unit in (
            ("max speed", self.max_speed, "m/s"),
            ("min speed", self.min_speed, "m/s"),
            ("max acceleration", self.max_acceleration, "m/s^2"),
            ("min acceleration", self.min_acceleration, "m/s^2"),
        ):
            rows += [
                (f"{label} crank angle", deg(ex.crank_angle), "deg"),
                (f"{label}", ex.magnitude / 1000, unit),
                (f"{label} direction", deg(ex.direction), "deg"),
            ]
        return rows


@dataclass(frozen=True)
class PlantingArm:
    """A crank-driven planting arm: a four-bar with its tip fixed on the coupler.

    Parameters
    ----------
    linkage : FourBar
    tip : (float, float)
        Tip (fork apex) in the coupler frame, mm (origin crank pin, x toward rocker pin).
    crank_speed : float
        rad/s, signed: > 0 counter-clockwise in the drawing frame.
    forward_speed : float
        Machine speed along +x, mm/s (>= 0).
    angle_reference : float
        rad; reported crank angles are measured from this direction.
    name : str
    """

    linkage: FourBar
    tip: tuple[float, float]
    crank_speed: float
    forward_speed: float = 0.0
    angle_reference: float = 0.0
    name: str = "arm"

    def __post_init__(self) -> None:
        u, v = (check_number("tip", x, -MAX_MAGNITUDE, MAX_MAGNITUDE, unit="mm") for x in self.tip)
        object.__setattr__(self, "tip", (u, v))
        w = check_number("crank_speed", self.crank_speed, -1e4, 1e4, unit="rad/s")
        if w == 0.0:
            raise SpecError.out_of_range("crank_speed", self.crank_speed, "non-zero (rad/s)")
        check_number("forward_speed", self.forward_speed, 0.0, unit="mm/s")
        self.linkage.require_full_rotation()

    @classmethod
    def from_dh(
        cls,
        dh: DHFourBar,
        x3: float,
        y3: float,
        crank_speed: float,
        forward_speed: float = 0.0,
        name: str = "arm",
    ) -> PlantingArm:
        """Arm from seed 000's description: tip (X3P, Y3P) in the rocker-pin frame."""
        return cls(
            linkage=dh.to_fourbar(),
            tip=dh.coupler_point(x3, y3),
            crank_speed=crank_speed,
            forward_speed=forward_speed,
            angle_reference=dh.phi,
            name=name,
        )

    @property
    def period(self) -> float:
        """s per crank revolution."""
        return 2 * math.pi / abs(self.crank_speed)

    def tip_motion(self, theta2: float | np.ndarray) -> PointMotion:
        """Tip relative to the frame at absolute crank angles ``theta2`` (constant crank speed)."""
        return self.linkage.solve(theta2, self.crank_speed).point(Link.COUPLER, self.tip)

    def reported_angle(self, theta2: float | np.ndarray) -> float | np.ndarray:
        """Absolute crank angle -> angle from ``angle_reference``, wrapped to [0, 2 pi)."""
        return np.mod(np.asarray(theta2) - self.angle_reference, 2 * math.pi)

    def cycle(self, n: int = 720, start: float | None = None) -> Cycle:
        """One revolution, ``n`` samples uniform in time, starting at crank angle ``start``
        (absolute, rad; default ``angle_reference``)."""
        if n < 8:
            raise SpecError.out_of_range("n", n, ">= 8 samples per revolution")
        t0 = self.angle_reference if start is None else float(start)
        time = np.arange(n) * (self.period / n)
        theta2 = t0 + self.crank_speed * time
        frame = self.tip_motion(theta2)
        gpos = frame.position + np.outer(time, [self.forward_speed, 0.0])
        gvel = frame.velocity + np.array([self.forward_speed, 0.0])
        return Cycle(theta2=theta2, time=time, frame=frame, ground_position=gpos, ground_velocity=gvel)

    def ground_path(self, time: np.ndarray, start: float | None = None) -> np.ndarray:
        """Tip relative to the ground at times ``time`` (s), (n, 2) mm (seed 000 eq. 11)."""
        t0 = self.angle_reference if start is None else float(start)
        time = np.asarray(time, dtype=float)
        pos = self.tip_motion(t0 + self.crank_speed * time).position
        return pos + np.outer(time, [self.forward_speed, 0.0])

    # -- metrics -------------------------------------------------------------------------
    def _state(self, theta2: float) -> TipState:
        pm = self.tip_motion(theta2)
        return TipState(
            crank_angle=float(self.reported_angle(theta2)),
            position=(float(pm.position[0, 0]), float(pm.position[0, 1])),
            velocity=(float(pm.velocity[0, 0]), float(pm.velocity[0, 1])),
            acceleration=(float(pm.acceleration[0, 0]), float(pm.acceleration[0, 1])),
        )

    def _extreme(self, cyc: Cycle, kind: str, largest: bool) -> Extreme:
        if kind == "speed":
            values = cyc.frame.speed

            def fn(t: float) -> float:
                return float(self.tip_motion(t).speed[0])
        else:
            values = cyc.frame.acceleration_magnitude

            def fn(t: float) -> float:
                return float(self.tip_motion(t).acceleration_magnitude[0])

        t, _ = refine_extreme(fn, cyc.theta2, values, largest, ANGLE_ROOT_RAD)
        st = self._state(t)
        vec = st.velocity if kind == "speed" else st.acceleration
        return Extreme(crank_angle=st.crank_angle, magnitude=math.hypot(*vec), direction=math.atan2(vec[1], vec[0]))

    def metrics(
        self, planting_depth: float | None = None, soil_level: float | None = None, n: int = 3600
    ) -> PlantingMetrics:
        """Seed 000 Table 2 metrics for a soil line ``planting_depth`` above the lowest tip
        position, or at the absolute height ``soil_level`` (mm, drawing frame).

        Raises
        ------
        SpecError
            If neither or both of ``planting_depth`` and ``soil_level`` are given, or the
            depth is not positive.
        GeometryError
            If the tip never goes below the soil line.
        """
        if (planting_depth is None) == (soil_level is None):
            raise SpecError("give exactly one of planting_depth (mm below soil) or soil_level (mm)")
        cyc = self.cycle(n)
        y = cyc.frame.position[:, 1]
        i_low = int(np.argmin(y))

        def tip_y(t: float) -> float:
            return float(self.tip_motion(t).position[0, 1])

        # lowest point: vy = 0 bracketed around the sampled minimum
        t_low, _ = refine_extreme(tip_y, cyc.theta2, y, xtol=ANGLE_ROOT_RAD)
        y_low = tip_y(t_low)
        if planting_depth is not None:
            depth = check_number("planting_depth", planting_depth, 0.0, low_open=True, unit="mm")  # no "40"
            level = y_low + depth
        else:
            level = check_number("soil_level", soil_level, None, unit="mm")  # exactly one of the two is given
            depth = level - y_low
            if depth <= 0.0:
                raise GeometryError(
                    f"soil_level = {level:.6g} mm is below the lowest tip position {y_low:.6g} mm: "
                    "the tip never enters the soil"
                )
        if level >= float(np.max(y)):
            raise GeometryError(
                f"soil line at {level:.6g} mm is above the whole tip path (top {np.max(y):.6g} mm): "
                f"planting_depth must be < loop height {np.max(y) - y_low:.6g} mm"
            )

        # walk from the lowest sample backwards/forwards in time to the soil crossings
        nn = y.shape[0]
        below = y < level
        k = i_low
        while below[(k - 1) % nn]:
            k -= 1
        j = i_low
        while below[(j + 1) % nn]:
            j += 1
        # crossings lie between samples (k-1, k) and (j, j+1); theta2 is monotone in time
        dt = cyc.theta2[1] - cyc.theta2[0]
        th_k = cyc.theta2[0] + k * dt
        th_j = cyc.theta2[0] + j * dt
        t_in = optimize.brentq(lambda t: tip_y(t) - level, th_k - dt, th_k, xtol=ANGLE_ROOT_RAD)
        t_out = optimize.brentq(lambda t: tip_y(t) - level, th_j, th_j + dt, xtol=ANGLE_ROOT_RAD)
        # ground-relative quantities over the in-soil interval (crank angle as parameter)
        w = self.crank_speed
        v = self.forward_speed

        def ground_speed(t: float) -> float:
            vel = self.tip_motion(t).velocity[0]
            return math.hypot(vel[0] + v, vel[1]) / abs(w)  # ds/dtheta

        length, _ = integrate.quad(ground_speed, min(t_in, t_out), max(t_in, t_out), limit=200, epsabs=1e-9)

        def ground_x(t: float) -> float:
            return float(self.tip_motion(t).position[0, 0]) + v * (t - t_in) / w

        x_in, x_out = ground_x(t_in), ground_x(t_out)
        ts = np.linspace(t_in, t_out, 2001)
        gx = self.tip_motion(ts).position[:, 0] + v * (ts - t_in) / w
        hole = float(np.max(gx) - np.min(gx))

        return PlantingMetrics(
            soil_level=level,
            planting_depth=depth,
            loop_height=float(np.max(y) - y_low),
            loop_width=float(np.ptp(cyc.frame.position[:, 0])),
            crank_angle_in_soil=abs(t_out - t_in),
            path_length_in_soil=float(length),
            entry_exit_distance=abs(x_out - x_in),
            hole_width=hole,
            entry=self._state(t_in),
            exit=self._state(t_out),
            lowest=self._state(t_low),
            max_speed=self._extreme(cyc, "speed", True),
            min_speed=self._extreme(cyc, "speed", False),
            max_acceleration=self._extreme(cyc, "acceleration", True),
            min_acceleration=self._extreme(cyc, "acceleration", False),
        )
