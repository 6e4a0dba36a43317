"""Seed 002's made teeth under the machine's load over the cycle (issue 44): the non-circular
stages 2-3 (sun 2 and gear 3) and 4-5 (gears 4 and 5), and the sectors 7-8.

Each mesh of :func:`~transplanter.families.machines.carrier_loads.model` is rated on its **made**
gears by :func:`transplanter.proof.mesh_cycle.mesh_cycle_load`, as seed 004's ring and planet are
(:func:`~transplanter.families.machines.planetary_loads.teeth_record`):

* **the outlines** re-read from the DXFs the machine is judged on
  (:func:`~transplanter.families.machines.carrier_posing.body_specs`: the pairs' driver and driven
  files, the parts study's sectors), from the cut layer, **mirrored** about their x-axes where the
  gear is mounted face down (stage 2-3's sun and gear 3: :mod:`transplanter.machine.carriers`);
* **the poses** the loads' model's links (the designed motion:
  :func:`~transplanter.families.machines.carrier_loads.loads_machine`), each gear on its own link
  (gear 4 on ``shaft3b``, its key, sector 8 on ``sector8``);
* **the torque** on the driven gear (gear 1 of the rating: gear 3, gear 5, sector 8) the mesh's
  normal force (:attr:`~transplanter.machine.dynamics.Loads.mesh`, along ``mesh_line`` through the
  ``pitch_point``) times its lever about that gear's centre; the driven gear is turned from its
  designed angle until its flank closes on the driver's against it, every contact rated there (the
  force, Hertz with both flanks' radii, ISO 6336-3's 30° root stress of both loaded teeth).

Nominal stresses (every ISO factor 1; two pairs in contact each carry the whole load). The gears
are C45 (the bill of materials): no ISO 6336-5 allowable for it can be cited
(:mod:`transplanter.shop.catalogue.gear_materials`), so no safety factor is stated — each record
says what the material must allow.

**Positions rated** (the cost: ~15 ms a position and mesh): every position where the driven
gear's torque is within ``1 - FULL_ABOVE`` of its largest, and every :data:`STRIDE`-th elsewhere
(on seed 002, ~56 % of the 360: ~9 s for the three meshes on one core; rating all 360 found the same
peaks). The spurs 9-10 and 10-11 (circular, ratio 1) are not rated here.

Teeth and flanks are named in each gear's own **DXF** frame (a mirrored gear's tooth angle and
flank turned back from the mirrored frame the rating works in).
"""

from __future__ import annotations

import math

import numpy as np

from transplanter.core.errors import GeometryError
from transplanter.core.precision import rounded
from transplanter.proof.mesh_cycle import Peak, mesh_cycle_load
from transplanter.shop import formats

__all__ = ["FULL_ABOVE", "MESHES", "STRIDE", "rated_positions", "teeth_records"]

#: the meshes rated: the loads model's mesh name, the pair study (``study.<pair>``), the bodies of
#: the driver (gear 0) and the driven gear (gear 1) as :func:`carrier_posing.body_specs` names them
MESHES = (
    ("sun 2 and gear 3", "stage23", "sun", "gear_3"),
    ("gears 4 and 5", "stage35", "gear_4", "gear_5"),
    ("sectors 7 and 8", "sectors", "sector_7", "sector_8"),
)
#: every position whose driven-gear torque is at least this share of its largest is rated ...
FULL_ABOVE = 0.8
#: ... and every STRIDE-th position elsewhere
STRIDE = 2


def rated_positions(torque: np.ndarray) -> np.ndarray:
    """The positions rated (module docstring): where ``|torque|`` is at least :data:`FULL_ABOVE` of
    its largest, and every :data:`STRIDE`-th one."""
    t = np.abs(np.asarray(torque, dtype=float))
    keep = t >= FULL_ABOVE * float(t.max())
    keep[::STRIDE] = True
    return np.nonzero(keep)[0]


def _outline(files: dict[str, bytes], fname: str, mirrored: bool) -> np.ndarray:
    if fname not in files:
        raise GeometryError(f"the teeth under load are rated on {fname}, which is not there")
    xy = np.asarray(formats.section_of(fname, files[fname], layer=formats.CUT).exterior.coords, dtype=float)
    return xy * [1.0, -1.0] if mirrored else xy


