"""Burmester synthesis studies: circle/centre points, the open-chain 3R mechanism, plots."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from transplanter.core.precision import rounded, significant
from transplanter.design.linkage.open_chain import OpenChain3R
from transplanter.families.builder.study import Built, StudyDefaults
from transplanter.report import plots
from transplanter.shop.export import csv_bytes, json_bytes

__all__ = ["SynthesisStudy"]


@dataclass(frozen=True)
class SynthesisStudy(StudyDefaults):
    """Burmester synthesis and the open-chain 3R mechanism ``chain`` built on it.

    ``boxes`` restricts the feasible region (``FourPoses.feasible`` keywords); ``link_range``
    (mm) applies to links 1 and 2.
    """

    cost = 2

    name: str
    chain: OpenChain3R
    boxes: dict = field(default_factory=dict)
    link_range: tuple[float, float] = (70.0, 100.0)
    x_range: tuple[float, float] = (-150.0, 150.0)
    step: float = 0.05

    def build(self, out: Path) -> Built:
        """Circle- and centre-point curves with the feasible region, link lengths and ratios, the
        trajectory, plots."""
        ch = self.chain
        sample = ch.poses.sample(self.x_range, self.step)
        feasible = ch.poses.feasible(sample, link1=self.link_range, link2=self.link_range, **self.boxes)
        l1, l2, l3 = ch.link_lengths
        tau = np.linspace(0.0, 2 * math.pi, 1441)
        st = ch.state(tau)
        ratio = ch.two_stage_ratio(tau)
        params = {
            "poses": [[p.x, p.y, rounded(math.degrees(p.theta))] for p in ch.poses.poses],
            "arm_attitudes_deg": [rounded(math.degrees(a)) for a in ch.arm_attitudes],
            "circle_point_mm": [rounded(v) for v in ch.circle],
            "extra_link2": [[rounded(math.degrees(t)), rounded(math.degrees(v))] for t, v in ch.extra_link2],
            "extra_link3": [[rounded(math.degrees(t)), rounded(math.degrees(v))] for t, v in ch.extra_link3],
            "feasible_boxes": {k: list(v) for k, v in self.boxes.items()},
            "link_range_mm": list(self.link_range),
        }
        results = {
            "centre_point_mm": [rounded(v) for v in ch.centre],
            "link_lengths_mm": [rounded(l1), rounded(l2), rounded(l3)],
            "ratio_L2_L1": rounded(l2 / l1),
            "ratio_L3_L2": rounded(l3 / l2),
            "pose_error_mm": significant(ch.pose_error()),
            "pose_carrier_angles_deg": [rounded(math.degrees(t)) for t in ch.pose_tau],
            "circle_curve_samples": len(sample.circle),
            "feasible_samples": int(feasible.sum()),
            "trajectory_height_mm": rounded(float(np.ptp(st.tip[:, 1]))),
            "trajectory_width_mm": rounded(float(np.ptp(st.tip[:, 0]))),
            "link2_swing_deg": rounded(math.degrees(float(np.ptp(ch.beta2(tau))))),
            "two_stage_ratio_range": [rounded(float(ratio.min())), rounded(float(ratio.max()))],
        }
        rows = [
            [f"{a:.4f}", f"{b:.6f}", f"{c:.6f}", f"{d:.6f}", f"{e:.6f}", f"{f:.6f}", int(g)]
            for (a, b), (c, d), e, f, g in zip(
                sample.circle, sample.centre, sample.link1, sample.link2, feasible, strict=True
            )
        ]
        files = {
            f"{self.name}.synthesis.json": json_bytes({"parameters": params, "results": results}),
            f"{self.name}.circle_points.csv": csv_bytes(
                ["circle_x_mm", "circle_y_mm", "centre_x_mm", "centre_y_mm", "link1_mm", "link2_mm", "feasible"], rows
            ),
            f"{self.name}.trajectory.csv": csv_bytes(
                ["tau_deg", "tip_x_mm", "tip_y_mm", "arm_deg", "two_stage_ratio"],
                [
                    [f"{t:.4f}", f"{x:.6f}", f"{y:.6f}", f"{a:.6f}", f"{i:.9f}"]
                    for t, (x, y), a, i in zip(np.degrees(tau), st.tip, np.degrees(st.arm), ratio, strict=True)
                ],
            ),
        }
        fig = plots.synthesis_figure(ch, sample, feasible, self.name)
        files.update(plots.figure_files(fig, f"{self.name}.synthesis"))
        return Built({"kind": "synthesis", "parameters": params, "results": results}, files)
