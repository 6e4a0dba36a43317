"""A machine under load: inverse dynamics of its moving links over the cycle, from the made parts.

The machine's links move as its kinematics prescribe (:class:`~transplanter.machine.bodies.Link`
poses, the driver turning at a constant ``speed``); each link carries **lumps** of mass — one per
slab of each body's solid, from the made part's material or the bought part's catalogue mass
(:mod:`~transplanter.machine.mass`) — each with its centre across the machine (z). Joined by

* :class:`Pin` — a revolute joint on two supports (bearings or bushes at ``z``), a point common
  to both links (its force: two unknowns in the plane, split between the supports by the
  out-of-plane moment balance);
* :class:`Mesh` — two gears' teeth: the normal force along the tooth normal through the **pitch
  point**, the two links' relative instant centre (found from their velocities, so the mesh force
  does no work in the motion: the law of gearing), tilted by the cutter's pressure angle from the
  pitch curves' common tangent (found from the pitch point's path in the driven link's frame)
  towards the flank that pushes (``F >= 0``; each position's flank chosen so), or circular gears' on
  their line of centres (``fraction``); :class:`Contact` — a cam on a roller, normal to its path on the cam;
* :class:`Drive` — a torque between a link and the frame (a motor at a constant speed);

and loaded by gravity (``-y``, the machine's plane vertical) and :class:`PointLoad` s (a tool's
work), :func:`solve` gives at every position the torque of every drive, the force of every pin
(and on each of its supports) and mesh, the shaking force and moment on the frame, two ways:

1. **Newton-Euler**: per moving link ``Σ F = Σ m a`` and ``Σ M_O = Σ (m r × a + I α)`` about the
   fixed origin O — one linear system per position (3 equations per link; as many unknowns);
2. **virtual power**: ``Σ τ ω = d(T + V)/dt - P_loads``, the kinetic and potential energy of the
   lumps differentiated in the driver angle (a five-point stencil of the energy itself, not the
   accelerations Newton-Euler uses); ``power_error`` is their largest difference relative to the
   largest drive power — the joints' forces do no work only if every pitch point and pin is right.

Derivatives of the poses are five-point central differences in the driver angle (step
:data:`STEP_RAD`): for poses smooth over the cycle (a Fourier pitch curve's harmonics up to k per
rad) the truncation is ~(k h)^4 / 30, 10^-9 for k = 20 — the kinematics the loads need, not the
made parts' micrometre transmission error (an excitation this rigid model leaves out: stated).

Supports: a pin's two supports at ``z1 < z2`` share its force ``f`` as the moments of every force on
its link about the x and y axes require (the in-plane forces at their lumps' and meshes' z): one
more linear system, square when the pins and the moving links are as many (a tree). No axial
load: spur teeth and gravity in the plane (stated where used).

Units: mm, kg, s inside; forces N, torques and moments N·m.

Examples
--------
A bar of 1 kg with its centre 100 mm from the pin, turned at 1 rad/s about a horizontal axis,
needs ``m g r cos θ`` to hold it against gravity, and its pin carries the centripetal force:

>>> import numpy as np
>>> from transplanter.machine.bodies import Link
>>> from transplanter.machine.dynamics import Drive, Lump, Machine, Pin, solve
>>> bar = Link("bar", lambda t: (np.zeros_like(t), np.zeros_like(t), np.asarray(t, dtype=float)))
>>> m = Machine({"bar": bar}, {"bar": (Lump(1.0, (100.0, 0.0, 0.0), 0.0),)},
...             pins=(Pin("O", "fixed", "bar", (-10.0, 10.0)),), drives=(Drive("motor", "bar"),))
>>> loads = solve(m, np.array([0.0, np.pi / 2]), speed=1.0)
>>> [round(float(t), 6) + 0.0 for t in loads.torque[:, 0]]
[0.980665, 0.0]
>>> round(float(loads.power_error), 9)
0.0
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import GeometryError, SpecError, check_number
from transplanter.machine.mass import Lump

__all__ = [
    "STANDARD_GRAVITY",
    "STEP_RAD",
    "Lump",
    "Pin",
    "Mesh",
    "Contact",
    "Drive",
    "PointLoad",
    "Machine",
    "Loads",
    "solve",
    "angular_speed", "link_motion", "Motion",
    "equivalent_load",
]

#: m/s², along -y of the machine frame
STANDARD_GRAVITY = 9.80665
#: the driver-angle step of the five-point stencils, rad
STEP_RAD = 1e-3
_FIXED = "fixed"


@dataclass(frozen=True)
class Pin:
    """A revolute joint: the force of link ``a`` on link ``b`` at ``point`` (mm, in ``b``'s frame),
    carried by two supports at ``z`` (mm across the machine; equal: one support takes it all)."""

    name: str
    a: str
    b: str
    z: tuple[float, float]
    point: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class Mesh:
    """Two gears' teeth: the force of link ``a``'s on link ``b``'s in the plane ``z`` (mm); ``ring``:
    which of the two is an internal gear (``"a"``, ``"b"`` or None); ``pressure_angle`` rad;
    ``fraction``: circular gears on their links' origins, the pitch point at ``r_a / (r_a + r_b)`` from ``a``'s."""

    name: str
    a: str
    b: str
    z: float
    pressure_angle: float = math.radians(20.0)
    ring: str | None = None
    fraction: float | None = None

    def __post_init__(self) -> None:
        if self.ring not in (None, "a", "b"):
            raise SpecError.out_of_range(f"mesh {self.name}: ring", self.ring, "None, 'a' or 'b'")
        check_number(f"mesh {self.name}: pressure_angle", self.pressure_angle, 0.0, 1.2, unit="rad")
        if self.fraction is not None:
            check_number(f"mesh {self.name}: fraction", self.fraction, 0.0, 1.0, low_open=True, high_open=True)


@dataclass(frozen=True)
class Contact:
    """A cam on a roller: link ``a``'s force on ``b`` through ``point`` (mm in ``b``'s frame: the roller's
    centre) normal to its path relative to ``a``, + away from ``a``'s origin, in the plane ``z`` mm."""

    name: str
    a: str
    b: str
    z: float
    point: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class Drive:
    """A motor: a torque on ``link`` from the frame (its reaction on the frame)."""

    name: str
    link: str


