"""Four-bar studies: a planting arm's kinematics, and balancing with mass data."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from transplanter.design.linkage import dynamics as dyn
from transplanter.design.linkage.fourbar import FourBar, Link
from transplanter.design.linkage.planting import PlantingArm, PlantingMetrics
from transplanter.families.builder.study import Built, StudyDefaults, Table
from transplanter.report import plots
from transplanter.shop.export import csv_bytes, json_bytes

__all__ = ["ArmStudy", "BalancingStudy"]


def _linkage_params(fb: FourBar) -> dict:
    """The linkage's dimensions as manifest parameters (mm, deg)."""
    return {
        "ground_mm": fb.ground,
        "crank_mm": fb.crank,
        "coupler_mm": fb.coupler,
        "rocker_mm": fb.rocker,
        "ground_angle_deg": math.degrees(fb.ground_angle),
        "branch": fb.branch,
    }


@dataclass(frozen=True)
class ArmStudy(StudyDefaults):
    """Kinematic study of a planting arm at a planting depth (mm)."""

    arm: PlantingArm
    planting_depth: float

    @property
    def name(self) -> str:
        """The arm's name (its files' stem)."""
        return self.arm.name

    def tables(self) -> list[Table]:
        """Seed 000's Table 2 metrics of the arm at its planting depth."""
        m = self.arm.metrics(planting_depth=self.planting_depth)
        title = f"{self.name}  ({self.arm.linkage.grashof_class().value})"
        return [Table(title, tuple((label, value, unit, None) for label, value, unit in m.table()))]

    def analysis_files(self) -> dict[str, bytes]:
        """The tip path and kinematics plots (``transplanter analyse --plots``)."""
        return self.plot_files(self.arm.metrics(planting_depth=self.planting_depth))

    def plot_files(self, m: PlantingMetrics) -> dict[str, bytes]:
        """Tip path and speed/acceleration diagrams, PNG and SVG, by file name."""
        return {
            **plots.figure_files(plots.coupler_curve_figure(self.arm, m), f"{self.name}.path"),
            **plots.figure_files(plots.kinematics_figure(self.arm, m), f"{self.name}.kinematics"),
        }

    def build(self, out: Path) -> Built:
        """Seed 000 Table 2 metrics and transmission angles (JSON, CSV), the tip path and the
        speed/acceleration diagrams."""
        m = self.arm.metrics(planting_depth=self.planting_depth)
        rows = m.table()
        fb = self.arm.linkage
        params = {
            **_linkage_params(fb),
            "tip_mm": list(self.arm.tip),
            "crank_speed_rad_s": self.arm.crank_speed,
            "forward_speed_mm_s": self.arm.forward_speed,
            "angle_reference_deg": math.degrees(self.arm.angle_reference),
            "planting_depth_mm": self.planting_depth,
            "grashof_class": fb.grashof_class().name,
        }
        mu = fb.transmission_angle(fb.solve(np.linspace(0, 2 * math.pi, 721)))
        results = {label: {"value": round(value, 9), "unit": unit} for label, value, unit in rows}
        results["transmission angle min"] = {"value": round(math.degrees(float(mu.min())), 9), "unit": "deg"}
        results["transmission angle max"] = {"value": round(math.degrees(float(mu.max())), 9), "unit": "deg"}
        files = {
            f"{self.name}.metrics.json": json_bytes({"parameters": params, "metrics": results}),
            f"{self.name}.metrics.csv": csv_bytes(["quantity", "value", "unit"], [[a, b, c] for a, b, c in rows]),
        }
        files.update(self.plot_files(m))
        return Built({"kind": "arm", "parameters": params, "results": results}, files)


@dataclass(frozen=True)
class BalancingStudy(StudyDefaults):
    """Shaking force, crank torque, counterweight and phasing of a four-bar with mass data."""

    name: str
    linkage: FourBar
    masses: dyn.MassModel
    crank_speed: float
    n_arms: tuple[int, ...] = (2, 4, 6, 8)
    n_harmonics: int = 9

    def build(self, out: Path) -> Built:
        """Shaking force and its harmonics, crank torque, counterweight and multi-arm phasing
        (JSON), and plots."""
        fb = self.linkage
        fb.require_full_rotation()
        n = 720
        rel = 2 * math.pi * np.arange(n) / n  # crank angle from the ground link
        motion = fb.solve(fb.ground_angle + rel, self.crank_speed)
        com = dyn.centre_of_mass(motion, self.masses)
        h = {axis: dyn.harmonics(com.acceleration[:, k] / 1000, self.n_harmonics) for k, axis in enumerate("xy")}
        force = dyn.shaking_force(motion, self.masses)
        torque = dyn.crank_torque(motion, self.masses)
        cw = {c: dyn.counterweight(fb, self.masses, self.crank_speed, c) for c in ("vertical", "rotating")}
        total = self.masses.total_mass
        phasing = {}
        for k in self.n_arms:
            for scheme in ("paired", "even"):
                if scheme == "paired" and k % 2:
                    continue
                ph = dyn.arm_phases(k, scheme)
                phasing[f"{k} arms, {scheme}"] = {
                    "phases_deg": [round(math.degrees(p), 6) for p in ph],
                    "harmonic_gain": [round(g, 9) for g in dyn.phasing_gain(ph, self.n_harmonics)],
                }
        results = {
            "total_moving_mass_kg": total,
            "com_acceleration_harmonics_m_s2": {
                axis: {
                    "A": [round(float(v), 9) for v in hh.A],
                    "B": [round(float(v), 9) for v in hh.B],
                    "R": [round(float(v), 9) for v in hh.R],
                    "phase_deg": [round(math.degrees(float(v)), 6) for v in hh.phase],
                }
                for axis, hh in h.items()
            },
            "shaking_force_peak_N": round(float(np.max(np.hypot(force[:, 0], force[:, 1]))), 9),
            "crank_torque_N_m": {"min": round(float(torque.min()), 9), "max": round(float(torque.max()), 9)},
            "counterweight": {
                c: {
                    "mass_moment_kg_mm": round(w.mass_moment, 9),
                    "angle_on_crank_deg": round(math.degrees(w.angle_on_crank) % 360, 6),
                    "angle_from_ground_link_deg": round(math.degrees(w.angle_on_crank + fb.ground_angle) % 360, 6),
                    "radius_for_total_mass_mm": round(w.radius_for(total), 9),
                }
                for c, w in cw.items()
            },
            "phasing": phasing,
            "sinusoidal_rocker_moment_kg_mm": [
                round(v, 9) for v in dyn.sinusoidal_rocker_moment(fb, self.masses.coupler)
            ],
            "force_balance_moments_kg_mm": {
                k.value: [round(v, 9) for v in mom]
                for k, mom in dyn.force_balance_moments(fb, self.masses.coupler).items()
            },
        }
        params = {
            **_linkage_params(fb),
            "crank_speed_rad_s": self.crank_speed,
            "masses": {
                k.value: {"mass_kg": lm.mass, "com_mm": list(lm.com), "inertia_kg_mm2": lm.inertia}
                for k in (Link.CRANK, Link.COUPLER, Link.ROCKER)
                for lm in [self.masses.of(k)]
            },
        }
        files = {f"{self.name}.balancing.json": json_bytes({"parameters": params, "results": results})}
        deg = np.degrees(rel)
        fig = plots.shaking_figure(deg, force, torque, f"{self.name}: shaking force and crank torque")
        files.update(plots.figure_files(fig, f"{self.name}.shaking"))
        return Built({"kind": "balancing", "parameters": params, "results": results}, files)
