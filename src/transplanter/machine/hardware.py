"""What holds and drives a machine's moving parts, as bodies a judge poses and parts a shop makes or
buys: turned parts (shafts, tubes, sleeves), bought parts placed on a link, and frames mounted on a
link at a fixed offset.

* :func:`mounted` — a link rigidly fixed on another at ``(x, y, angle)`` in its frame: a spacer tube
  between two carrier plates, a planet's bearing in the carrier, a screw on a bolt circle. Its
  pose is the frame a body drawn about its own origin is placed by (what the motion table
  records), and :func:`~transplanter.machine.bodies.moving_links` finds it rigid to its base.
* :class:`Turned` — a turned part: a plain cylinder ``outer`` × ``length`` (optionally bored),
  with DIN 6885 keyways (on +y, square-ended, the key's length) and DIN 471 circlip grooves. Its
  solid is exact (:meth:`Turned.solid`: slabs of its sections between feature edges — the
  assembly STEP's :class:`~transplanter.shop.assembly_step.Solid`); its drawing
  (:meth:`Turned.drawing`) is a side view on layer ``TURN`` (nothing on ``CUT``: a lathe, not a
  wire, makes it) with a section through each keyway, the bore on ``HIDDEN``, dimensions in the
  drawing style of :mod:`transplanter.shop.dxf` and the notes (fits, keyways, grooves, material,
  quantity) on ``ANNOTATION``; :func:`read_turned` re-reads the part from that drawing, so a judge
  poses it from the file (:meth:`Turned.section`: its envelope, the outer circle less the bore);
  :meth:`Turned.files` writes DXF, STL and STEP, each verified, and the record a bill of
  materials takes (``stem``, ``material``, ``quantity``, ``solid_volume_mm3``).
* :class:`Fitted` — a bought part of :mod:`transplanter.shop.catalogue` placed on a link: the
  section and z-range a judge measures it by (a bearing, bush, washer or circlip its ring; a
  cap screw its head; a nut its hexagon; a key is inside its hub and shaft and is not judged),
  drawn for the judge by :func:`bought_drawing` (layer ``BOUGHT``, not cut).

All lengths are mm; z runs across the machine, a part's own z from its back end.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass

import ezdxf
import manifold3d
import numpy as np
import shapely

from transplanter.core.errors import GeometryError, SpecError, check_int, finite_positive
from transplanter.core.precision import rounded, significant
from transplanter.core.tolerances import SOLID_VOLUME_REL
from transplanter.machine.bodies import Link
from transplanter.shop import assembly_step, dxf, formats, stl
from transplanter.shop.catalogue import material as catalogue_material
from transplanter.shop.solids import circle_polygon

__all__ = ["TURN", "HIDDEN", "mounted", "Turned", "read_turned", "Fitted", "bought_drawing"]

#: layers of a turned part's drawing: its outline (side view and keyway sections), its bore
TURN, HIDDEN = "TURN", "HIDDEN"
#: arcs are flattened to within this for the STL (mm)
FLATTEN_MM = 1e-3
#: how far below the side view each keyway's section is drawn, in outer diameters
SECTION_BELOW = 1.6


def mounted(link: Link, name: str, x: float, y: float, angle: float = 0.0) -> Link:
    """A frame fixed on ``link`` at ``(x, y)`` mm and ``angle`` rad in its frame, as a link of its
    own named ``name``: it turns as ``link`` does, its origin no faster than ``link``'s origin plus
    the turn rate times its offset."""

    def pose(theta):
        X, Y, A = (np.asarray(v, dtype=float) for v in link.pose(theta))
        c, s = np.cos(A), np.sin(A)
        return X + c * x - s * y, Y + s * x + c * y, A + angle

    return Link(name, pose, link.speed + link.turn_rate * math.hypot(x, y), link.turn_rate, ((link.name, x, y),))


def _keyway_contour(r: float, b: float, t1: float) -> np.ndarray:
    """A shaft's section with a keyway ``b`` wide, ``t1`` deep at +y: bulge vertices, counter-clockwise."""
    w = b / 2
    yc = math.sqrt(r * r - w * w)
    sweep = 2 * math.pi - (math.atan2(yc, -w) - math.atan2(yc, w))
    return np.array([[-w, yc, math.tan(sweep / 4)], [w, yc, 0.0], [w, r - t1, 0.0], [-w, r - t1, 0.0]])


