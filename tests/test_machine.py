"""The whole seed-004 machine (issue 29): the arms as parts, the machine record a judge re-poses,
the clearances bounded between samples, objectives i and ii on bodies, the animation and the slider
driven in a real headless browser."""

from __future__ import annotations

import csv
import io
import json
import math
import time

import ezdxf
import numpy as np
import pytest
import shapely

from transplanter.core.errors import PartScriptError
from transplanter.families import Family, build_family
from transplanter.families.builder.study import Built, StudyDefaults
from transplanter.machine.bodies import MOTION_POSITIONS
from transplanter.proof.clearance import CLEARANCE_REL_TOL, CLEARANCE_TOL_MM, Posed, closest_approach


def _machine(built, family: str = "planetary_seed004"):
    folder = built / family
    manifest = json.loads((folder / "manifest.json").read_text())
    return folder, manifest["parts"]["machine"]


def _section(data: bytes, layer: str) -> shapely.Polygon:
    """A DXF's contours on ``layer`` (the record states it: CUT for a made part, REFERENCE for an
    obstacle, BOUGHT for a bought part) read with ezdxf alone (bulges flattened to 1 µm): the largest
    the outline, the others holes — the judge's own reader, not the project's. A turned part (layer
    TURN) is the circle of its side view's diameter less its bore (the HIDDEN lines): its envelope."""
    doc = ezdxf.read(io.StringIO(data.decode()))
    if layer == "TURN":
        side = max(
            doc.modelspace().query("LWPOLYLINE[layer=='TURN']"),
            key=lambda e: np.ptp([p[0] for p in e.get_points("xy")]),
        )
        r = max(abs(p[1]) for p in side.get_points("xy"))
        bore = max((abs(e.dxf.start[1]) for e in doc.modelspace().query("LINE[layer=='HIDDEN']")), default=0.0)
        disc = shapely.Point(0.0, 0.0).buffer(r, quad_segs=256)
        return (disc.difference(shapely.Point(0.0, 0.0).buffer(bore, quad_segs=256)) if bore else disc).simplify(
            JUDGE_OUTLINE_MM
        )
    rings = []
    for e in doc.modelspace().query(f"LWPOLYLINE[layer=='{layer}']"):
        rings.append(shapely.Polygon(_flattened(e.get_points("xyb"))))
    rings.sort(key=lambda p: -p.area)
    # to 5 µm: the judge holds the record to 0.05 mm
    return shapely.Polygon(rings[0].exterior, [r.exterior for r in rings[1:]]).simplify(JUDGE_OUTLINE_MM)


#: the judge's outlines are simplified to this, mm
JUDGE_OUTLINE_MM = 0.005


def _flattened(verts, sagitta: float = 0.002) -> np.ndarray:
    """A closed polyline's points, each bulge arc sampled on the arc itself (ezdxf's bulge_to_arc:
    no Bézier in between, which would stand 2.7e-4 of the radius off a large arc)."""
    from ezdxf.math import bulge_to_arc

    verts = list(verts)
    out = []
    for k, (x0, y0, b) in enumerate(verts):
        x1, y1, _ = verts[(k + 1) % len(verts)]
        out.append((x0, y0))
        if b:
            centre, a0, a1, r = bulge_to_arc((x0, y0), (x1, y1), b)
            sweep = (a1 - a0) % (2 * math.pi)
            steps = max(2, math.ceil(sweep / (2 * math.acos(max(-1.0, 1 - sagitta / r)))))
            ang = a0 + sweep * np.arange(1, steps) / steps
            pts = np.stack([centre.x + r * np.cos(ang), centre.y + r * np.sin(ang)], axis=1)
            out.extend(map(tuple, pts[::-1] if b < 0 else pts))
    return np.array(out)


def _relative(pose_a, pose_b) -> tuple[np.ndarray, np.ndarray]:
    """Body a's pose in body b's frame at every column of ``pose_*`` (3 × m arrays of x, y, angle
    deg in the machine): its turn (rad) and its shift (m, 2)."""
    xa, ya, aa = (np.asarray(v, dtype=float) for v in pose_a)
    xb, yb, ab = (np.asarray(v, dtype=float) for v in pose_b)
    turn, b = np.radians(aa - ab), np.radians(ab)
    dx, dy = xa - xb, ya - yb
    return turn, np.stack([np.cos(b) * dx + np.sin(b) * dy, -np.sin(b) * dx + np.cos(b) * dy], axis=1)


def _posed(section, turn: np.ndarray, shift: np.ndarray) -> np.ndarray:
    """``section`` turned by each ``turn`` and moved by each ``shift``: an array of polygons, the
    rotation and the shift applied to all copies' points at once."""
    copies = np.array([section] * len(turn), dtype=object)
    per = len(shapely.get_coordinates(section))

    def move(xy):
        row = np.arange(len(xy)) // per
        c, s = np.cos(turn[row]), np.sin(turn[row])
        return np.stack([c * xy[:, 0] - s * xy[:, 1], s * xy[:, 0] + c * xy[:, 1]], axis=1) + shift[row]

    return shapely.transform(copies, move)


