"""What every gear cutter is: the :class:`Cutter` protocol the envelope uses, and the tooth the
shaper and the rack share.

A cutter's tooth proportions (pressure angle; addendum, dedendum and tip fillet in modules;
thickening in mm) and their checks are one dataclass base (``_Proportions``,
``_check_proportions``); its tooth is one profile parameter τ ∈ [0, 7] over seven pieces whose
lower half mirrors the upper (``_whole_tooth``: piece p at t <-> piece 6 - p at 1 - t, the tip
land split at its middle). The two cutters, :class:`~transplanter.geometry.cutter.ShaperCutter`
and :class:`~transplanter.geometry.rack_cutter.RackCutter`, give only their upper half.

Numpy only (``tests/test_layout.py``: one of the maths modules).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from transplanter.core.errors import SpecError, check_number
from transplanter.geometry.proportions import CUTTER_ADDENDUM, CUTTER_DEDENDUM

__all__ = ["Cutter"]


@runtime_checkable
class Cutter(Protocol):
    """What the envelope (:mod:`transplanter.geometry.teeth`) needs from a generating tool.

    The tool's tooth, centred on the +x axis of its own frame and pointing at the gear, is one
    profile parameter τ ∈ [0, 7] over seven pieces (lower flank to tip to upper flank, as
    :class:`~transplanter.geometry.cutter.ShaperCutter` describes); ``profile`` gives points and
    outward unit normals; ``placement`` where its frame is when it has rolled to ``s`` on the pitch
    curve; ``contact_rolls`` the roll at which each profile point touches the envelope; ``check_fits``
    refuses a curve the tool cannot roll on. ``thickening`` is the backlash allowance, and
    ``addendum``/``dedendum`` (in modules) bound the gear's dedendum and addendum.
    """

    module: float
    pressure_angle: float
    addendum: float
    dedendum: float
    thickening: float

    def profile(self, tau): ...

    def placement(self, frame, s, s_centre, side: float, shift: float): ...

    def contact_rolls(self, frame, q, n, s_centres, side: float, shift: float) -> np.ndarray: ...

    def check_fits(self, frame, internal: bool, shift: float) -> None: ...

    def outline(self, per_piece: int = 24) -> np.ndarray: ...


@dataclass(frozen=True, kw_only=True)
class _Proportions:
    """A cutter's tooth proportions, shared by the shaper and the rack (keyword fields): pressure
    angle (rad); addendum, dedendum and tip fillet in modules; thickening in mm."""

    pressure_angle: float = math.radians(20.0)
    addendum: float = CUTTER_ADDENDUM
    dedendum: float = CUTTER_DEDENDUM
    tip_fillet: float = 0.2
    thickening: float = 0.0

    @property
    def m(self) -> float:
        """The module, mm, of a sized cutter (SpecError for one given without a module)."""
        module = getattr(self, "module", None)
        if module is None:
            raise SpecError(
                "the cutter has no module: give it one (cutter.sized(m)), or leave it to a ToothedPairStudy"
            )
        return module


def _check_proportions(cutter) -> bool:
    """Check a cutter's proportions (pressure angle; addendum, dedendum, tip fillet in modules)
    and, when it has one, its module and thickening (mm). False for a cutter without a module
    (sized later by its study), whose thickening must then be 0."""
    check_number("cutter pressure_angle", cutter.pressure_angle, math.radians(10), math.radians(35), unit="rad")
    # a cutter's addendum is the gear's dedendum (~1.25 m); past 2 m its tip outruns the involute
    check_number("cutter addendum", cutter.addendum, 0.5, 2.0, unit="m")
    check_number("cutter dedendum", cutter.dedendum, 0.0, 3.0, low_open=True, unit="m")
    check_number("cutter tip_fillet", cutter.tip_fillet, 0.0, 0.5, unit="m")
    if cutter.module is None:
        if cutter.thickening != 0:
            raise SpecError("a cutter's thickening (mm) needs its module: give both, or neither")
        return False
    m = check_number("cutter module", cutter.module, 0.01, 100.0, unit="mm")
    check_number("cutter thickening", cutter.thickening, -m / 2, m / 2, low_open=True, high_open=True, unit="mm")
    return True


def _whole_tooth(upper, tau):
    """A tooth's point q, outward normal n and k = q × n at profile parameters τ ∈ [0, 7], from
    its upper half ``upper(piece, t)`` (pieces 3..6, ``t`` from the tooth centre outwards): the
    lower pieces mirror the upper ones, piece p (t) <-> piece 6 - p (1 - t), and the tip land,
    piece 3, runs across the centre, so it is split at its middle."""
    tau = np.asarray(tau, dtype=float)
    if np.any((tau < 0) | (tau > 7)) or not np.all(np.isfinite(tau)):
        raise SpecError("profile parameter τ must lie in [0, 7]")
    piece = np.minimum(np.floor(tau), 6).astype(int)
    t = tau - piece
    lower = piece <= 2
    land = piece == 3
    up_piece = np.where(lower, 6 - piece, piece)
    up_t = np.where(land, np.abs(2 * t - 1), np.where(lower, 1 - t, t))
    q, n = upper(up_piece, up_t)
    flip = lower | (land & (t < 0.5))
    q[flip, 1] *= -1
    n[flip, 1] *= -1
    return q, n, q[..., 0] * n[..., 1] - q[..., 1] * n[..., 0]
