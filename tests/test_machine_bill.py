"""A machine's bill of materials, assembly STEP, assembly drawing and picture
(``families.machines.bill``, ``assembly``, ``bought``; ``shop.assembly_drawing``) on a small machine
made here: a keyed base plate, a plate on it face down and a claw bolted to the base — the BOM one
to one with the made files, the balloons carrying its items, the STEP one volume per BOM body in
gmsh, and each mismatch named."""

from __future__ import annotations

import io
import json
import math
from types import SimpleNamespace

import ezdxf
import numpy as np
import pytest
import shapely

from transplanter.core.errors import GeometryError, SpecError
from transplanter.families.builder.making import Making, manufacture
from transplanter.families.machines.assembly import (
    BoughtBody,
    MadeBody,
    assembly_order,
    check_documents,
    machine_documents,
)
from transplanter.families.machines.bill import bom_from_csv, machine_bom, made_files, made_records
from transplanter.families.machines.bought import keys, screws
from transplanter.families.machines.record import obstacle_file
from transplanter.machine.arm_parts import CLEARANCE_M4, TAP_DRILL_M4
from transplanter.machine.bodies import Body
from transplanter.shop.assembly_drawing import BALLOONS, PARTS, Outline, _seen
from transplanter.shop.assembly_step import Solid
from transplanter.shop.catalogue import bearing
from transplanter.shop.export import json_bytes
from transplanter.shop.solids import Features

pytest.importorskip("gmsh")

BOLTS = ((40.0, -5.0), (40.0, 5.0))


class Still:
    """A link standing at (x, y) turned by ``angle``."""

    def __init__(self, x=0.0, y=0.0, angle=0.0):
        self.at = (x, y, angle)

    def pose(self, theta):
        z = np.zeros_like(np.asarray(theta, dtype=float))
        return tuple(z + v for v in self.at)


@pytest.fixture(scope="module")
def machine():
    """The files of a small family and its bodies: ``m.base`` (keyed Ø12 bore, two M4 tapped holes),
    ``m.plate`` (make 2: one behind the base, one face down in front of the claw), ``m.claw``
    bolted on the base, a drawing not to cut and an obstacle."""
    files: dict[str, bytes] = {}
    results = {}
    plate = shapely.Polygon([(-15, -15), (55, -15), (55, 15), (-15, 15)])
    claw = shapely.Polygon([(30, -12), (70, -12), (70, 12), (30, 12)])
    for stem, section, features, making in (
        ("m.base", plate, Features(bore=12.0, holes=tuple((x, y, TAP_DRILL_M4) for x, y in BOLTS)), (8.0, 1)),
        ("m.plate", plate, Features(bore=12.0), (8.0, 2)),
        ("m.claw", claw, Features(holes=tuple((x, y, CLEARANCE_M4) for x, y in BOLTS)), (6.0, 1)),
        ("m.sketch", claw, Features(), (6.0, 0)),
    ):
        made = Making(making[0], features, quantity=making[1], material="S235JR", step=stem != "m.sketch")
        res, shop, _ = manufacture(stem, section, shapely.Polygon(), made, (), str)
        results[stem.split(".")[1]] = res
        files.update(shop)
    # a turned shaft, made and drawn elsewhere: its record and its files (their bytes are its own study's)
    shaft = Solid.rod(12.0, 40.0)
    results["shaft"] = {"stem": "m.shaft", "material": "C45", "quantity": 1, "solid_volume_mm3": shaft.volume}
    results["shaft"].update({"dxf_R2000": {}, "stl": {}, "step": {}})
    files.update({f"m.shaft{ext}": b"" for ext in (".dxf", ".stl", ".step")})
    files["m.parts.json"] = json_bytes({"results": {k: v for k, v in results.items() if k != "plate"}})
    files.update(obstacle_file("m", "soil", shapely.box(-100, -100, 100, -60), (0.0, 40.0)))
    bodies = [
        Body("plate_back", plate, (0.0, 8.0), "turning", "m.plate.dxf"),
        Body("base", plate, (9.0, 17.0), "turning", "m.base.dxf"),
        Body("claw", claw, (17.0, 23.0), "turning", "m.claw.dxf"),
        Body("plate_front", plate, (24.0, 32.0), "other", "m.plate.dxf", mirrored=True),
        Body("soil", shapely.box(-100, -100, 100, -60), (0.0, 40.0), "fixed", "m.soil.obstacle.dxf"),
    ]
    links = {"turning": Still(), "other": Still(10.0, 0.0, math.radians(90)), "fixed": Still()}
    by = {b.name: b for b in bodies}
    bought = [
        *keys(bodies, files),
        *screws(by["claw"], by["base"], files),
        # placed as machine.hardware.Fitted places a catalogue part: at its (mounted) link's origin
        SimpleNamespace(name="bearing", part=bearing("6001"), link="turning", z=-9.0, flip=False),
    ]
    own = (results["plate"],)  # a part the machine study makes itself: its record handed in
    made = (MadeBody("shaft", "m.shaft", shaft, "turning", z=-1.0),)
    record, out = machine_documents("m.machine", bodies, links, {}, files, bought, own, made=made)
    return files, bodies, links, [BoughtBody.like(b) for b in bought], own, made, record, out


