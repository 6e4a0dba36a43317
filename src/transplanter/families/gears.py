"""Toothed pair studies: teeth by the shaper envelope, the made parts, their meshing check."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import shapely

from transplanter import dxf, plots, solids, stl, validate
from transplanter.cutter import ShaperCutter
from transplanter.errors import GeometryError, SpecError, TransplanterError
from transplanter.export import csv_array, csv_bytes, json_bytes, rounded
from transplanter.families.making import Making, manufacture
from transplanter.pitch import GearPair, Mesh
from transplanter.planetary import DifferentialTrain
from transplanter.teeth import CHORD_TOLERANCE, generate_pair

__all__ = ["MESH_STEPS", "ToothedPairStudy"]


#: meshing-check steps per driver turn (raised to be coprime with the driver's tooth count)
MESH_STEPS = 180


def _outline_polygon(data: bytes, internal: bool) -> shapely.Polygon:
    """Gear material from an outline CSV: inside it, or for a ring outside it (to a rim 5 mm
    beyond its farthest point — only the teeth matter for meshing)."""
    xy = csv_array(data)
    if not internal:
        return shapely.Polygon(xy)
    rim = float(np.linalg.norm(xy, axis=1).max()) + 5.0
    return shapely.Polygon(solids.circle_polygon(0.0, 0.0, rim).exterior.coords, [xy])


@dataclass(frozen=True)
class ToothedPairStudy:
    """Teeth of both gears of ``pair`` cut by ``cutter``; ``teeth`` is the driver's tooth count.

    ``rejected`` lists ``(label, teeth, cutter)`` alternatives (e.g. a published module) that
    are tried and must fail: their errors go into the manifest as findings.

    The pair is then *meshed* (``validate.mesh_check``): the generated outlines, and with
    ``making`` the DXF and the mid-plane section of the STL re-read from their bytes, turn
    through a full cycle at the design ratio; the report carries penetration, fouling,
    transmission error, backlash against ``validate.backlash_band`` and contact ratio, and a
    plot. A pair that does not mesh fails the part, unless ``must_mesh`` is False: then the
    study is a finding — figures and plot are written, the shop files (DXF, STL) are not.
    With ``train`` (the ``DifferentialTrain`` the pair drives) the train is rebuilt from each
    source's meshing and its needle-tip path compared with the designed one.
    """

    name: str
    pair: GearPair
    cutter: ShaperCutter
    teeth: int
    allow_undercut: bool = False
    rejected: tuple[tuple[str, int, ShaperCutter], ...] = ()
    making: tuple[Making, Making] | None = None
    must_mesh: bool = True
    train: DifferentialTrain | None = None

    def _sized(self) -> tuple[GearPair, object]:
        pair, sizing = self.pair.sized(teeth=self.teeth)
        if abs(sizing.module - self.cutter.module) > 1e-9 * sizing.module:
            raise SpecError.out_of_range(
                "cutter module", self.cutter.module, f"the pair's module {sizing.module!r} mm at {self.teeth} teeth"
            )
        return pair, sizing

    @property
    def _names(self) -> tuple[str, str]:
        return ("ring", "planet") if self.pair.ring == "driver" else ("driver", "driven")

    def meshing(self, files: dict[str, bytes], sources=("outline", "dxf", "stl")) -> dict:
        """Mesh the pair as found in ``files`` (this study's file names → bytes) for each source
        present; returns ``{source: validate.MeshReport}``."""
        pair, sizing = self._sized()
        internal = (pair.ring == "driver", pair.ring == "driven")
        readers = {
            "outline": (".outline.csv", lambda data, i: _outline_polygon(data, internal[i])),
            "dxf": (".dxf", lambda data, i: dxf.read_section(data)),
            "stl": (".stl", lambda data, i: stl.section(data)),
        }
        out = {}
        for source in sources:
            suffix, read = readers[source]
            names = [f"{self.name}.{role}{suffix}" for role in ("driver", "driven")]
            if not all(n in files for n in names):
                continue
            polys = [read(files[n], i) for i, n in enumerate(names)]
            out[source] = validate.mesh_check(pair, *polys, sizing.module, steps=MESH_STEPS, teeth=int(sizing.teeth[0]))
        return out

    @cached_property
    def _backlash_band(self) -> tuple[float, float]:
        return validate.backlash_band(self._sized()[0], self.cutter.thickening)

    def _problems(self, report) -> list[str]:
        return report.problems(backlash=self._backlash_band, names=self._names)

    def meshing_results(self, reports: dict) -> tuple[dict, dict[str, bytes], list[str]]:
        """Figures per source, the meshing plot, and the problems (``source: text``)."""
        band = self._backlash_band
        results: dict = {"backlash_band_mm": [rounded(band[0], 6), rounded(band[1], 6)], "steps": MESH_STEPS}
        problems = []
        trains = {}
        for source, rep in sorted(reports.items()):
            res = rep.summary()
            found = self._problems(rep)
            res["problems"] = found
            problems += [f"{source}: {p}" for p in found]
            if self.train is not None:
                trains[source] = validate.train_check(self.train, rep)
                res["train"] = trains[source].summary()
                if found:
                    res["train"]["note"] = "from the contact at the pitch point; the problems above are ignored"
            results[source] = res
        files = {}
        shown = trains.get("stl", trains.get("outline"))
        note = " (pitch-point contact; the interference above ignored)" if problems else ""
        for fmt in ("png", "svg"):
            fig = plots.meshing_figure(reports, self.name, shown, note)
            files[f"{self.name}.meshing.{fmt}"] = plots.figure_bytes(fig, fmt)
        return results, files, problems

    def build(self, out: Path) -> tuple[dict, dict[str, bytes]]:
        pair, sizing = self._sized()
        if self.train is not None and abs(self.train.pair.centre_distance - pair.centre_distance) > 1e-9:
            raise SpecError.out_of_range(
                "train",
                self.train.pair.centre_distance,
                f"a train on this pair (centre distance {pair.centre_distance})",
            )
        gears = generate_pair(pair, self.cutter, sizing.teeth, allow_undercut=self.allow_undercut)
        c = self.cutter
        params = {
            "teeth": list(sizing.teeth),
            "module_mm": rounded(sizing.module, 12),
            "cutter": {
                "teeth": c.teeth,
                "pressure_angle_deg": rounded(math.degrees(c.pressure_angle)),
                "addendum": c.addendum,
                "dedendum": c.dedendum,
                "tip_fillet": c.tip_fillet,
                "thickening_mm": c.thickening,
            },
            "chord_tolerance_mm": CHORD_TOLERANCE,
            "must_mesh": self.must_mesh,
        }
        results: dict = {}
        files: dict[str, bytes] = {}
        for role, gear in zip(("driver", "driven"), gears, strict=True):
            results[role] = {
                "teeth": gear.teeth,
                "internal": gear.internal,
                "vertices": len(gear.toothed_contour),
                "area_mm2": rounded(gear.polygon.area, 6),
                "undercut_mm": rounded(gear.undercut),
                "min_tip_land_mm": rounded(float(gear.tip_lands.min())),
            }
            rows = [[f"{x:.9f}", f"{y:.9f}"] for x, y in gear.toothed_contour]
            files[f"{self.name}.{role}.outline.csv"] = csv_bytes(["x_mm", "y_mm"], rows)
        reports = self.meshing(files, ("outline",))
        problems = self._problems(reports["outline"])
        if problems and self.must_mesh:
            raise GeometryError(f"{self.name}: the generated teeth do not mesh: " + "; ".join(problems))
        if problems:
            results["shop_files"] = "withheld: the generated teeth do not mesh (see meshing)"
        elif self.making is not None:
            for role, gear in zip(("driver", "driven"), gears, strict=True):
                making = self.making[0 if role == "driver" else 1]
                notes = (f"{gear.teeth} teeth", f"module {gear.module:.6g} mm", f"face width {making.width:g} mm")
                res, made = manufacture(
                    f"{self.name}.{role}",
                    gear.blank,
                    gear.cut,
                    making,
                    notes,
                    lambda pt, g=gear: f"tooth space {g.nearest_space(pt)}",
                )
                results[role]["made"] = res
                files.update(made)
            reports.update(self.meshing(files, ("dxf", "stl")))
        meshing, plot_files, problems = self.meshing_results(reports)
        results["meshing"] = meshing
        files.update(plot_files)
        if problems and not results.get("shop_files"):
            raise GeometryError(f"{self.name}: the made parts do not mesh: " + "; ".join(problems))
        findings = {}
        for label, teeth, cutter in self.rejected:
            alt, alt_sizing = self.pair.sized(teeth=teeth)
            try:
                generate_pair(alt, cutter, alt_sizing.teeth, allow_undercut=self.allow_undercut)
            except TransplanterError as exc:
                findings[label] = f"{type(exc).__name__}: {exc}"
            else:
                findings[label] = "generated without error"
        results["rejected_alternatives"] = findings
        files[f"{self.name}.teeth.json"] = json_bytes({"parameters": params, "results": results})
        for fmt in ("png", "svg"):
            fig = plots.toothed_pair_figure(
                gears[0].polygon,
                gears[1].polygon,
                pair.centre_distance,
                pair.mesh is Mesh.EXTERNAL,
                float(pair.driver.r(0.0)),
                self.name,
            )
            files[f"{self.name}.teeth.{fmt}"] = plots.figure_bytes(fig, fmt)
        return {"kind": "toothed_pair", "parameters": params, "results": results}, files

    def check(self, files: dict[str, bytes]) -> tuple[dict, list[str]]:
        """Re-run the meshing checks on this part's files as found on disk."""
        results, _, problems = self.meshing_results(self.meshing(files))
        return results, problems
