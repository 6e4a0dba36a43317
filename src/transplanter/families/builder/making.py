"""How a prismatic part is made: section, solid, and its shop files (DXF, STL, STEP) with their checks."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.errors import ExportError, GeometryError, SpecError, check_int, check_number
from transplanter.core.precision import rounded, significant
from transplanter.core.tolerances import WIRE_EDM_TOLERANCE
from transplanter.shop import catalogue, formats, machining, solids

__all__ = ["Making", "REFERENCE_ONLY", "manufacture", "operations", "step_file", "assembly_file", "check_shop_files"]


#: the thinnest part made, mm: below it an extruded solid's mesh is no longer watertight in
#: float round-off, and no wire-EDM plate is that thin
MIN_FACE_WIDTH_MM = 0.1


@dataclass(frozen=True)
class Making:
    """How a part is made: face width (mm), holes, wire (diameter, spark gap, mm), DXF versions,
    whether a STEP is written, how many to make, the contour tolerance (± mm) the shop holds and
    the material — the last three are stated in the part's notes and recorded in its results.

    ``material`` has no default: every part names its own, by the short name of the catalogue
    (``transplanter.shop.catalogue.material``, e.g. ``"C45"``, ``"S235JR"``, ``"6061-T6"``),
    so a drawing never carries a material nobody chose; a Making without one, or with a name the
    catalogue does not hold, is a :class:`~transplanter.core.errors.SpecError` naming ``material``.
    A part with ``quantity`` 0 is drawn, not cut: its outline goes on the DXF's ``REFERENCE``
    layer, not on ``CUT``.
    """

    width: float
    features: solids.Features = field(default_factory=solids.Features)
    wire: tuple[float, float] = (0.25, 0.02)
    dxf_versions: tuple[str, ...] = ("R2000",)
    #: write the STEP too (what CAD users open; ~1 s per 1000 arcs of outline)
    step: bool = True
    #: how many of the part to make (0: drawn as the proof of what another part is cut from — its
    #: notes say which)
    quantity: int = 1
    #: contour tolerance the shop holds, ± mm normal to the surface
    tolerance: float = WIRE_EDM_TOLERANCE
    #: the material, by its catalogue name (required: see above)
    material: str = ""
    #: what the shop does after the wire, in order (tapping, a circlip groove inside a bore…): the
    #: drawing lists them as numbered operations after "op 10: wire-cut" (:func:`operations`)
    operations: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        check_number("face width", self.width, MIN_FACE_WIDTH_MM, 10_000.0, unit="mm")
        if not isinstance(self.features, solids.Features):
            raise SpecError(f"features must be solids.Features, got {type(self.features).__name__}")
        if not isinstance(self.wire, tuple | list) or len(self.wire) != 2:
            raise SpecError.out_of_range("wire", self.wire, "(diameter, spark gap) in mm")
        check_number("wire diameter", self.wire[0], 0.0, 5.0, low_open=True, unit="mm")
        check_number("wire spark gap", self.wire[1], 0.0, 1.0, unit="mm")
        if not isinstance(self.step, bool):
            raise SpecError.out_of_range("step", self.step, "True or False")
        check_int("quantity", self.quantity, 0, 10_000)
        if not isinstance(self.operations, tuple) or not all(isinstance(o, str) and o for o in self.operations):
            raise SpecError.out_of_range("operations", self.operations, "a tuple of non-empty texts")
        check_number("tolerance", self.tolerance, 0.0, 1.0, low_open=True, unit="mm")
        for v in self.dxf_versions:
            if v not in ("R2000", "R12"):
                raise SpecError.out_of_range("dxf_versions", self.dxf_versions, "'R2000' and/or 'R12'")
        if self.material == "":
            raise SpecError(
                "material: a made part names its material (Making(..., material=...)), one of "
                f"{', '.join(sorted(catalogue.materials()))} (transplanter.shop.catalogue)"
            )
        catalogue.material(self.material)

    @property
    def layer(self) -> str:
        """The DXF layer of the part's outline: ``CUT`` if it is to be made, ``REFERENCE`` if it is
        only drawn (quantity 0)."""
        return formats.CUT if self.quantity else formats.REFERENCE


def operations(making: Making) -> tuple[str, ...]:
    """The drawing's numbered operations: the wire first, then ``making.operations`` in order —
    none for a part the wire finishes, or a drawing not to cut.

    >>> operations(Making(width=8, material="S235JR", operations=("tap 2 x M4 through",)))
    ('op 10: wire-cut every contour on CUT (a hole to tap at its tap drill)', 'op 20: tap 2 x M4 through')
    """
    if not making.operations or not making.quantity:
        return ()
    tapping = any(re.search(r"\btap\b", o) for o in making.operations)
    wire = f"wire-cut every contour on {making.layer}" + (" (a hole to tap at its tap drill)" if tapping else "")
    return tuple(f"op {10 * k}: {text}" for k, text in enumerate((wire, *making.operations), 1))


#: what a drawing not to cut ships, in its results (``formats.REFERENCE_ONLY``)
REFERENCE_ONLY = formats.REFERENCE_ONLY


def manufacture(
    stem: str,
    blank,
    cut,
    making: Making,
    notes: tuple[str, ...],
    locate,
    marks: tuple = (),
    paths: tuple = (),
) -> tuple[dict, dict, formats.MadePart]:
    """Section, solid and shop files of one prismatic part, each verified by its format
    (:mod:`transplanter.shop.formats`): the STL, every DXF version, the STEP (a part to cut).

    ``locate(point)`` names where a wire violation sits (e.g. "tooth space 12"); ``marks`` and
    ``paths`` go to the DXF's ANNOTATION layer (``formats.MadePart``); the notes get the material
    (its catalogue note), the numbered operations after the wire (:func:`operations`), the quantity
    with the plate's thickness (``making.width``: what the shop
    buys the stock as) and the contour tolerance from ``making``, and the outline
    goes on ``making.layer`` (CUT, or REFERENCE for a drawing not to cut, which ships its DXF only:
    no STL, no STEP — :data:`REFERENCE_ONLY` in its results). Returns the results (with
    the files' stem, the material, quantity and outline layer, for a bill of materials), the files
    by name and the :class:`~transplanter.shop.formats.MadePart` (for assemblies).
    """
    made = (
        f"make {making.quantity} from {making.width:g} mm plate"
        if making.quantity
        else "do not cut this drawing as it is (see the notes above)"
    )
    ops = operations(making)
    notes = (
        *notes,
        *ops,
        catalogue.material(making.material).note,
        f"{made}; contour tolerance +/-{making.tolerance:g} mm",
    )
    section = solids.part_section(blank, cut, making.features)
    wire_r = making.wire[0] / 2 + making.wire[1]
    bad = machining.wire_violations(section, wire_r)
    if not bad.is_empty:
        worst = max(bad.geoms, key=lambda g: g.area)
        where = locate(worst.centroid.coords[0])
        raise GeometryError(
            f"{stem}: an inside corner at {where} is tighter than the wire radius {wire_r:.4g} mm "
            f"(wire {making.wire[0]:g} mm + gap {making.wire[1]:g} mm; {len(bad.geoms)} places, "
            f"{worst.area:.3g} mm² uncut here); use a finer wire or a larger cutter tip fillet"
        )
    solid = solids.part_solid(blank, cut, making.features, making.width)
    made = formats.MadePart(
        stem, section, solid, making.width, tuple(notes), tuple(marks), tuple(paths), layer=making.layer
    )
    results: dict = {
        "stem": stem,
        "material": making.material,
        "quantity": making.quantity,
        "dxf_layer": making.layer,
        "section_area_mm2": rounded(section.area, 6),
        "solid_volume_mm3": rounded(solid.volume(), 6),
        "volume_rel_error": significant(abs(solid.volume() / made.volume - 1)),
        "wire_radius_mm": wire_r,
    }
    if ops:
        results["operations"] = list(ops)
    files: dict[str, bytes] = {}
    # a drawing not to cut ships as a drawing only: an STL or STEP beside it is a part a printer, a CAM
    # or a CAD import would take as one to make
    solid_formats = (formats.STL,) if making.quantity else ()
    for fmt in (*solid_formats, *(formats.Dxf(v) for v in making.dxf_versions)):
        data = fmt.write(made)
        results["stl" if fmt is formats.STL else f"dxf_{fmt.version}"] = fmt.verify(made, data)
        files[f"{stem}{fmt.suffix}"] = data
    if not making.quantity:
        results["shipped"] = REFERENCE_ONLY
    elif making.step:
        results["step"] = step_file(made, files)
    return results, files, made


def step_file(made: formats.MadePart, files: dict[str, bytes]) -> dict:
    """Write ``<stem>.step`` of a made part into ``files``; the results of its check.

    A study that also re-reads an assembly may call :func:`manufacture` without the STEP and
    this after the re-read: OpenCASCADE (~250 MB resident once imported) then joins the process
    after the 3MF reader's transient (~300 MB for the seed-004 ring), not under it. A drawing not
    to cut (on layer REFERENCE) gets none: :data:`REFERENCE_ONLY`."""
    if made.layer == formats.REFERENCE:
        return {"shipped": REFERENCE_ONLY}
    data, results = formats.STEP.write_checked(made)
    files[f"{made.stem}{formats.STEP.suffix}"] = data
    return results


def assembly_file(name: str, placed: list[tuple[str, formats.MadePart, np.ndarray]]) -> tuple[dict, dict[str, bytes]]:
    """``<name>.assembly.3mf`` of the made parts ``(body name, part, 4×4 placement)``, re-read and
    verified (one body per part, of its volume, none overlapping another); its results and file.
    Drawings not to cut have none (:data:`REFERENCE_ONLY`): the 3MF is a model a printer makes."""
    if all(part.layer == formats.REFERENCE for _, part, _ in placed):
        return {"file": None, "shipped": REFERENCE_ONLY}, {}
    data = formats.THREEMF.write([(body, part.solid, at) for body, part, at in placed])
    volumes = {body: part.volume for body, part, _ in placed}
    res = formats.THREEMF.verify(data, list(volumes), volumes)
    return {"file": f"{name}.assembly.3mf", **res}, {f"{name}.assembly.3mf": data}


def check_shop_files(files: dict[str, bytes], widths: dict[str, float], assembly: tuple[str, list[str]] | None = None):
    """Re-read what a built part left on disk, beyond its own checks: each STEP (``stem`` →
    width in ``widths``) against its DXF (``formats.Step.verify``), and the 3MF ``assembly``
    ``(file name, body names)``. Returns ``(results, problems)``."""
    results: dict = {}
    problems: list[str] = []

    def reread(fname: str, verify, *args) -> None:
        try:
            results[fname] = verify(*args)
        except (GeometryError, ExportError) as exc:
            results[fname] = {"error": str(exc)}
            problems.append(f"{fname}: {exc}")

    for stem, width in sorted(widths.items()):
        step_name, dxf_name = f"{stem}.step", f"{stem}.dxf"
        if step_name in files and dxf_name in files:
            reread(step_name, formats.STEP.verify, stem, files[step_name], files[dxf_name], width)
    if assembly is not None and assembly[0] in files:
        fname, bodies = assembly
        reread(fname, formats.THREEMF.verify, files[fname], bodies)
    return results, problems
