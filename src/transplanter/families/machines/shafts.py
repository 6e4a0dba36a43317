"""Keys and turned shafts checked under a machine's computed loads (issue 44).

* **Keys** (:func:`key_rows`): each DIN 6885 key's torque over the cycle (:func:`key_torque`) — a
  drive's for a drive hub's key, otherwise what the hub's bodies need (inertia and weight) less the
  torque of the joints and loads on them (:func:`hub_torque`: a planet's mesh, the needle's work, the
  planet pins on a carrier plate) — and its flank pressure at the peak by DIN 6892:2012 method C,
  ``p = 2 T / (d (h - t1) l_tr)`` (one key; ``l_tr = l - b``, form A), against the weaker of shaft and
  hub's minimum yield ``Re`` (the catalogue's :data:`STRENGTHS` table) over :data:`KEY_SAFETY`
  (bearing against yield as in Shigley, 9th ed., §7-7); one that falls short names a shaft and key
  that pass (``resize``) and the hub length it would need.
* **Shafts** (:func:`shaft_rows`): a beam on its link's two supports; every force on the link at its
  z — the supports' (``Loads.support``), meshes', contacts', point loads', each lump's ``m (g - a)``
  — gives ``M(z) = Σ_{z_i < z} F_i (z - z_i)`` (:func:`bending_moment`); the keys the torque between
  them. At keyseat ends, shoulders and retaining-ring grooves, **Shigley's DE-Goodman** (Budynas &
  Nisbett, *Shigley's Mechanical Engineering Design*, 9th ed., 2011, eq. 7-7, von Mises amplitudes
  eq. 7-5/7-6) on every fibre followed in the shaft's own turning frame: ``1/n = σ'_a/S_e +
  σ'_m/S_ut``, ``S_e = k_a k_b k_e 0.5 S_ut`` (eq. 6-8, 6-18; machined ``k_a = 4.51 S_ut^-0.265``
  Table 6-2; ``k_b`` eq. 6-20; ``k_c = k_d = 1``; ``k_e = 0.814``, 99 %, Table 6-5); Table 7-1's
  first-iteration ``K_t, K_ts`` (end-milled keyseat 2.14, 3.0; sharp shoulder fillet r/d = 0.02
  2.7, 2.2; retaining-ring groove 5.0, 3.0) with ``K_f = K_t`` (notch sensitivity 1, conservative);
  yield ``n_y = S_y / max σ'``. A section short of :data:`SHAFT_SAFETY` names the diameter that
  would pass (``resize_to_mm``, stresses scaling as 1/d³, 5 % over).

Units: mm, N, N·m, MPa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import GeometryError, SpecError
from transplanter.core.precision import rounded
from transplanter.families.machines.loads import link_lumps, link_of, z_span
from transplanter.machine.dynamics import Loads, Machine, Motion, link_motion
from transplanter.shop.catalogue import key_for, table

__all__ = [
    "KEY_SAFETY",
    "SHAFT_SAFETY",
    "STRENGTHS",
    "KeyJoint",
    "strength",
    "key_pressure",
    "bending_moment",
    "hub_torque",
    "key_torque",
    "key_rows",
    "shaft_rows",
    "shafts_record",
    "finding",
]

#: required safety of a key's flank pressure against the weaker member's Re (a stated choice)
KEY_SAFETY = 1.5
#: required fatigue (DE-Goodman) and yield safety of a shaft section (a stated choice: Shigley's usual design factor)
SHAFT_SAFETY = 1.5
#: the catalogue table of minimum strengths by ruling section
STRENGTHS = "material_strengths"
#: Shigley 9th ed. Table 7-1 (K_t bending, K_ts torsion), first-iteration estimates
_KT = {"keyseat": (2.14, 3.0), "shoulder": (2.7, 2.2), "groove": (5.0, 3.0)}
_KEY_METHOD = "DIN 6892:2012 method C, p = 2T/(d (h - t1) l_tr), l_tr = l - b; allowable Re/1.5 of the weaker member"
_SHAFT_METHOD = "Shigley 9th ed. DE-Goodman (eq. 7-7), Marin eq. 6-18..6-20, Tables 6-2, 6-5, 7-1; K_f = K_t"
_RELIABILITY_99 = 0.814  # k_e, Shigley 9th ed. Table 6-5
_GROOVE_MM = 2.0  # a slab this narrow, smaller than both neighbours, is a retaining ring's groove
_FIBRES = 72


@dataclass(frozen=True)
class KeyJoint:
    """A key ``key`` (placed body name, its catalogue part among the bought ones) between ``shaft``
    and ``hub`` (placed body names; ``hub`` None: a buyer's coupling on a drive). Its torque: the
    ``drive``'s (a :class:`~transplanter.machine.dynamics.Drive` name) or what the ``hub_bodies``
    need less the torque of the ``joints`` (pin, mesh, contact or point-load names) acting on them."""

    key: str
    shaft: str
    hub: str | None
    hub_bodies: tuple[str, ...] = ()
    joints: tuple[str, ...] = ()
    drive: str | None = None


def strength(name: str, section_mm: float) -> dict:
    """Minimum ``re_mpa``, ``rm_mpa`` and ``source`` of catalogue material ``name`` at the ruling section (mm)."""
    for r in table(STRENGTHS):
        if r["name"] == name and float(r["over_mm"]) < section_mm <= float(r["to_mm"]):
            return {"re_mpa": float(r["re_mpa"]), "rm_mpa": float(r["rm_mpa"]), "source": r["source"]}
    raise SpecError(f"material = {name!r}: no strength at a ruling section of {section_mm:g} mm in {STRENGTHS}.csv")


def key_pressure(torque_nm: float, d_mm: float, h_mm: float, t1_mm: float, bearing_mm: float) -> float:
    """DIN 6892 method C's mean flank pressure ``2 T / (d (h - t1) l_tr)`` (MPa) of one key.

    Examples
    --------
    >>> round(key_pressure(10.0, 20.0, 6.0, 3.5, 12.0 - 6.0), 3)  # 10 N·m, Ø20, key 6x6x12 form A
    66.667
    """
    for label, v in (("d", d_mm), ("h - t1", h_mm - t1_mm), ("bearing length l_tr", bearing_mm)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise SpecError(f"key {label} = {v!r} mm: must be a positive number")
    return 2e3 * abs(torque_nm) / (d_mm * (h_mm - t1_mm) * bearing_mm)


def bending_moment(z: np.ndarray, forces: list[tuple[float, np.ndarray]]) -> np.ndarray:
    """The bending moment (n, len(z), 2) N·m at sections ``z`` (mm) of a beam loaded by ``forces``:
    ``(z_i mm, F_i (n, 2) N)``, each section summing the forces before it; the forces must balance."""
    zs = np.array([f[0] for f in forces])
    fs = np.stack([np.asarray(f[1], dtype=float) for f in forces], axis=1)  # (n, k, 2)
    tol = 1e-6 * len(zs) * (float(np.max(np.abs(fs))) or 1.0)
    if np.max(np.abs(fs.sum(1))) > tol or np.max(np.abs((fs * zs[:, None]).sum(1))) > tol * (float(np.ptp(zs)) or 1):
        raise GeometryError("the forces on a shaft do not balance: its supports do not hold it")
    arm = np.clip(np.asarray(z, dtype=float)[:, None] - zs[None, :], 0.0, None)  # (s, k)
    return np.einsum("sk,nkd->nsd", arm, fs) * 1e-3


def _lump_forces(lumps, kin: Motion, gravity: float) -> list[tuple[float, np.ndarray, np.ndarray, float]]:
    """Each lump's d'Alembert force ``m (g - a)`` N with its position (mm), z (mm) and ``-I α`` (N·m)."""
    out = []
    for lump in lumps:
        pos, _, acc = kin.point(lump.com[:2])
        f = lump.mass * (np.array([0.0, -gravity * 1e3]) - acc) * 1e-3
        out.append((float(lump.com[2]), f, pos, -lump.izz * kin.alpha * 1e-6))
    return out


def _joint_forces(m: Machine, loads: Loads, link: str, names=None) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """The forces ``(z mm, F (n, 2) N, point (n, 2) mm)`` that the machine's joints and loads put on
    ``link`` (only those named ``names``, if given): pins' supports, meshes, contacts, point loads."""
    kins, out = {k: link_motion(m.links[k], loads.theta, loads.speed) for k in m.moving}, []
    for j, p in enumerate(m.pins):
        if link in (p.a, p.b) and (names is None or p.name in names):
            sign = 1.0 if p.b == link else -1.0
            at = kins[p.b].point(p.point)[0] if p.b != "fixed" else np.broadcast_to(p.point, loads.pin[:, j].shape)
            for side in (0, 1):
                out.append((p.z[side], sign * loads.support[:, j, side], at))
    lined = [
        (c, loads.mesh[:, j, None] * loads.mesh_line[:, j], loads.pitch_point[:, j]) for j, c in enumerate(m.meshes)
    ]
    for j, c in enumerate(m.contacts):
        at = kins[c.b].point(c.point)[0]
        lined.append((c, loads.contact[:, j, None] * loads.contact_line[:, j], at))
    for c, f, at in lined:
        if link in (c.a, c.b) and (names is None or c.name in names):
            out.append((c.z, (1.0 if c.b == link else -1.0) * f, at))
    for ld in m.loads:
        if ld.link == link and (names is None or ld.name in names):
            pos, vel, _ = kins[link].point(ld.point)
            out.append((ld.z, np.asarray(ld.force(loads.theta, pos, vel), dtype=float), pos))
    return out


def _cross(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def hub_torque(m: Machine, loads: Loads, link: str, lumps, joints: tuple[str, ...]) -> np.ndarray:
    """The torque (n,) N·m about ``link``'s origin the shaft must put on a hub whose bodies are
    ``lumps`` on ``link``, with the ``joints`` (names) acting on it: inertia and weight less the joints'."""
    kin = link_motion(m.links[link], loads.theta, loads.speed)
    o = kin.o
    t = np.zeros(loads.theta.size)
    for _, f, pos, spin in _lump_forces(lumps, kin, m.gravity):
        t -= _cross(pos - o, f) * 1e-3 + spin
    named = _joint_forces(m, loads, link, set(joints))
    found = {n for n in joints if any(n == j.name for j in (*m.pins, *m.meshes, *m.contacts, *m.loads))}
    if found != set(joints):
        raise SpecError(f"joints = {sorted(set(joints) - found)!r}: not joints or loads of the machine")
    for _, f, at in named:
        t -= _cross(at - o, f) * 1e-3
    return t


def _radii(body) -> list[tuple[float, float, float, float]]:
    """A turned body's slabs as ``(z0, z1, outer, inner)`` radii, mm, across the machine."""
    out = []
    for s in body.solid.slabs:
        rs = [(float(np.max(np.hypot(*np.asarray(v, dtype=float)[:, :2].T))), bool(hole)) for v, hole in s.contours]
        outer = max((r for r, hole in rs if not hole), default=0.0)
        inner = max((r for r, hole in rs if hole), default=0.0)
        z = sorted(float(body.at[2, 2] * v + body.at[2, 3]) for v in (s.z0, s.z0 + s.width))
        out.append((z[0], z[1], outer, inner))
    return sorted(out)


def _material(placed_by: dict, bom, name: str) -> str:
    items = {i.item: i for i in bom.items}
    return items[placed_by[name].item].material


def key_torque(m: Machine, loads: Loads, placed, bom, links_of, pose_of, kj: KeyJoint) -> np.ndarray:
    """The torque (n,) N·m key ``kj`` carries over the cycle (:class:`KeyJoint`)."""
    if kj.drive is not None:
        names = [d.name for d in m.drives]
        if kj.drive not in names:
            raise SpecError(f"key {kj.key}: drive = {kj.drive!r} is not one of the machine's drives {names}")
        return loads.torque[:, names.index(kj.drive)]
    by = {p.name: p for p in placed}
    missing = [n for n in (kj.hub, *kj.hub_bodies) if n not in by]
    if missing:
        raise SpecError(f"key {kj.key}: hub bodies {missing!r} are not placed bodies of the machine")
    link = link_of(links_of[kj.hub])
    lumps = link_lumps([by[n] for n in (kj.hub_bodies or (kj.hub,))], bom, links_of, pose_of).get(link, ())
    return hub_torque(m, loads, link, lumps, kj.joints)


def key_rows(loads: Loads, placed, bom, bought: dict, keys, torques: dict) -> list[dict]:
    """Each key's record (module docstring) from its torque series ``torques[key]``: peak torque and
    where, flank pressure, allowable, safety, ``pass``; when it falls short, what would pass."""
    by = {p.name: p for p in placed}
    rows = []
    for kj in keys:
        key = bought.get(kj.key)
        if key is None or not all(hasattr(key, a) for a in ("b", "h", "t1", "length")):
            raise SpecError(f"key = {kj.key!r}: not a bought DIN 6885 key of the machine")
        t = torques[kj.key]
        k = int(np.argmax(np.abs(t)))
        d = 2 * max(r[2] for r in _radii(by[kj.shaft]) if r[0] <= sum(z_span(placed, kj.key)) / 2 <= r[1])
        members = [(kj.shaft, d)] + ([(kj.hub, float(np.ptp(z_span(placed, kj.hub))))] if kj.hub else [])
        weak = min((strength(_material(by, bom, n), size)["re_mpa"], n) for n, size in members)
        p = key_pressure(float(t[k]), d, key.h, key.t1, key.length - key.b)
        allow = weak[0] / KEY_SAFETY
        row = {
            "key": kj.key,
            "shaft": kj.shaft,
            "hub": kj.hub or "the drive's coupling (not modelled: the shaft's material)",
            "shaft_d_mm": rounded(d, 4),
            "bxhxl_mm": [key.b, key.h, key.length],
            "peak_torque_nm": rounded(float(t[k]), 4),
            "at_driver_deg": round(float(np.degrees(loads.theta[k])), 4),
            "torque_from": f"drive {kj.drive}" if kj.drive else ", ".join(("the hub's bodies", *kj.joints)),
            "pressure_mpa": rounded(p, 4),
            "weaker_member": weak[1],
            "re_mpa": weak[0],
            "allowable_mpa": rounded(allow, 4),
            "safety": rounded(weak[0] / p, 4) if p > 0 else "inf",
            "required_safety": KEY_SAFETY,
            "pass": bool(p <= allow),
            "method": _KEY_METHOD,
        }
        if p > allow:
            hub_len = float(np.ptp(z_span(placed, kj.hub))) if kj.hub else key.length
            row["length_needed_mm"] = rounded(2e3 * abs(float(t[k])) / (d * (key.h - key.t1) * allow) + key.b, 2)
            row["resize"] = _key_resize(abs(float(t[k])), d, hub_len, allow)
        rows.append(row)
    return rows


def _key_resize(torque_nm: float, d: float, hub_len: float, allow: float) -> str:
    """The smallest shaft (whole mm, up to twice ``d``) whose DIN 6885 key in the same hub passes."""
    for dd in range(math.ceil(d) + 1, math.ceil(2 * d) + 1):
        try:
            k = key_for(dd, hub_len)
        except SpecError:
            continue
        if key_pressure(torque_nm, dd, k.h, k.t1, k.length - k.b) <= allow:
            return f"shaft Ø{dd} mm with key {k.b:g}x{k.h:g}x{k.length:g} in the {hub_len:g} mm hub"
    return f"no shaft up to Ø{2 * d:g} mm: a longer hub ({hub_len:g} mm now) or a second key"


def _sections(body, key_spans) -> list[tuple[float, str, float, float]]:
    """The shaft's critical sections ``(z, kind, outer, inner radius)``: keyseat ends, shoulders, grooves."""
    sl = _radii(body)
    out = []
    for z0, z1 in key_spans:
        for z, inside in ((z0, z0 + 1e-6), (z1, z1 - 1e-6)):
            out += [(z, "keyseat", s[2], s[3]) for s in sl if s[0] <= inside <= s[1]][:1]
    grooves = set()
    for i in range(1, len(sl) - 1):
        a, s, b = sl[i - 1], sl[i], sl[i + 1]
        if s[1] - s[0] <= _GROOVE_MM and s[2] < min(a[2], b[2]):
            grooves |= {i}
            out.append(((s[0] + s[1]) / 2, "groove", s[2], s[3]))
    for i in range(len(sl) - 1):
        a, b = sl[i], sl[i + 1]
        if abs(a[2] - b[2]) > 1e-6 and i not in grooves and i + 1 not in grooves:
            small = a if a[2] < b[2] else b
            out.append((a[1], "shoulder", small[2], max(a[3], b[3])))
    return sorted(out)


def _marin_se(sut: float, d: float) -> float:
    """Shigley 9th ed.: S_e = k_a k_b k_c k_d k_e S_e' (eq. 6-18), machined surface, 99 % reliability."""
    kb = 1.24 * d**-0.107 if d <= 51.0 else 1.51 * d**-0.157
    return 4.51 * sut**-0.265 * kb * _RELIABILITY_99 * 0.5 * sut


def _safety(mvec, angle, torque, kind, ro, ri, sut, sy):
    """DE-Goodman and yield safety (min over the fibres) of a section: moment (n, 2) N·m, the shaft's
    angle (n,), torque (n,) N·m."""
    kt, kts = _KT[kind]
    zb = math.pi * ((2 * ro) ** 4 - (2 * ri) ** 4) / (32 * 2 * ro)  # mm³
    phi = np.linspace(0.0, 2 * math.pi, _FIBRES, endpoint=False)
    u = np.stack([np.cos(angle[:, None] + phi), np.sin(angle[:, None] + phi)], axis=-1)  # (n, f, 2)
    sigma = kt * np.einsum("nd,nfd->nf", mvec, u) * 1e3 / zb
    tau = kts * torque * 1e3 / (2 * zb)
    sa, sm = np.ptp(sigma, axis=0) / 2, (sigma.max(0) + sigma.min(0)) / 2
    ta, tm = np.ptp(tau) / 2, (tau.max() + tau.min()) / 2
    se = _marin_se(sut, 2 * ro)
    inv = np.sqrt(sa**2 + 3 * ta**2) / se + np.sqrt(sm**2 + 3 * tm**2) / sut
    vm = np.sqrt(sigma**2 + 3 * tau[:, None] ** 2).max()
    n_f = float(1.0 / inv.max()) if inv.max() > 0 else math.inf
    n_y = float(sy / vm) if vm > 0 else math.inf
    return n_f, n_y, float(np.sqrt(sa**2 + 3 * ta**2).max()), float(np.sqrt(sm**2 + 3 * tm**2).max()), se


def shaft_rows(m: Machine, loads: Loads, placed, bom, links_of, shafts, keys, key_torques: dict) -> list[dict]:
    """Every critical section of each turned shaft in ``shafts`` (placed body names): its peak
    bending moment and torque over the cycle, the DE-Goodman and yield safeties (module docstring)."""
    by = {p.name: p for p in placed}
    rows = []
    for name in shafts:
        body = by.get(name)
        if body is None:
            raise SpecError(f"shaft = {name!r}: not a placed body of the machine")
        link = link_of(links_of[name])
        kin = link_motion(m.links[link], loads.theta, loads.speed)
        forces = [(z, f) for z, f, _ in _joint_forces(m, loads, link)]
        forces += [(z, f) for z, f, _, _ in _lump_forces(m.lumps.get(link, ()), kin, m.gravity)]
        mine = [kj for kj in keys if kj.shaft == name]
        spans = [z_span(placed, kj.key) for kj in mine]
        mids = [sum(s) / 2 for s in spans]
        big_t = [key_torques[kj.key] for kj in mine] or [np.zeros(loads.theta.size)]
        torque = max(big_t, key=lambda t: float(np.max(np.abs(t))))  # the largest, all along between the keys
        big = 2 * max(s[2] for s in _radii(body))
        mat = _material(by, bom, name)
        st = strength(mat, big)
        for z, kind, ro, ri in _sections(body, spans):
            mvec = bending_moment(np.array([z]), forces)[:, 0]
            t = torque if mids and min(mids) <= z <= max(mids) else np.zeros_like(torque)
            n_f, n_y, sa, sm, se = _safety(mvec, kin.a, t, kind, ro, ri, st["rm_mpa"], st["re_mpa"])
            k = int(np.argmax(np.linalg.norm(mvec, axis=1)))
            n = min(n_f, n_y)
            row = {
                "shaft": name,
                "section": kind,
                "z_mm": rounded(z, 4),
                "d_mm": rounded(2 * ro, 4),
                "bore_mm": rounded(2 * ri, 4),
                "peak_moment_nm": rounded(float(np.linalg.norm(mvec, axis=1)[k]), 4),
                "at_driver_deg": round(float(np.degrees(loads.theta[k])), 4),
                "peak_torque_nm": rounded(float(np.max(np.abs(t))), 4),
                "kt_kts": list(_KT[kind]),
                "von_mises_amplitude_mpa": rounded(sa, 4),
                "von_mises_mean_mpa": rounded(sm, 4),
                "endurance_limit_mpa": rounded(se, 4),
                "material": f"{mat}: Rm {st['rm_mpa']:g}, Re {st['re_mpa']:g} MPa at Ø{big:g} (catalogue {STRENGTHS})",
                "fatigue_safety": rounded(n_f, 4) if math.isfinite(n_f) else "inf",
                "yield_safety": rounded(n_y, 4) if math.isfinite(n_y) else "inf",
                "required_safety": SHAFT_SAFETY,
                "pass": bool(n >= SHAFT_SAFETY),
            }
            if n < SHAFT_SAFETY:
                row["resize_to_mm"] = math.ceil(2 * ro * (SHAFT_SAFETY / n) ** (1 / 3) * 1.05)
            rows.append(row)
    return rows


def shafts_record(m: Machine, loads: Loads, placed, bom, bought: dict, links_of, pose_of, keys, shafts) -> dict:
    """The keys' and shafts' rows and their verdicts (module docstring), JSON-able."""
    if not all(isinstance(kj, KeyJoint) for kj in keys):
        raise SpecError(f"keys = {keys!r}: each must be a KeyJoint")
    torques = {kj.key: key_torque(m, loads, placed, bom, links_of, pose_of, kj) for kj in keys}
    krows = key_rows(loads, placed, bom, bought, keys, torques)
    srows = shaft_rows(m, loads, placed, bom, links_of, shafts, keys, torques)
    worst_key = min(krows, key=lambda r: float(r["safety"])) if krows else None
    worst = min(srows, key=lambda r: min(float(r["fatigue_safety"]), float(r["yield_safety"]))) if srows else None
    return {
        "keys": krows,
        "shafts": srows,
        "smallest_key_safety": worst_key and {"key": worst_key["key"], "safety": worst_key["safety"]},
        "smallest_shaft_safety": worst
        and {k: worst[k] for k in ("shaft", "section", "z_mm", "fatigue_safety", "yield_safety")},
        "pass": all(r["pass"] for r in krows + srows),
        "method": f"keys: {_KEY_METHOD}; shafts: {_SHAFT_METHOD}",
    }


def finding(rec: dict, under: str) -> str | None:
    """The finding a machine record states when a key or shaft section of ``rec`` (a
    :func:`shafts_record`, with its ``needle_force_capacity`` if it has one) falls short ``under``
    the loads named; None when every one passes."""
    if rec["pass"]:
        return None
    keys = [r for r in rec["keys"] if not r["pass"]]
    sections = [r for r in rec["shafts"] if not r["pass"]]
    key, shaft = rec["smallest_key_safety"], rec["smallest_shaft_safety"]
    text = (
        f"under {under} {len(keys)} keys and {len(sections)} shaft sections fall short of their safety "
        f"({KEY_SAFETY:g}): smallest {key['key']} {key['safety']:g}, {shaft['shaft']} {shaft['section']} fatigue "
        f"{shaft['fatigue_safety']:g}"
    )
    cap = rec.get("needle_force_capacity")
    if cap:
        text += f"; the machine as drawn carries {cap['n']:g} N at each needle (limited by {cap['limited_by']})"
    remedies: dict[str, list[str]] = {}  # one remedy, the elements it is for (three arms' keys: one line)
    for r in keys:
        if r.get("resize"):
            remedies.setdefault(str(r["resize"]), []).append(r["key"])
    to: dict[str, float] = {}
    for r in sections:
        if r.get("resize_to_mm"):
            to[r["shaft"]] = max(to.get(r["shaft"], 0.0), float(r["resize_to_mm"]))
    for name, d in to.items():
        remedies.setdefault(f"Ø{d:g}", []).append(name)
    resize = sorted(f"{', '.join(sorted(names))}: {what}" for what, names in remedies.items())
    return text + ("; to carry it: " + "; ".join(resize) if resize else "")
