"""Part families: the scripts in ``parts/`` and building them into ``exports/``.

A part script is a short Python file that defines ``family()`` returning a :class:`Family`
(like manifold3d's ``examples/*.py`` define ``run()``). The builder loads each script,
builds every part of the family into ``<out>/<family>/``, writes every file atomically, and
records parameters, results, errors and file hashes in ``<out>/<family>/manifest.json``.
A part that fails leaves the other parts and its own previous files intact; its error goes
into the manifest and the build reports failure.

Part kinds so far
-----------------
``ArmStudy``
    A four-bar planting arm: seed 000 Table 2 metrics (JSON and CSV), the tip path relative
    to frame and ground, and the speed/acceleration diagrams (PNG and SVG).
``BalancingStudy``
    Mass data of a four-bar: harmonic analysis of the shaking force, crank torque,
    counterweight and multi-arm phasing (seed 003), as JSON and plots.
``PitchPairStudy``
    A conjugate pair of pitch curves: closure, ratio check, curvature, pressure angle,
    tooth count and module (JSON), the curves as CSV points, and plots.
``PlanetaryStudy``
    A planetary transplanting train: agronomic metrics beside published values, the
    sensitivity to stated variants, the trajectory (CSV) and plots.
"""

from __future__ import annotations

import hashlib
import math
import re
import runpy
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from transplanter import plots
from transplanter.agronomy import TransplantingMetrics, transplanting_metrics
from transplanter.errors import PartScriptError, SpecError, TransplanterError
from transplanter.export import atomic_write, csv_bytes, json_bytes
from transplanter.linkage import dynamics as dyn
from transplanter.linkage.fourbar import FourBar, Link
from transplanter.linkage.planting import PlantingArm, PlantingMetrics
from transplanter.pitch import GearPair, Mesh
from transplanter.planetary import DifferentialTrain

__all__ = [
    "ArmStudy",
    "BalancingStudy",
    "PitchPairStudy",
    "PlanetaryStudy",
    "Family",
    "load_family",
    "discover",
    "build_family",
]

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")