@dataclass(frozen=True)
class PointLoad:
    """A force on ``link`` at ``point`` (mm in its frame, plane ``z``): ``force(theta, position,
    velocity) -> (n, 2)`` N, from the point's position (mm) and velocity (mm/s) in the machine frame."""

    name: str
    link: str
    point: tuple[float, float]
    z: float
    force: Callable = field(repr=False)


@dataclass(frozen=True)
class Machine:
    """The moving ``links`` (name -> :class:`~transplanter.machine.bodies.Link`; ``fixed`` is the
    frame), the ``lumps`` each carries, and what joins, drives and loads them."""

    links: dict
    lumps: dict
    pins: tuple[Pin, ...] = ()
    meshes: tuple[Mesh, ...] = ()
    drives: tuple[Drive, ...] = ()
    loads: tuple[PointLoad, ...] = ()
    gravity: float = STANDARD_GRAVITY
    contacts: tuple[Contact, ...] = ()

    @property
    def moving(self) -> list[str]:
        return [k for k in self.links if k != _FIXED]

    def check(self) -> None:
        names = set(self.moving) | {_FIXED}
        for j in (*self.pins, *self.meshes, *self.contacts):
            for side in (j.a, j.b):
                if side not in names:
                    raise SpecError(f"{type(j).__name__.lower()} {j.name}: link {side!r} is not a link of the machine")
        for d in (*self.drives, *self.loads):
            if d.link not in self.links or d.link == _FIXED:
                raise SpecError(f"{d.name}: link {d.link!r} is not a moving link of the machine")
        unknowns = 2 * len(self.pins) + len(self.meshes) + len(self.contacts) + len(self.drives)
        if unknowns != 3 * len(self.moving):
            raise SpecError(
                f"the machine is not determinate: {unknowns} unknown forces and torques (2 per pin, 1 per mesh, "
                f"contact and drive) for {3 * len(self.moving)} equations (3 per moving link)"
            )