def test_the_bought_parts_are_read_from_the_drawings(machine):
    _, _, _, bought, *_ = machine
    by = {b.name: b for b in bought}
    assert sorted(by) == ["bearing", "key_base", "key_plate_back", "key_plate_front", "screw_claw_1", "screw_claw_2"]
    key = by["key_base"].part
    assert by["key_base"].designation == "DIN 6885 A 4x4x8" and by["key_base"].y == pytest.approx(6.0 - key.t1)
    # face down: the keyway points along -y of the link, the key turned half a turn
    assert by["key_plate_front"].y == pytest.approx(-(6.0 - key.t1)) and by["key_plate_front"].angle == math.pi
    # the claw in front of the base: each screw put in from the front, its head on the claw's face,
    # 6 mm grip + 1.5 d engaged <= 12 <= 6 + 8 mm of thread
    found = {(b.designation, round(b.x, 9), round(b.y, 9), b.z, b.flip) for b in bought if b.name.startswith("screw")}
    assert found == {("ISO 4762 M4x12", 40.0, -5.0, 23.0, True), ("ISO 4762 M4x12", 40.0, 5.0, 23.0, True)}
    assert by["bearing"].designation == "6001-2Z"


def test_the_bill_is_one_to_one_with_the_made_files(machine):
    files, _, _, bought, own, _, record, out = machine
    bom = bom_from_csv(out["m.machine.bom.csv"])
    made = {i.name: i for i in bom.items if i.made}
    assert sorted(made) == ["m.base", "m.claw", "m.plate", "m.shaft"] and made["m.plate"].quantity == 2
    assert made["m.base"].files == ("m.base.dxf", "m.base.step", "m.base.stl")
    assert sorted(i.designation for i in bom.items if not i.made) == [
        "6001-2Z", "DIN 6885 A 4x4x8", "ISO 4762 M4x12",
    ]  # fmt: skip
    assert {i.designation: i.quantity for i in bom.items}["DIN 6885 A 4x4x8"] == 3
    table = record["bill_of_materials"]
    assert table["items"] == 7 and table["made_parts"] == 5 and table["bought_parts"] == 6
    # made parts by name, then bought ones by standard and designation
    assert [(r[0], r[1]) for r in table["table"]["rows"]] == [
        ("1", "m.base"), ("2", "m.claw"), ("3", "m.plate"), ("4", "m.shaft"),
        ("5", "parallel key"), ("6", "deep groove ball bearing"), ("7", "socket head cap screw"),
    ]  # fmt: skip
    # the drawing not to cut, the obstacle and the machine's own documents are not made files
    records = made_records(files, own)
    assert "m.sketch.dxf" not in made_files(files, records) and records["m.sketch"]["quantity"] == 0
    assert made_files([*files, *out], records) == sorted(
        made["m.base"].files + made["m.claw"].files + made["m.plate"].files + made["m.shaft"].files
    )
    # a made file no record accounts for, or a made part's file gone: named
    with pytest.raises(SpecError, match="m.extra.step is in no item"):
        machine_bom("m.machine", [*files, "m.extra.step"], records, [])
    with pytest.raises(SpecError, match="m.claw.stl is missing"):
        machine_bom("m.machine", [f for f in files if f != "m.claw.stl"], records, [])
    assert bom_from_csv(out["m.machine.bom.csv"]).csv() == out["m.machine.bom.csv"]


def test_the_assembly_step_has_one_volume_per_bom_body_in_gmsh(machine):
    files, bodies, links, bought, _, made, record, out = machine
    assert record["assembly_step"]["bodies"] == 11 and record["assembly_step"]["parts"] == 7
    assert record["assembly_step"]["made_volume_vs_record_rel"] < 1e-4  # the arcs within 0.55 µm all round
    shop = {**files, **out}
    results, problems = check_documents("m.machine", bodies, links, {}, shop, bought, ("ocp", "gmsh"), made)
    assert problems == []
    checked = results["m.machine.assembly.step"]
    bom = bom_from_csv(out["m.machine.bom.csv"])
    assert checked["gmsh"]["volumes"] == checked["ocp"]["volumes"] == sum(i.quantity for i in bom.items) == 11
    # a BOM that lost an item no longer matches the files or the assembly
    lines = out["m.machine.bom.csv"].decode().splitlines(keepends=True)
    cut = "".join(line for line in lines if not line.startswith("3,")).encode()
    _, problems = check_documents("m.machine", bodies, links, {}, {**shop, "m.machine.bom.csv": cut}, bought, made=made)
    assert any("m.plate" in p for p in problems)