def _relative_many(section, pose_a, pose_b) -> np.ndarray:
    """``section`` (body a) posed in body b's frame at every column of ``pose_*``."""
    return _posed(section, *_relative(pose_a, pose_b))


def _round(section) -> bool:
    """Whether every boundary of ``section`` is a circle about its frame origin (a disc, a ring, a
    bearing's annulus): its vertices' distances from the origin agree to 1 nm on each, and its
    edges' midpoints lie within the judge's outline tolerance of that circle (a square or a hexagon,
    whose corners lie on one circle, is not round). Such a body is the same turned about its
    origin, but for its outline's flattening between the vertices."""
    rings = shapely.get_rings(shapely.get_parts(section))

    def circle(ring) -> bool:
        xy = shapely.get_coordinates(ring)
        r = np.hypot(*xy.T)
        mid = np.hypot(*(0.5 * (xy[1:] + xy[:-1])).T)
        return bool(np.ptp(r) <= 1e-6 and r.max() - mid.min() <= JUDGE_OUTLINE_MM)

    return bool(len(rings)) and all(circle(r) for r in rings)


def _pose_keys(turn: np.ndarray, shift: np.ndarray, a_round: bool, b_round: bool) -> np.ndarray:
    """Body a's pose in body b's frame (:func:`_relative`'s turn and shift) as rows equal wherever
    the two bodies' distance is: its turn and shift; with a round body a its shift alone; with a
    round body b its distance from b's origin and its turn less the shift's direction (the pair
    turned about that origin); with both round that distance alone. Rounded to 1e-9 mm and rad:
    poses merged in rounding move a point by < 1e-6 mm."""
    sx, sy = shift[:, 0], shift[:, 1]
    if b_round:
        keys = [np.hypot(sx, sy)] if a_round else [np.hypot(sx, sy), (turn - np.arctan2(sy, sx)) % (2 * np.pi)]
    else:
        keys = [sx, sy] if a_round else [turn % (2 * np.pi), sx, sy]
    return np.round(np.stack(keys, axis=1), 9)


def test_the_judge_s_poses_merge_only_where_the_distance_is_the_same():
    """The judge measures one pose per key of :func:`_pose_keys`: every pose of a key is at its
    representative's distance (to the flattening of a round outline), and a body that is not round
    keeps a key per turn."""
    rng = np.random.default_rng(29)
    disc = shapely.Point(0.0, 0.0).buffer(5.0, quad_segs=512).difference(shapely.Point(0.0, 0.0).buffer(2.0))
    bar = shapely.box(-3.0, -1.0, 9.0, 2.0)
    assert _round(disc) and not _round(bar) and not _round(shapely.Point(1.0, 0.0).buffer(5.0))
    # corners on one circle are not a circle: a square, a hexagon
    assert not _round(shapely.box(-1.0, -1.0, 1.0, 1.0)) and not _round(shapely.Point(0.0, 0.0).buffer(5.0, 2))
    m = 400  # poses on a small grid, so that many repeat up to a round body's own turn
    pa = [rng.integers(0, 3, m) * 7.0 + 20.0, rng.integers(0, 3, m) * 5.0, rng.integers(0, 4, m) * 30.0]
    pb = [np.zeros(m), np.zeros(m), rng.integers(0, 4, m) * 45.0]
    for a, b in ((disc, bar), (bar, disc), (disc, disc), (bar, bar)):
        d = shapely.distance(b, _relative_many(a, pa, pb))
        _, one, every = np.unique(
            _pose_keys(*_relative(pa, pb), _round(a), _round(b)), axis=0, return_index=True, return_inverse=True
        )
        assert np.abs(d[one][every.ravel()] - d).max() < 1e-4
        assert (
            len(one) < m / 2 if _round(a) or _round(b) else len(one) == len(np.unique(np.stack(pa + pb[2:]), axis=1).T)
        )