@dataclass(frozen=True)
class Loads:
    """What the machine carries at each driver angle ``theta`` (rad) at driver ``speed`` (rad/s).

    ``torque`` (n, drives) N·m on each drive's link; ``pin`` (n, pins, 2) N of ``a`` on ``b``;
    ``support`` (n, pins, 2, 2) N of the pin's two supports (at ``z[0]``, ``z[1]``); ``mesh`` (n,
    meshes) N, the tooth normal force, along ``mesh_line`` (n, meshes, 2) through ``pitch_point``
    (n, meshes, 2) mm; ``shaking_force`` (n, 2) N and ``shaking_moment`` (n,) N·m about O, what
    the moving links' inertia puts on the frame (``-Σ m a``, ``-Σ (m r × a + I α)``; weight apart);
    ``power`` (n,) W by the drives (Newton-Euler), ``energy_rate`` (n,) W (virtual power) and
    ``power_error`` their largest difference over the largest |power|; ``contact`` (n, contacts) N
    along ``contact_line`` (n, contacts, 2) (negative: the cam would have to pull)."""

    theta: np.ndarray
    speed: float
    torque: np.ndarray
    pin: np.ndarray
    support: np.ndarray
    mesh: np.ndarray
    mesh_line: np.ndarray
    pitch_point: np.ndarray
    shaking_force: np.ndarray
    shaking_moment: np.ndarray
    power: np.ndarray
    energy_rate: np.ndarray
    power_error: float
    frame_force: np.ndarray
    contact: np.ndarray
    contact_line: np.ndarray


# -- kinematics -------------------------------------------------------------------------------

_W1 = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / 12.0  # f' h
_W2 = np.array([-1.0, 16.0, -30.0, 16.0, -1.0]) / 12.0  # f'' h²
_OFFSETS = np.arange(-2, 3)


@dataclass(frozen=True)
class Motion:
    """A link's frame over θ: origin ``o`` (n, 2) mm, angle ``a``, velocity, acceleration (per s)."""

    o: np.ndarray
    a: np.ndarray
    v: np.ndarray
    w: np.ndarray
    acc: np.ndarray
    alpha: np.ndarray

    def point(self, local: np.ndarray):
        """Position, velocity, acceleration of the point ``local`` (2,) or (n, 2) of the link's frame."""
        c, s = np.cos(self.a), np.sin(self.a)
        lx, ly = np.broadcast_to(local, self.o.shape).T
        r = np.stack([c * lx - s * ly, s * lx + c * ly], axis=1)
        perp = np.stack([-r[:, 1], r[:, 0]], axis=1)
        acc = self.acc + self.alpha[:, None] * perp - (self.w**2)[:, None] * r
        return self.o + r, self.v + self.w[:, None] * perp, acc


def _pose(link, theta: np.ndarray) -> np.ndarray:
    x, y, a = (np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in link.pose(theta))
    return np.stack([x, y, a], axis=-1)


def link_motion(link, theta: np.ndarray, speed: float, h: float = STEP_RAD) -> Motion:
    grid = theta[None, :] + h * _OFFSETS[:, None]  # (5, n)
    p = _pose(link, grid.ravel()).reshape(5, -1, 3)
    p = p - p[2]
    p[..., 2] = np.angle(np.exp(1j * p[..., 2]))  # angle steps, unwrapped about the middle
    d1 = np.tensordot(_W1, p, axes=1) / h * speed
    d2 = np.tensordot(_W2, p, axes=1) / h**2 * speed**2
    base = _pose(link, theta)
    return Motion(base[:, :2], base[:, 2], d1[:, :2], d1[:, 2], d2[:, :2], d2[:, 2])


def angular_speed(link, theta: np.ndarray, speed: float) -> np.ndarray:
    """The link's angular velocity (rad/s, counter-clockwise +) at driver angles ``theta`` turning at ``speed``."""
    return link_motion(link, np.atleast_1d(np.asarray(theta, dtype=float)), speed).w


