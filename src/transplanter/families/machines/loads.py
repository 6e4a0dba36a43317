"""A machine under load, from its made parts: mass properties, drive torques, joint, bearing and
tooth loads, the shaking force on the frame (issue 44).

* **Mass** (:func:`link_lumps`): every body of the assembly STEP (:mod:`~transplanter.families.machines.assembly`),
  one lump per slab of its solid, of the density its bill-of-materials item gives — a made part's
  mass over its solid's volume (its material's density), a bought part's catalogue mass spread
  over its modelled solid — in the frame of the link that moves it (a mounted frame
  ``link@where`` moves with ``link``).
* **Loads** (:func:`machine_loads`): :func:`transplanter.machine.dynamics.solve` over the cycle
  at the machine's driver speed — Newton-Euler and virtual power, their largest difference stated.
* **Supports** (:func:`support_rows`): each pin's two supports — a bearing's ISO 281 equivalent
  load over the cycle (the cube mean weighted by the rings' relative turn), its L10h at the mean
  relative speed and its static safety at the cycle's peak; a wrapped bush's pressure ``K F / C``
  and sliding speed against its limits (:mod:`transplanter.shop.catalogue.bushes`).
* **Shaking** (:func:`shaking_record`): the frame's shaking force harmonics per driver turn
  (seed 003's form) and what a counterweight on the driver could cancel of the first.
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.design.linkage.dynamics import harmonics
from transplanter.machine.dynamics import Loads, Machine, angular_speed, equivalent_load, solve
from transplanter.machine.mass import Lump, slab_lump, to_link_frame
from transplanter.shop.arcs import bulge_points
from transplanter.shop.catalogue.bearings import LIFE_H, STATIC_SAFETY, Bearing, rating_life_h
from transplanter.shop.catalogue.bushes import LIMITS, Bush

__all__ = [
    "POSITIONS",
    "POWER_AGREEMENT",
    "link_of",
    "link_lumps",
    "z_span",
    "machine_loads",
    "support_rows",
    "shaking_record",
    "mass_record",
    "drive_rows",
    "mesh_rows",
    "supports_short",
]

#: positions per driver turn the loads are computed at (the harmonics need it even; 1° apart)
POSITIONS = 360
#: Newton-Euler's drive power and virtual power's energy rate must agree to this, relative to
#: the largest drive power (issue 44)
POWER_AGREEMENT = 1e-6
#: the arcs of a slab's section are flattened to within this for its moments, mm
SAGITTA_MM = 1e-3


def link_of(name: str) -> str:
    """The moving link of a body's link name (``carrier@planet_1`` moves with ``carrier``)."""
    return name.split("@", 1)[0]


def link_lumps(placed, bom, links_of: dict[str, str], pose_of) -> dict[str, tuple[Lump, ...]]:
    """Every placed body's slabs as lumps in its moving link's frame (module docstring):
    ``placed`` the assembly's :class:`~transplanter.shop.assembly_step.Placed` bodies (at the
    start), ``links_of`` body name -> its link name, ``pose_of(link) -> (x, y, angle)`` the moving
    link's pose at the start. Bodies on ``fixed`` are the frame's: not lumps."""
    items = {i.item: i for i in bom.items}
    out: dict[str, list[Lump]] = {}
    for p in placed:
        link = link_of(links_of[p.name])
        if link == "fixed":
            continue
        volume = p.solid.volume
        if volume <= 0.0:
            raise GeometryError(f"body {p.name}: its solid has no volume")
        density = items[p.item].mass_kg / volume  # kg/mm³
        pose = pose_of(link)
        for slab in p.solid.slabs:
            rings = [(bulge_points(np.asarray(v, dtype=float), SAGITTA_MM), bool(hole)) for v, hole in slab.contours]
            out.setdefault(link, []).append(to_link_frame(slab_lump(rings, slab.z0, slab.width, density, p.at), pose))
    return {k: tuple(v) for k, v in out.items()}


def z_span(placed, name: str) -> tuple[float, float]:
    """The z-range (mm) a placed body takes across the machine."""
    for p in placed:
        if p.name == name:
            zs = [float(p.at[2, 2] * z + p.at[2, 3]) for s in p.solid.slabs for z in (s.z0, s.z0 + s.width)]
            return min(zs), max(zs)
    raise GeometryError(f"no placed body {name!r} (a support of the machine's loads)")


def machine_loads(model: Machine, speed: float, positions: int = POSITIONS) -> Loads:
    """The loads over one driver turn at ``speed`` rad/s, ``positions`` apart; GeometryError when
    Newton-Euler and virtual power disagree past :data:`POWER_AGREEMENT`."""
    theta = 2 * math.pi * np.arange(positions) / positions
    loads = solve(model, theta, speed)
    if loads.power_error > POWER_AGREEMENT:
        raise GeometryError(
            f"the drives' power by Newton-Euler and the energy rate by virtual power differ by "
            f"{loads.power_error:.3g} of the largest power (> {POWER_AGREEMENT:g}): a joint does work"
        )
    return loads