def test_the_machine_record_is_a_data_contract(built):
    folder, rec = _machine(built)
    machine = rec["results"]["machine"]
    names = set(machine["bodies"])
    assert {"ring", "carrier", "box", "soil"} | {
        f"{k}_{i}" for k in ("planet", "arm", "needle") for i in (1, 2, 3)
    } < names
    for body in machine["bodies"].values():
        assert (folder / body["dxf"]).is_file() and body["z_mm"][0] < body["z_mm"][1]
    rows = list(csv.DictReader(io.StringIO((folder / machine["motion"]).read_text())))
    assert len(rows) == MOTION_POSITIONS >= 720
    assert {f"{n}.{c}" for n in names for c in ("x_mm", "y_mm", "angle_deg")} | {"driver_deg"} == set(rows[0])
    from PIL import Image

    gif = folder / machine["animation"]
    with Image.open(gif) as im:
        assert gif.stat().st_size <= 2_000_000 and im.n_frames >= 72
    # the arms ship as parts: plate and needle, DXF, STL, STEP, three of each
    for stem in ("machine.arm_plate", "machine.needle"):
        for ext in (".dxf", ".stl", ".step"):
            assert f"{stem}{ext}" in rec["files"]
        assert b"make 3" in (folder / f"{stem}.dxf").read_bytes()
    assert rec["results"]["assembly"]["bodies"] == 11 and rec["results"]["assembly"]["max_overlap_mm3"] <= 1e-6


@pytest.mark.parametrize(("family", "pairs"), [("planetary_seed004", 30), ("potseedling_seed002", 17)])
def test_an_independent_judge_finds_every_stated_clearance(built, family, pairs):
    """Pose the DXF bodies (read with ezdxf; a body the record says is mounted face down mirrored
    about its DXF's x-axis) from the motion CSV: every pair that shares a plane and is neither
    joined nor rigid is in the record, and its stated smallest distance is what the judge finds —
    on the 1440 rows, then between the rows around the closest (poses interpolated) — within
    0.05 mm, never below the stated figure by more than its tolerance; every pair judged on its
    axial gap has the gap its bodies' planes leave, at least the stated minimum."""
    folder, rec = _machine(built, family)
    machine = rec["results"]["machine"]
    bodies = machine["bodies"]
    read: dict = {}  # one reading per file and layer (three planets share a DXF)
    for b in bodies.values():
        if (b["dxf"], b["layer"]) not in read:
            read[b["dxf"], b["layer"]] = _section((folder / b["dxf"]).read_bytes(), b["layer"])
    sections = {n: read[b["dxf"], b["layer"]] for n, b in bodies.items()}
    for n, b in bodies.items():
        if b.get("mirrored"):
            sections[n] = shapely.affinity.scale(sections[n], 1.0, -1.0, origin=(0, 0))
    with open(folder / machine["motion"]) as f:
        cols = next(csv.reader(f))
    table = np.loadtxt(folder / machine["motion"], delimiter=",", skiprows=1)

    def pose(name, rows):
        i = cols.index(f"{name}.x_mm")
        return [table[rows, i + k] for k in range(3)]

    stated = {frozenset(c["bodies"]): c for c in machine["clearances"]}
    joined = {frozenset(j.split(" + ")) for j in machine["joined"]}
    rigid = {frozenset(j.split(" + ")) for j in machine["pairs"]["rigid"]}
    n = len(table)
    names = sorted(bodies)
    judged = axial = 0
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            za, zb = bodies[a]["z_mm"], bodies[b]["z_mm"]
            row = stated.get(frozenset((a, b)))
            if row is not None and row["kind"] == "axial gap":
                gap = max(za[0], zb[0]) - min(za[1], zb[1])
                assert row["figure_mm"] == pytest.approx(gap, abs=1e-9) and gap >= machine["min_axial_gap_mm"] >= 0.5
                axial += 1
                continue
            if row is None or row["kind"] == "joint":
                apart = min(za[1], zb[1]) <= max(za[0], zb[0]) or frozenset((a, b)) in joined | rigid
                assert apart, f"{a} and {b} share a plane but the record leaves them out"
                continue
            small, big = sorted((a, b), key=lambda m: len(shapely.get_coordinates(sections[m])))
            hulls = {m: sections[m].convex_hull for m in (small, big)}
            shapely.prepare([sections[big], hulls[big]])
            rounds = (_round(sections[small]), _round(sections[big]))  # so are their hulls

            def at(rows, f=0.0, shapes=sections, small=small, big=big, rounds=rounds):
                """The distances at rows (+ f of the next, interpolated), measured once per pose
                that differs (a round body's own turn does not count)."""

                def between(now, nxt):  # x, y, then the angle the short way round (deg)
                    step = [w - u for u, w in zip(now, nxt, strict=True)]
                    step[2] = (step[2] + 180.0) % 360.0 - 180.0
                    return [u + f * d for u, d in zip(now, step, strict=True)]

                p1 = between(pose(small, rows % n), pose(small, (rows + 1) % n))
                p2 = between(pose(big, rows % n), pose(big, (rows + 1) % n))
                turn, shift = _relative(p1, p2)  # each pose keyed, then the poses that differ measured
                _, one, every = np.unique(
                    _pose_keys(turn, shift, *rounds), axis=0, return_index=True, return_inverse=True
                )
                return shapely.distance(shapes[big], _posed(shapes[small], turn[one], shift[one]))[every.ravel()]

            def least(rows, f=0.0, at=at, hulls=hulls):
                """The smallest distance at these poses and its first row (``rows`` ascending), as
                measuring them all gives it. The hulls' distance is below the bodies' at every pose
                (but for GEOS's rounding, ~1e-13 mm: 1e-9 of slack), so the poses are measured
                nearest hulls first, and the search stops once no hull is nearer than the least
                found — every pose that may tie it measured, the first of them kept."""
                below = at(rows, f, hulls)
                order = np.argsort(below, kind="stable")
                best, where = math.inf, int(rows[order[0]])
                for start in range(0, len(order), 8):
                    take = order[start : start + 8]
                    take = take[below[take] <= best + 1e-9]
                    if not take.size:
                        break
                    d = at(rows[take], f)
                    first = int(rows[take][d == d.min()].min())
                    if d.min() < best or (d.min() == best and first < where):
                        best, where = float(d.min()), first
                return best, where

            coarse, k = least(np.arange(0, n, 12))
            # between the rows around the closest, poses interpolated — not across the end of the
            # turn: a body on the ring is not back at its start after one carrier turn
            near = np.arange(max(k - 12, 0), min(k + 12, n - 1))
            found = min(coarse, least(np.array([n - 1]))[0], *(least(near, f)[0] for f in (0.0, 0.5)))
            # the true minimum lies in [claim, nearest]: one figure, or a far pair's bracket (found to a
            # share of its margin over its minimum, stated as its lower bound)
            claim, nearest = row["min_mm"], row.get("nearest_measured_mm", row["min_mm"])
            assert row.get("exact", True) == (nearest == claim) and claim <= nearest <= claim + 0.01 * max(
                0.0, nearest - (row.get("minimum_mm") or nearest)
            ) + max(CLEARANCE_TOL_MM, CLEARANCE_REL_TOL * nearest), row
            # + the readers' flattening and the judge's outlines
            tol = max(CLEARANCE_TOL_MM, CLEARANCE_REL_TOL * claim) + 0.002 + 2 * JUDGE_OUTLINE_MM
            assert found >= claim - tol, f"{a}-{b}: the judge finds {found:.4f} mm, the record {claim}"
            if found > 0.05:  # a clearance (not a working overlap) must be found where it is said to be
                assert found - nearest <= 0.05, f"{a}-{b}: the judge finds {found:.4f} mm, the record {nearest}"
            judged += 1
    joints = sum(r["kind"] == "joint" for r in machine["clearances"])
    assert judged >= pairs and judged + axial + joints == len(machine["clearances"])