def _cross(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def _pitch_point(ma: Motion, mb: Motion, name: str) -> np.ndarray:
    """The relative instant centre of two links: where their velocities are equal."""
    dw = ma.w - mb.w
    if np.any(np.abs(dw) < 1e-9 * (np.abs(ma.w) + np.abs(mb.w) + 1e-12)):
        raise GeometryError(f"mesh {name}: the two gears do not turn against each other at some position")
    jo_a = np.stack([-ma.o[:, 1], ma.o[:, 0]], axis=1)
    jo_b = np.stack([-mb.o[:, 1], mb.o[:, 0]], axis=1)
    rhs = (mb.v - ma.v + ma.w[:, None] * jo_a - mb.w[:, None] * jo_b) / dw[:, None]  # = J P
    return np.stack([rhs[:, 1], -rhs[:, 0]], axis=1)


def _mesh_frame(m: Machine, mesh: Mesh, theta: np.ndarray, speed: float, h: float):
    """The pitch point (n, 2), the common tangent (n, 2) (the pitch point's path on gear ``b``) and
    the separating normal (n, 2) pointing into ``b``'s side."""
    if mesh.fraction is not None:
        oa, ob = (_pose(m.links[k], theta)[:, :2] for k in (mesh.a, mesh.b))
        sep = (ob - oa) / np.linalg.norm(ob - oa, axis=1)[:, None]
        return oa + mesh.fraction * (ob - oa), np.stack([-sep[:, 1], sep[:, 0]], axis=1), sep
    flat = (theta[None, :] + h * _OFFSETS[:, None]).ravel()
    ma, mb = link_motion(m.links[mesh.a], flat, speed, h), link_motion(m.links[mesh.b], flat, speed, h)
    p = _pitch_point(ma, mb, mesh.name)
    t = _path_tangent(p, mb)
    pitch, ob = p.reshape(5, -1, 2)[2], mb.o.reshape(5, -1, 2)[2]
    n = np.stack([-t[:, 1], t[:, 0]], axis=1)
    towards_b = np.sign(np.einsum("ij,ij->i", n, ob - pitch))
    towards_b[towards_b == 0] = 1.0
    side = -1.0 if mesh.ring == "b" else 1.0  # a ring's body lies outside its pitch curve
    return pitch, t, side * towards_b[:, None] * n


def _path_tangent(p: np.ndarray, mo: Motion) -> np.ndarray:
    """The unit tangent (n, 2, machine frame) of the path of points ``p`` (5n, 2: the stencil's) in ``mo``'s frame."""
    c, s = np.cos(mo.a), np.sin(mo.a)
    d = p - mo.o
    local = np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1).reshape(5, -1, 2)
    tl = np.tensordot(_W1, local, axes=1)
    c, s = c.reshape(5, -1)[2], s.reshape(5, -1)[2]
    t = np.stack([c * tl[:, 0] - s * tl[:, 1], s * tl[:, 0] + c * tl[:, 1]], axis=1)
    return t / np.linalg.norm(t, axis=1)[:, None]


def _contact_frame(m: Machine, con: Contact, theta: np.ndarray, speed: float, h: float):
    """The roller's centre (n, 2) and the contact's normal (n, 2), away from ``a``'s origin."""
    flat = (theta[None, :] + h * _OFFSETS[:, None]).ravel()
    ma, mb = link_motion(m.links[con.a], flat, speed, h), link_motion(m.links[con.b], flat, speed, h)
    p = mb.point(np.array(con.point))[0]
    t = _path_tangent(p, ma)
    p, oa = p.reshape(5, -1, 2)[2], ma.o.reshape(5, -1, 2)[2]
    u = np.stack([-t[:, 1], t[:, 0]], axis=1)
    return p, u * np.where(np.einsum("ij,ij->i", u, p - oa) < 0.0, -1.0, 1.0)[:, None]


def _line_columns(a: np.ndarray, rows: dict, joint, col: int, point: np.ndarray, u: np.ndarray) -> None:
    """Column ``col`` of ``a``: a unit force along ``u`` through ``point`` of ``joint.a`` on ``joint.b``."""
    for link, sign in ((joint.b, 1.0), (joint.a, -1.0)):
        if link != _FIXED:
            r = rows[link]
            a[:, r, col] += sign * u[:, 0]
            a[:, r + 1, col] += sign * u[:, 1]
            a[:, r + 2, col] += sign * _cross(point, u)


# -- the loads --------------------------------------------------------------------------------


