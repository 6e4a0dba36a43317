"""A built part's proof figures in words, one line each, as ``check`` and ``pair`` print them: a
gear pair's meshing, an incomplete pair's per phase, a re-read shop file's, and lengths in µm.
"""

from __future__ import annotations

__all__ = ["carried_line", "fmt_um", "made_line", "mesh_line", "phases_line"]


def fmt_um(mm: float) -> str:
    """A length in µm, or in mm from 1 mm up (no "3.2e+03 µm")."""
    return f"{mm:.3g} mm" if abs(mm) >= 1 else f"{mm * 1000:.3g} µm"


def mesh_line(r: dict) -> str:
    """One source's meshing check (``validate.mesh_check`` figures), or what it carries, in words."""
    if "carried_from" in r:
        return carried_line(r)
    clearance = ""
    if "clearance_mm" in r:
        clearance = f"clearance {fmt_um(r['clearance_mm'])} at {r['clearance_at_driver_deg']:.1f} deg, "
    return (
        f"overlap {r['max_penetration_mm2']:.3g} mm² (fouling {r['max_fouling_mm2']:.3g}), "
        f"TE max {fmt_um(r['max_transmission_error_mm'])} "
        f"rms {fmt_um(r['rms_transmission_error_mm'])}, "
        f"backlash {fmt_um(r['backlash_mm'][0])}..{fmt_um(r['backlash_mm'][1])}, "
        f"{clearance}contact ratio {r['contact_ratio']:.3g}"
    )


def carried_line(r: dict) -> str:
    """A source whose meshing is carried from the proved one (``PairProof.mesh_once``), in words."""
    within = "/".join(fmt_um(w) for w in r["teeth_within_mm"])
    return (
        f"the {r['carried_from']}'s proof carried: teeth within {within} of the {r['carried_from']}'s "
        f"(driver/driven), clearance at least {fmt_um(r['clearance_at_least_mm'])} at "
        f"{r['clearance_at_driver_deg']:.1f} deg"
    )


def phases_line(r: dict) -> str:
    """An incomplete pair's meshing figures (one source), per phase, in words."""
    parts = []
    if "motion" in r:
        lo, hi = r["motion"]["free_play_mm"]
        parts.append(f"motion free play {fmt_um(lo)}..{fmt_um(hi)}")
    for phase in ("dwell", "transition"):
        if phase in r:
            parts.append(f"{phase} play <= {r[phase]['largest_play_deg']:.3f} deg")
    return f"overlap {r['max_penetration_mm2']:.3g} mm², " + ", ".join(parts)


def made_line(r: dict) -> str:
    """One re-read shop file's figures (``formats``), in words."""
    if "error" in r:
        return "cannot be checked (see below)"
    if "bodies" in r and "max_overlap_mm3" in r:
        return f"{r['bodies']} bodies, largest overlap {r['max_overlap_mm3']:.3g} mm³"
    if "bodies" in r:
        read = ", ".join(
            f"{reader} {v['volumes']} volumes, volume off by {v['volume_rel_error']:.3g}, "
            f"centre {v['centre_off_mm']:.3g} mm"
            for reader, v in r.items()
            if isinstance(v, dict) and "volumes" in v
        )
        return f"{r['bodies']} bodies placed" + (f" (read by {read})" if read else "")
    return (
        f"{r['solids']} solid, {r['faces']} faces, {'valid' if r['valid'] else 'INVALID'} "
        f"({r.get('checked_by', 'not checked')}), "
        f"volume off by {r['volume_rel_error']:.3g} (relative)"
    )
