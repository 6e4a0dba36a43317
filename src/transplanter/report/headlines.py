"""What a designer looks for first on a part's page: the few figures the part is made to and what
its proofs found, read from what its study recorded (the manifest's ``parameters`` and
``results``), per kind of part — a pair's module, teeth, centre distance and backlash band, a
four-bar's figures in its seed table's order, a machine's clearances.

:func:`headline` gives rows of (quantity, value, unit) and sentences (the proofs); a kind it does
not know, or a record missing a figure, gives fewer rows — never an error. :data:`ORDERS` gives the
order a kind's metric records are tabulated in (its paper's table).
"""

from __future__ import annotations

import dataclasses
import importlib
import sys
from functools import cache

from transplanter.report.tables import is_metric, number, unit_text, value

__all__ = ["ORDERS", "headline", "table_order"]

Row = tuple[str, str, str]
#: the metrics a kind records, by the class whose ``table()`` gives them in its paper's order
#: (module, class: imported when a page tabulates that kind — a pair's page loads no paper's metrics)
ORDERS = {
    "arm": ("transplanter.design.linkage.planting", "PlantingMetrics"),
    "planetary": ("transplanter.design.agronomy", "TransplantingMetrics"),
}


def _blank(cls):
    """An instance of a metrics dataclass with every figure 0 (its ``table()`` names its rows)."""
    names = vars(sys.modules[cls.__module__])

    def of(kind: str):
        if kind in ("float", "int"):
            return 0
        if kind.startswith("tuple"):
            return (0.0, 0.0)
        return _blank(names[kind])

    return cls(**{f.name: of(str(f.type)) for f in dataclasses.fields(cls)})


@cache
def table_order(kind: str) -> tuple[str, ...]:
    """The quantities of a kind's metrics table in its paper's order (seed 000's Table 2 for a
    four-bar arm), () for a kind without one (or a metrics class this cannot fill with zeros)."""
    where = ORDERS.get(kind)
    cls = getattr(importlib.import_module(where[0]), where[1]) if where else None
    try:
        return tuple(row[0] for row in _blank(cls).table()) if cls else ()
    except (KeyError, TypeError, ValueError, ArithmeticError):  # a field of a type _blank does not know
        return ()


def _dict(v) -> dict:
    return v if isinstance(v, dict) else {}


def _list(v) -> list:
    return v if isinstance(v, list) else []


def _get(d, *path):
    for p in path:
        if not isinstance(d, dict):
            return None
        d = d.get(p)
    return d


def _span(pair) -> str | None:
    if isinstance(pair, list | tuple) and len(pair) == 2 and all(isinstance(x, int | float) for x in pair):
        return f"{number(pair[0])} – {number(pair[1])}"
    if isinstance(pair, dict) and {"min", "max"} <= set(pair):
        return f"{number(pair['min'])} – {number(pair['max'])}"
    return None


def _extreme(values, pick=min):
    found = [v for v in values if isinstance(v, int | float) and not isinstance(v, bool)]
    return pick(found) if found else None


def _rows(*rows) -> list[Row]:
    """(name, value, unit) rows whose value was recorded (None: left out), values as shown."""
    return [(n, v if isinstance(v, str) else value(v), u) for n, v, u in rows if v is not None and v != []]


def _sources(record) -> dict[str, dict]:
    """The proof's sources (outline, dxf, stl …) of a meshing record: those with a problems list."""
    if not isinstance(record, dict):
        return {}
    return {k: v for k, v in sorted(record.items()) if isinstance(v, dict) and isinstance(v.get("problems"), list)}


#: what a meshing proof without problems has shown, by kind of pair
_PROVED = {
    "toothed_pair": "no overlap, free play inside the band, every gap kept",
    "incomplete_pair": "no overlap, the dwells locked within their play, the motion in the band, every gap kept",
}


