"""A fixed shaft built into one plate, rated as a cantilever under the machine's loads (issue 42).

Seed 002's central shaft carries the sun and, through the drive tube's two bushes, carrier 1 and
everything on it. Carrier 1 turns round it through the whole circle, reaching 167 mm from the axis
in every plane from the cam's to the claw's, so no part of the frame can reach the shaft's front
end: the shaft is **built in** — clamped in the frame plate (H7/k6, keyed, a retaining ring each
side) — and the bearing of carrier 1's front plate on its front end is a seat of carrier 1, not a
support of the shaft. "Supported at both ends" is replaced by this stated equivalent, rated from
the clamp's front face under the loads of :mod:`transplanter.machine.dynamics`:

* the forces the named joints put on the shaft over the cycle (the bushes' two supports, the sun's
  mesh) give ``M(z) = Σ_{z_i > z} F_i (z_i - z)`` in front of the clamp;
* at the clamp's face and every critical section in front of it (keyseat ends, retaining-ring
  grooves, shoulders), Shigley's DE-Goodman and yield safety as for every shaft
  (:mod:`~transplanter.families.machines.shafts`, Table 7-1's ``K_t``), under the moment and the
  torque of the loads beyond the section, the shaft standing still while its loads turn;
* the seat's pressure in the plate, ``p = F/(d L) + 6 M/(d L²)`` at the plate's faces (a rigid pin
  built into a plate of thickness ``L``: the force spread evenly, the moment as a linear pressure),
  against the weaker member's ``Re`` over :data:`~transplanter.families.machines.shafts.KEY_SAFETY`
  (bearing against yield, as the keys);
* its deflection and slope at each load: point loads on a cantilever superposed (``x`` from the
  clamp's face, a load at ``a``: ``F x² (3a - x) / 6EI`` for ``x <= a``, ``F a² (3x - a) / 6EI``
  beyond; slope ``F x (2a - x) / 2EI``, ``F a² / 2EI``), ``E = 210 000 N/mm²`` (steel, EN 1993-1-1
  §3.2.6), ``I = π d⁴/64`` of the shaft's smallest section in front of the clamp (its grooves' root:
  the stiffness is not overstated), the plate taken as rigid — at the mesh against Shigley's limits
  (Budynas & Nisbett, 9th ed., Table 7-2): transverse deflection at a spur gear 0.010 in for a
  diametral pitch P < 10 teeth/in, 0.005 in for 11-19, 0.003 in for 20-50 (P = 25.4/m), slope at an
  uncrowned spur gear 0.0005 rad.

Units: mm, N, N·m, MPa.

>>> beam = deflection_and_slope(np.array([[[0.0, 100.0]]]), np.array([20.0]), np.array([30.0]), 17.0)
>>> [round(float(v), 6) for v in beam]  # 100 N, 20 mm from the clamp, seen 30 mm from it (mm, rad)
[0.000542, 2.3e-05]
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.errors import SpecError
from transplanter.core.precision import rounded
from transplanter.families.machines import shafts
from transplanter.families.machines.loads import z_span
from transplanter.machine.dynamics import Loads, Machine

__all__ = ["E_STEEL_MPA", "built_in_row", "deflection_and_slope", "gear_deflection_limit_mm"]

#: Young's modulus of steel, N/mm² (EN 1993-1-1:2005 §3.2.6)
E_STEEL_MPA = 210_000.0
#: Shigley 9th ed. Table 7-2: the slope a shaft may have at an uncrowned spur gear, rad
SLOPE_LIMIT_RAD = 0.0005


def gear_deflection_limit_mm(module_mm: float) -> float:
    """Shigley 9th ed. Table 7-2's transverse deflection a shaft may have at a spur gear, by its
    diametral pitch ``P = 25.4 / m`` teeth/in (mm): 0.010 in below 11, 0.005 in to 19, 0.003 in above.

    >>> gear_deflection_limit_mm(1.5)  # P = 16.9
    0.127
    """
    pitch = 25.4 / module_mm
    inch = 0.010 if pitch < 11.0 else 0.005 if pitch < 20.0 else 0.003
    return round(inch * 25.4, 6)


def deflection_and_slope(forces: np.ndarray, at: np.ndarray, x: np.ndarray, d_mm: float):
    """The largest deflection (mm) and slope (rad) over the rows of ``forces`` (n, k) — or
    (n, k, 2) vectors — at ``at`` (k,) mm from the clamp, seen ``x`` mm from it: per row, the loads'
    superposed vectors (module docstring), their largest length over the rows and the ``x``."""
    ei = E_STEEL_MPA * math.pi * d_mm**4 / 64
    f = np.asarray(forces, dtype=float)
    f = f[..., None] if f.ndim == 2 else f  # (n, k, c)
    a, xs = np.asarray(at, dtype=float)[:, None], np.asarray(x, dtype=float)[None, :]  # (k, 1), (1, s)
    near = xs <= a
    w = np.where(near, xs**2 * (3 * a - xs), a**2 * (3 * xs - a)) / (6 * ei)  # (k, s) per newton
    s = np.where(near, xs * (2 * a - xs), a**2) / (2 * ei)
    dev = np.linalg.norm(np.einsum("ks,nkc->nsc", w, f), axis=-1)
    tilt = np.linalg.norm(np.einsum("ks,nkc->nsc", s, f), axis=-1)
    return float(dev.max()), float(tilt.max())


def built_in_row(
    m: Machine,
    loads: Loads,
    placed,
    bom,
    shaft: str,
    plate: str,
    joints,
    mesh: tuple[str, float],
    keys: tuple[str, ...] = (),
    why: str = "",
) -> dict:
    """The record of ``shaft`` (a placed body on the fixed link) built into ``plate`` (a placed body),
    loaded by ``joints`` (pin, mesh, contact names on the fixed link); ``mesh`` ``(its joint name,
    the gears' module mm)`` the gear the deflection limit is for, ``keys`` the placed keys in the
    shaft (their seats' ends are critical sections), ``why`` the reason it is built in, for the
    record (module docstring). Every critical section in front of the clamp — keyseat ends, grooves,
    shoulders, and the clamp's face — is rated under ``M(x)`` and the torque of the loads beyond it."""
    by = {p.name: p for p in placed}
    if shaft not in by or plate not in by:
        raise SpecError(f"built in: {shaft!r} or {plate!r} is not a placed body of the machine")
    forces = shafts._joint_forces(m, loads, "fixed", set(joints))
    if not forces:
        raise SpecError(f"built in: none of {sorted(joints)} acts on the fixed link")
    clamp = z_span(placed, plate)
    zs = np.array([z for z, _, _ in forces])
    front = clamp[1] if zs.mean() > clamp[1] else clamp[0]  # the face the loads stand off
    sign = 1.0 if front == clamp[1] else -1.0
    arm = sign * (zs - front)  # mm from the clamp's face
    if arm.min() < 0:
        raise SpecError(f"built in: a load on {shaft} stands inside {plate}'s clamp ({zs.min():g} mm)")
    fs = np.stack([np.asarray(f, dtype=float) for _, f, _ in forces], axis=1)  # (n, k, 2)
    twist = np.stack([shafts._cross(np.asarray(p, dtype=float), np.asarray(f, dtype=float)) for _, f, p in forces], 1)
    body = by[shaft]
    radii = shafts._radii(body)
    mid = (clamp[0] + clamp[1]) / 2
    d = 2 * next(r[2] for r in radii if r[0] <= mid <= r[1])  # the seat's diameter
    ahead = [r for r in radii if (r[1] > front if sign > 0 else r[0] < front)]
    d_min = 2 * min(r[2] for r in ahead)
    mat, hub = shafts._material(by, bom, shaft), shafts._material(by, bom, plate)
    st, hub_st = shafts.strength(mat, d), shafts.strength(hub, clamp[1] - clamp[0])
    sections = [(front, "keyseat" if keys else "shoulder", d / 2, 0.0)]
    sections += [c for c in shafts._sections(body, [z_span(placed, k) for k in keys]) if sign * (c[0] - front) > 0]
    zero = np.zeros(loads.theta.size)
    rated = []
    for z, kind, ro, ri in sections:
        x = sign * (z - front)
        beyond = np.clip(arm - x, 0.0, None)  # each load's lever about the section (0: behind it)
        moment = np.einsum("k,nkd->nd", beyond, fs) * 1e-3  # N·m
        torque = (twist * (beyond > 0)).sum(1) * 1e-3
        n_f, n_y, sa, _, se = shafts._safety(moment, zero, torque, kind, ro, ri, st["rm_mpa"], st["re_mpa"])
        rated.append((min(n_f, n_y), z, kind, n_f, n_y, sa, se, moment))
    n, z_worst, kind, n_f, n_y, sa, se, _ = min(rated, key=lambda r: r[0])
    moment = rated[0][7]  # at the clamp's face
    mnorm = np.linalg.norm(moment, axis=1)
    length = clamp[1] - clamp[0]
    pressure = np.linalg.norm(fs.sum(1), axis=1) / (d * length) + 6 * mnorm * 1e3 / (d * length**2)
    allow = min(st["re_mpa"], hub_st["re_mpa"]) / shafts.KEY_SAFETY
    mesh_z = next(c.z for c in m.meshes if c.name == mesh[0])
    x_mesh = sign * (mesh_z - front)
    dev, tilt = deflection_and_slope(fs, arm, np.array([x_mesh]), d_min)
    dev_all, _ = deflection_and_slope(fs, arm, arm, d_min)
    limit = gear_deflection_limit_mm(mesh[1])
    k = int(np.argmax(mnorm))
    checks = {
        "bending": n >= shafts.SHAFT_SAFETY,
        "seat pressure": float(pressure.max()) <= allow,
        "deflection at the gear": dev <= limit,
        "slope at the gear": tilt <= SLOPE_LIMIT_RAD,
    }
    return {
        "shaft": shaft,
        "built_into": plate,
        "clamp_z_mm": [rounded(clamp[0], 4), rounded(clamp[1], 4)],
        "why": why,
        "loads_from": sorted(set(joints)),
        "peak_moment_at_clamp_nm": rounded(float(mnorm[k]), 4),
        "at_driver_deg": round(float(np.degrees(loads.theta[k])), 4),
        "sections_rated": len(rated),
        "least_safe_section": {"z_mm": rounded(z_worst, 4), "kind": kind, "kt_kts": list(shafts._KT[kind])},
        "fatigue_safety": rounded(n_f, 4) if math.isfinite(n_f) else "inf",
        "yield_safety": rounded(n_y, 4) if math.isfinite(n_y) else "inf",
        "required_safety": shafts.SHAFT_SAFETY,
        "von_mises_amplitude_mpa": rounded(sa, 4),
        "endurance_limit_mpa": rounded(se, 4),
        "seat_pressure_mpa": rounded(float(pressure.max()), 4),
        "seat_pressure_allowable_mpa": rounded(allow, 4),
        "seat": f"Ø{d:g} over {length:g} mm in {hub} (Re {hub_st['re_mpa']:g} MPa), the shaft {mat}",
        "deflection_at_gear_mm": rounded(dev, 6),
        "deflection_limit_mm": limit,
        "slope_at_gear_rad": rounded(tilt, 8),
        "slope_limit_rad": SLOPE_LIMIT_RAD,
        "largest_deflection_at_a_load_mm": rounded(dev_all, 6),
        "stiffness_section_mm": d_min,
        "gear": f"{mesh[0]}, module {mesh[1]:g} mm",
        "gear_from_clamp_mm": rounded(x_mesh, 4),
        "method": (
            "cantilever from the clamp's face; Shigley 9th ed. DE-Goodman at every critical section in front of it "
            "(Table 7-1 K_t, K_ts), the loads beyond it; seat pressure "
            "F/(dL) + 6M/(dL^2) against Re/1.5 of the weaker member; deflection and slope of superposed point loads, "
            "E 210000 N/mm^2 (EN 1993-1-1 3.2.6), limits Shigley 9th ed. Table 7-2"
        ),
        "pass": all(checks.values()),
        **({"short": [k for k, ok in checks.items() if not ok]} if not all(checks.values()) else {}),
    }