def test_objectives_i_and_ii_on_bodies_and_why_two_planes(built):
    _, rec = _machine(built)
    res = rec["results"]
    i, ii = (
        res["objectives_on_bodies"]["i arms do not interfere"],
        res["objectives_on_bodies"]["ii arms clear the seedling box"],
    )
    assert i["min_mm"] >= i["limit_mm"] and ii["min_mm"] >= ii["limit_mm"] and res["objectives_on_bodies"]["all_met"]
    assert i["margin_mm"] == pytest.approx(i["min_mm"] - i["limit_mm"], abs=1e-6)
    assert i["needle_lines_mm"] >= 10.0  # the needle-line figure of objective i, as a second column
    # with each planet anywhere in its play the needles come closer, by no more than the turn
    # times both needles' reach, and still keep the clearance
    play = res["machine"]["under_play"]
    reach = 168.0  # mm, a needle's farthest point from its planet's centre
    assert i["min_mm"] - 2 * math.radians(play["turn_deg"]) * reach <= i["under_play_mm"] < i["min_mm"]
    assert i["under_play_mm"] >= i["limit_mm"] and play["below_clearance"] == [] and play["measured"] >= 3
    # in one plane an arm plate meets another arm's needle: the layout needs two planes
    assert res["one_plane"]["min_mm"] == 0.0 and "two planes" in res["one_plane"]["finding"]
    for row in res["machine"]["clearances"]:
        assert row["pass"] and row.get("bound_mm", 0.0) <= row.get("min_mm", 0.0)
        if "working" in row:  # a needle meets its work with its plain bar only (103 mm of it), never its tab
            depth = row["enters_from_tip_mm"]
            assert 10.0 < depth["deepest_from_tip_mm"] <= depth["at_most_mm"] < 103.0