def _circle(r: float, hole: bool = False) -> np.ndarray:
    b = -1.0 if hole else 1.0
    return np.array([[r, 0.0, b], [-r, 0.0, b]])


@dataclass(frozen=True)
class Turned:
    """A turned part (module docstring). ``keyways``: ``(z0, length, width b, depth t1, note)``;
    ``grooves``: ``(z0, width m, diameter d2, note)``; ``fits``: ``(z0, z1, text)`` — a seat's
    fit (e.g. ``fit(10, "k6").text``) over its length; z from the part's back end."""

    name: str
    outer: float
    length: float
    bore: float = 0.0
    keyways: tuple[tuple[float, float, float, float, str], ...] = ()
    grooves: tuple[tuple[float, float, float, str], ...] = ()
    fits: tuple[tuple[float, float, str], ...] = ()
    material: str = "C45"
    quantity: int = 1
    notes: tuple[str, ...] = ()
    #: what the shop does after turning, grooving and milling the keyways (e.g. tapping its ends)
    operations: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        r = finite_positive(f"{self.name}: outer diameter", self.outer) / 2
        finite_positive(f"{self.name}: length", self.length)
        if not 0.0 <= self.bore < self.outer:
            raise SpecError.out_of_range(f"{self.name}: bore", self.bore, f"0 <= bore < outer ({self.outer:g} mm)")
        check_int(f"{self.name}: quantity", self.quantity, 0, 10_000)
        catalogue_material(self.material)
        spans = [(z0, z0 + n) for z0, n, *_ in self.keyways] + [(z0, z0 + m) for z0, m, *_ in self.grooves]
        for z0, z1 in spans:
            if not (-1e-9 <= z0 < z1 <= self.length + 1e-9):
                raise SpecError.out_of_range(f"{self.name}: feature", (z0, z1), f"within 0..{self.length:g} mm")
        for z0, n, b, t1, _ in self.keyways:
            if not (0 < b < self.outer and r - t1 > self.bore / 2):
                raise SpecError.out_of_range(
                    f"{self.name}: keyway depth", t1, f"leaving a wall over the bore {self.bore:g}"
                )
            if any(g0 < z0 + n and z0 < g0 + m for g0, m, *_ in self.grooves):
                raise SpecError(f"{self.name}: a circlip groove crosses the keyway at z {z0:g} mm")
        for _, _, d2, _ in self.grooves:
            if not self.bore < d2 < self.outer:
                raise SpecError.out_of_range(f"{self.name}: groove diameter", d2, f"between bore and {self.outer:g} mm")

    # -- geometry ----------------------------------------------------------------------------

    def section(self) -> shapely.Polygon:
        """Its envelope across the machine: the outer circle less the bore (what a judge measures)."""
        disc = circle_polygon(0.0, 0.0, self.outer / 2)
        return disc.difference(circle_polygon(0.0, 0.0, self.bore / 2)) if self.bore else disc

    def _breaks(self) -> list[float]:
        zs = {0.0, float(self.length)}
        for z0, n, *_ in self.keyways:
            zs |= {z0, z0 + n}
        for z0, m, *_ in self.grooves:
            zs |= {z0, z0 + m}
        return sorted(zs)

    def _at(self, z: float) -> tuple[float, tuple[float, float] | None]:
        """The radius and the keyway ``(b, t1)`` (or None) at ``z``."""
        r = next((d2 / 2 for z0, m, d2, _ in self.grooves if z0 <= z <= z0 + m), self.outer / 2)
        key = next(((b, t1) for z0, n, b, t1, _ in self.keyways if z0 <= z <= z0 + n), None)
        return r, key

    def solid(self) -> assembly_step.Solid:
        """The exact solid: a slab per span between feature edges (the assembly STEP's)."""
        slabs = []
        zs = self._breaks()
        for z0, z1 in zip(zs, zs[1:], strict=False):
            r, key = self._at((z0 + z1) / 2)
            outer = _keyway_contour(self.outer / 2, *key) if key else _circle(r)
            contours = [(outer, False)] + ([(_circle(self.bore / 2, True), True)] if self.bore else [])
            slabs.append(assembly_step.Slab(tuple(contours), z0, z1 - z0))
        return assembly_step.Solid(tuple(slabs))

    def manifold(self):
        """The solid as manifold3d (arcs flattened to ``FLATTEN_MM``), for the STL."""
        out = None
        for slab in self.solid().slabs:
            rings = [dxf.arcs_to_points(v, FLATTEN_MM) for v, _ in slab.contours]
            poly = shapely.Polygon(rings[0], rings[1:])
            piece = manifold3d.Manifold.extrude(
                manifold3d.CrossSection(
                    [np.asarray(poly.exterior.coords)[:-1]] + [np.asarray(h.coords)[:-1] for h in poly.interiors],
                    manifold3d.FillRule.EvenOdd,
                ),
                slab.width,
            ).translate((0.0, 0.0, slab.z0))
            out = piece if out is None else out + piece
        return out

    # -- the drawing -------------------------------------------------------------------------

    def _profile(self) -> np.ndarray:
        """The side view's outline (x along the part, y across it, keyways on +y), counter-clockwise."""
        zs = self._breaks()
        top, bottom = [], []
        for z0, z1 in zip(zs, zs[1:], strict=False):
            r, key = self._at((z0 + z1) / 2)
            up = min(r, self.outer / 2 - key[1]) if key else r
            bottom += [(z0, -r), (z1, -r)]
            top += [(z0, up), (z1, up)]
        ring = shapely.Polygon(bottom + top[::-1]).simplify(0.0)
        return np.asarray(shapely.orient_polygons(ring).exterior.coords)[:-1]

    def drawing(self) -> bytes:
        """The part's drawing, R2000 (module docstring)."""
        r, span = self.outer / 2, max(self.length, self.outer * 3)
        height = dxf.lettering(span)
        with dxf._writing(f"the drawing of {self.name}"):
            doc = dxf._new_doc("R2000")
            for layer, colour in ((TURN, 7), (HIDDEN, 8), ("DIMENSIONS", 5)):
                doc.layers.add(layer, color=colour)
            doc.layers.get(HIDDEN).dxf.linetype = "DASHED" if "DASHED" in doc.linetypes else "CONTINUOUS"
            dxf._add_dimension_style(doc, height)
            msp = doc.modelspace()
            msp.add_lwpolyline(self._profile().tolist(), format="xy", close=True, dxfattribs={"layer": TURN})
            msp.add_line((-0.05 * span, 0.0), (self.length + 0.05 * span, 0.0), dxfattribs={"layer": "ANNOTATION"})
            if self.bore:
                for s in (-1.0, 1.0):
                    msp.add_line(
                        (0.0, s * self.bore / 2), (self.length, s * self.bore / 2), dxfattribs={"layer": HIDDEN}
                    )
            below = -SECTION_BELOW * self.outer - r - 6 * height
            for z0, n, b, t1, _ in self.keyways:  # a section through each keyway, below it
                verts = _keyway_contour(r, b, t1)
                verts[:, 0] += z0 + n / 2
                verts[:, 1] += below
                dxf.add_contour(msp, verts, "R2000", TURN)
                if self.bore:
                    hole = _circle(self.bore / 2, True)
                    hole[:, 0] += z0 + n / 2
                    hole[:, 1] += below
                    dxf.add_contour(msp, hole, "R2000", HIDDEN)
            dims = [((0.0, r), (self.length, r), (0.0, r + 2.5 * height), 0)]  # overall length
            dims.append(((0.0, -r), (0.0, r), (-3 * height, 0.0), 90))  # the outer diameter
            for z0, n, *_ in self.keyways:
                dims.append(((z0, r), (z0 + n, r), (z0, r + 1.2 * height), 0))
            for k, (z0, *_) in enumerate(sorted(self.grooves)):
                dims.append(((0.0, -r), (z0, -r), (0.0, -r - 1.6 * height * (1 + k % 3)), 0))
            for p1, p2, base, angle in dims:
                dim = msp.add_linear_dim(
                    base=base, p1=p1, p2=p2, angle=angle, dimstyle=dxf.DIMSTYLE, dxfattribs={"layer": "DIMENSIONS"}
                )
                if angle == 90:
                    dim.dimension.dxf.text = f"%%c{self.outer:g}"
                dim.render()
            made = f"make {self.quantity}" if self.quantity else "do not make: drawn for reference"
            lines = [
                f"{self.name} (mm): turned part, Ø{self.outer:g}"
                + (f" bored Ø{self.bore:g}" if self.bore else "")
                + f" x {self.length:g} long; outline on layer {TURN} (not a wire-cut part: nothing on CUT)",
                *self.operation_lines(),
                *self.notes,
                *(() if any(n.startswith("timing") for n in self.notes) else (self._timing(),)),
                catalogue_material(self.material).note,
                f"{made}; turned part: unstated diameters and lengths +/-0.1 mm; z from its back end (left here)",
            ]
            for k, line in enumerate(lines):
                msp.add_text(line, dxfattribs={"layer": "ANNOTATION", "height": height}).set_placement(
                    (0.0, below - r - (k + 2) * 1.6 * height)
                )
            return dxf._write(doc)

    def operation_lines(self) -> list[str]:
        """The drawing's operations in order, numbered as a routing sheet: turn (the seats' fits
        under it), the circlip grooves, the keyways, then ``operations``; each feature a line.

        >>> shaft = Turned("s", 10.0, 30.0, grooves=((1.0, 1.1, 9.6, "DIN 471 10x1"),), fits=((5.0, 15.0, "k6"),))
        >>> shaft.operation_lines()
        ['op 10: turn Ø10 x 30', '  z 5..15: k6', 'op 20: turn the circlip grooves', '  z 1..2.1: DIN 471 10x1']
        """
        steps: list[tuple[str, list[str]]] = [
            (
                f"turn Ø{self.outer:g}" + (f", bore Ø{self.bore:g}" if self.bore else "") + f" x {self.length:g}",
                [f"z {a:g}..{b:g}: {text}" for a, b, text in self.fits],
            )
        ]
        if self.grooves:
            grooves = [f"z {z0:g}..{z0 + m:g}: {note}" for z0, m, _, note in sorted(self.grooves)]
            steps.append(("turn the circlip grooves", grooves))
        if self.keyways:
            keys = [f"z {z0:g}..{z0 + n:g}: {note}" for z0, n, _, _, note in sorted(self.keyways)]
            steps.append(("mill the keyways" + (" in line" if len(keys) > 1 else ""), keys))
        steps += [(text, []) for text in self.operations]
        out = []
        for k, (head, items) in enumerate(steps, 1):
            out += [f"op {10 * k}: {head}", *(f"  {item}" for item in items)]
        return out

    def _timing(self) -> str:
        """The timing note a part that states none gets: a round part has no angle to keep; keyways
        are cut in line, the key setting the angle of what the shaft carries."""
        if not self.keyways:
            return "timing: none (round)"
        if len(self.keyways) == 1:
            return "timing: its keyway sets the angle of what it carries"
        return "timing: its keyways in line (the keys set the angles of what it carries)"

    def files(self) -> tuple[dict, dict[str, bytes]]:
        """``<name>.dxf``, ``.stl`` and ``.step``, each verified (the DXF re-read as this part, the
        STL watertight and of the flattened solid's volume, the STEP one solid of the exact volume),
        and the record a bill of materials takes. A part drawn for reference (``quantity`` 0) ships
        its drawing only (``formats.REFERENCE_ONLY``)."""
        data = self.drawing()
        again = read_turned(data, self.name)
        if not again.same_as(self):
            raise GeometryError(f"{self.name}: its drawing re-reads as {again}, not as made")
        ops = [line for line in self.operation_lines() if line.startswith("op ")]
        head = {"stem": self.name, "kind": "turned", "material": self.material, "quantity": self.quantity}
        if not self.quantity:
            return {**head, "dxf_layer": TURN, "operations": ops, "shipped": formats.REFERENCE_ONLY}, {
                f"{self.name}.dxf": data
            }
        solid = self.solid()
        flat = self.manifold()
        mesh = stl.stl_bytes(flat)
        rep = stl.mesh_report(mesh)
        stl_err = abs(rep.volume / flat.volume() - 1)
        if not (rep.watertight and rep.winding_consistent and stl_err < SOLID_VOLUME_REL):
            raise GeometryError(f"{self.name}: the STL fails its checks ({rep})")
        at = assembly_step.frame()
        step_data, step_res = assembly_step.write_checked(
            self.name, [assembly_step.Placed(self.name, self.name, 1, solid, at)]
        )
        record = {
            **head,
            "dxf_layer": TURN,
            "operations": ops,
            "outer_mm": self.outer,
            "bore_mm": self.bore,
            "length_mm": rounded(self.length, 6),
            "solid_volume_mm3": rounded(solid.volume, 6),
            "dxf_R2000": {"layer": TURN, "reread": "the same part (read_turned)"},
            "stl": {"triangles": rep.triangles, "watertight": rep.watertight, "volume_rel_error": significant(stl_err)},
            "step": {"solids": 1, "volume_rel_error": step_res["volume_rel_error"]},
        }
        return record, {f"{self.name}.dxf": data, f"{self.name}.stl": mesh, f"{self.name}.step": step_data}

    def same_as(self, other: Turned, tol: float = 1e-6) -> bool:
        """Whether ``other`` has this part's geometry (its notes aside), within ``tol`` mm."""

        def numbers(t: Turned) -> list[float]:
            out = [t.outer, t.length, t.bore]
            for k in sorted(t.keyways):
                out += k[:4]
            for g in sorted(t.grooves):
                out += g[:3]
            return out

        a, b = numbers(self), numbers(other)
        return len(a) == len(b) and all(abs(x - y) <= tol for x, y in zip(a, b, strict=True))