def _pose(link, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    x, y, a = (np.broadcast_to(np.asarray(v, dtype=float), theta.shape) for v in link.pose(theta))
    return np.stack([x, y], axis=1), np.array(a)


def _named(tooth: float, flank: str, mirrored: bool) -> tuple[float, str]:
    """A tooth (deg) and flank named in the rating's frame, in the gear's DXF frame."""
    if not mirrored:
        return tooth, flank
    return (-tooth) % 360.0, {"ccw": "cw", "cw": "ccw"}[flank]


def _peak(p: Peak, gears: tuple[tuple[str, bool], tuple[str, bool]]) -> dict:
    pl = p.place
    out = {
        "value": rounded(float(p.value), 4),
        "at_driver_deg": round(float(p.theta), 4),
        "force_n": rounded(float(pl.load.force), 4),
    }
    for g, (name, mirrored) in enumerate(gears):
        tooth, flank = _named(float(pl.teeth[g]), pl.flanks[g], mirrored)
        out[f"{name}_tooth_deg"] = round(tooth, 4)
        out[f"{name}_flank"] = flank
    return out


def teeth_records(study, machine, m, loads, files: dict[str, bytes], specs) -> list[dict]:
    """Each mesh of :data:`MESHES` rated on its made gears over the cycle (module docstring).

    Parameters
    ----------
    study : DoubleCarrierMachineStudy
        The machine (its pairs' modules and pressure angles).
    machine : DoubleCarrierMachine
        The loads' machine (the designed motion), whose links pose each gear.
    m, loads : Machine, Loads
        The loads' model and its loads over the cycle.
    files : dict
        The family's files: the gears' DXFs.
    specs : list
        The bodies ``(name, DXF, plane, link, mirrored)`` (:func:`carrier_posing.body_specs`).
    """
    by_name = {s[0]: s for s in specs}
    index = {mesh.name: j for j, mesh in enumerate(m.meshes)}
    out = []
    for mesh_name, what, driver, driven in MESHES:
        missing = [b for b in (driver, driven) if b not in by_name]
        if mesh_name not in index or missing:
            raise GeometryError(f"{study.name}: mesh {mesh_name!r} cannot be rated: no {missing or 'such mesh'}")
        j = index[mesh_name]
        (_, f0, plane, l0, mir0), (_, f1, _, l1, mir1) = by_name[driver], by_name[driven]
        c0, a0 = _pose(machine.links[l0], loads.theta)
        c1, a1 = _pose(machine.links[l1], loads.theta)
        line, arm = loads.mesh_line[:, j], loads.pitch_point[:, j] - c1
        torque = loads.mesh[:, j] * (arm[:, 0] * line[:, 1] - arm[:, 1] * line[:, 0])  # N mm on gear 1, ccw +
        k = rated_positions(torque)
        pair = getattr(study, what)
        res = mesh_cycle_load(
            (_outline(files, f0, mir0), _outline(files, f1, mir1)),
            ((c0[k], a0[k]), (c1[k], a1[k])),
            torque[k],
            width=plane[1] - plane[0],
            module=pair.sized.tool.module,
            ring=False,
            pressure_angle=math.degrees(pair.cutter.pressure_angle),
            theta=loads.theta[k],
        )
        material = study.sector.material if what == "sectors" else pair.making[0].material
        out.append(_record(m.meshes[j].name, (driver, mir0), (driven, mir1), res, k, torque, pair, material))
    return out


def _record(name: str, g0, g1, res, k: np.ndarray, torque: np.ndarray, pair, material: str) -> dict:
    gears = (g0, g1)
    mirrored = [n for n, mir in gears if mir]
    rec: dict = {
        "mesh": name,
        "gears": {"driver": g0[0], "driven": g1[0], "mirrored": mirrored},
        "reading": (
            f"the made teeth of {g0[0]} and {g1[0]} (re-read from their DXFs"
            + (f", {' and '.join(mirrored)} mirrored: mounted face down" if mirrored else "")
            + ") posed by the designed motion, the driven gear closed against the mesh torque (the normal force at "
            "the pitch point times its lever about the driven gear's centre), every contact rated: the force "
            "there (torque over the contact normal's lever), Hertz with both flanks' local radii, ISO 6336-3's 30° "
            "tangent root section on each loaded tooth's actual outline; nominal (every ISO factor 1), two pairs in "
            "contact each taking the whole load; teeth (polar angle of the tip's middle) and flanks in each "
            "gear's DXF frame"
        ),
        "positions_rated": int(len(k)),
        "positions_rule": (
            f"every position where the driven gear's torque is at least {FULL_ABOVE:g} of its largest "
            f"({rounded(float(np.max(np.abs(torque))) * 1e-3, 4)} N m), and one in {STRIDE} of the {len(torque)}"
        ),
        "positions_with_two_contacts": int(np.sum(res.contacts >= 2)),
        "closing_turn_deg": [round(float(np.degrees(res.turn.min())), 4), round(float(np.degrees(res.turn.max())), 4)],
        "max_force_n": rounded(float(np.nanmax(res.force)), 4),
        "module_mm": rounded(float(pair.sized.tool.module), 6),
        "note": res.note,
    }
    if res.max_sigma_h is not None:
        rec["max_contact_stress_mpa"] = _peak(res.max_sigma_h, gears)
    for (gear, _), peak in zip(gears, res.max_sigma_f, strict=True):
        if peak is not None:
            rec[f"max_root_stress_{gear}_mpa"] = _peak(peak, gears)
    need_f = [rec[f"max_root_stress_{g}_mpa"]["value"] for g, _ in gears if f"max_root_stress_{g}_mpa" in rec]
    rec["material"] = {
        "gears": f"{material} (the bill of materials)",
        "allowables": None,
        "why": f"no ISO 6336-5 allowable for {material} could be read from a source that can be cited",
        "needs_sigma_hlim_mpa_at_least": rec.get("max_contact_stress_mpa", {}).get("value"),
        "needs_sigma_fe_mpa_at_least": max(need_f, default=None),
    }
    return rec
