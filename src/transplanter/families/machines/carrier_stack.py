"""A shaft's stack in seed 002's structure (:mod:`~transplanter.families.machines.carrier_structure`):
what it carries in order along it — bearings in plates, keyed hubs — and what that makes: the turned
shaft with its keyways and ring grooves, the spacers between, its bearings and retaining rings placed
on their links, and the joints between them (:func:`stack`); where a part sits (:class:`Placement`).
"""

from __future__ import annotations

from dataclasses import dataclass

from transplanter.machine.hardware import Fitted, Turned
from transplanter.shop.catalogue import bearing, circlip_for_shaft, fit, key_for

__all__ = ["RING_PLAY_MM", "SPACER_WALL_MM", "Item", "Placement", "flush", "roller_stack", "stack"]

#: a spacer on a shaft is this much larger in radius than the shaft (it bears on the inner ring
#: inside its shoulder), mm
SPACER_WALL_MM = 1.5
#: a retaining ring's groove ends this far off the face the ring holds (the ring's axial play; the
#: groove then never meets a keyway that runs to a hub's face), mm
RING_PLAY_MM = 0.05


@dataclass(frozen=True)
class Placement:
    """Where a body of a made or bought part sits: its body name, the link, the offset in that
    link's frame (mm) and its z-range across the machine (mm)."""

    body: str
    link: str
    x: float
    y: float
    z: tuple[float, float]


@dataclass(frozen=True)
class Item:
    """One thing a shaft carries: a bearing (its plate's body, z, the mounted link it sits on and
    the catalogue part) or a keyed hub (``part`` None)."""

    name: str
    z: tuple[float, float]
    link: str = ""
    part: object = None


def stack(
    name: str,
    stem: str,
    d: float,
    link: str,
    items: list[Item],
    notes: tuple[str, ...],
    spacers: bool = True,
) -> tuple[Turned, list[tuple[float, float, str]], list[Fitted], dict, list[tuple[str, tuple[float, float]]]]:
    """A shaft of diameter ``d`` on ``link`` carrying ``items`` (module docstring): the turned shaft
    (``stem``, z from its back end), the spacers to make ``(z0, z1, body name)``, its bearings and
    rings as :class:`~transplanter.machine.hardware.Fitted`, the joints, and the keyed hubs
    ``(body, z)`` its keyways are cut under. ``spacers`` False: a ring on each side of every item
    and no spacers (a fixed shaft)."""
    items = sorted(items, key=lambda i: i.z[0])
    ring = circlip_for_shaft(d)
    joints: dict = {}
    fitted: list[Fitted] = []
    ring_at: list[tuple[float, bool]] = []  # (z of the face it bears on, behind it?)
    if spacers:
        ring_at = [(items[0].z[0], True), (items[-1].z[1], False)]
    else:
        for it in items:
            ring_at += [(it.z[0], True), (it.z[1], False)]
    made: list[tuple[float, float, str]] = []
    for k, (a, b) in enumerate(zip(items, items[1:], strict=False)):
        if spacers and b.z[0] - a.z[1] > 1e-9:
            body = f"spacer_{name}_{k + 1}"
            made.append((a.z[1], b.z[0], body))
            for it in (a, b):
                if it.part is not None:
                    joints[frozenset((body, f"bearing_{it.name}_{name}"))] = "spacer: against the bearing's inner ring"
    for it in items:
        if it.part is None:
            continue
        body = f"bearing_{it.name}_{name}"
        fitted.append(Fitted(body, it.part, it.link, it.z[0]))
        kind = "bush" if hasattr(it.part, "bush") else "bearing"
        joints[frozenset((body, it.name))] = f"{kind}: in its bore ({fit(it.part.D, 'H7').text})"
        joints[frozenset((body, f"shaft_{name}"))] = f"{kind}: on its shaft ({fit(d, 'k6').text})"
    grooves = []
    end = ring.groove_width + RING_PLAY_MM + ring.n_min
    z_back = round(min(z for z, _ in ring_at) - end, 6)
    z_front = round(max(z for z, _ in ring_at) + end, 6)
    for k, (z, behind) in enumerate(ring_at):
        body = f"ring_{name}_{k + 1}"
        fitted.append(Fitted(body, ring, link, z - ring.s - RING_PLAY_MM if behind else z + RING_PLAY_MM))
        g0 = z - ring.groove_width - RING_PLAY_MM if behind else z + RING_PLAY_MM
        grooves.append((round(g0 - z_back, 6), ring.groove_width, ring.groove_diameter, ring.groove_note))
        for it in items:
            if it.part is not None and abs((it.z[0] if behind else it.z[1]) - z) < 1e-9:
                joints[frozenset((body, f"bearing_{it.name}_{name}"))] = (
                    "retaining ring: against the bearing's inner ring"
                )
    keyed = [(it.name, it.z) for it in items if it.part is None]
    keyways = []
    for body, (z0, z1) in keyed:
        key = key_for(d, z1 - z0)
        mid = (z0 + z1) / 2 - z_back
        keyways.append(
            (
                round(mid - key.length / 2, 6),
                key.length,
                key.b,
                key.t1,
                f"{key.designation} for {body}; {key.shaft_note(d)}",
            )
        )
    fits = [
        (round(it.z[0] - z_back, 6), round(it.z[1] - z_back, 6), f"bearing seat {fit(d, 'k6').text}")
        for it in items
        if it.part
    ]
    shaft = Turned(
        stem,
        d,
        round(z_front - z_back, 6),
        keyways=tuple(keyways),
        grooves=tuple(grooves),
        fits=tuple(fits),
        notes=notes,
    )
    joints.update(
        {
            frozenset((f"shaft_{name}", f"ring_{name}_{k + 1}")): "retaining ring: in its groove"
            for k in range(len(ring_at))
        }
    )
    return shaft, made, fitted, joints, [(f"shaft_{name}", (z_back, z_front))]


