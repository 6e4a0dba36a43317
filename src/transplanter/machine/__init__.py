"""Whole machines: bodies posed over the cycle from their made parts, judged pair by pair.

A machine is bodies in planes, posed over its cycle, with the clearance between every two that
could meet (:mod:`~transplanter.machine.bodies`), and with the planets anywhere in their play
(:mod:`~transplanter.machine.play`); seed 004's planting arms as plates
(:mod:`~transplanter.machine.arm_parts`); seed 002's double carrier as moving links
(:mod:`~transplanter.machine.carriers`) and its parts as a designer draws them
(:mod:`~transplanter.machine.carrier_parts`); the cycle to watch (:mod:`~transplanter.machine.animation`);
what the machine carries — its bodies' masses (:mod:`~transplanter.machine.mass`) and the inverse
dynamics of its links, Newton-Euler checked by virtual power (:mod:`~transplanter.machine.dynamics`).

Takes
    made gears and their meshing (:mod:`transplanter.proof`), trains (:mod:`transplanter.design`).
Gives
    posed bodies, motion tables and judged pairs.
May import
    every station below it: core, geometry, design, shop, proof.

``transplanter.machine`` was a module before 0.2; its names stay importable from here.
"""

from transplanter.core.forwarding import forward
from transplanter.machine.bodies import *  # noqa: F403 - the former module's names
from transplanter.machine.bodies import __all__  # noqa: F401

#: names this module gave before issue 41 moved them to modules of their own, still found here
__getattr__ = forward(
    __name__,
    {
        "LEVELS_MM": "transplanter.machine.bodies",
        "clearances_under_play": "transplanter.machine.play",
        "turned": "transplanter.machine.play",
    },
)
