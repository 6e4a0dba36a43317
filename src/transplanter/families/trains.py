"""Planetary train studies: agronomic metrics beside published values, variants, plots."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from transplanter import plots
from transplanter.agronomy import TransplantingMetrics, transplanting_metrics
from transplanter.export import csv_bytes, json_bytes, rounded, significant
from transplanter.planetary import DifferentialTrain

__all__ = ["PlanetaryStudy"]


@dataclass(frozen=True)
class PlanetaryStudy:
    """Agronomic study of a planetary transplanting train.

    ``reference`` holds published values ``(quantity, value, unit)`` to tabulate beside the
    computed ones (quantities as in :meth:`TransplantingMetrics.table`); ``variants`` holds
    ``(label, train)`` alternatives whose metrics show what the result depends on.
    """

    name: str
    train: DifferentialTrain
    seedling_box: tuple[float, float]
    plant_spacing: float
    planting_depth: float
    gearbox_radius: float
    reference: tuple[tuple[str, float, str], ...] = ()
    variants: tuple[tuple[str, DifferentialTrain], ...] = ()

    def metrics(self, train: DifferentialTrain | None = None) -> TransplantingMetrics:
        return transplanting_metrics(
            train or self.train, self.seedling_box, self.plant_spacing, self.planting_depth, self.gearbox_radius
        )

    def build(self, out: Path) -> tuple[dict, dict[str, bytes]]:
        m = self.metrics()
        tr = self.train
        ref = {q: v for q, v, _ in self.reference}
        rows = [[q, rounded(v, 6), ref.get(q, ""), u] for q, v, u in m.table()]
        params = {
            "centre_distance_mm": rounded(tr.pair.centre_distance, 12),
            "lobes": list(tr.pair.lobes),
            "planets": tr.planets,
            "speed_ratio_ring_to_carrier": rounded(tr.speed_ratio, 12),
            "carrier_start_deg": rounded(math.degrees(tr.carrier_start)),
            "arm_tip_S_mm": tr.arm.tip,
            "arm_knee_H1_mm": tr.arm.knee,
            "arm_mount_beta_deg": rounded(math.degrees(tr.arm.mount)),
            "seedling_box_mm": list(self.seedling_box),
            "plant_spacing_mm": self.plant_spacing,
            "planting_depth_mm": self.planting_depth,
            "gearbox_radius_mm": self.gearbox_radius,
        }
        results = {
            "metrics": {q: {"value": rounded(v, 6), "unit": u, "published": ref.get(q)} for q, v, u in m.table()},
            "phase_error_mm": significant(tr.phase_error()),
            "trajectory_closure_mm": significant(tr.closure_error()),
            "variants": {
                label: {q: rounded(v, 6) for q, v, _ in self.metrics(variant).table()}
                for label, variant in self.variants
            },
        }
        cyc = tr.cycle(1440)
        traj = [
            [f"{t:.6f}", f"{x:.6f}", f"{y:.6f}", f"{a:.6f}"]
            for t, (x, y), a in zip(np.degrees(cyc.theta), cyc.tip, np.degrees(cyc.attitude), strict=True)
        ]
        files = {
            f"{self.name}.metrics.json": json_bytes({"parameters": params, "results": results}),
            f"{self.name}.metrics.csv": csv_bytes(["quantity", "value", "published", "unit"], rows),
            f"{self.name}.trajectory.csv": csv_bytes(
                ["carrier_angle_deg", "tip_x_mm", "tip_y_mm", "attitude_deg"], traj
            ),
        }
        fig = plots.planetary_trajectory_figure(tr, m, self.name, self.seedling_box)
        files.update(plots.figure_files(fig, f"{self.name}.trajectory"))
        return {"kind": "planetary", "parameters": params, "results": results}, files