def flush(plate: tuple[float, float], width: float, keyed_z: list[float]) -> tuple[float, float]:
    """A bearing ``width`` wide in ``plate``, flush with its face towards the nearest keyed hub."""
    mid = (plate[0] + plate[1]) / 2
    near = min(keyed_z, key=lambda z: (abs(z - mid), -z))
    return (plate[1] - width, plate[1]) if near > mid else (plate[0], plate[0] + width)


def roller_stack(study, mount):
    """The follower's roller pin, pressed into the lever, with the spacer that holds the roller (a
    bearing in the cam's plane) off the lever and the ring that holds it on; ``mount(base, where, x,
    y)`` names the link the pin sits on."""
    L, n = study.layers, study.parts
    f = study.cam.follower
    roller = bearing("625")
    d = roller.d
    ring = circlip_for_shaft(d)
    mid = (L.cam[0] + L.cam[1]) / 2
    r0, r1 = mid - roller.B / 2, mid + roller.B / 2
    z_back = round(r0 - ring.groove_width - RING_PLAY_MM - ring.n_min, 6)
    link = mount("follower", "roller", f.arm_length, 0.0)
    groove = round(r0 - ring.groove_width - RING_PLAY_MM - z_back, 6)
    pin = Turned(
        f"{n}.roller_pin",
        d,
        round(L.lever[1] - z_back, 6),
        grooves=((groove, ring.groove_width, ring.groove_diameter, ring.groove_note),),
        fits=(
            (L.lever[0] - z_back, L.lever[1] - z_back, f"pressed in the lever: {fit(d, 'k6').text}"),
            (r0 - z_back, r1 - z_back, f"the roller's seat {fit(d, 'k6').text}"),
        ),
        notes=(f"the follower's roller pin: carries the roller ({roller.designation}) in the cam's plane",),
    )
    spacer = Turned(
        f"{n}.roller_spacer",
        d + 2 * SPACER_WALL_MM,
        L.lever[0] - r1,
        bore=d,
        notes=("holds the roller off the lever, against its inner ring",),
    )
    turned = [
        (pin, (Placement("roller_pin", link, 0.0, 0.0, (z_back, L.lever[1])),)),
        (spacer, (Placement("spacer_roller", link, 0.0, 0.0, (r1, L.lever[0])),)),
    ]
    fitted = [Fitted("ring_roller", ring, link, r0 - ring.s - RING_PLAY_MM)]
    joints = {
        frozenset(("roller", "roller_pin")): f"bearing: the roller ({roller.designation}) on its pin",
        frozenset(("roller", "spacer_roller")): "spacer: against the roller's inner ring",
        frozenset(("roller", "ring_roller")): "retaining ring: against the roller's inner ring",
    }
    return turned, fitted, joints