def _polylines(msp, layer: str) -> list[np.ndarray]:
    out = []
    for e in msp.query("LWPOLYLINE"):
        if e.dxf.layer == layer:
            out.append(np.array([(x, y, b) for x, y, _, _, b in e.get_points("xyseb")], dtype=float))
    return out


def read_turned(data: bytes, name: str = "turned part") -> Turned:
    """The turned part a drawing of :meth:`Turned.drawing` shows: its outer diameter, length and
    bore, keyways (depth from the side view, width from their sections) and grooves, z from its
    left end; GeometryError when the drawing has no side view on ``TURN``."""
    try:
        doc = ezdxf.read(io.StringIO(data.decode()))
    except (ezdxf.DXFError, UnicodeDecodeError) as exc:
        raise GeometryError(f"{name}: not a readable DXF: {exc}") from exc
    msp = doc.modelspace()
    lines = _polylines(msp, TURN)
    if not lines:
        raise GeometryError(f"{name}: no side view on layer {TURN}")
    profile = max(lines, key=lambda v: np.ptp(v[:, 0]))
    x0 = float(profile[:, 0].min())
    pts = profile[:, :2] - [x0, 0.0]
    length, r = float(pts[:, 0].max()), float(pts[:, 1].max())
    bores = [abs(e.dxf.start[1]) for e in msp.query("LINE") if e.dxf.layer == HIDDEN]
    bore = 2 * max(bores) if bores else 0.0
    ring = shapely.Polygon(pts)
    xs = sorted(set(np.round(pts[:, 0], 9)))
    spans = []  # (z0, z1, top radius, bottom radius) between the side view's edges
    for a, b in zip(xs, xs[1:], strict=False):
        cut = ring.intersection(shapely.LineString([((a + b) / 2, -2 * r), ((a + b) / 2, 2 * r)]))
        lo, hi = cut.bounds[1], cut.bounds[3]
        spans.append((a, b, hi, -lo))
    grooves, keys = [], []
    for a, b, top, bottom in spans:
        if bottom < r - 1e-9:
            if grooves and abs(grooves[-1][0] + grooves[-1][1] - a) < 1e-9 and abs(grooves[-1][2] - 2 * bottom) < 1e-9:
                grooves[-1] = (grooves[-1][0], b - grooves[-1][0], 2 * bottom, "")
            else:
                grooves.append((a, b - a, 2 * bottom, ""))
        elif top < r - 1e-9:
            if keys and abs(keys[-1][1] - a) < 1e-9:
                keys[-1] = (keys[-1][0], b, r - top)
            else:
                keys.append((a, b, r - top))
    sections = [v for v in lines if v is not profile]
    keyways = []
    for a, b, t1 in keys:
        mid = x0 + (a + b) / 2
        found = [v for v in sections if abs((v[:, 0].min() + v[:, 0].max()) / 2 - mid) < 1e-6]
        if len(found) != 1:
            raise GeometryError(f"{name}: the keyway at z {a:g}..{b:g} has {len(found)} sections, not one")
        v = found[0]
        width = float(abs(v[1, 0] - v[0, 0]))  # the notch's edges (Turned's keyway contour)
        keyways.append((float(a), float(b - a), round(width, 9), round(float(t1), 9), ""))
    grooves = [(float(a), float(m), float(d2), note) for a, m, d2, note in grooves]
    return Turned(name, round(2 * r, 9), round(length, 9), round(bore, 9), tuple(keyways), tuple(grooves))


