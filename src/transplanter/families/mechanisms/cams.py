"""Cam studies: the profile for a follower motion, the made cam, the follower run on it."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from transplanter.core.errors import ExportError, GeometryError
from transplanter.core.precision import rounded
from transplanter.core.tolerances import FOLLOWER_TOL
from transplanter.families.builder.making import Making, check_shop_files, manufacture
from transplanter.families.builder.study import Built, Checked, StudyDefaults
from transplanter.geometry.cams import disc_cam
from transplanter.geometry.pitch import Periodic
from transplanter.proof import validate
from transplanter.report import plots
from transplanter.shop import formats
from transplanter.shop.export import json_bytes

__all__ = ["FOLLOWER_STEPS", "FOLLOWER_TOL", "CamStudy"]


#: follower-check samples per cam turn
FOLLOWER_STEPS = 720


@dataclass(frozen=True)
class CamStudy(StudyDefaults):
    """A disc cam giving ``follower`` the ``motion`` (a 2π-periodic function of the cam angle).

    The follower is then run on the made contour (``validate.follower_check``): the profile
    CSV, and with ``making`` the DXF and the STL's mid-plane section re-read from their bytes;
    an error above ``FOLLOWER_TOL`` at the roller fails the part.
    """

    cost = 5

    name: str
    motion: Periodic
    follower: object
    n: int = 3600
    max_pressure_angle_deg: float = 45.0
    making: Making | None = None

    def following(self, files: dict[str, bytes], sources=("profile", "dxf", "stl")) -> dict:
        """Run the follower on the cam as found in ``files`` for each source present;
        returns ``{source: validate.FollowerReport}``."""
        out = {}
        for source in sources:
            fname = f"{self.name}.{source}.csv" if source == "profile" else f"{self.name}.cam.{source}"
            if fname in files:
                try:
                    contour = formats.section_of(fname, files[fname])
                except ExportError as exc:
                    out[source] = str(exc)
                    continue
                out[source] = validate.follower_check(contour, self.motion, self.follower, FOLLOWER_STEPS)
        return out

    def following_results(self, reports: dict) -> tuple[dict, dict[str, bytes], list[str]]:
        """Figures, plot and problems of the follower run on each source (``following``)."""
        readable, unreadable, problems = formats.split_unreadable(reports)
        results: dict = {"tolerance_mm": FOLLOWER_TOL, **unreadable}
        for source, rep in sorted(readable.items()):
            results[source] = rep.summary()
            if rep.max_error > FOLLOWER_TOL:
                k = int(np.argmax(np.abs(rep.error)))
                problems.append(
                    f"{source}: the follower on the made cam misses the law by {rep.error[k] * 1000:.2f} µm at cam "
                    f"angle {math.degrees(rep.theta[k]):.1f} deg (limit {FOLLOWER_TOL * 1000:g} µm)"
                )
        files = plots.figure_files(plots.follower_figure(readable, self.name), f"{self.name}.follower")
        return results, files, problems

    def check(self, files: dict[str, bytes]) -> Checked:
        """Re-run the follower check on this part's files as found on disk."""
        results, _, problems = self.following_results(self.following(files))
        if self.making is not None:  # the STEP against the DXF as found
            results["made"], more = check_shop_files(files, {f"{self.name}.cam": self.making.width})
            problems += more
        return Checked(results, problems)

    def build(self, out: Path) -> Built:
        """The cam profile and pitch curve (CSV), pressure angle and radius of curvature (JSON),
        plots; with ``making`` the DXF, STL and STEP, and the follower run on the made contour."""
        cam = disc_cam(self.motion, self.follower, self.n, math.radians(self.max_pressure_angle_deg))
        k = int(np.argmax(cam.pressure_angle))
        f = self.follower
        params = {
            "follower": type(f).__name__,
            **{k2: getattr(f, k2) for k2 in f.__dataclass_fields__},
            "samples": self.n,
            "max_pressure_angle_limit_deg": self.max_pressure_angle_deg,
        }
        results = {
            "max_pressure_angle_deg": rounded(math.degrees(cam.max_pressure_angle)),
            "at_cam_angle_deg": rounded(math.degrees(cam.theta[k])),
            "min_convex_radius_of_curvature_mm": rounded(cam.min_convex_radius),
            "profile_radius_range_mm": [
                rounded(float(np.linalg.norm(cam.profile, axis=1).min())),
                rounded(float(np.linalg.norm(cam.profile, axis=1).max())),
            ],
            "follower_stroke": rounded(float(np.ptp(cam.follower_position(cam.theta)))),
        }
        files = {f"{self.name}.profile.csv": formats.CSV.write(cam.profile, {"cam_angle_deg": np.degrees(cam.theta)})}
        files.update(plots.figure_files(plots.cam_figure(cam, self.name), f"{self.name}.cam"))
        if self.making is not None:
            blank = shapely.Polygon(cam.profile)
            notes = (
                f"max pressure angle {math.degrees(cam.max_pressure_angle):.2f} deg",
                f"width {self.making.width:g} mm",
                f"mates: the {type(self.follower).__name__} follower of {self.name} (see the manifest)",
                "timing: cam angles are measured from +x of this drawing (the profile CSV is listed against them)",
            )
            res, made, _ = manufacture(
                f"{self.name}.cam",
                blank,
                shapely.Polygon(),
                self.making,
                notes,
                lambda pt: f"cam angle {math.degrees(math.atan2(pt[1], pt[0])) % 360:.1f} deg",
            )
            results["made"] = res
            files.update(made)
        following, plot_files, problems = self.following_results(self.following(files))
        if problems:
            raise GeometryError(
                f"{self.name}: the made cam does not give the prescribed motion: " + "; ".join(problems)
            )
        results["follower_check"] = following
        files.update(plot_files)
        files[f"{self.name}.cam.json"] = json_bytes({"parameters": params, "results": results})
        return Built({"kind": "cam", "parameters": params, "results": results}, files)
