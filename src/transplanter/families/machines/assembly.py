"""A machine as a shop assembles it: its bill of materials, its assembly STEP, its assembly
drawing with balloons and the assembly order, and a picture — from the bodies the judge re-read
and posed, the parts the machine buys, and the records of its family's made parts.

:func:`machine_documents` is what a machine study calls once its bodies are judged:

* the bill of materials (:func:`~transplanter.families.machines.bill.machine_bom`): every made
  file of the family one to one with a made item, the :class:`BoughtBody` parts counted by
  designation; ``<machine>.bom.csv`` and the record's ``bill_of_materials`` table;
* ``<machine>.assembly.step`` (:mod:`transplanter.shop.assembly_step`): every body but the
  obstacles, at the start pose — a made body as its DXF's lines and arcs extruded across its
  layer (a body mounted face down turned over), a bought body as the simple solid of its
  catalogue part — named ``"<item> <body>"``, an occurrence of the product ``"<item> <part>"``;
  each solid checked as written, and each made body's volume within what the one-sided arc fit
  takes (``ARC_FIT_MM`` × its perimeter × its width) of the made part's solid volume as recorded;
  :func:`check_documents` re-reads the file with OCP (one volume per body, of its exact volume,
  where its placement puts it) and the bill against the made files, as ``transplanter check`` finds
  them;
* ``<machine>.assembly.dxf`` (:mod:`transplanter.shop.assembly_drawing`): the bodies seen from the
  front, a balloon on each item, the parts list and the assembly order;
* ``<machine>.assembly.png`` (and ``.svg``): the same view with its balloons, for the report and
  the README.

A bought part drawn for the judge (``.bought.dxf``, such as seed 002's roller) is placed by the
:class:`BoughtBody` of the same name, as its catalogue solid (anything that places a catalogue part
on a link, such as :class:`transplanter.machine.hardware.Fitted`, is taken as one:
:meth:`BoughtBody.like`); a made part that is not a section the judge re-reads from a DXF — a
turned shaft — is placed by its own solid (:class:`MadeBody`), and a judged body of its name by
it. The **assembly order** (unless the study states one) goes from the back of the machine to the
front: one step per plane of made bodies (their z-range), with the bought parts that sit in that
plane, or nearest it.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass

import numpy as np

from transplanter.core.errors import ExportError, GeometryError, SpecError
from transplanter.core.precision import significant
from transplanter.core.tolerances import DXF_ARC_TOLERANCE_MM, DXF_INSET_MM
from transplanter.families.builder.workers import Beside
from transplanter.families.machines.bill import bom_from_csv, bom_record, machine_bom, made_files, made_records
from transplanter.families.machines.record import BOUGHT, OBSTACLE, outline_layer, start_assembly, start_pose
from transplanter.report.machine_picture import assembly_picture
from transplanter.shop import assembly_drawing, assembly_read, assembly_step, catalogue, formats
from transplanter.shop.bom import Bom, BoughtPart

__all__ = [
    "ARC_FIT_MM",
    "BoughtBody",
    "MadeBody",
    "bought_parts",
    "start_pose",
    "assembly_order",
    "AssemblyFiles",
    "machine_documents",
    "documents_and_assembly",
    "step_made",
    "check_documents",
]

#: the DXF's arcs lie at most this far inside the made part's outline, mm (inset + fit tolerance)
ARC_FIT_MM = DXF_INSET_MM + DXF_ARC_TOLERANCE_MM


@dataclass(frozen=True)
class BoughtBody:
    """A bought part placed in the machine: its body name, the catalogue part
    (:mod:`transplanter.shop.catalogue`), the link that carries it and where it sits in that
    link's frame — ``(x, y)`` mm and ``angle`` rad in the plane, ``z`` mm across the machine where
    its own z = 0 goes, ``flip``: its own +z pointing back (a screw put in from the front)."""

    name: str
    part: object
    link: str
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    angle: float = 0.0
    flip: bool = False

    @property
    def designation(self) -> str:
        """What a shop orders: a catalogue bearing row is bought shielded (``-2Z``) where there is one."""
        shielded = getattr(self.part, "designation_2z", None)
        return shielded or self.part.designation

    @property
    def solid(self) -> assembly_step.Solid:
        return assembly_step.solid_of(self.part)

    def bought_part(self, quantity: int) -> BoughtPart:
        p = self.part
        # a catalogue bearing row (not chosen for a load case) has no name of its own
        name = "deep groove ball bearing" if isinstance(p, catalogue.Bearing) else p.name
        return BoughtPart(self.designation, p.standard, quantity, float(p.mass_kg), name)

    def key(self) -> str:
        """The bill of materials' key of its item (:attr:`transplanter.shop.bom.Item.key`)."""
        return f"bought:{self.part.standard}:{self.designation}"

    @classmethod
    def like(cls, fitted) -> BoughtBody:
        """The bought body of anything that places a catalogue part on a link the same way — a
        ``name``, ``part``, ``link``, ``z`` and ``flip``, and ``x``, ``y``, ``angle`` if it has them
        (0 otherwise; :class:`transplanter.machine.hardware.Fitted` sits at a mounted link's origin)."""
        if isinstance(fitted, cls):
            return fitted
        where = {k: float(getattr(fitted, k, 0.0)) for k in ("x", "y", "angle")}
        return cls(fitted.name, fitted.part, fitted.link, z=float(fitted.z), flip=bool(fitted.flip), **where)