def _check_name(kind: str, name: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise SpecError.out_of_range(f"{kind} name", name, "letters, digits, '_', '-', '.' (a file name)")
    return name


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
class ArmStudy:
    """Kinematic study of a planting arm at a planting depth (mm)."""

    arm: PlantingArm
    planting_depth: float

    @property
    def name(self) -> str:
        return self.arm.name

    def plot_files(self, m: PlantingMetrics) -> dict[str, bytes]:
        """Tip path and speed/acceleration diagrams, PNG and SVG, by file name."""
        files = {}
        for fmt in ("png", "svg"):
            files[f"{self.name}.path.{fmt}"] = plots.figure_bytes(plots.coupler_curve_figure(self.arm, m), fmt)
            files[f"{self.name}.kinematics.{fmt}"] = plots.figure_bytes(plots.kinematics_figure(self.arm, m), fmt)
        return files

    def build(self, out: Path) -> tuple[dict, dict[str, bytes]]:
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
        return {"kind": "arm", "parameters": params, "results": results}, files


@dataclass(frozen=True)
class BalancingStudy:
    """Shaking force, crank torque, counterweight and phasing of a four-bar with mass data."""

    name: str
    linkage: FourBar
    masses: dyn.MassModel
    crank_speed: float
    n_arms: tuple[int, ...] = (2, 4, 6, 8)
    n_harmonics: int = 9

    def build(self, out: Path) -> tuple[dict, dict[str, bytes]]:
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
        for fmt in ("png", "svg"):
            fig = plots.shaking_figure(deg, force, torque, f"{self.name}: shaking force and crank torque")
            files[f"{self.name}.shaking.{fmt}"] = plots.figure_bytes(fig, fmt)
        return {"kind": "balancing", "parameters": params, "results": results}, files


def _r(value: float, digits: int = 9) -> float | None:
    """Rounded for the manifest; None for inf (JSON has no infinity: "no limit")."""
    v = float(value)
    return round(v, digits) if math.isfinite(v) else None


def _curve_summary(curve, teeth: int, module: float) -> dict:
    return {
        "lobes": curve.lobes,
        "teeth": teeth,
        "module_mm": _r(module),
        "perimeter_mm": _r(curve.perimeter),
        "radius_min_mm": _r(curve.min_radius().value),
        "radius_max_mm": _r(curve.max_radius().value),
        "convex": bool(curve.is_convex),
        "min_convex_radius_of_curvature_mm": _r(curve.min_convex_radius()),
        "min_concave_radius_of_curvature_mm": _r(curve.min_concave_radius()),
        "max_pressure_deviation_deg": _r(math.degrees(curve.max_pressure_deviation())),
    }


@dataclass(frozen=True)
class PitchPairStudy:
    """A conjugate pitch-curve pair with its tooth sizing.

    Give ``teeth`` (driver tooth count) to derive the module, or ``module`` (mm) to scale the
    curves to a whole number of teeth of that module.
    """

    name: str
    pair: GearPair
    teeth: int | None = None
    module: float | None = None
    require_convex: bool = False

    def build(self, out: Path) -> tuple[dict, dict[str, bytes]]:
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
            "centre_distance_mm": _r(pair.centre_distance, 12),
            "closure_error_rad": float(f"{pair.closure_error:.3e}"),
            "ratio_error": float(f"{pair.ratio_error():.3e}"),
            "centre_distance_error_mm": float(f"{pair.centre_distance_error():.3e}"),
            "scale_applied": _r(sizing.scale, 12),
            "driver": _curve_summary(pair.driver, sizing.teeth[0], sizing.module),
            "driven": _curve_summary(pair.driven, sizing.teeth[1], sizing.module),
        }
        if pair.mesh is Mesh.EXTERNAL:
            results["convexity_index_p"] = _r(pair.convexity_index().p)
        phi = np.linspace(0.0, 2 * math.pi, 3601)[:-1]
        files = {f"{self.name}.pitch.json": json_bytes({"parameters": params, "results": results})}
        for role, curve in (("driver", pair.driver), ("driven", pair.driven)):
            pts = curve.points(phi)
            rows = [[f"{a:.6f}", f"{x:.9f}", f"{y:.9f}"] for a, (x, y) in zip(np.degrees(phi), pts, strict=True)]
            files[f"{self.name}.{role}.csv"] = csv_bytes(["polar_angle_deg", "x_mm", "y_mm"], rows)
        for fmt in ("png", "svg"):
            files[f"{self.name}.pitch.{fmt}"] = plots.figure_bytes(plots.pitch_pair_figure(pair, self.name), fmt)
        return {"kind": "pitch_pair", "parameters": params, "results": results}, files


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
        rows = [[q, _r(v, 6), ref.get(q, ""), u] for q, v, u in m.table()]
        params = {
            "centre_distance_mm": _r(tr.pair.centre_distance, 12),
            "lobes": list(tr.pair.lobes),
            "planets": tr.planets,
            "speed_ratio_ring_to_carrier": _r(tr.speed_ratio, 12),
            "carrier_start_deg": _r(math.degrees(tr.carrier_start)),
            "arm_tip_S_mm": tr.arm.tip,
            "arm_knee_H1_mm": tr.arm.knee,
            "arm_mount_beta_deg": _r(math.degrees(tr.arm.mount)),
            "seedling_box_mm": list(self.seedling_box),
            "plant_spacing_mm": self.plant_spacing,
            "planting_depth_mm": self.planting_depth,
            "gearbox_radius_mm": self.gearbox_radius,
        }
        results = {
            "metrics": {q: {"value": _r(v, 6), "unit": u, "published": ref.get(q)} for q, v, u in m.table()},
            "phase_error_mm": float(f"{tr.phase_error():.3e}"),
            "trajectory_closure_mm": float(f"{tr.closure_error():.3e}"),
            "variants": {
                label: {q: _r(v, 6) for q, v, _ in self.metrics(variant).table()} for label, variant in self.variants
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
        for fmt in ("png", "svg"):
            fig = plots.planetary_trajectory_figure(tr, m, self.name, self.seedling_box)
            files[f"{self.name}.trajectory.{fmt}"] = plots.figure_bytes(fig, fmt)
        return {"kind": "planetary", "parameters": params, "results": results}, files


Part = ArmStudy | BalancingStudy | PitchPairStudy | PlanetaryStudy


@dataclass(frozen=True)
class Family:
    """A named set of parts defined by one part script."""

    name: str
    description: str
    parts: tuple[Part, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        _check_name("family", self.name)
        object.__setattr__(self, "parts", tuple(self.parts))
        seen: set[str] = set()
        for p in self.parts:
            if not isinstance(p, Part):
                raise PartScriptError(
                    f"family {self.name!r}: parts must be one of ArmStudy, BalancingStudy, PitchPairStudy, "
                    f"PlanetaryStudy; got {type(p).__name__}"
                )
            _check_name("part", p.name)
            if p.name in seen:
                raise PartScriptError(f"family {self.name!r}: part name {p.name!r} is used twice")
            seen.add(p.name)


def load_family(path: str | Path) -> Family:
    """Run a part script and return the :class:`Family` its ``family()`` builds.

    Raises
    ------
    PartScriptError
        If the file is missing, does not parse, lacks ``family()``, raises, or returns
        something that is not a Family. The message names the script (and line).
    """
    p = Path(path)
    if not p.is_file():
        raise PartScriptError(f"part script {p} does not exist")
    try:
        ns = runpy.run_path(str(p), run_name="transplanter_part_script")
    except SyntaxError as exc:
        raise PartScriptError(f"{p}:{exc.lineno}: syntax error: {exc.msg}") from exc
    except TransplanterError as exc:
        raise PartScriptError(f"{p}: {exc}") from exc
    except Exception as exc:  # a user script can raise anything; report where
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: {type(exc).__name__}: {exc}") from exc
    fn = ns.get("family")
    if not callable(fn):
        raise PartScriptError(f"{p}: a part script must define family() returning transplanter.families.Family")
    try:
        fam = fn()
    except TransplanterError as exc:
        raise PartScriptError(f"{p}: {exc}") from exc
    except Exception as exc:
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: family() raised {type(exc).__name__}: {exc}") from exc
    if not isinstance(fam, Family):
        raise PartScriptError(f"{p}: family() returned {type(fam).__name__}, expected transplanter.families.Family")
    return fam


def _script_line(exc: BaseException, path: Path) -> str:
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if Path(f.filename).resolve() == path.resolve()]
    return str(frames[-1].lineno) if frames else "?"


def discover(parts_dir: str | Path) -> list[Path]:
    """Part scripts in ``parts_dir`` (``*.py`` not starting with ``_``), sorted by name."""
    d = Path(parts_dir)
    if not d.is_dir():
        raise PartScriptError(f"parts folder {d} does not exist (run from the project root or pass scripts)")
    return sorted(p for p in d.glob("*.py") if not p.name.startswith("_"))


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def build_family(family: Family, out_dir: str | Path, progress: Callable[[str], None] | None = None) -> dict:
    """Build every part of ``family`` into ``out_dir/<family.name>/``; returns the manifest.

    The manifest (also written as ``manifest.json``) lists for each part its parameters,
    results, files with SHA-256, or its error. ``manifest["ok"]`` is False if any part failed.
    """
    root = Path(out_dir) / family.name
    manifest: dict = {"family": family.name, "description": family.description, "parts": {}, "ok": True}
    for part in family.parts:
        if progress is not None:
            progress(f"{family.name}/{part.name}")
        try:
            record, files = part.build(root)
        except TransplanterError as exc:
            manifest["parts"][part.name] = {"error": f"{type(exc).__name__}: {exc}"}
            manifest["ok"] = False
            continue
        for fname, data in sorted(files.items()):
            atomic_write(root / fname, data)
        record["files"] = {fname: _sha256(data) for fname, data in sorted(files.items())}
        manifest["parts"][part.name] = record
    atomic_write(root / "manifest.json", json_bytes(manifest))
    return manifest