def test_the_drawing_balloons_every_item_and_cuts_nothing(machine):
    *_, record, out = machine
    data = out["m.machine.assembly.dxf"]
    doc = ezdxf.read(io.StringIO(data.decode()))
    assert doc.dxfversion == "AC1015"  # R2000
    msp = doc.modelspace()
    assert not [e for e in msp if e.dxf.layer == "CUT"]
    numbers = sorted(int(t.dxf.text) for t in msp.query("TEXT") if t.dxf.layer == BALLOONS)
    assert numbers == [1, 2, 3, 4, 5, 6, 7] == list(range(1, record["bill_of_materials"]["items"] + 1))
    assert len([c for c in msp.query("CIRCLE") if c.dxf.layer == BALLOONS]) == 2 * 7  # balloon and dot
    on = {
        layer: len(msp.query("LWPOLYLINE").filter(lambda e, x=layer: e.dxf.layer == x)) for layer in (PARTS, "BOUGHT")
    }
    # two plates (outline, bore), the base (and 2 tapped holes), the claw (outline, 2 holes), the
    # shaft's end; 3 keys, 2 screw heads and the bearing's ring (its outline and bore), as seen from the front
    assert on == {PARTS: 2 + 2 + 4 + 3 + 1, "BOUGHT": 3 + 2 + 2}
    text = " ".join(t.dxf.text for t in msp.query("TEXT"))
    # back to front: the shaft with the bearing behind everything, then each plane with its keys and screws
    assert "1. z -1..39 mm: item 4 m.shaft; item 6 6001-2Z" in text
    assert "2. z 0..8 mm: item 3 m.plate; item 5 DIN 6885 A 4x4x8" in text
    assert "ISO 4762 M4x12 x 2" in text
    assert json.loads(json.dumps(record))["assembly_drawing"]["balloons"] == 7
    assert out["m.machine.assembly.png"][:8] == b"\x89PNG\r\n\x1a\n"


def test_the_assembly_order_goes_back_to_front():
    order = assembly_order(
        [((10.0, 20.0), "item 2 b", True), ((0.0, 10.0), "item 1 a", True), ((12.0, 14.0), "item 5 key", False)]
        + [((21.0, 25.0), "item 6 screw", False)] * 2
    )
    assert order == ("z 0..10 mm: item 1 a", "z 10..20 mm: item 2 b; item 5 key; item 6 screw x 2")


def test_an_item_with_fewer_bodies_than_its_quantity_fails(machine):
    files, bodies, links, bought, own, made, _, _ = machine
    without = [b for b in bodies if b.name != "plate_front"]
    with pytest.raises(GeometryError, match=r"item 3 \(m.plate\): 1 bodies, quantity 2"):
        machine_documents(
            "m.machine", without, links, {}, files, [b for b in bought if b.name != "key_plate_front"], own, made=made
        )


def test_what_the_drawing_shows_of_a_body_is_its_section_less_every_body_above_it():
    """The drawing's covers are gathered level by level from the top (issue 46): what each body
    shows is its section less the union of every body higher in z, whatever their order."""

    def square(x, y, size):
        v = np.array([[x, y, 0.0], [x + size, y, 0.0], [x + size, y + size, 0.0], [x, y + size, 0.0]])
        return ((v, False),)

    rng = np.random.default_rng(7)
    zs = [(0.0, 5.0), (6.0, 9.0), (6.0, 9.0), (10.0, 12.0), (2.0, 14.0), (0.0, 5.0)]
    outlines = [
        Outline(f"b{k}", k + 1, square(*rng.uniform(0.0, 20.0, 2), rng.uniform(5.0, 25.0)), z) for k, z in enumerate(zs)
    ]
    seen = _seen(outlines)
    for o in outlines:
        above = [p.section for p in outlines if sum(p.z) > sum(o.z)]
        want = o.section.difference(shapely.union_all(above)) if above else o.section
        assert seen[o.name].symmetric_difference(want).area < 1e-9, o.name
    assert seen["b3"].equals(outlines[3].section)  # the highest (z 10..12) is seen whole
