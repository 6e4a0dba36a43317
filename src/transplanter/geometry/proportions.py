"""Standard tooth proportions, in modules: one source for each (ISO 53 basic rack and the
shaper cutters built on it).

A gear's dedendum is its cutter's addendum; a ring keeps a rim of ``RING_RIM`` modules under
its deepest tooth space (``teeth.generate``), so its material reaches ``RING_DEPTH`` modules
beyond its pitch curve — what a housing around it must clear (``objectives``) and where bolt
holes sit in it (``parts/planetary_seed004.py``).
"""

from __future__ import annotations

__all__ = ["CUTTER_ADDENDUM", "CUTTER_DEDENDUM", "RING_DEPTH", "RING_RIM"]

#: cutter addendum (= the cut gear's dedendum: 1 m plus 0.25 m tip clearance, ISO 53)
CUTTER_ADDENDUM = 1.25
#: cutter dedendum: its root, 0.35 m below a standard 1 m gear tip
CUTTER_DEDENDUM = 1.35
#: a ring's rim under its deepest tooth space
RING_RIM = 3.0
#: how far a ring's material reaches beyond its pitch curve: its dedendum and its rim
RING_DEPTH = CUTTER_ADDENDUM + RING_RIM
