"""Geometry of the parts that mesh: pitch curves, the gear cutter and the teeth it cuts, cams.

The first stations a gear passes through — *size* and *cut*: closed pitch curves of external and
internal non-circular pairs (:mod:`~transplanter.geometry.pitch`), the standard tooth proportions
and the backlash a pair is cut for, the shaper and rack cutters (:mod:`~transplanter.geometry.cutter`,
the protocol and tooth they share in :mod:`~transplanter.geometry.cutter_tooth`, the rack in
:mod:`~transplanter.geometry.rack_cutter`), the teeth as the cutter's envelope
(:mod:`~transplanter.geometry.teeth`, sampled by :mod:`~transplanter.geometry.envelope`, checked
for secondary cutting by :mod:`~transplanter.geometry.secondary_cutting`,
:mod:`~transplanter.geometry.tooth_spaces`), the closed-form interference limits of ring pairs and
the gate that cuts both gears of a sized pair (:mod:`~transplanter.geometry.pair_gate`,
:mod:`~transplanter.geometry.cutter_choice`), incomplete gears with locking arcs and the sweep that
relieves them (:mod:`~transplanter.geometry.incomplete`, their toothed sectors
:mod:`~transplanter.geometry.toothed_sectors`, the first contact after a dwell
:mod:`~transplanter.geometry.dwell_entry`, :mod:`~transplanter.geometry.sweep`), disc cam profiles
(:mod:`~transplanter.geometry.cams`) and the closed-form first contact of two turning outlines
(:mod:`~transplanter.geometry.contact`).

Takes
    numbers (mm, radians) and :mod:`transplanter.core`.
Gives
    numpy arrays (``(n, 2) float, mm``), shapely polygons of outlines and frozen dataclasses.
May import
    :mod:`transplanter.core` only. The maths modules (``pitch``, ``cutter``, ``cutter_tooth``,
    ``rack_cutter``, ``cams``, ``backlash``, ``proportions``, ``contact``) import numpy and scipy and
    no geometry kernel or file format (``tests/test_layout.py``).
"""