@dataclass(frozen=True)
class MadeBody:
    """A made part placed in the machine by its own solid, not as a section the judge re-read
    from a DXF (a turned shaft, a tube): its body name, its files' ``stem`` (its bill of materials
    item), its :class:`~transplanter.shop.assembly_step.Solid` in its own frame, the link that
    carries it and where it sits in that link's frame, as a :class:`BoughtBody`. A judged body of
    the same name is placed by this instead of by its drawing."""

    name: str
    stem: str
    solid: assembly_step.Solid
    link: str
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    angle: float = 0.0
    flip: bool = False


def bought_parts(bodies: list[BoughtBody]) -> list[BoughtPart]:
    """The bought parts of ``bodies``, one per designation, counted."""
    count: dict[str, list[BoughtBody]] = {}
    for b in bodies:
        count.setdefault(b.key(), []).append(b)
    return [group[0].bought_part(len(group)) for _, group in sorted(count.items())]


def _compose(pose, b: BoughtBody | MadeBody) -> tuple[np.ndarray, tuple[float, float, float]]:
    """A bought body's 4×4 placement in the machine and its plan pose (x, y, angle)."""
    x0, y0, a0 = pose
    c, s = math.cos(a0), math.sin(a0)
    x, y = x0 + c * b.x - s * b.y, y0 + s * b.x + c * b.y
    return assembly_step.frame(x, y, b.z, a0 + b.angle, b.flip), (x, y, a0 + b.angle)


def _z_range(solid: assembly_step.Solid, z: float, flip: bool) -> tuple[float, float]:
    lo = min(s.z0 for s in solid.slabs)
    hi = max(s.z0 + s.width for s in solid.slabs)
    return (z - hi, z - lo) if flip else (z + lo, z + hi)


def _off(z: float, plane: tuple[float, float]) -> float:
    """How far ``z`` lies outside the z-range ``plane`` (0 inside it), mm."""
    return max(0.0, plane[0] - z, z - plane[1])


def assembly_order(steps: list[tuple[tuple[float, float], str, bool]]) -> tuple[str, ...]:
    """The assembly order, back to front: ``steps`` are ``(z-range, what, made)`` one per body; one
    step per z-range of made bodies (``what`` counted: ``x 3``), the bought ones joining the step
    whose range holds their middle (the narrowest, or the nearest)."""
    planes = sorted({z for z, _, made in steps if made})
    if not planes:
        raise SpecError("an assembly order needs at least one made body")
    into: dict[tuple[float, float], dict[str, int]] = {p: {} for p in planes}
    for z, what, made in sorted(steps, key=lambda s: (not s[2], s[0], s[1])):
        if made:
            near = z
        else:
            mid = sum(z) / 2
            near = min(planes, key=lambda p: (_off(mid, p), p[1] - p[0], p))  # the narrowest plane holding it
        into[near][what] = into[near].get(what, 0) + 1
    return tuple(
        f"z {p[0]:g}..{p[1]:g} mm: " + "; ".join(w + (f" x {n}" if n > 1 else "") for w, n in into[p].items())
        for p in planes
    )