def _relative_rpm(model: Machine, pin, loads: Loads) -> np.ndarray:
    """The relative turn rate of a pin's two links over the cycle, r/min."""
    w = np.zeros(loads.theta.size)
    for link, sign in ((pin.b, 1.0), (pin.a, -1.0)):
        if link != "fixed":
            w = w + sign * angular_speed(model.links[link], loads.theta, loads.speed)
    return np.abs(w) * 60.0 / (2 * math.pi)


def support_rows(
    model: Machine, loads: Loads, parts: dict[str, tuple[object, object]], life_h: float = LIFE_H
) -> list[dict]:
    """Each pin's supports as the record states them: ``parts[pin name] = (part at z[0], part at
    z[1])`` — a catalogue bearing (ISO 281 life at the cycle's equivalent load, ``pass`` when it is
    at least ``life_h`` and its static safety at least the catalogue's ``STATIC_SAFETY``) or a
    wrapped bush (its pressure and sliding speed; ``pass`` when the peak load is within its rating
    and the sliding speed within its limit) — with the largest radial load and where."""
    rows = []
    deg = np.degrees(loads.theta)
    for j, pin in enumerate(model.pins):
        rpm = _relative_rpm(model, pin, loads)
        for side in (0, 1):
            f = np.linalg.norm(loads.support[:, j, side], axis=1)
            k = int(np.argmax(f))
            part = parts[pin.name][side]
            row = {
                "joint": pin.name,
                "support": "rear" if side == 0 else "front",
                "z_mm": rounded(pin.z[side], 4),
                "max_radial_n": rounded(float(f[k]), 4),
                "at_driver_deg": round(float(deg[k]), 4),
                "mean_speed_rpm": rounded(float(np.mean(rpm)), 4),
            }
            row.update(_rating(part, f, rpm, life_h))
            rows.append(row)
    return rows


def _rating(part, f: np.ndarray, rpm: np.ndarray, life_h: float) -> dict:
    bearing = getattr(part, "bearing", part)
    if isinstance(bearing, Bearing):
        p = equivalent_load(f, rpm)
        n = float(np.mean(rpm))
        life = rating_life_h(bearing.C_n, p, n) if p > 0 else math.inf
        peak = float(np.max(f))
        return {
            "designation": getattr(part, "designation", bearing.designation),
            "standard": "ISO 15",
            "equivalent_load_n": rounded(p, 4),
            "C_n": bearing.C_n,
            "life_h": rounded(life, 4) if math.isfinite(life) else "inf",
            "required_life_h": life_h,
            "static_safety": rounded(bearing.C0_n / peak, 4) if peak > 0 else "inf",
            "pass": bool(life >= life_h and (peak == 0 or bearing.C0_n / peak >= STATIC_SAFETY)),
            "method": "ISO 281:2007 L10h = 10^6 (C/P)^3 / (60 n), P the cube mean of F_r weighted by revolutions",
        }
    bush = getattr(part, "bush", part)
    if isinstance(bush, Bush):
        K, v_max = LIMITS[bush.variant]
        peak = float(np.max(f))
        v = math.pi * bush.d * float(np.max(rpm)) / 60000.0
        return {
            "designation": bush.designation,
            "standard": "ISO 3547-1",
            "pressure_n_mm2": rounded(K * peak / bush.C_n, 4),
            "sliding_m_s": rounded(v, 6),
            "C_n": bush.C_n,
            "load_fraction_of_C": rounded(peak / bush.C_n, 6),
            "sliding_limit_m_s": v_max,
            "pass": bool(peak <= bush.C_n and peak <= bush.C0_n and v <= v_max),
            "method": "wrapped bush: p = K F / C at the peak load, v at the peak relative speed",
        }
    raise GeometryError(f"a support's part {part!r} is neither a catalogue bearing nor a wrapped bush")


