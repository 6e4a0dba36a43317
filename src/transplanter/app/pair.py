"""``transplanter pair``: one gear pair from its transmission
(:func:`transplanter.families.pairs.gear_pair.gear_pair`), its assembly and meshing proof printed —
for an incomplete pair its locks, entry shocks and proof per phase.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from transplanter.app.options import PAIR_FLAGS
from transplanter.app.proof_lines import mesh_line, phases_line
from transplanter.core.text import shown

__all__ = ["run"]


def run(args: argparse.Namespace) -> int:
    """Make the gear pair ``args`` describes and print its proof; the exit status."""
    from transplanter.families.pairs.gear_pair import gear_pair

    names = ("internal", "teeth", "module", "centre_distance", "driven_lobes", "ring", "backlash", "cutter_teeth")
    names += ("scale_to_close", "addendum", "shift", "trim_ring_tips", "allow_undercut")
    names += ("lock_clearance", "lock_depth", "locking_play")
    options = {k: getattr(args, k) for k in (*names, "rack", "width", "name")}
    options = {k: v for k, v in options.items() if v is not None or k not in ("locking_play", "ring")}
    # every option checked before anything is written, each error naming it as typed (--centre-distance)
    manifest = gear_pair(args.transmission, args.output, names=PAIR_FLAGS, **options)
    folder = Path(args.output) / manifest["family"]
    print(shown(manifest["description"]))
    rec = manifest["parts"][args.name]
    if "error" in rec:
        print(shown(f"FAILED -> {folder}"), file=sys.stderr)
        print(shown(f"  error: {rec['error']}"), file=sys.stderr)
        return 1
    if rec.get("kind") == "incomplete_pair":
        return _print_incomplete(rec, folder)
    asm = rec["results"]["assembly"]
    print(
        f"  centre distance {asm['centre_distance_mm']:.6f} mm; driven axis at {asm['driven_centre_mm']} mm in the "
        f"driver's DXF frame, turned {asm['driven_angle_at_start_deg']:g} deg at the start"
    )
    for source, r in sorted((k, v) for k, v in rec["results"]["meshing"].items() if isinstance(v, dict)):
        print(f"  meshing [{source}]: {mesh_line(r)}")
    shop = [f for f in rec["files"] if f.endswith((".dxf", ".stl", ".step", ".3mf"))]
    print(shown(f"  shop files: {', '.join(shop)}"))
    print(shown(f"ok -> {folder} (report.html)"))
    return 0


def _print_incomplete(rec: dict, folder: Path) -> int:
    """What ``pair`` says of an incomplete pair: locks, entry shocks and the proof per phase."""
    res = rec["results"]
    asm = res["assembly"]
    print(
        f"  centre distance {asm['centre_distance_mm']:.6f} mm; driven axis at {asm['driven_centre_mm']} mm in the "
        f"driver's DXF frame, turned {asm['driven_angle_at_start_deg']:g} deg at the start"
    )
    for lock in res["locks"]:
        print(
            f"  dwell {lock['dwell_deg'][0]:g}..{lock['dwell_deg'][1]:g} deg: locking arcs "
            f"{lock['driver_arc_radius_mm']:.4f} / {lock['driven_arc_radius_mm']:.4f} mm, "
            f"horns at +/-{lock['horns_half_angle_deg']:.1f} deg"
        )
    for t in res["transitions"]:
        print(
            f"  {t['kind']} at driver {t['driver_deg']:g} deg: driven speed jumps by "
            f"{t['speed_jump_w2_per_w1']:.4g} x the driver's, "
            f"acceleration by {t['acceleration_jump_per_w1_squared']:.4g} x w1^2"
        )
    for e in res["entry"]:
        if "first_contact_driver_deg" in e:
            print(
                f"  first tooth contact after the dwell at driver {e['first_contact_driver_deg']:.3f} deg "
                f"({e['after_dwell_end_deg']:+.3f} deg from the law's), "
                f"{e['driver_radius_below_tip_m']:.2f} m below the "
                f"driver's tip, {e['driven_radius_from_tip_m']:.2f} m from the driven's"
            )
    for source, r in sorted((k, v) for k, v in res["meshing"].items() if isinstance(v, dict)):
        print(f"  meshing [{source}]: {phases_line(r)}")
    shop = [f for f in rec["files"] if f.endswith((".dxf", ".stl", ".step", ".3mf"))]
    print(shown(f"  shop files: {', '.join(shop)}"))
    print(shown(f"ok -> {folder} (report.html)"))
    return 0
