"""A machine's planets anywhere in their play: each pair with a body on a planet judged with the
planet turned to either end of its play (the backlash its meshes leave it), independently.

A turn of the planet about its own centre moves no point of a body further than the turn times
the body's reach, so a pair whose nominal clearance less those moves still keeps what it is judged
against is settled by that bound alone (its figure a lower bound, not ``exact``); the others are
measured with their links turned (:func:`turned`), by the same bounded search as the nominal
figure (:func:`transplanter.proof.clearance.closest_approach`).

Moved here from :mod:`transplanter.machine.bodies` (issue 46); ``transplanter.machine`` still
gives these names.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from transplanter.machine.bodies import Body, Judged, Link, Pair
from transplanter.proof.clearance import CLEARANCE_TOL_MM, Posed, closest_approach, reach

__all__ = ["clearances_under_play", "turned"]


def turned(link: Link, turn: float) -> Link:
    """``link`` turned a further ``turn`` rad about its frame origin (a planet at an end of its
    play): its points move no faster than before."""

    def pose(theta):
        x, y, a = link.pose(theta)
        return x, y, np.asarray(a, dtype=float) + turn

    return Link(link.name, pose, link.speed, link.turn_rate)


def clearances_under_play(
    bodies: list[Body],
    ready: dict[str, Posed],
    links: dict[str, Link],
    pairs: list[Pair],
    theta: np.ndarray,
    turn: float,
    playing: set[str],
    nominal: dict[frozenset, Judged],
    settle: float,
    tol: float = CLEARANCE_TOL_MM,
    wrap: Callable[[Posed], Posed] | None = None,
) -> list[Judged]:
    """Each pair's closest approach with every link in ``playing`` (the planets) at either end of
    its play, ± ``turn`` rad, independently: the smallest over those poses, for the pairs that
    have a playing link (the others are not returned); ``ready`` the bodies as
    :func:`~transplanter.machine.bodies.posed` gives them on ``links`` (any frame: a turn about its
    own origin is the same in all), each turned body through ``wrap`` if given (as the nominal
    figure was measured).

    A turn of ``turn`` moves no point of a body further than ``turn`` times its reach, so a pair
    whose ``nominal`` closest approach less those moves stays at or above ``settle`` (the
    clearance judged against) is settled without measuring: its figure is that lower bound,
    marked not ``exact`` (and without a ``nearest``)."""
    by_name = {b.name: b for b in bodies}
    todo = [p for p in pairs if {by_name[p.a].link, by_name[p.b].link} & playing]

    def judge(p: Pair) -> Judged:
        la, lb = by_name[p.a].link, by_name[p.b].link
        known = nominal[frozenset((p.a, p.b))]
        moves = sum(turn * reach(by_name[n].section) for n, ln in ((p.a, la), (p.b, lb)) if ln in playing)
        if known.distance - moves >= settle:
            return Judged(
                p,
                max(0.0, known.distance - moves),
                known.at_deg,
                max(0.0, known.bound - moves),
                known.samples,
                exact=False,
            )
        signs_a = (-1.0, 1.0) if la in playing else (0.0,)
        signs_b = (-1.0, 1.0) if lb in playing and lb != la else (0.0,)
        worst = None
        for sa in signs_a:
            for sb in signs_b:
                # (a turn about the link's origin leaves its speed bound and outlines as they were)
                a = dataclasses.replace(ready[p.a], pose=turned(links[la], sa * turn).pose)
                b = dataclasses.replace(ready[p.b], pose=turned(links[lb], (sa if lb == la else sb) * turn).pose)
                a, b = (wrap(a), wrap(b)) if wrap else (a, b)
                found = Judged.of(p, closest_approach(a, b, theta, tol))  # exactly: the play's figures are stated
                if worst is None or found.distance < worst.distance:
                    worst = found
        assert worst is not None
        return worst

    with ThreadPoolExecutor(max_workers=2) as pool:
        return list(pool.map(judge, todo))