class AssemblyFiles:
    """A machine's two largest files, its assembly 3MF
    (:func:`~transplanter.families.machines.record.start_assembly`: written, re-read and checked
    for overlaps) and its assembly STEP (:func:`~transplanter.shop.assembly_step.write_checked`),
    each made in a process of its own forked when this block is entered — before the machine is
    posed and judged, while the part's process holds little — and handed its bodies once they are
    known. Issue 46: the 3MF's re-read with trimesh and its overlap check (~210 MB for seed 002's)
    and OpenCASCADE's model of the assembly and its text (~230 MB) no longer stack on what the
    judge and the documents hold in one process, nor on each other: seed 002's machine built in
    one process peaked at 717 MB in the build, its three now at 537 MB at most. A
    :class:`~transplanter.families.builder.workers.Beside` each: where no process can be forked,
    each file is made here when its result is asked, the same bytes."""

    def __enter__(self) -> AssemblyFiles:
        with contextlib.ExitStack() as stack:
            self.threemf = stack.enter_context(Beside(_start_assembly_received, inbox=True))
            self.step = stack.enter_context(Beside(_step_received, inbox=True))
            self._stack = stack.pop_all()
        return self

    def __exit__(self, *exc) -> None:
        self._stack.close()  # (a process not asked for its file — the part failed — is stopped)

    def start_assembly(self, name: str, bodies, links, at: dict) -> None:
        """:func:`~transplanter.families.machines.record.start_assembly` of ``bodies`` (posed by
        ``links`` at the start, or ``at[link]``) begun in its process (:meth:`start_assembly_made`)."""
        poses = {b.link: start_pose(b.link, links, at) for b in bodies}
        self.threemf.send((name, list(bodies), poses))

    def start_assembly_made(self) -> tuple[dict, dict[str, bytes]]:
        """The 3MF's record and file (waiting for its process)."""
        return self.threemf.result()


def _start_assembly_received(receive) -> tuple[dict, dict[str, bytes]]:
    name, bodies, poses = receive()
    return start_assembly(name, bodies, {}, poses)


def _step_received(receive) -> tuple[bytes, dict]:
    name, placed = receive()
    return assembly_step.write_checked(name, placed)


def machine_documents(*args, **kwargs) -> tuple[dict, dict[str, bytes]]:
    """The bill of materials, assembly STEP, assembly drawing and picture of a machine: the record
    and the files of :func:`documents_and_assembly` (its arguments)."""
    record, out, _, _ = documents_and_assembly(*args, **kwargs)
    return record, out