def test_what_holds_and_drives_seed_004(built):
    """Seed 004's structure as the record and the files state it: every shaft supported at both
    ends by bearings or bushes the bill of materials lists, each sized for the stated load, both
    drives at the train's speeds, the frame above the soil by objective x's 20 mm and inside its
    gearbox radius, the needle through the seedling door (clear of its floor and walls), and every
    turned part a drawing with nothing on CUT."""
    folder, rec = _machine(built)
    machine = rec["results"]["machine"]
    structure, joined = machine["structure"], machine["joined"]
    shafts = [n for n in machine["bodies"] if n.startswith("planet_shaft_")] + ["carrier_shaft", "ring_shaft"]
    assert len(shafts) == 5
    for shaft in shafts:  # two supports each: a bearing or a bush joined to it
        held = [j for j in joined if shaft in j.split(" + ")]
        supports = [j for j in held if any(w in j.replace(shaft, "") for w in ("bearing", "bush"))]
        assert len(supports) >= 2, f"{shaft} is held by {held}"
    bom = {
        r["designation"]: int(r["quantity"])
        for r in csv.DictReader(io.StringIO((folder / "machine.bom.csv").read_text()))
    }
    for row in structure["bearings"]:
        assert bom[row["designation"]] == row["count"]
        if "life_h" in row:  # ISO 281 at the stated load and speed, and the static safety
            assert row["life_h"] >= 3000 and row["static_safety"] >= 1.5
            assert row["radial_n"] == structure["loads"]["design_radial_n"] > 0  # the stated load, whole
    speeds = structure["speeds_rpm"]
    ratio = json.loads((folder / "manifest.json").read_text())["parts"]["optimised_train"]["parameters"]
    assert speeds["ring"] == pytest.approx(ratio["speed_ratio_ring_to_carrier"] * speeds["carrier"], rel=1e-9)
    assert structure["drives"]["carrier"]["speed_rpm"] == speeds["carrier"]
    assert structure["drives"]["ring"]["speed_rpm"] == speeds["ring"]
    rows = {frozenset(r["bodies"]): r for r in machine["clearances"]}
    for plate in ("frame_front", "frame_rear"):
        row = rows[frozenset((plate, "soil"))]
        assert row["pass"] and row["minimum_mm"] == 20.0 and row["min_mm"] >= 20.0
    assert structure["plates_mm"]["frame_radius"] <= ratio["gearbox_radius_mm"]
    door = structure["door"]
    for part in ("box_door_back", "box_door_front", "box_wall_back", "box_wall_front"):
        assert door[part]["kind"] == "axial gap" and door[part]["mm"] >= machine["min_axial_gap_mm"]
    assert door["box_floor"]["kind"] == "in-plane" and door["box_floor"]["mm"] >= machine["clearance_required_mm"]
    for k in (1, 2, 3):  # and with the planet anywhere in its play
        assert rows[frozenset((f"needle_{k}", "box_floor"))]["under_play_mm"] >= machine["clearance_required_mm"]
    turned = {b["dxf"] for b in machine["bodies"].values() if b["layer"] == "TURN"}
    made = {r[1]: r[9] for r in rec["results"]["bill_of_materials"]["table"]["rows"] if r[3] == "made"}
    assert len(turned) >= 8
    for name in turned:  # a lathe part: its drawing has nothing for the wire, and it is a made item
        layers = {e.dxf.layer for e in ezdxf.read(io.StringIO((folder / name).read_text())).modelspace()}
        assert "CUT" not in layers and "TURN" in layers and name in made[name.removesuffix(".dxf")]


def test_seed_004_under_load(built):
    """Issue 44 on the build: the drives' power by Newton-Euler and virtual power agree to 1e-6;
    every support is checked at the computed loads (a bearing's L10h at least the structure's life,
    its static safety at least 1.5; a bush within its rating and sliding limit), its load the pin's
    share; the masses are the bill of materials' (every moving body's, the frame's apart); the
    three arms at 120 deg leave the shaking force only its multiples of 3 per carrier turn."""
    folder, rec = _machine(built)
    loads = rec["results"]["loads"]
    assert loads["power_agreement"]["newton_euler_vs_virtual_power_rel"] <= 1e-6
    assert {d["drive"] for d in loads["drives"]} == {"ring motor", "carrier motor"}
    for d in loads["drives"]:  # the needle's work costs more than inertia and weight
        assert abs(d["peak_torque_nm"]) > d["peak_torque_without_work_nm"] > 0
        assert d["rms_torque_nm"] <= abs(d["peak_torque_nm"])
    supports = loads["supports"]
    assert len(supports) == 10 and all(r["pass"] for r in supports)
    for r in supports:
        if "life_h" in r:
            assert r["life_h"] >= r["required_life_h"] == 3000.0 and r["static_safety"] >= 1.5
    bom = {r["name"]: r for r in csv.DictReader(io.StringIO((folder / "machine.bom.csv").read_text()))}
    planet = float(bom["optimised_ring_planet.driven"]["mass_kg"]) + float(bom["machine.arm_plate"]["mass_kg"])
    assert loads["mass"]["planet.1"]["mass_kg"] > planet + float(bom["machine.needle"]["mass_kg"])
    assert loads["mass"]["ring"]["mass_kg"] > float(bom["optimised_ring_planet.driver"]["mass_kg"])
    shaking = loads["shaking"]
    for axis in ("harmonics_x_n", "harmonics_y_n"):
        h = shaking[axis]
        assert max(h[0], h[1], h[3], h[4]) < 0.1 * h[2]
    assert (folder / "machine.loads.png").stat().st_size > 10_000
    # the made teeth under that load: the force at the actual contact is the torque over its lever,
    # so within a few per cent of the pitch-point force's largest; nominal stresses, no allowable
    teeth = loads["teeth"]
    largest = max(m["max_normal_force_n"] for m in loads["meshes"])
    assert 0.9 * largest < teeth["max_force_n"] < 1.1 * largest
    assert 0.0 < teeth["max_root_stress_planet_mpa"]["value"] < teeth["max_contact_stress_mpa"]["value"]
    assert teeth["material"]["allowables"] is None
    assert teeth["material"]["needs_sigma_hlim_mpa_at_least"] == teeth["max_contact_stress_mpa"]["value"]
    # every key and shaft section checked; short of its safety: what the machine carries is a finding
    ks = loads["keys_and_shafts"]
    assert len(ks["keys"]) == 11 and {r["shaft"] for r in ks["shafts"]} >= {"planet_shaft_1", "carrier_shaft"}
    findings = rec["results"]["machine"].get("findings", [])
    if not ks["pass"]:
        cap = ks["needle_force_capacity"]
        assert 0 < cap["n"] < cap["stated_n"] and cap["least_margin_there"] >= 0
        assert any(f"carries {cap['n']:g} N at each needle" in f for f in findings)


