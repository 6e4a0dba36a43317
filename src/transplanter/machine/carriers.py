"""Seed 002's double-carrier machine as moving links, posed from its made parts.

Seed 002 (Fig. 10): the **first carrier** (link 1) turns clockwise about the frame's shaft at the
centre point A0, on which the sun gear 2 and the cam 6 are fixed. On it ride the non-circular
stages 2-3 and 4-5 (gear 4 on gear 3's shaft), the cam follower 7 with its sector gear, and, at the
circle point A_c, gear 5 with gear 9 on one shaft. The **second carrier** (link 2) turns about A_c,
fixed to the sector gear 8 that the follower's sector drives (ratio 1): the cam sets its swing β2.
On it the equal spur gears 9-10-11 (10 an idler) turn the **planting arm** (link 3, fixed to
gear 11 at Q) as gear 5 turns, so the arm turns relative to carrier 1 by what stages 2-3 and 4-5
give — the two routes meet at the arm (seed 002 eqs 12-18 with ``i^8_{5,11} = 1``).

:class:`DoubleCarrierMachine` poses every member over the driver angle θ (carrier 1's clockwise
turn from the chain's pose 1, ``τ`` of :class:`~transplanter.design.linkage.open_chain.OpenChain3R`):

* each gear pair by its **made meshing** (:class:`MadeMesh`): the pair's design motion plus the
  driven gear's error the pair's proof measured on its re-read DXFs at driving-flank contact (the
  idler 10 and gear 11 are the spur pair's driven and driver gears again, their mesh posed in that
  pair's geometry with the same table);
* the second carrier by the follower's swing **on the re-read cam** (``follower.follower_check``);
* each pair drawn in its DXF frames as :mod:`transplanter.geometry.pitch.pair` puts them (driver at its
  centre turning clockwise, driven on the line of centres, 180° at the start). A pair whose driver
  turns counter-clockwise in the machine is seen from its back: its gears are **mirrored** (mounted
  face down) — stage 2-3 (the sun turns counter-clockwise relative to carrier 1) and the spur gears
  9-10-11 (gear 9 turns counter-clockwise relative to carrier 2).

Frames: :attr:`DoubleCarrierMachine.frame` maps the synthesis frame (seed 002 Table 1) to the
machine frame — A0 at the origin, turned so the soil is horizontal below (``down``: the direction
of the tip's farthest reach from A0, where a rotary planter plants).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from transplanter.core.errors import GeometryError, SpecError
from transplanter.design.linkage.open_chain import OpenChain3R
from transplanter.geometry.cams import OscillatingRollerFollower
from transplanter.geometry.pitch import GearPair
from transplanter.machine.bodies import Link
from transplanter.proof.train_rebuild import measured_error

__all__ = ["MadeMesh", "CarrierLayout", "DoubleCarrierMachine", "machine_frame", "pair_pose"]

TWO_PI = 2 * math.pi
#: samples per turn the speed bounds are taken from (plus the largest change between two)
BOUND_SAMPLES = 20_000
#: the last sets of positions whose poses are kept (:meth:`DoubleCarrierMachine.poses`)
POSES_KEPT = 4


@dataclass(frozen=True)
class MadeMesh:
    """A made pair's motion: the driven gear's turn (rad, magnitude) when the driver has turned
    ``t1`` (clockwise in the pair's frame), the design's plus the error measured on the re-read
    DXFs (``angle`` → ``error``, rad, interpolated periodically; empty: none measured)."""

    pair: GearPair
    angle: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    error: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

    def driven(self, t1) -> np.ndarray:
        t1 = np.asarray(t1, dtype=float)
        turn = np.asarray(self.pair.driven_rotation(t1), dtype=float)
        if len(self.angle):
            turn = turn + measured_error(self.angle, self.error, t1)
        return turn


def pair_pose(line: float, t1, t2, mirrored: bool) -> tuple[np.ndarray, np.ndarray]:
    """Angles of a pair's driver and driven DXF frames in the frame its line of centres is drawn
    in (the line at angle ``line``), driver turned ``t1`` and driven ``t2`` (rad, pair senses);
    ``mirrored``: the pair seen from its back (its sections mirrored about their x-axes)."""
    t1, t2 = np.asarray(t1, dtype=float), np.asarray(t2, dtype=float)
    if mirrored:
        return line + t1, line - math.pi - t2
    return line - t1, line + math.pi + t2


@dataclass(frozen=True)
class CarrierLayout:
    """Where the shafts sit (mm): on carrier 1 (origin A0, +x towards A_c) gear 3/4's shaft ``s3``
    and the follower pivot ``pivot``; on carrier 2 (origin A_c, +x towards Q) the idler ``idler``."""

    s3: tuple[float, float]
    pivot: tuple[float, float]
    idler: tuple[float, float]

    @staticmethod
    def solve(l1: float, l2: float, a23: float, a35: float, pivot: float, a78: float, a910: float) -> CarrierLayout:
        """The shafts from the distances they must keep: gear 3 at ``a23`` from A0 and ``a35`` from
        A_c (below the line A0-A_c), the follower pivot ``pivot`` from A0 (the cam's axis) and
        ``a78`` from A_c (above it), the idler ``a910`` from A_c and from Q (below the line A_c-Q)."""

        def apex(base: float, r0: float, r1: float, what: str, side: float) -> tuple[float, float]:
            x = (base * base + r0 * r0 - r1 * r1) / (2 * base)
            h2 = r0 * r0 - x * x
            if h2 < 0:
                raise GeometryError(
                    f"{what} cannot be placed: {r0:.4g} and {r1:.4g} mm from two shafts {base:.4g} mm apart "
                    f"(each must be less than the other two together)"
                )
            return x, side * math.sqrt(h2)

        return CarrierLayout(
            apex(l1, a23, a35, "gear 3's shaft (stages 2-3 and 4-5)", -1.0),
            apex(l1, pivot, a78, "the follower pivot (cam pivot distance and sector gears 7-8)", 1.0),
            apex(l2, a910, a910, "the idler 10 (spur gears 9-10-11)", -1.0),
        )


def _angle(p) -> float:
    return math.atan2(p[1], p[0])


def machine_frame(chain: OpenChain3R) -> tuple[float, float, float]:
    """(x, y, turn) of the synthesis frame's map to the machine frame of ``chain``'s machine:
    p ↦ R(turn)(p - A0) — A0 at the origin, turned so that the tip's farthest reach from A0 (over
    1441 positions of the turn) points straight down (:attr:`DoubleCarrierMachine.frame`)."""
    tau = np.linspace(0.0, TWO_PI, 1441)
    tip = chain.state(tau).tip
    a0 = np.asarray(chain.centre, dtype=float)
    far = tip[int(np.argmax(np.linalg.norm(tip - a0, axis=1)))] - a0
    return (*chain.centre, -math.pi / 2 - math.atan2(far[1], far[0]))


@dataclass(frozen=True)
class DoubleCarrierMachine:
    """Seed 002's machine (module docstring) from its made meshes and the follower's swing.

    ``swing`` is the follower's swing from its base position at the driver angles ``swing_at``
    (rad, uniform over a turn; measured on the re-read cam), ``follower`` the cam's
    ``OscillatingRollerFollower``; ``stage23``/``stage35``/``sectors``/``spurs`` the made meshes
    (stage 2-3's driver is the sun, 7-8's the follower's sector, 9-10's gear 9)."""

    chain: OpenChain3R
    layout: CarrierLayout
    stage23: MadeMesh
    stage35: MadeMesh
    sectors: MadeMesh
    spurs: MadeMesh
    follower: OscillatingRollerFollower
    swing_at: np.ndarray = field(repr=False)
    swing: np.ndarray = field(repr=False)
    #: the keys as cut (rad): gear 9 on gear 5's shaft (gear 5's angle less carrier 2's where the
    #: spur pair starts) and the arm on gear 11's (the arm's angle less gear 11's); None: set where
    #: this machine's own meshes put them at the chain's pose 1 — a made machine takes the design's
    keys: tuple[float, float] | None = None
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if len(self.swing_at) != len(self.swing) or len(self.swing) < 8:
            raise SpecError("swing and swing_at must be matching arrays of at least 8 positions")

    # -- the chain's numbers ----------------------------------------------------------------

    @cached_property
    def _start(self) -> dict:
        ch = self.chain
        tau = np.linspace(0.0, TWO_PI, 1441)
        b2 = ch.beta2(tau)
        st = ch.state(tau)
        return {"beta2_min": float(b2.min()), "abs1": float(st.link1[0]), "rot": machine_frame(ch)[2]}

    @property
    def frame(self) -> tuple[float, float, float]:
        """(x, y, turn) of the synthesis frame's map to the machine frame: p ↦ R(turn)(p - A0)."""
        return (*self.chain.centre, self._start["rot"])

    def to_machine(self, points) -> np.ndarray:
        """Points (n, 2) of the synthesis frame in the machine frame."""
        cx, cy, rot = self.frame
        p = np.asarray(points, dtype=float) - [cx, cy]
        c, s = math.cos(rot), math.sin(rot)
        return np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1]], axis=-1)

    # -- the members' angles (carrier 1's frame), θ = τ --------------------------------------

    def _swing(self, theta) -> np.ndarray:
        return np.interp(np.mod(theta, TWO_PI), self.swing_at, self.swing, period=TWO_PI)

    @cached_property
    def _lines(self) -> tuple[float, float, float]:
        """The lines of centres on carrier 1 (rad): sun → gear 3, gear 4 → gear 5, the follower's
        sector 7 → sector 8."""
        lay, l1 = self.layout, self.chain.link_lengths[0]
        return (
            _angle(lay.s3),
            _angle((l1 - lay.s3[0], -lay.s3[1])),
            _angle((l1 - lay.pivot[0], -lay.pivot[1])),
        )

    def _on_carrier1(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """The members turning on carrier 1 relative to it (rad): the sun, gears 3, 4, 5, the
        follower lever, sector 7 and carrier 2 (sector 8 turned so that it lies at β2's smallest
        value where the swing is 0)."""
        sig3, sig5, sig8 = self._lines
        t3 = self.stage23.driven(theta)  # gear 3's turn (clockwise in carrier 1)
        sun, gear3 = pair_pose(sig3, theta, t3, mirrored=True)
        gear4, gear5 = pair_pose(sig5, t3, self.stage35.driven(t3), mirrored=False)
        s = self._swing(theta)
        sector7, sector8 = pair_pose(sig8, s, self.sectors.driven(s), mirrored=False)
        return {
            "sun": sun,
            "gear3": gear3,
            "gear4": gear4,
            "gear5": gear5,
            "lever": _angle(self.layout.pivot) + math.pi - self._g0 - s,
            "sector7": sector7,
            "carrier2": sector8 - (sig8 + math.pi) + self._start["beta2_min"],
        }

    def angles(self, theta) -> dict[str, np.ndarray]:
        """Each member's angle at driver angles ``theta``: carrier 1 absolute (synthesis frame);
        the sun, gears 3, 4, 5, the follower lever, sector 7, carrier 2 relative to carrier 1;
        gears 9, 10, 11 and the arm relative to carrier 2 (rad)."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        lay = self.layout
        out = self._on_carrier1(theta)
        # gear 9 (on gear 5's shaft) relative to carrier 2, from its start
        lam9 = _angle(lay.idler)
        t9 = (out["gear5"] - out["carrier2"]) - self._gear9_zero
        gear9, gear10 = pair_pose(lam9, t9, self.spurs.driven(t9), mirrored=True)
        # gear 11 drives 10 backwards in the same pair's geometry: seen from gear 11 the idler is
        # the driven gear of a pair on the line Q -> idler
        l2 = self.chain.link_lengths[1]
        lam11 = _angle((lay.idler[0] - l2, lay.idler[1]))
        t10 = lam11 - math.pi - gear10  # gear 10's turn as 11's driven gear (mirrored)
        t11 = t10 - (self.spurs.driven(t10) - t10)  # ratio 1: the driver's turn less the error
        gear11, _ = pair_pose(lam11, t11, t10, mirrored=True)
        return {"carrier1": self._start["abs1"] - theta, **out, "gear9": gear9, "gear10": gear10, "gear11": gear11}

    @cached_property
    def _gear9_zero(self) -> float:
        """Gear 5's angle less carrier 2's at the start: gear 9 is keyed to gear 5's shaft so that
        the spur pair starts at its design start there (or as :attr:`keys` says)."""
        if self.keys is not None:
            return self.keys[0]
        start = self._on_carrier1(np.zeros(1))
        return float(start["gear5"][0] - start["carrier2"][0])

    @cached_property
    def _g0(self) -> float:
        f = self.follower
        d, arm, prime = f.pivot_distance, f.arm_length, f.base_radius + f.roller_radius
        return math.acos((d * d + arm * arm - prime * prime) / (2 * d * arm))

    @cached_property
    def arm_offset(self) -> float:
        """The arm's angle less gear 11's (its key): the arm at the chain's attitude at pose 1 (or
        as :attr:`keys` says)."""
        if self.keys is not None:
            return self.keys[1]
        a = self.angles(np.zeros(1))
        design = float(self.chain.state(np.zeros(1)).arm[0])
        return design - float(a["carrier1"][0] + a["carrier2"][0] + a["gear11"][0])

    # -- poses in the machine frame ------------------------------------------------------------

    def poses(self, theta) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Each member's DXF-frame pose (x, y, angle) in the machine frame: ``carrier1``, ``sun``,
        ``shaft3`` (gear 3), ``shaft3b`` (gear 4 — same shaft, its own key), ``shaft5`` (gear 5),
        ``gear9``, ``follower`` (lever, roller, sector 7), ``carrier2`` (with sector 8),
        ``sector8``, ``idler`` (gear 10), ``gear11`` and ``arm`` (link 3's frame: origin Q, +x to
        the tip) — each a link's ``pose``."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        # each body's link asks for the same positions in turn (a clearance pair, the motion
        # table; the loads ask each link at its five-point stencil, then at the positions): the
        # last few answers are kept, read-only (one answer's arrays are shared by its links)
        key = (theta.shape, theta.tobytes())
        kept = self._memo.setdefault("poses", {})
        if key in kept:
            return kept[key]
        a = self.angles(theta)
        lay = self.layout
        l1, l2, _ = self.chain.link_lengths
        _, _, rot = self.frame
        c1 = a["carrier1"] + rot  # carrier 1 in the machine frame
        c2 = c1 + a["carrier2"]

        def at(origin_angle, p, base=(0.0, 0.0)):
            bx, by = base
            c, s = np.cos(origin_angle), np.sin(origin_angle)
            return bx + c * p[0] - s * p[1], by + c * p[1] + s * p[0]

        ax, ay = at(c1, (l1, 0.0))
        zero = np.zeros_like(theta)
        sx, sy = at(c1, lay.s3)
        px, py = at(c1, lay.pivot)
        ix, iy = at(c2, lay.idler, (ax, ay))
        qx, qy = at(c2, (l2, 0.0), (ax, ay))
        sig8 = self._lines[2]
        out = {
            "carrier1": (zero, zero, c1),
            "sun": (zero, zero, c1 + a["sun"]),
            "shaft3": (sx, sy, c1 + a["gear3"]),
            "shaft3b": (sx, sy, c1 + a["gear4"]),
            "shaft5": (ax, ay, c1 + a["gear5"]),
            "gear9": (ax, ay, c2 + a["gear9"]),
            "follower": (px, py, c1 + a["lever"]),
            "sector7": (px, py, c1 + a["sector7"]),
            "carrier2": (ax, ay, c2),
            "sector8": (ax, ay, c2 + sig8 + math.pi - self._start["beta2_min"]),
            "idler": (ix, iy, c2 + a["gear10"]),
            "gear11": (qx, qy, c2 + a["gear11"]),
            "arm": (qx, qy, c2 + a["gear11"] + self.arm_offset),
        }
        for pose in out.values():
            for v in pose:
                v.flags.writeable = False
        if len(kept) >= POSES_KEPT:
            del kept[next(iter(kept))]  # the oldest
        kept[key] = out
        return out

    @property
    def cut_keys(self) -> tuple[float, float]:
        """The keys this machine sets (:attr:`keys`), to cut into a made machine's parts."""
        return self._gear9_zero, self.arm_offset

    def tip(self, theta) -> np.ndarray:
        """The claw tip (the arm's frame at L3 on +x), (n, 2) mm, machine frame."""
        x, y, a = self.poses(theta)["arm"]
        length = self.chain.link_lengths[2]
        return np.stack([x + length * np.cos(a), y + length * np.sin(a)], axis=1)

    @cached_property
    def links(self) -> dict[str, Link]:
        """Each member as a :class:`~transplanter.machine.bodies.Link` with its speed bounds (the largest
        speed of its frame origin and turn rate over :data:`BOUND_SAMPLES` positions, plus the
        largest change between two of them: the bound between samples), and ``fixed``."""
        n = BOUND_SAMPLES
        theta = TWO_PI * np.arange(n + 1) / n
        out = {"fixed": Link.fixed()}
        lay = self.layout
        l1, l2, _ = self.chain.link_lengths
        a0 = (("fixed", 0.0, 0.0), ("carrier1", 0.0, 0.0))
        ac = (("carrier1", l1, 0.0), ("carrier2", 0.0, 0.0))
        origins = {
            "carrier1": a0,
            "sun": a0,
            "shaft3": (("carrier1", *lay.s3),),
            "shaft3b": (("carrier1", *lay.s3),),
            "shaft5": ac,
            "gear9": ac,
            "follower": (("carrier1", *lay.pivot),),
            "sector7": (("carrier1", *lay.pivot),),
            "carrier2": ac,
            "sector8": ac,
            "idler": (("carrier2", *lay.idler),),
            "gear11": (("carrier2", l2, 0.0),),
            "arm": (("carrier2", l2, 0.0),),
        }
        for name, (x, y, a) in self.poses(theta).items():
            speed = np.hypot(np.diff(x), np.diff(y)) / (TWO_PI / n)
            rate = np.abs(np.diff(a)) / (TWO_PI / n)
            bound_v = float(speed.max() + np.abs(np.diff(speed)).max())
            bound_w = float(rate.max() + np.abs(np.diff(rate)).max())
            out[name] = Link(name, lambda t, name=name: self.poses(t)[name], bound_v, bound_w, origins[name])
        return out
