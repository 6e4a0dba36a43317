"""Pitch-curve pair studies: closure, ratio, curvature, pressure angle, tooth sizing."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from transplanter.core.precision import rounded, significant
from transplanter.families.builder.study import Built, StudyDefaults
from transplanter.geometry.pitch import GearPair, Mesh
from transplanter.report import plots
from transplanter.shop.export import csv_bytes, json_bytes

__all__ = ["PitchPairStudy"]


def _curve_summary(curve, teeth: int, module: float) -> dict:
    return {
        "lobes": curve.lobes,
        "teeth": teeth,
        "module_mm": rounded(module),
        "perimeter_mm": rounded(curve.perimeter),
        "radius_min_mm": rounded(curve.min_radius().value),
        "radius_max_mm": rounded(curve.max_radius().value),
        "convex": bool(curve.is_convex),
        "min_convex_radius_of_curvature_mm": rounded(curve.min_convex_radius()),
        "min_concave_radius_of_curvature_mm": rounded(curve.min_concave_radius()),
        "max_pressure_deviation_deg": rounded(math.degrees(curve.max_pressure_deviation())),
    }


@dataclass(frozen=True)
class PitchPairStudy(StudyDefaults):
    """A conjugate pitch-curve pair with its tooth sizing.

    Give ``teeth`` (driver tooth count) to derive the module, or ``module`` (mm) to scale the
    curves to a whole number of teeth of that module.
    """

    cost = 2

    name: str
    #: the pitch pair, any size: sized here by ``teeth`` or ``module``
    pair: GearPair
    #: the driver's tooth count (the module follows from the curves)
    teeth: int | None = None
    #: the module, mm (the curves are scaled to a whole number of its teeth)
    module: float | None = None
    #: refuse concave parts of either curve
    require_convex: bool = False

    def build(self, out: Path) -> Built:
        """Closure, ratio check, curvature, pressure angle, teeth and module (JSON), the curves as
        CSV points, and plots."""
        pair, sizing = self.pair.sized(module=self.module, teeth=self.teeth)
        if self.require_convex:
            pair.driver.require_convex(f"{self.name} driver")
            pair.driven.require_convex(f"{self.name} driven")
        params = {
            "mesh": pair.mesh.value,
            "ring": pair.ring,
            "lobes": list(pair.lobes),
            "teeth_requested": self.teeth,
            "module_requested_mm": self.module,
        }
        results = {
            "centre_distance_mm": rounded(pair.centre_distance, 12),
            "closure_error_rad": significant(pair.closure_error),
            "ratio_error": significant(pair.ratio_error()),
            "centre_distance_error_mm": significant(pair.centre_distance_error()),
            "scale_applied": rounded(sizing.scale, 12),
            "driver": _curve_summary(pair.driver, sizing.teeth[0], sizing.module),
            "driven": _curve_summary(pair.driven, sizing.teeth[1], sizing.module),
        }
        if pair.mesh is Mesh.EXTERNAL:
            results["convexity_index_p"] = rounded(pair.convexity_index().p)
        phi = np.linspace(0.0, 2 * math.pi, 3601)[:-1]
        files = {f"{self.name}.pitch.json": json_bytes({"parameters": params, "results": results})}
        for role, curve in (("driver", pair.driver), ("driven", pair.driven)):
            pts = curve.points(phi)
            rows = [[f"{a:.6f}", f"{x:.9f}", f"{y:.9f}"] for a, (x, y) in zip(np.degrees(phi), pts, strict=True)]
            files[f"{self.name}.{role}.csv"] = csv_bytes(["polar_angle_deg", "x_mm", "y_mm"], rows)
        files.update(plots.figure_files(plots.pitch_pair_figure(pair, self.name), f"{self.name}.pitch"))
        return Built({"kind": "pitch_pair", "parameters": params, "results": results}, files)