def _meshing_proof(meshing, shown: str, what: str = "meshing") -> list[str]:
    """What the meshing proof found, in a line (its problems are written out with its results)."""
    src = _sources(meshing)
    if not src:
        return []
    problems = sum(len(r["problems"]) for r in src.values())
    if problems:
        where = ", ".join(s for s, r in src.items() if r["problems"])
        return [f"{what} on {where}: {problems} problem{'s' * (problems != 1)} (see {what} in the results)"]
    # a source the proof was carried to (PairProof.mesh_once) is said apart: its gaps only
    carried = [s for s, r in src.items() if "carried_from" in r]
    meshed = [s for s in src if s not in carried]
    within = _extreme([w for s in carried for w in _list(src[s].get("teeth_within_mm"))], max)
    also = f"; {', '.join(carried)} within {number(within * 1e3)} µm of it, every gap kept" if within else ""
    return [f"{what} proved on {', '.join(meshed)}: {shown}{also}"]


def _arm(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    order = table_order("arm")
    rows = [
        (k, number(float(res[k]["value"])), unit_text(res[k]["unit"]))
        for k in (*order[:7], "transmission angle min", "transmission angle max")
        if is_metric(res.get(k))
    ]
    grashof = par.get("grashof_class")
    if isinstance(grashof, str):
        rows.append(("Grashof class", grashof.lower().replace("_", "-"), ""))
    return rows, []


def _plates(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    made = sorted(k for k, v in res.items() if isinstance(v, dict) and "solid_volume_mm3" in v)
    tip = _dict(res.get("tip_path"))
    rows = _rows(
        ("links between the holes", _get(tip, "links_from_holes_mm"), "mm"),
        ("plate thickness", par.get("thickness_mm"), "mm"),
        ("plates made", f"{len(made)}: {', '.join(made)}" if made else None, ""),
        ("tip path off the design", tip.get("max_deviation_mm"), "mm"),
        ("overlap in the assembly", _get(res, "assembly", "max_overlap_mm3"), "mm³"),
    )
    proofs = []
    if isinstance(tip.get("max_deviation_mm"), int | float):
        proofs.append(
            f"proved: the tip path rebuilt from the plates' holes keeps within {number(tip.get('tolerance_mm'))} mm "
            f"of the design over {number(tip.get('steps'))} positions"
        )
    return rows, proofs


def _balancing(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    cw = _dict(_get(res, "counterweight", "vertical"))
    return _rows(
        ("total moving mass", res.get("total_moving_mass_kg"), "kg"),
        ("shaking force peak", res.get("shaking_force_peak_N"), "N"),
        ("crank torque", _span(res.get("crank_torque_N_m")), "N·m"),
        ("counterweight (vertical force) mass moment", cw.get("mass_moment_kg_mm"), "kg·mm"),
        ("counterweight angle on the crank", cw.get("angle_on_crank_deg"), "deg"),
        ("sinusoidal rocker moment", res.get("sinusoidal_rocker_moment_kg_mm"), "kg·mm"),
    ), []


def _pitch_pair(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    gears = [_dict(res.get("driver")), _dict(res.get("driven"))]
    both = lambda key: [g.get(key) for g in gears] if all(key in g for g in gears) else None  # noqa: E731
    rows = _rows(
        ("module", _get(res, "driver", "module_mm"), "mm"),
        ("teeth (driver, driven)", both("teeth"), ""),
        ("lobes (driver, driven)", both("lobes"), ""),
        ("centre distance", res.get("centre_distance_mm"), "mm"),
        ("convex (driver, driven)", both("convex"), ""),
        ("max pressure deviation", _extreme(both("max_pressure_deviation_deg") or [], max), "deg"),
        ("min convex radius of curvature", _extreme(both("min_convex_radius_of_curvature_mm") or []), "mm"),
    )
    proofs = []
    if "closure_error_rad" in res:
        proofs.append(
            f"closed pitch curves: closure error {number(res.get('closure_error_rad'))} rad, ratio error "
            f"{number(res.get('ratio_error'))}, centre distance error {number(res.get('centre_distance_error_mm'))} mm"
        )
    return rows, proofs


def _pair_rows(res: dict, par: dict, teeth, middle: list[Row] = (), gaps=None) -> list[Row]:
    """Module, teeth, centre distance, mesh, ``middle``, then the backlash band and what the proof
    measured of a made pair (``gaps``: the gaps measured, default each source's smallest)."""
    assembly, meshing = _dict(res.get("assembly")), _dict(res.get("meshing"))
    src = _sources(meshing)
    made = src.get("dxf") or next(iter(src.values()), {})
    gaps = [r.get("clearance_mm") for r in src.values()] if gaps is None else gaps
    return [
        *_rows(
            ("module", par.get("module_mm"), "mm"),
            ("teeth (driver, driven)", teeth, ""),
            ("centre distance", assembly.get("centre_distance_mm") or par.get("centre_distance_mm"), "mm"),
            ("mesh", assembly.get("kind") or par.get("mesh"), ""),
        ),
        *middle,
        *_rows(
            ("backlash band", _span(meshing.get("backlash_band_mm") or par.get("backlash_band_mm")), "mm"),
            ("backlash cut for", par.get("backlash_mm"), "mm"),
            ("free play measured", _span(assembly.get("backlash_mm") or made.get("backlash_mm")), "mm"),
            ("smallest gap at mid-play", _extreme(gaps), "mm"),
            ("gap required", meshing.get("min_clearance_mm"), "mm"),
            ("largest overlap", _extreme([r.get("max_penetration_mm2") for r in src.values()], max), "mm²"),
            ("smallest contact ratio", _extreme([r.get("contact_ratio") for r in src.values()]), ""),
        ),
    ]


def _toothed_pair(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    rows = _pair_rows(res, par, par.get("teeth"))
    proofs = _meshing_proof(res.get("meshing"), _PROVED["toothed_pair"])
    trains = [r["train"] for r in _sources(res.get("meshing")).values() if isinstance(r.get("train"), dict)]
    tip = _extreme([t.get("max_tip_deviation_mm") for t in trains], max)
    if tip is not None and not any(r["problems"] for r in _sources(res.get("meshing")).values()):
        proofs.append(
            f"the train rebuilt from the made gears puts the needle tip within {number(tip)} mm of the design"
        )
    verdict = _get(res, "interference", "verdict")
    if isinstance(verdict, str):  # its first clause: "confirmed by …" or "shown harmless by …"
        proofs.append(f"interference screen: {verdict.split(':')[0]}")
    return rows, proofs


def _incomplete_pair(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    teeth = _dict(res.get("teeth"))
    src = _sources(res.get("meshing"))
    dwells = [d.get("made_driver_deg") for d in _list(res.get("dwells")) if isinstance(d, dict)]
    middle = _rows(
        ("dwells made (driver)", "; ".join(s for s in map(_span, dwells) if s) or None, "deg"),
        ("locking play allowed", par.get("locking_play_deg"), "deg"),
        ("largest play in a dwell", _extreme([_get(r, "dwell", "largest_play_deg") for r in src.values()], max), "deg"),
    )
    gaps = [p.get("clearance_mm") for r in src.values() for p in r.values() if isinstance(p, dict)]
    rows = _pair_rows(res, par, [teeth.get("driver"), teeth.get("driven")] if teeth else None, middle, gaps)
    law = par.get("law")
    proved = _meshing_proof(res.get("meshing"), _PROVED["incomplete_pair"])
    return rows, proved + ([f"law: {law}"] if isinstance(law, str) else [])


def _train(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    metrics = _dict(res.get("metrics"))
    rows = _rows(
        ("planets", par.get("planets"), ""),
        ("module", par.get("module_mm"), "mm"),
        ("lobes (ring, planet)", par.get("lobes"), ""),
        ("centre distance", par.get("centre_distance_mm"), "mm"),
    )
    rows += [
        (k, number(float(m["value"])), unit_text(m["unit"]))
        for k in table_order("planetary")
        if is_metric(m := metrics.get(k)) and m.get("published") is not None
    ]
    objectives = _dict(res.get("objectives"))
    proofs = []
    if isinstance(objectives.get("rows"), list) and "this design" in _list(objectives.get("columns")):
        at = objectives["columns"].index("this design")
        cells = [r[at] for r in objectives["rows"] if isinstance(r, list) and len(r) > at]
        met = sum(" pass" in str(c) for c in cells)
        rows.append(("seed 004 objectives met", f"{met} of {len(cells)}", ""))
        missed = [str(r[0]) for r in objectives["rows"] if " pass" not in str(r[at])]
        proofs.append("every objective met" if not missed else "objectives not met: " + "; ".join(missed))
    return rows, proofs


def _synthesis(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    rows = _rows(
        ("link lengths", res.get("link_lengths_mm"), "mm"),
        ("ratio L2/L1", res.get("ratio_L2_L1"), ""),
        ("ratio L3/L2", res.get("ratio_L3_L2"), ""),
        ("link 2 swing", res.get("link2_swing_deg"), "deg"),
        ("trajectory height", res.get("trajectory_height_mm"), "mm"),
        ("trajectory width", res.get("trajectory_width_mm"), "mm"),
    )
    proofs = []
    if "pose_error_mm" in res:
        proofs.append(
            f"through its four poses (pose error {number(res.get('pose_error_mm'))} mm); "
            f"{number(res.get('feasible_samples'))} of {number(res.get('circle_curve_samples'))} circle points feasible"
        )
    return rows, proofs


def _cam(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    check = _dict(res.get("follower_check"))
    src = {k: v for k, v in sorted(check.items()) if isinstance(v, dict)}
    stroke_unit = next((v.get("stroke_unit") for v in src.values() if v.get("stroke_unit")), "")
    worst = _extreme([v.get("max_error_mm") for v in src.values()], max)
    rows = _rows(
        ("max pressure angle", res.get("max_pressure_angle_deg"), "deg"),
        ("pressure angle allowed", par.get("max_pressure_angle_limit_deg"), "deg"),
        ("follower stroke", res.get("follower_stroke"), stroke_unit),
        ("profile radius", _span(res.get("profile_radius_range_mm")), "mm"),
        ("min convex radius of curvature", res.get("min_convex_radius_of_curvature_mm"), "mm"),
        ("follower error on the made contour", worst, "mm"),
    )
    proofs = []
    if worst is not None:
        proofs.append(
            f"proved: the follower run on the made contour ({', '.join(src)}) keeps within "
            f"{number(check.get('tolerance_mm'))} mm of the law"
        )
    return rows, proofs


def _carrier_parts(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    made = sorted(k for k, v in res.items() if isinstance(v, dict) and "solid_volume_mm3" in v)
    read = _extreme([_get(res, k, "dxf_R2000", "readback_deviation_mm") for k in made], max)
    return _rows(
        ("plates made", f"{len(made)}: {', '.join(made)}" if made else None, ""),
        ("largest DXF read-back deviation", read, "mm"),
    ), []


def _machine(res: dict, par: dict) -> tuple[list[Row], list[str]]:
    m = _dict(res.get("machine"))
    found = [c for c in _list(m.get("clearances")) if isinstance(c, dict) and isinstance(c.get("min_mm"), int | float)]
    gaps = [c for c in found if "working" not in c]  # a working contact (the claw in the soil) is meant
    low = min(gaps, key=lambda c: c["min_mm"]) if gaps else {}
    poses = [p for p in _list(m.get("poses")) if isinstance(p, dict)]
    soil = _dict(m.get("gearbox_above_soil"))
    req2 = _get(m, "tray", "requirements", "2")
    rows = _rows(
        ("bodies", _get(res, "assembly", "bodies"), ""),
        ("overlap in the assembly", _get(res, "assembly", "max_overlap_mm3"), "mm³"),
        ("smallest clearance", low.get("min_mm"), "mm"),
        ("between", " and ".join(map(str, low.get("bodies", []))) or None, ""),
        # the pair's own minimum (``minimum_mm``, what its verdict was judged by), not the machine's
        ("its clearance required", low.get("minimum_mm", m.get("clearance_required_mm")) if low else None, "mm"),
        ("poses passed", f"{sum(bool(p.get('pass')) for p in poses)} of {len(poses)}" if poses else None, ""),
        ("tip off under the gears' play", _get(m, "tip_under_play", "max_mm"), "mm"),
        ("smallest gap under the gears' play", _get(m, "under_play", "smallest_mm"), "mm"),
        ("gearbox above the soil", soil.get("min_mm"), "mm"),
        ("gearbox above the soil required", soil.get("required_mm"), "mm"),
        ("claw into the picked pot", _get(m, "tray", "requirements", "3", "depth_mm"), "mm"),
        ("its margin to requirement 3", _get(m, "tray", "requirements", "3", "margin_mm"), "mm"),
        ("clearance to the tray (negative: a body crosses it)", _get(req2, "signed_clearance_mm"), "mm"),
        ("its margin to requirement 2", _get(req2, "margin_mm"), "mm"),
    )
    rows += _loads(_dict(res.get("loads")))
    proofs = [f"finding: {f}" for f in _list(m.get("findings")) if isinstance(f, str)]
    agree = _get(res, "loads", "power_agreement", "newton_euler_vs_virtual_power_rel")
    if isinstance(agree, int | float):
        proofs.append(f"under load: the drives' power by Newton-Euler and by virtual power agree to {agree:.1e}")
    if gaps:
        passed = all(c.get("pass") for c in gaps)
        proofs.append(
            f"posed from the made parts' files over {number(m.get('positions'))} positions: "
            + ("every clearance kept" if passed else "clearances not kept")
        )
    met = _get(res, "objectives_on_bodies", "all_met")
    if isinstance(met, bool):
        proofs.append("the objectives hold on the bodies" if met else "objectives not met on the bodies")
    finding = _get(res, "one_plane", "finding")
    if isinstance(finding, str):
        proofs.append(finding)
    return rows, proofs


def _loads(loads: dict) -> list[Row]:
    """The verdicts a designer reads first of a machine under load: each drive's peak and RMS
    torque and peak power, the largest tooth force, the shortest bearing life, the shaking force."""
    rows: list[Row] = []
    for d in _list(loads.get("drives")):
        if isinstance(d, dict):
            rows += _rows(
                (f"{d.get('drive')}: peak torque (RMS)", _pair(d.get("peak_torque_nm"), d.get("rms_torque_nm")), "N m"),
                (f"{d.get('drive')}: peak power", d.get("peak_power_w"), "W"),
            )
    meshes = [x for x in _list(loads.get("meshes")) if isinstance(x, dict)]
    supports = [x for x in _list(loads.get("supports")) if isinstance(x, dict)]
    lives = [x for x in supports if isinstance(x.get("life_h"), int | float)]
    shortest = min(lives, key=lambda x: x["life_h"]) if lives else {}
    roots = ("max_root_stress_ring_mpa", "max_root_stress_planet_mpa")
    ks = _dict(loads.get("keys_and_shafts"))
    return rows + _rows(
        ("largest tooth normal force", _extreme([x.get("max_normal_force_n") for x in meshes], max), "N"),
        ("shortest bearing life L10h", shortest.get("life_h"), "h"),
        ("at", f"{shortest.get('designation')}, {shortest.get('joint')}" if shortest else None, ""),
        ("largest tooth contact stress, nominal", _get(loads, "teeth", "max_contact_stress_mpa", "value"), "MPa"),
        ("largest tooth root stress, nominal", _extreme([_get(loads, "teeth", k, "value") for k in roots], max), "MPa"),
        ("cam on the roller: contact stress, nominal", _get(loads, "cam", "contact_stress", "value_mpa"), "MPa"),
        ("smallest key safety", _get(ks, "smallest_key_safety", "safety"), ""),
        ("smallest shaft fatigue safety", _get(ks, "smallest_shaft_safety", "fatigue_safety"), ""),
        ("needle force the machine carries", _get(ks, "needle_force_capacity", "n"), "N"),
        ("largest shaking force on the frame", _get(loads, "shaking", "max_n"), "N"),
    )


def _pair(a, b) -> str | None:
    if not isinstance(a, int | float) or not isinstance(b, int | float):
        return None
    return f"{number(a)} ({number(b)})"


_KINDS = {
    "arm": _arm,
    "link_plates": _plates,
    "balancing": _balancing,
    "pitch_pair": _pitch_pair,
    "toothed_pair": _toothed_pair,
    "incomplete_pair": _incomplete_pair,
    "planetary": _train,
    "synthesis": _synthesis,
    "cam": _cam,
    "carrier_parts": _carrier_parts,
    "machine": _machine,
}


def headline(rec: dict) -> tuple[list[Row], list[str]]:
    """(rows of quantity, value as shown, unit; sentences of what the proofs found) for a part
    record; nothing for a kind not known here or a record without results."""
    kind = rec.get("kind")
    make = _KINDS.get(kind) if isinstance(kind, str) else None
    res, par = rec.get("results"), rec.get("parameters")
    if make is None or not isinstance(res, dict):
        return [], []
    return make(res, par if isinstance(par, dict) else {})