def documents_and_assembly(
    name: str,
    bodies,
    links,
    at: dict,
    files: dict[str, bytes],
    bought: list[BoughtBody],
    own: tuple[dict, ...] = (),
    order: tuple[str, ...] | None = None,
    made: tuple[MadeBody, ...] = (),
    step: Beside | None = None,
) -> tuple[dict, dict[str, bytes], Bom, list[assembly_step.Placed]]:
    """The bill of materials, assembly STEP, assembly drawing and picture of the machine ``name``
    (module docstring) from its judged ``bodies`` (posed by ``links``, or ``at[link]`` at the
    start), the family's ``files``, the ``bought`` bodies (:meth:`BoughtBody.like`), the ``made``
    bodies placed by their own solids and the records ``own`` of the parts the study makes itself
    (their results, each with its ``stem``). Returns the record (``bill_of_materials``,
    ``assembly_step``, ``assembly_drawing``), the files, and the bill of materials and the
    assembly's placed bodies they were made from (what the machine's mass properties are read
    from: :mod:`~transplanter.families.machines.loads`). ``step``: the process the STEP is written
    in (:attr:`AssemblyFiles.step`), handed its bodies here and asked for the file by the caller —
    :func:`step_made` puts it into the record and the files once the caller's own work beside it is
    done (the machine's loads) — else it is written here, once the drawing and the picture are made."""
    bought = [BoughtBody.like(b) for b in bought]
    records = made_records(files, own)
    bom = machine_bom(name, files, records, bought_parts(bought))
    record, out = {}, {}
    record["bill_of_materials"], more = bom_record(name, bom)
    out.update(more)
    placed, outlines, steps, fit = _placed(bom, records, bodies, links, at, files, bought, made)
    _one_body_each(name, bom, placed)
    if step is not None:
        step.send((f"{name}.assembly", placed))
    order = order if order is not None else assembly_order(steps)
    head = ["item", "qty", "name", "designation or material", "mass each"]
    rows = [[r[0], r[2], r[1], r[6] or r[4], f"{r[8]} kg"] for r in bom.rows()[1:]]
    notes = (f"balloons: the item numbers of {name}.bom.csv; z across the machine, from its back (mm)",)
    out[f"{name}.assembly.dxf"] = assembly_drawing.drawing_bytes(
        f"{name}.assembly", outlines, [head, *rows], order, notes
    )
    _, shown = assembly_drawing.layout(outlines)
    title = f"{name}: assembled at the start (balloons: the BOM's items)"
    out.update(assembly_picture(outlines, shown, title, f"{name}.assembly"))
    record["assembly_drawing"] = {
        "file": f"{name}.assembly.dxf",
        "picture": f"{name}.assembly.png",
        "balloons": len(shown),
        "order": list(order),
    }
    record["assembly_step"] = {"file": f"{name}.assembly.step", "made_volume_vs_record_rel": significant(fit)}
    if step is None:
        step_made(None, name, record, out, placed)
    return record, out, bom, placed


def step_made(step: Beside | None, name: str, record: dict, files: dict[str, bytes], placed=None) -> None:
    """The assembly STEP of :func:`documents_and_assembly`'s ``record`` put into it and into
    ``files``: from ``step``'s process (waiting for it), or written here from ``placed``."""
    if step is None and placed is None:
        raise ValueError("step_made: no process to ask for the assembly STEP and no bodies to write it from")
    data, written = step.result() if step is not None else assembly_step.write_checked(f"{name}.assembly", placed)
    record["assembly_step"].update(written)
    files[f"{name}.assembly.step"] = data


def check_documents(
    name: str,
    bodies,
    links,
    at: dict,
    files: dict[str, bytes],
    bought: list[BoughtBody],
    readers=("ocp",),
    made: tuple[MadeBody, ...] = (),
) -> tuple[dict, list[str]]:
    """The machine's bill of materials and assembly STEP as found: ``<name>.bom.csv`` one to one
    with the made files among ``files``, and ``<name>.assembly.step`` re-read (``readers``:
    :func:`~transplanter.shop.assembly_read.verify`) against the bodies placed again from
    ``bodies``, ``links``, ``at``, ``bought`` and ``made`` with the CSV's item numbers. Returns the
    results and the problems."""
    bought = [BoughtBody.like(b) for b in bought]
    results: dict = {}
    problems: list[str] = []
    try:
        bom = bom_from_csv(files[f"{name}.bom.csv"])
        records = made_records(files)
        found = bom.problems(made_files(files, records))
        problems += [f"{name}.bom.csv: {p}" for p in found]
        placed = _placed(bom, records, bodies, links, at, files, bought, made, against_records=False)[0]
        _one_body_each(name, bom, placed)
        results[f"{name}.assembly.step"] = assembly_read.verify(files[f"{name}.assembly.step"], placed, readers)
    except (KeyError, SpecError, GeometryError, ExportError) as exc:
        problems.append(f"{name}: the bill of materials or the assembly STEP: {exc}")
    return results, problems


def _one_body_each(name: str, bom: Bom, placed: list[assembly_step.Placed]) -> None:
    """Every item of the bill of materials is as many bodies of the assembly as its quantity."""
    bodies: dict[int, int] = {}
    for p in placed:
        bodies[p.item] = bodies.get(p.item, 0) + 1
    wrong = [f"item {i.item} ({i.name}): {bodies.get(i.item, 0)} bodies, quantity {i.quantity}" for i in bom.items]
    wrong = [w for w, i in zip(wrong, bom.items, strict=True) if bodies.get(i.item, 0) != i.quantity]
    if wrong:
        raise GeometryError(f"{name}: the assembly and the bill of materials disagree: " + "; ".join(wrong))


