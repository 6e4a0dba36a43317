"""What holds and drives seed 002's machine, as parts a shop makes or buys and bodies the judge poses.

Seed 002 drives carrier 1 about a fixed central shaft that carries the sun 2 and the cam 6
(§4.2, Fig. 10), at 60 r/min (§5.1). Carrier 1 and everything on it turn through the whole circle
and reach 167 mm from the axis, in every plane from the cam's to the claw's; the lever and its
roller, beside the cam, sweep the ring the cam's track leaves. A drive from outside can therefore
reach carrier 1 only **along its axis, through the cam**: here the fixed shaft (``main_shaft``,
Ø17) is clamped in a **frame** plate behind the cam; a **drive tube** (Ø36) turns on it in two
wrapped bushes, passes through the cam's bore with running clearance, and is keyed into carrier
1's **hub** plate, which is bolted to carrier 1; its rear end, between the frame and the cam, is
keyed for the input sprocket (the tractor's chain: 60 r/min, not drawn). The cam is bolted to
three **posts** standing on the frame (the chain leaves between two of them); the sun is keyed on
the fixed shaft between two retaining rings.

Every gear shaft is held **at both ends**: carrier 1 and a **front plate** on it (``cover``,
joined by three **standoffs** and M4 screws) carry the shafts of gears 3-4, of gears 5-9 and of the
follower (lever behind carrier 1, sector 7 in front of the cover: both overhung on a shaft in two
bearings) and the fixed shaft's front end; carrier 2 and its **front plate** (two standoffs) carry
the idler 10 and gear 11 with the arm (overhung). Carrier 2 and sector 8 (bolted to it with M3
screws across spacers) turn on gear 5-9's shaft in a bearing each.

A shaft's **stack** (:func:`~transplanter.families.machines.carrier_stack.stack`): its bearings sit
flush with the face of their plate towards the shaft's nearest keyed member; spacers fill every gap
between the inner rings and the keyed hubs; a DIN 471 ring at each end clamps the stack (each
bearing's outer ring held in its H7 bore with a bearing retaining compound: the spur and sector
gears put no axial load on them). Bearings are chosen by
:func:`~transplanter.shop.catalogue.bearing_for` at the stated radial load and the largest speed of
the shaft against its plate over the cycle (its links' turn-rate bound times ``speed_rpm``).

The structure is stated by :class:`CarrierStructure` (the part script); :func:`hardware` lays it
out from the machine as designed; :func:`plates` draws the plates it adds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import SpecError, check_number
from transplanter.core.precision import rounded
from transplanter.families.machines.carrier_stack import (
    RING_PLAY_MM,
    SPACER_WALL_MM,
    Item,
    Placement,
    flush,
    roller_stack,
    stack,
)
from transplanter.machine.hardware import Fitted, Turned
from transplanter.shop.catalogue import bearing_for, bush_for, circlip_for_shaft, fit, key_for

__all__ = [
    "CarrierStructure",
    "Hardware",
    "bores",
    "cam_angle",
    "hardware",
    "post_positions",
    "sector_bolts",
    "speeds",
]


@dataclass(frozen=True)
class CarrierStructure:
    """Seed 002's structure (module docstring), as the part script states it, mm and degrees.

    The planes it adds (z-ranges, across the machine from the cam's back face): ``frame``, carrier
    1's ``hub``, carrier 1's front plate ``cover`` and carrier 2's front plate ``front``. ``posts``:
    their radius and angles about the cam's centre in the cam's frame (the cam's bolt holes);
    ``standoffs_1``/``standoffs_2``: the standoffs between carrier 1 and its cover, carrier 2 and
    its front plate, in those carriers' frames; ``hub_bolts``: radius and angles (carrier 1's frame)
    of the screws holding the hub; ``load_n``: the radial design load every bearing and bush is
    chosen for; ``speed_rpm``: carrier 1's speed; ``hardware_clearance``: the radial clearance
    concentric hardware keeps from a bore it passes (a ring, a spacer or a shaft in a plate's bore)."""

    frame: tuple[float, float]
    hub: tuple[float, float]
    cover: tuple[float, float]
    front: tuple[float, float]
    posts: tuple[float, tuple[float, ...]]
    standoffs_1: tuple[tuple[float, float], ...]
    standoffs_2: tuple[tuple[float, float], ...]
    hub_bolts: tuple[float, tuple[float, ...]]
    main_shaft: float = 17.0
    tube: float = 36.0
    shaft: float = 12.0
    load_n: float = 300.0
    speed_rpm: float = 60.0
    hardware_clearance: float = 0.5
    #: sector 8's two screws to carrier 2 sit on this radius about A_c (its hub is 20 mm, its bearing
    #: bore 21 mm), each through a spacer across the gap between them, mm
    sector_bolt_circle: float = 16.0
    #: screws (size, clearance hole, tapping drill): posts, hub, standoffs, sector 8 on carrier 2
    screws: dict = field(
        default_factory=lambda: {
            "posts": ("M5", 5.5, 4.2),
            "hub": ("M5", 5.5, 4.2),
            "standoffs": ("M4", 4.5, 3.3),
            "sector": ("M3", 3.4, 2.5),
        }
    )

    def __post_init__(self) -> None:
        for what in ("frame", "hub", "cover", "front"):
            z = getattr(self, what)
            if not (len(z) == 2 and z[0] < z[1]):
                raise SpecError.out_of_range(f"structure.{what}", z, "(z0, z1) mm with z0 < z1")
        check_number("structure.main_shaft", self.main_shaft, 5.0, 50.0, unit="mm")
        check_number("structure.tube", self.tube, self.main_shaft, 100.0, low_open=True, unit="mm")
        check_number("structure.shaft", self.shaft, 5.0, 50.0, unit="mm")
        check_number("structure.load_n", self.load_n, 0.0, 1e5, low_open=True, unit="N")
        check_number("structure.speed_rpm", self.speed_rpm, 0.0, 1e4, low_open=True, unit="r/min")
        check_number("structure.hardware_clearance", self.hardware_clearance, 0.5, 10.0, unit="mm")
        check_number("structure.posts radius", self.posts[0], 0.0, 1000.0, low_open=True, unit="mm")
        check_number("structure.hub_bolts radius", self.hub_bolts[0], 0.0, 1000.0, low_open=True, unit="mm")
        if len(self.posts[1]) < 3 or len(self.standoffs_1) < 2 or len(self.standoffs_2) < 2:
            raise SpecError("structure: at least 3 posts and 2 standoffs on each carrier")

    def record(self) -> dict:
        return {
            "planes_mm": {w: list(getattr(self, w)) for w in ("frame", "hub", "cover", "front")},
            "main_shaft_mm": self.main_shaft,
            "drive_tube_mm": self.tube,
            "gear_shafts_mm": self.shaft,
            "design_radial_load_n": self.load_n,
            "carrier_1_speed_rpm": self.speed_rpm,
            "hardware_clearance_mm": self.hardware_clearance,
        }


@dataclass(frozen=True)
class Hardware:
    """The structure laid out (:func:`hardware`): the turned parts with their placements, the
    bought parts (each a :class:`~transplanter.machine.hardware.Fitted` on a mounted link), the
    mounted links ``(name, base link, x, y)``, the joints (pair of body names -> what joins them),
    what each shaft is held by, and the bearings chosen (rows for the record)."""

    turned: tuple[tuple[Turned, tuple[Placement, ...]], ...]
    fitted: tuple[Fitted, ...]
    mounts: tuple[tuple[str, str, float, float], ...]
    joints: dict
    shafts: dict
    bearings: tuple[dict, ...]
    #: pairs of bodies on one axis, one passing through the other's bore: they keep the structure's
    #: ``hardware_clearance`` (a ring, a spacer or a shaft in a plate's bore)
    concentric: frozenset = frozenset()
    #: every hub keyed on a shaft of the structure: (body, the shaft's link, shaft diameter, z-range)
    keyed: tuple = ()


def cam_angle(machine) -> float:
    """The cam's DXF frame in the machine frame (rad): its follower frame (pivot on +x) where
    carrier 1 puts the pivot at the start, the cam fixed there."""
    x, y, _ = machine.poses(np.zeros(1))["follower"]
    return float(math.atan2(float(y[0]), float(x[0])))


def speeds(machine, n: int = 2880) -> dict[tuple[str, str], float]:
    """The largest turn rate of each shaft's link against each plate it runs in, per turn of
    carrier 1 (sampled ``n`` times a turn; the largest change between two samples added)."""
    theta = 2 * math.pi * np.arange(n + 1) / n
    p = machine.poses(theta)

    def rate(a: str, b: str) -> float:
        da = p[a][2] if a != "fixed" else np.zeros_like(theta)
        db = p[b][2] if b != "fixed" else np.zeros_like(theta)
        r = np.abs(np.diff(np.unwrap(da - db))) / (2 * math.pi / n)
        return float(r.max() + np.abs(np.diff(r)).max())

    pairs = [
        ("follower", "carrier1"),
        ("shaft3", "carrier1"),
        ("shaft5", "carrier1"),
        ("shaft5", "carrier2"),
        ("idler", "carrier2"),
        ("gear11", "carrier2"),
        ("carrier1", "fixed"),
    ]
    return {(a, b): rate(a, b) for a, b in pairs}


def hardware(study, machine) -> Hardware:
    """Seed 002's structure laid out from the machine ``study`` states (``study.structure``) and the
    machine as designed (``machine``: where the shafts sit and how fast they turn)."""
    S, L, n = study.structure, study.layers, study.parts
    lay = machine.layout
    l1, l2, _ = study.chain.link_lengths
    rates = speeds(machine)
    d = S.shaft
    mounts: list[tuple[str, str, float, float]] = []
    rows: list[dict] = []

    def mount(base: str, where: str, x: float, y: float) -> str:
        name = f"{base}@{where}"
        if (x, y) == (0.0, 0.0):
            return base
        if name not in {m[0] for m in mounts}:
            mounts.append((name, base, x, y))
        return name

    def bearing(shaft_link: str, plate_link: str, bore: float, where: str):
        rpm = rates[(shaft_link, plate_link)] * S.speed_rpm
        b = bearing_for(bore, rpm, S.load_n)
        rows.append(
            {
                "where": where,
                "designation": b.designation,
                "d_D_B_mm": [b.d, b.D, b.B],
                "speed_rpm": rounded(rpm, 4),
                "radial_load_n": S.load_n,
                "life_h": rounded(b.life_h, 1),
                "static_safety": rounded(b.static_safety, 3),
            }
        )
        return b

    front_of = {"carrier_1": L.carrier1, "carrier_1_front": S.cover, "sector_8": L.sectors, "carrier_2": L.carrier2}
    front_of["carrier_2_front"] = S.front
    plates = {  # shaft -> (link, where it sits on its carrier, the plates it runs in, keyed hubs)
        "pivot": (
            "follower",
            ("carrier1", lay.pivot),
            ("carrier_1", "carrier_1_front"),
            (("lever", L.lever), ("sector_7", L.sectors)),
        ),
        "3": (
            "shaft3",
            ("carrier1", lay.s3),
            ("carrier_1", "carrier_1_front"),
            (("gear_3", L.stage23), ("gear_4", L.stage35)),
        ),
        "5": (
            "shaft5",
            ("carrier1", (l1, 0.0)),
            ("carrier_1", "carrier_1_front", "sector_8", "carrier_2"),
            (("gear_5", L.stage35), ("gear_9", L.spurs)),
        ),
        "idler": ("idler", ("carrier2", lay.idler), ("carrier_2", "carrier_2_front"), (("gear_10", L.spurs),)),
        "q": (
            "gear11",
            ("carrier2", (l2, 0.0)),
            ("carrier_2", "carrier_2_front"),
            (("gear_11", L.spurs), ("arm", L.arm)),
        ),
    }
    turned: list[tuple[Turned, tuple[Placement, ...]]] = []
    fitted: list[Fitted] = []
    joints: dict = {}
    shafts: dict = {}
    spacer_parts: dict[float, list[Placement]] = {}
    concentric: set = set()
    keyed_hubs: list = []
    for key, (link, (carrier, at), runs_in, keyed) in plates.items():
        keyed_z = [z for _, z in keyed for z in z]
        items = [Item(body, z) for body, z in keyed]
        for plate in runs_in:
            on = "carrier2" if plate in ("sector_8", "carrier_2", "carrier_2_front") else "carrier1"
            xy = at if on == carrier else (0.0, 0.0)  # gear 5-9's shaft: carrier 2 turns about it
            b = bearing(link, on, d, f"{plate} on the {key} shaft")
            where = {"pivot": "pivot", "3": "s3", "5": "Ac", "idler": "idler", "q": "Q"}[key]
            items.append(Item(plate, flush(front_of[plate], b.B, keyed_z), mount(on, where, *xy), b))
        shaft, made, fit_, jts, spans = stack(
            key,
            f"{n}.shaft_{key}",
            d,
            link,
            items,
            (
                f"shaft of {', '.join(b for b, _ in keyed)}; runs in {', '.join(runs_in)}",
                *(
                    ("keyways drawn at one angle: cut them as machine.machine.json keys_deg states",)
                    if len(keyed) > 1
                    else ()
                ),
            ),
        )
        turned.append((shaft, (Placement(f"shaft_{key}", link, 0.0, 0.0, spans[0][1]),)))
        for z0, z1, body in made:
            spacer_parts.setdefault(round(z1 - z0, 6), []).append(Placement(body, link, 0.0, 0.0, (z0, z1)))
        fitted += fit_
        joints.update(jts)
        on_shaft = [f"shaft_{key}", *(b for _, _, b in made), *(f.name for f in fit_ if f.name.startswith("ring_"))]
        concentric |= {frozenset((b, plate)) for b in on_shaft for plate in runs_in}
        keyed_hubs += [(body, link, d, z) for body, z in keyed]
        shafts[f"shaft_{key}"] = {"held_by": list(runs_in), "carries": [b for b, _ in keyed], "z_mm": list(spans[0][1])}
    for length, where in sorted(spacer_parts.items()):
        part = Turned(
            f"{n}.spacer_{d:g}x{length:g}",
            d + 2 * SPACER_WALL_MM,
            length,
            bore=d,
            quantity=len(where),
            notes=(
                f"spacer on a Ø{d:g} shaft between bearing inner rings and hubs; bore sliding on {fit(d, 'h6').text}",
            ),
        )
        turned.append((part, tuple(where)))
    for part in (_centre(study, machine, bearing, mount), roller_stack(study, mount)):
        turned += part[0]
        fitted += part[1]
        joints.update(part[2])
    main = ["shaft_main", *(f.name for f in fitted if f.name.startswith("ring_main_"))]
    concentric |= {frozenset((b, p)) for b in main for p in ("drive_tube", "carrier_1", "hub", "carrier_1_front")}
    concentric.add(frozenset(("drive_tube", "cam")))
    shafts["main_shaft"] = {
        "held_by": ["frame (keyed, two retaining rings)"],
        "carries": ["sun", "cam (on posts)"],
        "supports": (
            "fixed: built into the frame (H7/k6, keyed, a retaining ring each side) — a cantilever by necessity, "
            "carrier 1 turning round it in every plane in front of the frame; rated as such in "
            "loads.built_in_shaft; the cover's bearing on its front end is carrier 1's seat"
        ),
    }
    shafts["drive_tube"] = {
        "held_by": ["main shaft (two wrapped bushes)"],
        "carries": ["hub (keyed)", "input sprocket (keyed)"],
    }
    keyed_hubs += [("frame", "fixed", S.main_shaft, S.frame), ("sun", "fixed", S.main_shaft, study.layers.stage23)]
    return Hardware(
        tuple(turned),
        tuple(fitted),
        tuple(mounts),
        joints,
        shafts,
        tuple(rows),
        frozenset(concentric),
        tuple(keyed_hubs),
    )


def _centre(study, machine, bearing, mount):
    """The fixed shaft, the drive tube with its bushes, the standoffs and the posts."""
    S, L, n = study.structure, study.layers, study.parts
    gap = L.min_axial_gap
    cover_b = bearing("carrier1", "fixed", S.main_shaft, "carrier_1_front on the main shaft")
    items = [
        Item("frame", S.frame),
        Item("sun", L.stage23),
        Item("carrier_1_front", flush(S.cover, cover_b.B, [L.stage35[1]]), "carrier1", cover_b),
    ]
    main, _, fitted, joints, spans = stack(
        "main",
        f"{n}.main_shaft",
        S.main_shaft,
        "fixed",
        items,
        ("fixed central shaft: keyed in the frame, carries the sun (keyed) and the cover's bearing",),
        spacers=False,
    )
    turned = [(main, (Placement("shaft_main", "fixed", 0.0, 0.0, spans[0][1]),))]
    # the drive tube: from the frame's ring to the hub's front face, in two bushes on the main shaft
    ring = circlip_for_shaft(S.main_shaft)
    z0, z1 = S.frame[1] + ring.s + RING_PLAY_MM + gap, S.hub[1]
    bush = bush_for(S.main_shaft, min(40.0, (z1 - z0) / 2), S.load_n, S.speed_rpm)
    hub_key = key_for(S.tube, S.hub[1] - S.hub[0])
    in_key = key_for(S.tube, L.cam[0] - gap - z0)
    keyways = (
        (
            0.0,
            in_key.length,
            in_key.b,
            in_key.t1,
            f"{in_key.designation}: the input sprocket; {in_key.shaft_note(S.tube)}",
        ),
        (
            S.hub[0] - z0,
            hub_key.length,
            hub_key.b,
            hub_key.t1,
            f"{hub_key.designation}: the hub; {hub_key.shaft_note(S.tube)}",
        ),
    )
    tube = Turned(
        f"{n}.drive_tube",
        S.tube,
        z1 - z0,
        bore=bush.bush.D,
        keyways=keyways,
        fits=(
            (
                0.0,
                z1 - z0,
                f"{fit(S.tube, 'k6').text} (hub H7); bore {fit(bush.bush.D, 'H7').text} for two {bush.designation}",
            ),
        ),
        notes=(f"carrier 1's drive: turns at {S.speed_rpm:g} r/min on the fixed Ø{S.main_shaft:g} shaft",),
    )
    turned.append((tube, (Placement("drive_tube", "carrier1", 0.0, 0.0, (z0, z1)),)))
    for k, zb in enumerate((z0, z1 - bush.bush.B)):
        body = f"bush_tube_{k + 1}"
        fitted.append(Fitted(body, bush, "carrier1", zb))
        joints[frozenset((body, "drive_tube"))] = f"bush: in its bore ({fit(bush.bush.D, 'H7').text})"
        joints[frozenset((body, "shaft_main"))] = "bush: on its shaft (sliding)"
    joints[frozenset(("drive_tube", "hub"))] = f"key: {hub_key.designation}, {fit(S.tube, 'k6').text} in H7"
    # standoffs and posts: turned spacers with screws through them (bores for the screws)
    for what, pts, base, (a, b) in (
        ("standoff_1", S.standoffs_1, "carrier1", (L.carrier1[1], S.cover[0])),
        ("standoff_2", S.standoffs_2, "carrier2", (L.carrier2[1], S.front[0])),
    ):
        size, clear, _ = S.screws["standoffs"]
        part = Turned(
            f"{n}.{what}",
            12.0,
            b - a,
            bore=clear,
            quantity=len(pts),
            material="S235JR",
            notes=(f"standoff: an {size} screw through it joins the plates",),
        )
        turned.append(
            (
                part,
                tuple(
                    Placement(f"{what}_{k + 1}", mount(base, f"{what}_{k + 1}", x, y), 0.0, 0.0, (a, b))
                    for k, (x, y) in enumerate(pts)
                ),
            )
        )
    posts = [
        Placement(f"post_{k + 1}", mount("fixed", f"post_{k + 1}", x, y), 0.0, 0.0, (S.frame[1], L.cam[0]))
        for k, (x, y) in enumerate(post_positions(study, machine))
    ]
    # sector 8 is screwed to carrier 2 across the gap the follower shaft's end needs: a spacer at each screw
    size, clear, _ = S.screws["sector"]
    gap_z = (L.sectors[1], L.carrier2[0])
    spacers = [
        Placement(f"sector_spacer_{k}", mount("carrier2", f"sector_spacer_{k}", x, y), 0.0, 0.0, gap_z)
        for k, (x, y) in enumerate(sector_bolts(S.sector_bolt_circle), 1)
    ]
    turned.append(
        (
            Turned(
                f"{n}.sector_spacer",
                7.0,
                gap_z[1] - gap_z[0],
                bore=clear,
                quantity=len(spacers),
                material="S235JR",
                notes=(f"spacer between sector 8 and carrier 2, an {size} screw through it",),
            ),
            tuple(spacers),
        )
    )
    size, _, tap = S.screws["posts"]
    turned.append(
        (
            Turned(
                f"{n}.post",
                16.0,
                L.cam[0] - S.frame[1],
                quantity=len(posts),
                material="S235JR",
                notes=(f"post: {size} tapped 10 deep at each end; holds the cam on the frame",),
                operations=(f"drill Ø{tap:g} and tap {size} 10 deep at each end",),
            ),
            tuple(posts),
        )
    )
    return turned, fitted, joints


def bores(hw: Hardware) -> dict[str, list[tuple[float, float, float]]]:
    """Each plate's bearing bores ``(x, y, D)`` in its carrier's frame, mm (sector 8's at its origin)."""
    offsets = {m[0]: (m[2], m[3]) for m in hw.mounts}
    out: dict[str, list[tuple[float, float, float]]] = {}
    for f in hw.fitted:
        if f.name.startswith("bearing_"):
            plate = f.name.removeprefix("bearing_").rsplit("_", 1)[0]
            out.setdefault(plate, []).append((*offsets.get(f.link, (0.0, 0.0)), float(f.part.D)))
    return out


def sector_bolts(radius: float) -> list[tuple[float, float]]:
    """Sector 8's screws in carrier 2's frame: two on a circle of ``radius`` about A_c, mm."""
    return [(radius * math.cos(math.radians(a)), radius * math.sin(math.radians(a))) for a in (45.0, 225.0)]


def post_positions(study, machine) -> list[tuple[float, float]]:
    """The posts' centres in the machine frame (the cam's bolt holes, turned with the cam), mm."""
    r, angles = study.structure.posts
    cam = cam_angle(machine)
    return [(r * math.cos(math.radians(a) + cam), r * math.sin(math.radians(a) + cam)) for a in angles]
