"""The designs on which the fouling screen is validated against the full meshing check.

Each case is an internal ring/planet pair of a seed-004-like train (ratio law ``i(φ)`` with a
mean of 4, carrier radius 57.7 mm, see ``DifferentialTrain.from_ratio``), a tooth count, a
shaper cutter and the two addenda. Its *screen verdict* is ``interference.fouling_screen(...)``
without problems (contact ratio aside: the full check does not judge it); its *full verdict* is
the meshing check of the cut teeth (``pair_gate.generate_pair`` then ``validate.mesh_check`` over a
whole ring turn): no overlap above ``SHOP_OVERLAP_MM2`` at any step, pitch point or fouling, and
a tooth pair in contact at every step.

Both cut the ring's tips as the screen's policy does (trimmed to the fillet limit less 0.02 m,
``fouling_screen(ring_addendum=None)``); the screen's verdict counts a contact ratio below 1 (the
teeth let go) like the full check does. The full check takes 3-6 s a case, so
``python tests/screen_cases.py`` records the full verdicts in ``tests/data/screen_record.json``;
``tests/test_screen.py`` compares the screen with the record on every case and re-runs the
full check live on two of them.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from transplanter.core.errors import GeometryError
from transplanter.core.tolerances import SHOP_OVERLAP_MM2
from transplanter.design.planetary import ArmGeometry, DifferentialTrain
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.interference import fouling_screen
from transplanter.geometry.pair_gate import generate_pair
from transplanter.proof import validate

RECORD = Path(__file__).parent / "data" / "screen_record.json"
STEPS = 360
#: ratio laws (harmonics of i/4 - 1): circular, mild, the search's kind, sharper, sharpest
LAWS = {
    "circular": (),
    "mild": ((-0.1, 0.1),),
    "two harmonics": ((-0.15, 0.15), (0.0, -0.05)),
    "sharp": ((-0.2, 0.2), (0.05, -0.05)),
    "sharper": ((-0.25, 0.2), (0.05, -0.08)),
}
#: (law, planet teeth, cutter teeth): the ring's tips trimmed as the screen does, each law from
#: coarse to fine; then cases with standard ring tips
CASES = tuple(
    (law, z2, z0)
    for law, teeth, z0 in (
        ("circular", (10, 12, 14, 16), 12),
        ("mild", (11, 13, 15), 12),
        ("mild", (14, 16), 16),
        ("two harmonics", (12, 14, 16, 18), 12),
        ("sharp", (10, 12, 16, 20, 24, 28), 12),
        ("sharper", (18, 22, 26, 30), 12),
        ("sharper", (24, 30), 14),
    )
    for z2 in teeth
) + (
    # standard (untrimmed) ring tips: (law, planet teeth, cutter teeth, ring addendum)
    ("circular", 14, 12, 1.0),
    ("circular", 18, 20, 1.0),
    ("mild", 13, 12, 1.0),
    ("mild", 16, 16, 0.9),
    ("two harmonics", 16, 12, 1.0),
    ("sharp", 18, 12, 1.0),
)


def case_pair(law: str, planet_teeth: int, cutter_teeth: int):
    train = DifferentialTrain.from_ratio(4, LAWS[law], 57.7, ArmGeometry(150.0, 80.0, -0.7), 0.7)
    pair, sizing = train.pair.sized(teeth=4 * planet_teeth)
    return pair, sizing, ShaperCutter(cutter_teeth, sizing.module)


def screen_limits(case):
    pair, _, cutter = case_pair(*case[:3])
    return fouling_screen(pair, cutter, ring_addendum=case[3] if len(case) > 3 else None)


def screen_verdict(case) -> list[str]:
    return screen_limits(case).problems(("ring", "planet"), min_contact_ratio=1.0, trochoid=False)


def full_verdict(case) -> dict:
    pair, sizing, cutter = case_pair(*case[:3])
    ring_add, pin_add = screen_limits(case).ring_addendum, 1.0
    try:
        gears = generate_pair(
            pair, cutter, sizing.teeth, addendum=(ring_add, pin_add), check_interference=False, allow_undercut=True
        )
    except GeometryError as exc:  # the cutter cannot make this pair (e.g. secondary cutting)
        return {"module_mm": round(sizing.module, 6), "meshes": False, "cannot_cut": str(exc)}
    rep = validate.mesh_check(
        pair, gears[0].polygon, gears[1].polygon, sizing.module, steps=STEPS, teeth=sizing.teeth[0]
    )
    return {
        "module_mm": round(sizing.module, 6),
        "max_overlap_mm2": float(f"{rep.max_penetration:.3e}"),
        "max_fouling_mm2": float(f"{rep.max_fouling:.3e}"),
        "min_contacts": rep.min_contacts,
        "contact_ratio": round(rep.contact_ratio, 3),
        "ring_addendum": ring_add,
        "meshes": bool(rep.max_penetration <= SHOP_OVERLAP_MM2 and rep.min_contacts > 0),
    }


def main() -> None:
    record = json.loads(RECORD.read_text()) if RECORD.exists() else {}
    for case in CASES:
        if " | ".join(map(str, case)) in record:
            continue
        full = full_verdict(case)
        record[" | ".join(map(str, case))] = full
        print(case, full, "screen:", screen_verdict(case) or "meshes", flush=True)
        RECORD.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    sys.exit(main())
