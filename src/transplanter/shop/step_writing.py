"""What every STEP file of the package is written with: the writer's settings (AP214, mm, no
PCURVE), a fixed header (no time stamp: identical bytes on a rebuild) and the model printed to
bytes — shared by a part's STEP (:mod:`~transplanter.shop.step`) and the assembly's
(:mod:`~transplanter.shop.assembly_step`). The ``occ`` argument is OCP's modules as
:mod:`~transplanter.shop.step` imports them on first use.
"""

from __future__ import annotations

import io

from transplanter.core.errors import ExportError

__all__ = ["ORIGINATING_SYSTEM", "fixed_header", "write_settings", "model_bytes", "sent", "printed", "joined"]

#: what the file says wrote it
ORIGINATING_SYSTEM = "transplanter (OpenCASCADE STEP processor)"


def fixed_header(occ, writer, name: str) -> None:
    """The file's header fixed: the part's ``name``, no time stamp, no author, transplanter as its
    originating system — so rebuilding gives identical bytes."""
    header = occ.MakeHeader(writer.Model())
    header.SetName(occ.HString(name))
    header.SetTimeStamp(occ.HString("1970-01-01T00:00:00"))
    header.SetAuthorValue(1, occ.HString(""))
    header.SetOrganizationValue(1, occ.HString(""))
    header.SetOriginatingSystem(occ.HString(ORIGINATING_SYSTEM))
    header.SetAuthorisation(occ.HString(""))
    header.SetPreprocessorVersion(occ.HString(ORIGINATING_SYSTEM))


def write_settings(occ) -> None:
    """The STEP writer's settings every file of the package is written with: AP214, mm, no PCURVE."""
    occ.STEPControl_Controller.Init_s()  # the write.* settings exist once the controller is set up
    occ.Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    # no 2D curves of the edges on their faces (PCURVE): optional in STEP, derived by every reader
    # for planes and cylinders, and two thirds of the file (a 1260-face gear: 6.0 -> 2.2 MB)
    occ.Interface_Static.SetIVal_s("write.surfacecurve.mode", 0)
    occ.Interface_Static.SetCVal_s("write.step.unit", "MM")


def model_bytes(occ, writer, what: str) -> bytes:
    """The STEP file of a ``writer``'s transferred model (its header fixed first) as bytes;
    ExportError naming ``what`` when OpenCASCADE cannot print it."""
    return printed(sent(occ, writer), what)


def sent(occ, writer):
    """A ``writer``'s transferred model as the file's text lines (``StepData_StepWriter``), which
    need neither the model nor its writer any more: a large model's writer dropped before
    :func:`printed` lowers the peak (an assembly: :mod:`~transplanter.shop.assembly_step`)."""
    out = occ.StepData_StepWriter(writer.Model())
    out.SendModel(writer.WS().Protocol())
    return out


def printed(lines, what: str) -> bytes:
    """The text lines :func:`sent` made, as the file's bytes; ExportError naming ``what`` when
    OpenCASCADE cannot print them."""
    buffer = io.BytesIO()
    if not lines.Print(buffer):
        raise ExportError(f"cannot write {what}")
    return buffer.getvalue()


#: lines joined at a time by :func:`joined`
JOINED = 4096


def joined(lines) -> bytes:
    """The text lines :func:`sent` made as the file's bytes, as :func:`printed` gives them, joined
    here a few thousand at a time: OpenCASCADE's print gathers the whole file in a C++ string that
    Python then copies, ~100 MB more than the file for seed 002's 23 MB assembly; this needs the
    file once (its 465 440 lines in 0.5 s)."""
    out = io.BytesIO()
    n = lines.NbLines()
    for start in range(1, n + 1, JOINED):
        out.write("".join(lines.Line(i).ToCString() + "\n" for i in range(start, min(start + JOINED, n + 1))).encode())
    return out.getvalue()