def solve(m: Machine, theta: np.ndarray, speed: float, h: float = STEP_RAD) -> Loads:
    """The loads of machine ``m`` at driver angles ``theta`` (rad) turning at ``speed`` rad/s
    (module docstring): Newton-Euler, checked by virtual power."""
    m.check()
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    n = theta.size
    moving = m.moving
    motions = {k: link_motion(m.links[k], theta, speed, h) for k in moving}
    g = np.array([0.0, -m.gravity * 1e3])  # mm/s²
    # each link's lumps: positions, accelerations (machine frame), the inertia terms
    rows = {k: 3 * i for i, k in enumerate(moving)}
    rhs = np.zeros((n, 3 * len(moving)))
    lumped: dict[str, list] = {}
    for k in moving:
        mo, at = motions[k], []
        for lump in m.lumps.get(k, ()):
            pos, _, acc = mo.point(np.array(lump.com[:2]))
            at.append((lump, pos, acc))
            rhs[:, rows[k] : rows[k] + 2] += lump.mass * (acc - g)
            rhs[:, rows[k] + 2] += lump.mass * _cross(pos, acc - g) + lump.izz * mo.alpha
        lumped[k] = at
    # external loads: on the right-hand side with their sign turned
    ext = []
    for ld in m.loads:
        pos, vel, _ = motions[ld.link].point(np.array(ld.point))
        f = np.asarray(ld.force(theta, pos, vel), dtype=float) * 1e3  # N -> kg mm/s²
        ext.append((ld, pos, vel, f))
        rhs[:, rows[ld.link] : rows[ld.link] + 2] -= f
        rhs[:, rows[ld.link] + 2] -= _cross(pos, f)
    base = np.zeros((n, 3 * len(moving), 3 * len(moving)))
    col = 0
    for p in m.pins:
        on_b = p.b if p.b != _FIXED else p.a
        pos = motions[on_b].point(np.array(p.point))[0] if p.b != _FIXED else np.broadcast_to(p.point, (n, 2))
        for k, u in enumerate(np.eye(2)):  # its force's x and y
            _line_columns(base, rows, p, col + k, pos, np.broadcast_to(u, (n, 2)))
        col += 2
    mesh_cols = list(range(col, col + len(m.meshes)))
    col += len(m.meshes)
    contacts = [_contact_frame(m, c, theta, speed, h) for c in m.contacts]
    for c, (point, u) in zip(m.contacts, contacts, strict=True):
        _line_columns(base, rows, c, col, point, u)
        col += 1
    for d in m.drives:
        base[:, rows[d.link] + 2, col] = 1e6  # N·m -> kg mm²/s²
        col += 1
    frames = [_mesh_frame(m, mesh, theta, speed, h) for mesh in m.meshes]
    flank = np.ones((n, len(m.meshes)))
    for _ in range(4):
        a = base.copy()
        lines = np.zeros((n, len(m.meshes), 2))
        for j, (mesh, (pitch, t, sep)) in enumerate(zip(m.meshes, frames, strict=True)):
            ca, sa = math.cos(mesh.pressure_angle), math.sin(mesh.pressure_angle)
            u = flank[:, j, None] * ca * t + sa * sep
            lines[:, j] = u
            _line_columns(a, rows, mesh, mesh_cols[j], pitch, u)
        try:
            x = np.linalg.solve(a, rhs[..., None])[..., 0]
        except np.linalg.LinAlgError as exc:
            raise GeometryError(f"the machine's joints do not hold its links at some position: {exc}") from exc
        wrong = x[:, mesh_cols] < 0.0
        if not wrong.any():
            break
        flank = np.where(wrong, -flank, flank)
    else:
        raise GeometryError("a mesh's force pulls on either flank at some position: the teeth cannot carry it")
    force = x * 1e-3  # kg mm/s² -> N
    pins = force[:, : 2 * len(m.pins)].reshape(n, -1, 2)
    meshes = force[:, mesh_cols]
    touch = force[:, col - len(m.drives) - len(m.contacts) : col - len(m.drives)]
    touch_line = np.stack([u for _, u in contacts], axis=1) if contacts else np.zeros((n, 0, 2))
    torque = x[:, col - len(m.drives) : col]
    pitch = np.stack([f[0] for f in frames], axis=1) if frames else np.zeros((n, 0, 2))
    # what the inertia puts on the frame (weight apart), and the frame's reactions
    shaking_f, shaking_m = np.zeros((n, 2)), np.zeros(n)
    energy = _energy_rate(m, theta, speed, h)
    for k in moving:
        for lump, pos, acc in lumped[k]:
            shaking_f -= lump.mass * acc * 1e-3
            shaking_m -= (lump.mass * _cross(pos, acc) + lump.izz * motions[k].alpha) * 1e-6
    frame = np.zeros((n, 2))
    for j, p in enumerate(m.pins):
        frame += pins[:, j] * (float(p.b == _FIXED) - float(p.a == _FIXED))
    power = sum(torque[:, i] * motions[d.link].w for i, d in enumerate(m.drives)) if m.drives else np.zeros(n)
    for _, _, vel, f in ext:
        energy -= np.einsum("ij,ij->i", f, vel) * 1e-6  # the loads' power: kg mm²/s³ -> W
    scale = max(float(np.max(np.abs(power))), float(np.max(np.abs(energy))), 1e-300)
    error = float(np.max(np.abs(power - energy))) / scale
    lined = [(mesh, meshes[:, j, None] * lines[:, j]) for j, mesh in enumerate(m.meshes)]
    lined += [(c, touch[:, j, None] * touch_line[:, j]) for j, c in enumerate(m.contacts)]
    support = _supports(m, theta, motions, lumped, pins, lined, ext, g)
    out = (theta, speed, torque, pins, support, meshes, lines, pitch, shaking_f, shaking_m, power, energy, error)
    return Loads(*out, frame, touch, touch_line)