def _made(b, item, record: dict | None, files: dict[str, bytes], solids: dict, pose) -> tuple:
    """A made body's placement, outline and how far its arcs' volume is from its recorded solid
    volume, relative (GeometryError past what the arc fit allows; 0 without a ``record``)."""
    stem = b.dxf.removesuffix(".dxf")
    contours = formats.DXF.arcs(files[b.dxf], layer=outline_layer(b.dxf))
    width = b.z[1] - b.z[0]
    excess = 0.0
    if stem not in solids:
        solids[stem] = assembly_step.Solid.prism(contours, width)
    if record is not None:
        arcs, made = solids[stem].volume, float(record["solid_volume_mm3"])
        allowed = b.section.length * ARC_FIT_MM * width * 1.01  # the arcs' one-sided inset, all round
        excess = abs(arcs - made) / made
        if abs(arcs - made) > allowed:
            raise GeometryError(
                f"body {b.name}: its DXF's arcs enclose {arcs:.6f} mm3 across its layer, its part's solid "
                f"{made:.6f} mm3 ({stem}'s record): more apart than the arc fit allows ({allowed:.3g} mm3)"
            )
    x, y, a = pose
    flip = bool(b.mirrored)  # face down: the same solid turned over about its x-axis
    at = assembly_step.frame(x, y, b.z[1] if flip else b.z[0], a, flip)
    placed = assembly_step.Placed(b.name, stem, item.item, solids[stem], at)
    outline = assembly_drawing.Outline(b.name, item.item, assembly_drawing.placed(contours, x, y, a, flip), tuple(b.z))
    return placed, outline, excess


def _placed(bom: Bom, records: dict, bodies, links, at, files, bought, made=(), against_records=True):
    """The assembly's bodies (:class:`~transplanter.shop.assembly_step.Placed`), the drawing's
    outlines, the assembly steps and the largest relative difference of a made body's volume from
    its part's record (:func:`_made`; ``against_records``: each compared)."""
    items = {i.key: i for i in bom.items}
    by_name = {b.name: b for b in bought}
    if len(by_name) != len(bought):
        raise SpecError("two bought bodies share a name")
    placed, outlines, steps = [], [], []
    solids: dict[str, assembly_step.Solid] = {}
    worst = 0.0
    own = {m.name for m in made}
    for b in bodies:
        if b.dxf.endswith(OBSTACLE) or b.name in own:
            continue
        if b.dxf.endswith(BOUGHT):
            if b.name not in by_name:
                raise SpecError(f"the bought body {b.name} ({b.dxf}) has no catalogue part (BoughtBody)")
            continue
        stem = b.dxf.removesuffix(".dxf")
        item = items.get(f"made:{stem}")
        if item is None:
            raise SpecError(f"body {b.name}: its part {stem} is not a made item of the bill of materials")
        record = records[stem] if against_records else None
        p, o, excess = _made(b, item, record, files, solids, start_pose(b.link, links, at))
        placed.append(p)
        outlines.append(o)
        worst = max(worst, excess)
        steps.append((tuple(b.z), f"item {item.item} {stem}" + (" (face down)" if b.mirrored else ""), True))
    for b in [*made, *bought]:
        is_made = isinstance(b, MadeBody)
        part = b.stem if is_made else b.designation
        item = items.get(f"made:{b.stem}" if is_made else b.key())
        if item is None:
            raise SpecError(f"body {b.name}: {part} is not an item of the bill of materials")
        at_b, (x, y, a) = _compose(start_pose(b.link, links, at), b)
        solid, z = b.solid, _z_range(b.solid, b.z, b.flip)
        placed.append(assembly_step.Placed(b.name, part, item.item, solid, at_b))
        widest = max(solid.slabs, key=lambda s: s.area)  # what the front view shows of it
        shown = assembly_drawing.placed(widest.contours, x, y, a, b.flip)
        outlines.append(assembly_drawing.Outline(b.name, item.item, shown, z, bought=not is_made))
        steps.append((z, f"item {item.item} {part}", is_made))
    return placed, outlines, steps, worst