def test_seed_002_under_load(built):
    """Seed 002's machine at 60 r/min (its ADAMS speed): Newton-Euler and virtual power agree to
    1e-6, every support passes at the computed loads, and a roller the cam would have to pull is a
    finding naming the return torque a spring on the follower must give."""
    _, rec = _machine(built, "potseedling_seed002")
    loads = rec["results"]["loads"]
    assert loads["power_agreement"]["newton_euler_vs_virtual_power_rel"] <= 1e-6
    assert [d["speed_rpm"] for d in loads["drives"]] == [60.0]
    assert len(loads["meshes"]) == 5 and all(r["pass"] for r in loads["supports"])
    cam = loads["cam"]
    findings = rec["results"]["machine"].get("findings", [])
    leaves = [f for f in findings if "leaves the cam" in f]
    assert cam["stays_on_the_cam"] == (cam["min_n"] >= 0.0) == (not leaves)
    if leaves:
        assert f"{cam['return_torque_needed_nm']:g} N m" in leaves[0]
    # the roller on the cam by Hertz: the profile's least convex radius, from the motion's own
    # curvature, is the swing cam's own record of it; the stress is the closed form at its figures
    hertz = cam["contact_stress"]
    folder = built / "potseedling_seed002"
    made = json.loads((folder / "manifest.json").read_text())["parts"]["swing_cam"]["results"]
    assert hertz["least_convex_profile_radius_mm"] == pytest.approx(made["min_convex_radius_of_curvature_mm"], abs=0.01)
    kappa, r = 1 / 8.0 + 1 / hertz["profile_radius_mm"], 2 * (1 - 0.3**2) / 206_000.0
    closed = math.sqrt(hertz["force_n"] / (math.pi * hertz["width_mm"]) * kappa / r)
    assert 0 < hertz["value_mpa"] == pytest.approx(closed, rel=1e-4) and hertz["force_n"] <= cam["max_n"]
    # the fixed shaft, built into the frame, rated as a cantilever (issue 42): its clamp moment is no
    # more than every load's peak at its distance from the clamp's face, and it passes every limit
    shaft = loads["built_in_shaft"]
    face = shaft["clamp_z_mm"][1]
    bound = sum(
        r["max_radial_n"] * (r["z_mm"] - face)
        for r in loads["supports"]
        if r["joint"] == "carrier 1 on the fixed shaft"
    )
    sun = next(r for r in loads["meshes"] if r["mesh"] == "sun 2 and gear 3")
    bound += sun["max_normal_force_n"] * shaft["gear_from_clamp_mm"]
    assert 0 < shaft["peak_moment_at_clamp_nm"] <= bound * 1e-3 * (1 + 1e-9)
    assert shaft["pass"] and shaft["deflection_at_gear_mm"] <= shaft["deflection_limit_mm"] == 0.127
    # every critical section in front of the frame rated: the ring's groove off its face is the least
    assert shaft["sections_rated"] >= 4 and shaft["least_safe_section"]["kind"] == "groove"
    assert min(shaft["fatigue_safety"], shaft["yield_safety"]) >= shaft["required_safety"]
    assert shaft["seat_pressure_mpa"] <= shaft["seat_pressure_allowable_mpa"] and shaft["slope_at_gear_rad"] <= 5e-4
    assert "built into the frame" in rec["results"]["machine"]["structure"]["shafts"]["main_shaft"]["supports"]


