"""What a designer reads: a family's HTML report (:mod:`~transplanter.report.pages`: every part's
verdict first, then each part's key figures (:mod:`~transplanter.report.headlines`), plots and
tables (:mod:`~transplanter.report.tables`: a unit per column)) and its plots
(:mod:`~transplanter.report.plots`: coupler curves, speed and acceleration, shaking force, trains,
cams; :mod:`~transplanter.report.gear_plots`: pitch curves, teeth, meshing;
:mod:`~transplanter.report.machine_picture`: a machine assembled, with its balloons; all drawn by
:mod:`~transplanter.report.figure` to be legible at the width the page shows them).

Takes
    a built family's records and the studies' arrays.
Gives
    HTML pages and PNG/SVG figures.
May import
    core, geometry, design, shop, proof and machine.

``transplanter.report`` was a module before 0.2; its names stay importable from here.
"""

from transplanter.core.forwarding import forward
from transplanter.report.pages import *  # noqa: F403 - the former module's names
from transplanter.report.pages import __all__  # noqa: F401

#: names this module gave before issue 41 moved them to modules of their own, still found here
__getattr__ = forward(
    __name__,
    {
        "OPEN_ROWS": "transplanter.report.tables",
        "ROUND_OFF": "transplanter.report.tables",
        "SLIDER_SUFFIX": "transplanter.report.pages",
    },
)