def _energy_rate(m: Machine, theta: np.ndarray, speed: float, h: float) -> np.ndarray:
    """d(T + V)/dt, W: the energy of the lumps at θ ± h, ± 2h, differentiated."""
    grid = (theta[None, :] + h * _OFFSETS[:, None]).ravel()
    e = np.zeros(grid.size)
    for k in m.moving:
        mo = link_motion(m.links[k], grid, speed, h)
        for lump in m.lumps.get(k, ()):
            pos, vel, _ = mo.point(np.array(lump.com[:2]))
            e += 0.5 * lump.mass * (vel**2).sum(1) + 0.5 * lump.izz * mo.w**2 + lump.mass * m.gravity * 1e3 * pos[:, 1]
    return np.tensordot(_W1, e.reshape(5, -1), axes=1) / h * speed * 1e-6


def _supports(m: Machine, theta, motions, lumped, pins, lined, ext, g) -> np.ndarray:
    """Each pin's force split between its two supports by every moving link's moment balance
    about the x- and y-axes: ``Σ z F = 0`` over the forces in its plane (inertia as ``-m a``)."""
    n, moving = theta.size, m.moving
    rows = {k: 2 * i for i, k in enumerate(moving)}
    a = np.zeros((n, 2 * len(moving), 2 * len(m.pins)))
    b = np.zeros((n, 2 * len(moving)))
    for k in moving:
        for lump, _, acc in lumped[k]:
            b[:, rows[k] : rows[k] + 2] -= lump.mass * (g - acc) * 1e-3 * lump.com[2]
    for ld, _, _, f in ext:
        b[:, rows[ld.link] : rows[ld.link] + 2] -= f * 1e-3 * ld.z
    for joint, f in lined:  # the meshes' and contacts' forces (N) in their planes
        for link, sign in ((joint.b, 1.0), (joint.a, -1.0)):
            if link != _FIXED:
                b[:, rows[link] : rows[link] + 2] -= sign * f * joint.z
    for j, p in enumerate(m.pins):
        for link, sign in ((p.b, 1.0), (p.a, -1.0)):
            if link != _FIXED:  # the pin's moment z1 f1 + z2 f2, unknown
                a[:, rows[link], 2 * j] += sign
                a[:, rows[link] + 1, 2 * j + 1] += sign
    if a.shape[1] != a.shape[2]:  # a closed loop (a four-bar): each pin's force whole on one support
        out = np.zeros((n, len(m.pins), 2, 2))
        out[:, :, 0] = pins
        return out
    try:
        moment = np.linalg.solve(a, b[..., None])[..., 0].reshape(n, -1, 2)
    except np.linalg.LinAlgError as exc:
        raise GeometryError(f"the supports' shares are not determinate: {exc}") from exc
    out = np.zeros((n, len(m.pins), 2, 2))
    for j, p in enumerate(m.pins):
        z1, z2 = p.z
        f = pins[:, j]
        if abs(z2 - z1) < 1e-9:
            out[:, j, 0] = f
            continue
        out[:, j, 0] = (z2 * f - moment[:, j]) / (z2 - z1)
        out[:, j, 1] = (moment[:, j] - z1 * f) / (z2 - z1)
    return out


def equivalent_load(force: np.ndarray, turn: np.ndarray) -> float:
    """ISO 281's equivalent load of a varying radial ``force`` (n,) N over a cycle whose relative
    turn of the bearing's rings per position is ``turn`` (n,) (any unit): ``(Σ F³ |Δ| / Σ |Δ|)^(1/3)``,
    the cube mean weighted by revolutions (ISO 281:2007 eq. for variable load and speed)."""
    f = np.abs(np.asarray(force, dtype=float))
    w = np.abs(np.asarray(turn, dtype=float))
    if w.sum() <= 0.0:
        return float(np.max(f))
    return float((np.sum(f**3 * w) / np.sum(w)) ** (1.0 / 3.0))