def test_the_readme_shows_the_bill_of_materials_the_build_writes(built):
    """The README's machine section shows seed 004's bill of materials: the table under its marker
    is the build's ``machine.bom.csv`` (item, part, quantity, made or bought, material or
    designation, mass), summed up in its heading."""
    from pathlib import Path

    from transplanter.families.machines.bill import bom_from_csv

    bom = bom_from_csv((built / "planetary_seed004" / "machine.bom.csv").read_bytes())
    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    block = readme.split("<!-- bom: planetary_seed004", 1)[1].split("</details>", 1)[0]
    summary = block.split("<summary>", 1)[1].split("</summary>", 1)[0]
    table = "\n".join(line for line in block.splitlines() if line.startswith("|"))
    want = f"Seed 004's bill of materials ({bom.summary()})"
    assert (summary, table) == (want, bom.markdown()), f"the README's BOM should read:\n{want}\n\n{bom.markdown()}"


def test_a_narrow_approach_between_samples_is_bracketed():
    """A thin blade on a crank sweeps past a pin its tip just misses, between two samples 45°
    apart: the bound finds the pass (0.15 mm) that the samples step over (they see > 5 mm)."""
    blade = shapely.box(0.0, -0.05, 29.75, 0.05)  # 29.75 mm long, 0.1 mm thick, turning about its root
    pin = shapely.Point(30.0, 0.3).buffer(0.1, quad_segs=64)  # its nearest point 29.9 mm out

    def pose(t):
        t = np.asarray(t, dtype=float)
        return np.zeros_like(t), np.zeros_like(t), t + math.pi / 8  # the pass lies between samples

    theta = 2 * math.pi * np.arange(8) / 8
    found = closest_approach(Posed(blade, pose, speed=29.75), Posed(pin, Posed.fixed, speed=0.0), theta)
    near = np.linspace(-0.05, 0.05, 20_001)  # around the pin's direction, 5e-6 rad apart
    truth = min(
        shapely.distance(shapely.affinity.rotate(blade, float(t), origin=(0, 0), use_radians=True), pin) for t in near
    )
    assert found.sampled.min() > 5.0 and 0.14 < truth < 0.16
    assert truth - 1e-6 <= found.distance <= truth + CLEARANCE_TOL_MM
    assert found.bound <= truth and math.cos(found.theta + math.pi / 8) > 0.999


def test_bodies_at_rest_in_their_frame_are_measured_once_and_moving_ones_are_not():
    """A ring turning in a bore, both posed in the bore's frame with speed 0 (the ring's points
    occupy one annulus whatever its angle): one measure, the radial gap; the same ring stated as
    moving (its points' true speed, 0.2 mm/rad) is searched over the cycle and finds the same gap."""

    def annulus(outer, inner):
        disc = shapely.Point(0.0, 0.0).buffer
        return disc(outer, quad_segs=64).difference(disc(inner, quad_segs=64))

    bore, ring = annulus(20.0, 10.5), annulus(10.0, 5.0)

    def turning(t):
        t = np.asarray(t, dtype=float)
        return np.zeros_like(t), np.zeros_like(t), 0.02 * t  # 0.2 mm/rad at the ring's 10 mm

    theta = 2 * math.pi * np.arange(90) / 90
    still = closest_approach(Posed(ring, turning, speed=0.0), Posed(bore, Posed.fixed, speed=0.0), theta)
    moving = closest_approach(Posed(ring, turning, speed=0.2), Posed(bore, Posed.fixed, speed=0.0), theta)
    assert still.evaluations == 1 and moving.evaluations >= len(theta)
    assert abs(still.distance - 0.5) < 1e-3 and abs(moving.distance - still.distance) < CLEARANCE_TOL_MM
    assert np.all(still.sampled == still.distance) and still.bound == still.distance