def shaking_record(loads: Loads, n_harmonics: int = 6) -> dict:
    """The frame's shaking force (the links' inertia, weight apart): its largest value and where,
    its harmonics per driver turn in x and y (seed 003's ``R_n``), and the first harmonic's part
    that turns with the driver — what a counterweight on the driver can cancel (its mass moment
    ``m r = |c| / ω²``) — with the largest force left after it."""
    f = loads.shaking_force
    mag = np.linalg.norm(f, axis=1)
    k = int(np.argmax(mag))
    hx, hy = harmonics(f[:, 0], n_harmonics), harmonics(f[:, 1], n_harmonics)
    z = f[:, 0] + 1j * f[:, 1]
    n = z.size
    # z = Σ c_k e^{i k θ}; the driver turns clockwise (its angle -θ), so a mass on it gives c_-1
    c_minus = complex(np.sum(z * np.exp(1j * loads.theta)) / n)
    left = z - c_minus * np.exp(-1j * loads.theta)
    mass_moment = abs(c_minus) / loads.speed**2 * 1e3  # N / (rad/s)² = kg m -> kg mm
    return {
        "max_n": rounded(float(mag[k]), 4),
        "at_driver_deg": round(float(np.degrees(loads.theta[k])), 4),
        "harmonics_x_n": [rounded(float(v), 4) for v in hx.R[1:]],
        "harmonics_y_n": [rounded(float(v), 4) for v in hy.R[1:]],
        "turning_with_driver_n": rounded(abs(c_minus), 6),
        "counterweight_kg_mm": rounded(mass_moment, 4),
        "counterweight_angle_deg": round(math.degrees(math.atan2(c_minus.imag, c_minus.real)) % 360.0, 4),
        "max_after_counterweight_n": rounded(float(np.max(np.abs(left))), 4),
        "max_moment_nm": rounded(float(np.max(np.abs(loads.shaking_moment))), 4),
    }


def mass_record(lumps: dict[str, tuple[Lump, ...]]) -> dict:
    """Each moving link's mass (kg), centre of mass (mm) and moment of inertia about its centre of
    mass (kg·mm², about z), from its lumps. The centre is in the **link's frame** — the frame its
    pose moves, which is its main body's drawing frame as mounted: for a link whose main body is
    mounted face down (a mirrored gear) its y is that drawing's mirrored; z across the machine.
    Every body of the assembly counts, the keys inside their hubs too (bought bodies of the
    assembly STEP, not bodies of the clearance judge or the motion table: they never meet
    anything their hub and shaft do not already stand for)."""
    out = {}
    for link in sorted(lumps):
        ls = lumps[link]
        m = sum(lp.mass for lp in ls)
        c = np.sum([np.multiply(lp.com, lp.mass) for lp in ls], axis=0) / m
        izz = sum(lp.izz + lp.mass * ((lp.com[0] - c[0]) ** 2 + (lp.com[1] - c[1]) ** 2) for lp in ls)
        com = [rounded(float(v), 4) for v in c]
        out[link] = {"mass_kg": rounded(m, 6), "com_mm": com, "izz_kg_mm2": rounded(izz, 4)}
    return out


def drive_rows(m: Machine, loads: Loads, idle: Loads | None = None) -> list[dict]:
    """Each drive's speed, torque (peak, where, RMS) and power (peak, mean) over the cycle — the
    motor's size — and, given ``idle`` (the same machine without its work loads), its peak torque
    from the links' inertia and weight alone."""
    rows = []
    for i, d in enumerate(m.drives):
        t = loads.torque[:, i]
        w = angular_speed(m.links[d.link], loads.theta, loads.speed)
        p = t * w
        k = int(np.argmax(np.abs(t)))
        row = {
            "drive": d.name,
            "speed_rpm": rounded(float(np.mean(np.abs(w))) * 30 / math.pi, 6),
            "peak_torque_nm": rounded(float(t[k]), 4),
            "at_driver_deg": round(float(np.degrees(loads.theta[k])), 4),
            "rms_torque_nm": rounded(float(np.sqrt(np.mean(t**2))), 4),
            "peak_power_w": rounded(float(np.max(np.abs(p))), 4),
            "mean_power_w": rounded(float(np.mean(p)), 4),
        }
        if idle is not None:
            row["peak_torque_without_work_nm"] = rounded(float(np.max(np.abs(idle.torque[:, i]))), 4)
        rows.append(row)
    return rows


def mesh_rows(m: Machine, loads: Loads) -> list[dict]:
    """Each mesh's largest tooth normal force, where, and its mean over the cycle."""
    rows = []
    for j, mesh in enumerate(m.meshes):
        f = loads.mesh[:, j]
        k = int(np.argmax(f))
        rows.append(
            {
                "mesh": mesh.name,
                "max_normal_force_n": rounded(float(f[k]), 4),
                "at_driver_deg": round(float(np.degrees(loads.theta[k])), 4),
                "mean_normal_force_n": rounded(float(np.mean(f)), 4),
            }
        )
    return rows


def supports_short(rows: list[dict], sized_for: str) -> str | None:
    """The problem a machine states when a support of ``rows`` (:func:`support_rows`) falls short at
    the computed loads — each with its peak load and life — and the load the structure sized it for
    (``sized_for``): a larger stated structure load sizes it again; None when every one passes."""
    short = [r for r in rows if not r["pass"]]
    if not short:
        return None
    said = "; ".join(
        f"{r['designation']} ({r['joint']}, {r['support']}: peak {r['max_radial_n']} N, L10h {r.get('life_h', '-')} h)"
        for r in short
    )
    return f"under load: {said} short of its life or rating: sized for {sized_for}, state a larger load"