@dataclass(frozen=True)
class Fitted:
    """A bought part (a catalogue part: bearing, bush, washer, circlip, key, screw, nut) placed on
    ``link`` (usually a :func:`mounted` one) with its own z = 0 at ``z`` across the machine — its
    own +z pointing back with ``flip`` (a screw put in from the front)."""

    name: str
    part: object
    link: str
    z: float
    flip: bool = False

    @property
    def kind(self) -> str:
        return type(self.part).__name__

    def judged(self) -> tuple[shapely.Polygon, tuple[float, float]] | None:
        """The section and z-range a judge measures it by (module docstring); None for a key."""
        p = self.part

        def own(lo: float, hi: float) -> tuple[float, float]:
            return (self.z - hi, self.z - lo) if self.flip else (self.z + lo, self.z + hi)

        kind = self.kind
        if kind in ("SelectedBearing", "Bearing", "SelectedBush", "Bush"):
            row = getattr(p, "bearing", None) or getattr(p, "bush", None) or p
            return _ring(row.d, row.D), own(0.0, row.B)
        if kind == "Washer":
            return _ring(p.inner, p.outer), own(0.0, p.thickness)
        if kind == "Circlip":
            g = p.groove_diameter
            inner, outer = (g, g + 2 * p.lug) if p.standard == "DIN 471" else (g - 2 * p.lug, g)
            return _ring(inner, outer), own(0.0, p.s)
        if kind == "Screw":
            return circle_polygon(0.0, 0.0, p.head_diameter / 2), own(-p.head_height, 0.0)
        if kind == "Nut":
            a = math.pi / 6 + np.arange(6) * math.pi / 3
            rr = p.across_flats / math.sqrt(3.0)
            hexagon = shapely.Polygon(np.stack([rr * np.cos(a), rr * np.sin(a)], axis=1))
            return hexagon.difference(circle_polygon(0.0, 0.0, p.d / 2)), own(0.0, p.height)
        if kind == "Key":
            return None
        raise SpecError(f"{self.name}: no judged section for a bought {kind}")


def _ring(inner: float, outer: float) -> shapely.Polygon:
    disc = circle_polygon(0.0, 0.0, outer / 2)
    return disc.difference(circle_polygon(0.0, 0.0, inner / 2)) if inner > 0 else disc


def bought_drawing(stem: str, section: shapely.Polygon, width: float, notes: tuple[str, ...]) -> bytes:
    """A bought part's section drawn for the judge and the assembly: its outline on layer
    ``BOUGHT`` (not cut), in its own frame (``<stem>.bought.dxf``)."""
    return formats.DXF.write(formats.MadePart(stem, section, None, width, notes, layer=formats.BOUGHT))