@pytest.mark.parametrize(
    ("family", "arms"), [("planetary_seed004", ("arm 1: ", "arm 3: ")), ("potseedling_seed002", ("arm: ",))]
)
def test_the_slider_scrubs_the_cycle_in_headless_chromium(built, browser, family, arms):
    """report.html opened from the file in headless Chromium: the machine's slider is moved with
    the keyboard, the canvas changes and the read-out names the angle, each arm's phase and the
    smallest clearance."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    browser.get((built / family / "report.html").as_uri())
    box = browser.find_element(By.CSS_SELECTOR, "div.machine")
    browser.execute_script("arguments[0].scrollIntoView()", box)
    canvas, slider, out = (box.find_element(By.TAG_NAME, t) for t in ("canvas", "input", "output"))
    slider.send_keys(Keys.HOME)
    first_text, first = out.text, canvas.screenshot_as_png
    slider.send_keys(Keys.ARROW_RIGHT * 90)  # 90 key presses, sent at once
    for _ in range(100):  # (each press is handled as it is dispatched; a loaded machine is given 10 s)
        if out.text.startswith("driver 90.0 deg"):
            break
        time.sleep(0.1)
    second_text, second = out.text, canvas.screenshot_as_png
    errors = [e for e in browser.get_log("browser") if e.get("level") == "SEVERE"]
    assert first_text.startswith("driver 0.0 deg") and second_text.startswith("driver 90.0 deg")
    for text in (first_text, second_text):
        assert all(a in text for a in arms) and "smallest clearance" in text
        assert any(p in text for p in ("picking", "conveying", "planting", "return"))
    assert first != second and not errors


class _Uses(StudyDefaults):
    def __init__(self, name, uses=(), payload=""):
        self.name, self.uses, self.payload = name, tuple(uses), payload

    def build(self, out):
        if self.name == "broken":
            raise ValueError("broken on purpose")
        return Built({"kind": "t", "results": {}}, {f"{self.name}.txt": (self.name + self.payload).encode()})

    def build_using(self, out, files):
        return Built(
            {"kind": "t", "results": {"got": sorted(files)}}, {f"{self.name}.txt": b"+".join(sorted(files.values()))}
        )


def test_a_part_is_built_from_the_files_of_the_parts_it_uses(tmp_path):
    fam = Family("uses_demo", "d", (_Uses("a"), _Uses("b", ["a"])))
    manifest = build_family(fam, tmp_path)
    assert manifest["parts"]["b"]["results"]["got"] == ["a.txt"]
    assert (tmp_path / "uses_demo" / "b.txt").read_bytes() == b"a"
    # nothing changed: both kept; the used part changed: the part that uses it is rebuilt too
    again = build_family(Family("uses_demo", "d", (_Uses("a"), _Uses("b", ["a"]))), tmp_path)
    assert again["build"]["kept"] == ["a", "b"]
    changed = build_family(Family("uses_demo", "d", (_Uses("a", payload="!"), _Uses("b", ["a"]))), tmp_path)
    assert sorted(changed["build"]["rebuilt"]) == ["a", "b"]
    assert (tmp_path / "uses_demo" / "b.txt").read_bytes() == b"a!"
    failed = build_family(Family("uses_fail", "d", (_Uses("broken"), _Uses("c", ["broken"]))), tmp_path)
    assert "built from the files of broken, which failed" in failed["parts"]["c"]["error"]
    with pytest.raises(PartScriptError, match="not a part listed before it"):
        Family("uses_order", "d", (_Uses("b", ["a"]), _Uses("a")))


def test_bad_machine_input_is_named():
    from transplanter.core.errors import SpecError
    from transplanter.design.planetary import ArmGeometry
    from transplanter.families import Layers
    from transplanter.machine.arm_parts import arm_parts

    with pytest.raises(SpecError, match=r"layers\.plates = \(34, 26\)"):
        Layers((0, 12), (12, 24), (34, 26), (34, 40))
    arm = ArmGeometry(tip=150.0, knee=80.0, mount=-0.7)
    with pytest.raises(SpecError, match="tab = 500"):
        arm_parts(arm, tab=500.0)
    with pytest.raises(SpecError, match="hub radius = 90"):
        arm_parts(arm, hub=90.0)
    with pytest.raises(PartScriptError, match="uses 'nowhere'"):
        Family("uses_missing", "d", (_Uses("a"), _Uses("b", ["nowhere"])))


def test_the_arm_parts_sit_where_the_train_puts_the_knee_and_the_tip():
    """The plate's knee-boss holes and the needle's point are where seed 004 eqs 9-10 put A and B
    in the planet's frame, and the needle's farthest point along it is B."""
    from transplanter.design.planetary import ArmGeometry
    from transplanter.machine.arm_parts import arm_parts

    arm = ArmGeometry(tip=167.86, knee=69.0, mount=math.radians(-37.93))
    made = arm_parts(arm)
    a = arm.knee * np.array([math.cos(arm.mount + arm.knee_angle), math.sin(arm.mount + arm.knee_angle)])
    b = arm.tip * np.array([math.cos(arm.mount), math.sin(arm.mount)])
    assert np.allclose(made.plate_holes[0][:2], a, atol=1e-9) and np.allclose(made.tip, b, atol=1e-9)
    u = (b - a) / np.linalg.norm(b - a)
    along = shapely.get_coordinates(made.needle) @ u
    assert along.max() == pytest.approx(b @ u, abs=1e-3)  # the point (R0.5, polygonal) ends at B
    assert made.plate.contains(shapely.Point(0, 0)) and made.needle.is_valid and made.plate.is_valid
