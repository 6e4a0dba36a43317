"""Planetary train studies: agronomic metrics beside published values, variants, plots; the
seed-004 objectives beside other designs; the carrier plate."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from transplanter.core.errors import GeometryError, SpecError, finite_array, finite_positive
from transplanter.core.precision import rounded, significant
from transplanter.design.agronomy import TransplantingMetrics, transplanting_metrics
from transplanter.design.objectives import Objective, Site, box_depth, gearbox_radius, seed004_objectives, worst_of
from transplanter.design.planetary import DifferentialTrain
from transplanter.families.builder.making import Making, manufacture
from transplanter.families.builder.study import Built, StudyDefaults, Table
from transplanter.geometry.cutter import ShaperCutter
from transplanter.geometry.interference import SCREEN_CUTTERS, fouling_screen
from transplanter.geometry.pair_gate import generate_pair
from transplanter.proof import validate
from transplanter.proof.train_rebuild import turned_within_play
from transplanter.report import plots
from transplanter.shop import formats
from transplanter.shop.export import csv_bytes, json_bytes
from transplanter.shop.solids import circle_polygon

__all__ = ["FrontPoint", "PlanetaryStudy", "TrainProof", "non_dominated"]


@dataclass(frozen=True)
class TrainProof:
    """The train a gear pair drives, as the pair's proof hook (``families.pair_proof.TrainHook``):
    the ring/planet pair of ``train`` is meshed from its made parts, and for each source the train
    is rebuilt from that meshing and its needle tip compared with the design; with ``site``, seed
    004's objectives are measured again on the rebuilt train (:mod:`transplanter.design.objectives`) and a
    missed one fails the part. Its planets are made ``train.planets`` times, placed on the carrier
    as the assembly record says."""

    train: DifferentialTrain
    #: where the train works; None: the needle tip is compared, the objectives are not measured
    site: Site | None = None
    #: ``(objective number, margin)``: what each must keep with the planets anywhere in their play
    #: (mm or deg); judged on the train rebuilt from the shop's DXF
    keep: tuple[tuple[str, float], ...] = ()
    #: a margin not kept fails the part (False: it is said in the results, beside the verdicts)
    must_keep: bool = False

    @property
    def planets(self) -> int:
        return self.train.planets

    @property
    def centre_distance(self) -> float:
        return self.train.pair.centre_distance

    def _under_play(self, report, module: float, turn: float) -> dict:
        """Each objective's worst value and margin with the planets turned to either end of the
        play (± ``turn`` rad, the bound the proof states over the arm's length) on the train rebuilt
        from the parts: the margins that survive the pair's own play (figures; issue 27 asks a
        re-design to keep v >= 2 deg, i >= 3 mm, vi >= 2 mm of them), and the needle tip's envelope
        over a carrier turn (720 positions): its largest distance from the design path."""
        theta = 2 * math.pi * np.arange(720) / 720  # carrier turn
        design = self.train.state(theta).tip
        envelope = np.zeros(len(theta))
        measured = []
        for sign in (-1.0, 1.0):
            played = turned_within_play(self.train, report, sign * turn)
            envelope = np.maximum(envelope, np.linalg.norm(played.state(theta).tip - design, axis=1))
            measured.append(seed004_objectives(played, self.site, module))
        worst = {f"{o.number} {o.name}": o for o in worst_of(*measured)}
        keep = dict(self.keep)
        need = {key: keep[o.number] for key, o in worst.items() if o.number in keep}
        short = {key: round(need[key] - worst[key].margin, 6) for key in need if worst[key].margin < need[key]}

        def said(key: str, o) -> str:
            kept = (
                ""
                if key not in need
                else f", must keep {need[key]:g}: " + (f"short by {short[key]:.3g}" if key in short else "kept")
            )
            return f"{o.value:.4g} {o.unit} (margin {o.margin:+.3g}{kept})".replace("  ", " ")

        at = int(np.argmax(envelope))
        # where it matters: at the picking point (deepest into the box) and the push (lowest)
        pick = int(np.argmax(box_depth(design, self.site)))
        push = int(np.argmin(design[:, 1]))
        return {
            "turn_deg": rounded(math.degrees(turn), 6),
            # the needle tip's envelope under the play: how far from the design path it can sit
            "tip_envelope_mm": {
                "max": rounded(float(envelope[at]), 6),
                "at_carrier_deg": rounded(math.degrees(theta[at]), 3),
                "at_picking": rounded(float(envelope[pick]), 6),
                "picking_at_carrier_deg": rounded(math.degrees(theta[pick]), 3),
                "at_pushing": rounded(float(envelope[push]), 6),
                "pushing_at_carrier_deg": rounded(math.degrees(theta[push]), 3),
            },
            **{key: said(key, o) for key, o in worst.items()},
            "margins_to_keep": keep,
            "margins_short_mm_or_deg": short,
        }

    def carrier(self) -> dict:
        """How many planets to make, and where they sit on the carrier."""
        n = self.train.planets
        offsets = -2 * math.pi * np.arange(n) / n  # arm k's carrier line, from arm I's
        contact = self.train.pair.driven_contact_angle(offsets)  # on each planet, at the start
        return {
            "planets": n,
            # counter-clockwise in the ring's DXF frame: planet k's contact with the ring lies on its
            # carrier line, where the ring meets it at the start (arm k+1 is where arm k will be
            # after a further 360/N deg of clockwise carrier turn)
            "planet_carrier_angles_deg": [rounded(math.degrees(o) % 360.0) for o in offsets],
            # the planet's DXF +x from its carrier line (centre of the ring -> planet centre), turning
            # counter-clockwise: its pitch point at polar angle `contact` then meets the ring
            "planet_body_angle_to_carrier_line_deg": [rounded(math.degrees(-c) % 360.0) for c in contact],
            "ring_contact_angles_deg": [rounded(math.degrees(o) % 360.0) for o in offsets],
        }

    def prove(self, source: str, report, found: list[str], module: float) -> tuple[object, dict, list[str]]:
        """The train rebuilt from ``report`` (``source``'s meshing, whose problems are ``found``):
        its check, its figures, and the problems it finds."""
        check = validate.train_check(self.train, report)
        res = check.summary()
        problems = []
        # the planet may turn by (half the backlash + transmission error) / its pitch radius
        # off the design: the needle tip by S times that at most
        bound = (
            self.train.arm.tip
            * (report.backlash_max.value / 2 + report.max_transmission_error)
            / self.train.pair.driven.min_radius().value
        )
        res["predicted_bound_mm"] = rounded(bound, 6)
        if not found and check.max_deviation > bound:
            problems.append(
                f"{source}: the train rebuilt from the parts leaves the design by "
                f"{check.max_deviation:.4g} mm, more than the {bound:.4g} mm its backlash allows"
            )
        if found:
            res["note"] = "from the contact at the pitch point; the problems above are ignored"
        if self.site is not None and source == "dxf":  # the shop's file: the objectives where its play lets the arm sit
            played = self._under_play(report, module, bound / self.train.arm.tip)
            res["objectives_under_play"] = played
            if self.must_keep:
                keep = dict(self.keep)
                problems += [
                    f"{source}: with the planets anywhere in their play, objective {key} keeps "
                    f"{keep[key.split()[0]] - gap:.3g} of the {keep[key.split()[0]]:g} margin it must keep"
                    for key, gap in played["margins_short_mm_or_deg"].items()
                ]
        if self.site is not None:
            objectives = seed004_objectives(check.made, self.site, module)
            res["objectives"] = {f"{o.number} {o.name}": f"{o.verdict} (limit {o.limit})" for o in objectives}
            problems += [
                f"{source}: the train rebuilt from the parts misses objective "
                f"{o.number} {o.name} = {o.value:.4g} {o.unit} (limit {o.limit})"
                for o in objectives
                if not o.ok
            ]
        return check, res, problems


@dataclass(frozen=True)
class FrontPoint:
    """A design on the trade-off between the module and the objectives' margins."""

    label: str
    #: the module its teeth can be cut at, mm (0: none)
    module: float
    #: its smallest objective margin beyond what each must keep (mm or deg; < 0: one is short)
    margin: float
    #: the objective that has it
    binding: str
    #: this study's own design
    chosen: bool = False
    #: it meets the search's hard rules (every objective at the design place, the gear rules)
    feasible: bool = True


def non_dominated(points) -> list[bool]:
    """Which of ``points`` (``FrontPoint``) are on the front: feasible, and beaten by no other
    feasible point in both module and margin."""
    pool = [p for p in points if p.feasible]
    return [
        p in pool
        and not any(
            (q.module >= p.module and q.margin >= p.margin) and (q.module > p.module or q.margin > p.margin)
            for q in pool
        )
        for p in points
    ]


@dataclass(frozen=True)
class PlanetaryStudy(StudyDefaults):
    """Agronomic study of a planetary transplanting train.

    ``reference`` holds published values ``(quantity, value, unit)`` to tabulate beside the
    computed ones (quantities as in :meth:`TransplantingMetrics.table`); ``variants`` holds
    ``(label, train)`` alternatives whose metrics show what the result depends on.

    **Objectives.** With ``site`` and ``module`` (of the teeth cut for the train, mm) the study
    measures seed 004's twelve objectives (:mod:`transplanter.design.objectives`) and tabulates them
    with value, limit and pass beside ``compare`` — other ``(label, train, module)`` designs
    (module 0: none meshes) — and the paper's own figures from ``reference``; with
    ``must_meet`` a missed objective fails the part. The gearbox radius then follows from the
    ring and the module (``objectives.gearbox_radius``) instead of ``gearbox_radius``.

    **Pareto front.** ``front`` holds :class:`FrontPoint` designs — each the best a search found
    for one least module (the part script's design problem says how its module and margin are
    measured) — plotted as module against the smallest objective margin, the non-dominated ones
    joined, this design starred; and the constraint that stops this design's next coarser tooth
    count is named with its numbers (with ``min_ring_addendum``, ring tips shorter than that count
    as the reason they fail).

    **Carrier plate.** ``carrier = (outer radius mm, Making)`` makes the plate (DXF, STL); its
    ``Making.features`` carry the central bore and the planet-shaft holes, which must lie on the
    carrier radius (the pair's centre distance) at equal spacing, the first on +x (arm I) —
    checked on the re-read DXF.
    """

    cost = 6

    name: str
    train: DifferentialTrain
    seedling_box: tuple[float, float]
    plant_spacing: float
    planting_depth: float
    #: radius of the gearbox circle, mm (objective x's height above ground); None with ``module``:
    #: derived from the ring and the module (``objectives.gearbox_radius``)
    gearbox_radius: float | None = None
    reference: tuple[tuple[str, float, str], ...] = ()
    variants: tuple[tuple[str, DifferentialTrain], ...] = ()
    site: Site | None = None
    module: float | None = None
    compare: tuple[tuple[str, DifferentialTrain, float], ...] = ()
    must_meet: bool = False
    carrier: tuple[float, Making] | None = None
    front: tuple[FrontPoint, ...] = ()
    #: the shortest ring tips (modules) the design's teeth may have (the binding constraint's rule)
    min_ring_addendum: float | None = None

    def __post_init__(self) -> None:
        finite_positive("plant_spacing", self.plant_spacing)
        finite_positive("planting_depth", self.planting_depth)
        if not isinstance(self.seedling_box, tuple | list) or len(self.seedling_box) != 2:
            raise SpecError.out_of_range("seedling_box", self.seedling_box, "(x, y) in mm")
        finite_array("seedling_box", list(self.seedling_box))
        if (self.site is None) != (self.module is None):
            raise SpecError(f"{self.name}: give both site and module (objectives), or neither")
        if self.module is not None:
            finite_positive("module", self.module)
        elif self.gearbox_radius is None:
            raise SpecError(f"{self.name}: give gearbox_radius (mm), or site and module to derive it")
        else:
            finite_positive("gearbox_radius", self.gearbox_radius)
        if self.carrier is not None and not (len(self.carrier) == 2 and isinstance(self.carrier[1], Making)):
            raise SpecError(f"{self.name}: carrier must be (outer radius in mm, Making)")

    def tables(self) -> list[Table]:
        """The agronomic metrics beside the published values (``reference``)."""
        ref = {q: v for q, v, _ in self.reference}
        rows = tuple((label, value, unit, ref.get(label)) for label, value, unit in self.metrics().table())
        return [Table(f"{self.name}  (planetary, {self.train.planets} arms)", rows)]

    def metrics(self, train: DifferentialTrain | None = None) -> TransplantingMetrics:
        """Seed 004's agronomic metrics of ``train`` (default: this study's) at its site."""
        tr = train or self.train
        radius = self.gearbox_radius
        if self.module is not None:
            radius = gearbox_radius(tr.pair.driver.max_radius().value, self.module)
        return transplanting_metrics(tr, self.seedling_box, self.plant_spacing, self.planting_depth, radius)

    def objectives(self) -> dict[str, tuple[Objective, ...]]:
        """This design's objectives, then each compared design's, by label."""
        out = {"this design": seed004_objectives(self.train, self.site, self.module)}
        for label, train, module in self.compare:
            out[label] = seed004_objectives(train, self.site, module or 1.0)
            if not module:  # no module meshes: objective xi reads 0
                out[label] = tuple(dataclasses.replace(o, value=0.0) if o.number == "xi" else o for o in out[label])
        return out

    def _objective_table(self) -> tuple[dict, list[str]]:
        found = self.objectives()
        ref = {q: v for q, v, _ in self.reference}
        labels = list(found)
        columns = ["objective", "limit"] + [f"{lb}" for lb in labels] + ["paper"]
        rows = []
        for k, o in enumerate(found["this design"]):
            cells = [f"{o.number}. {o.name}", o.limit]
            for lb in labels:
                other = found[lb][k]
                cells.append(other.verdict)
            paper = ref.get(o.name, ref.get("module") if o.number == "xi" else None)
            cells.append(f"{paper:g} {o.unit}" if paper is not None else "met (stated)")
            rows.append(cells)
        missed = [
            f"{o.number} {o.name} = {o.value:.4g} {o.unit} (limit {o.limit})" for o in found["this design"] if not o.ok
        ]
        return {"columns": columns, "rows": rows, "all_met": not missed}, missed

    def _front(self) -> tuple[list, str, dict[str, bytes]]:
        points = list(self.front)
        best = non_dominated(points)
        rows = [
            {
                "label": p.label,
                "chosen": p.chosen,
                "feasible": p.feasible,
                "pareto": ok,
                "module_mm": rounded(p.module, 6),
                "smallest_margin": rounded(p.margin, 6),
                "binding_objective": p.binding,
            }
            for p, ok in zip(points, best, strict=True)
        ]
        binding = self._binding()
        fig = plots.front_figure(rows, self.name, binding)
        files = plots.figure_files(fig, f"{self.name}.front")
        keys = list(rows[0])
        files[f"{self.name}.front.csv"] = csv_bytes(keys, [[r[k] for k in keys] for r in rows])
        return rows, binding, files

    def _binding(self) -> str:
        """Why the design's teeth cannot be one step coarser, with the numbers: the screen's
        verdict, or the cutter's, for the first cutter and planet addendum it tries."""
        pair = self.train.pair
        teeth = round(pair.driver.perimeter / (math.pi * self.module))
        coarser = teeth - pair.driver.lobes
        sized, sizing = pair.sized(teeth=coarser)
        reasons = []
        for z0 in SCREEN_CUTTERS:
            for pin in (1.0, 0.8):
                cutter = ShaperCutter(z0, sizing.module)
                lim = fouling_screen(sized, cutter, pinion_addendum=pin)
                found = lim.problems(("ring", "planet"), trochoid=False)
                if not found and self.min_ring_addendum is not None and lim.ring_addendum < self.min_ring_addendum:
                    found = [
                        f"the ring's tips must be trimmed to {lim.ring_addendum:g} m (fillet/cutter limit "
                        f"{lim.max_ring_addendum:.3f} m), under the {self.min_ring_addendum:g} m required"
                    ]
                if not found:
                    try:
                        generate_pair(
                            sized, cutter, sizing.teeth, addendum=(lim.ring_addendum, pin), check_interference=False
                        )
                        found = ["clear"]
                    except GeometryError as exc:
                        found = [f"the cutter cannot make it: {exc}"]
                reasons.append(f"{z0}-tooth cutter, planet addendum {pin:g} m: {found[0]}")
        return (
            f"binding at {coarser} ring teeth (m = {sizing.module:.3f} mm, one step coarser than {teeth}): "
            f"{reasons[0]} (and {len(reasons) - 1} other cutter/addendum choices: "
            f"{sum(r.endswith('clear') for r in reasons)} clear)"
        )

    def _carrier_plate(self) -> tuple[dict, dict[str, bytes]]:
        radius, making = self.carrier
        tr = self.train
        a = tr.pair.centre_distance
        holes = making.features.holes
        want = [
            (a * math.cos(2 * math.pi * k / tr.planets), a * math.sin(2 * math.pi * k / tr.planets))
            for k in range(tr.planets)
        ]
        if len(holes) != tr.planets or max(math.dist(h[:2], w) for h, w in zip(holes, want, strict=True)) > 1e-9:
            raise GeometryError(
                f"{self.name}: the carrier plate needs {tr.planets} planet-shaft holes at radius {a:.6g} mm, "
                f"120 deg apart from +x (Features.bolt_circle({tr.planets}, {a:.6g}, d)); got {holes}"
            )
        stem = f"{self.name}.carrier"
        notes = (
            f"carrier plate: {tr.planets} planet shafts on R{a:.4f} mm, {360 / tr.planets:g} deg apart",
            "mates: the planets on their shafts, inside the ring; the carrier shaft in the bore",
            "timing: the shaft on +x carries arm I",
            f"width {making.width:g} mm",
        ) + (
            # drawn, not cut: another part (seed 004's machine) cuts its carrier plates to this layout
            ("the planet layout the shop cuts the machine's carrier plates to: their bearing seats on these centres",)
            if making.quantity == 0
            else ()
        )
        res, files, _ = manufacture(
            stem,
            circle_polygon(0.0, 0.0, radius),
            shapely.Polygon(),
            making,
            notes,
            lambda pt: f"({pt[0]:.1f}, {pt[1]:.1f})",
        )
        # the shop's reading: the planet-shaft holes' centres from the re-read DXF, each design
        # hole matched with the nearest re-read round hole of its diameter
        area = math.pi * (holes[0][2] / 2) ** 2
        rounds = [shapely.Polygon(c) for c in formats.DXF.contours(files[f"{stem}.dxf"])]
        centres = [p.centroid.coords[0] for p in rounds if abs(p.area - area) < 1e-3 * area]
        err = max((min(math.dist(c, w) for c in centres) for w in want), default=math.inf)
        if len(centres) != tr.planets or err > 1e-3:
            raise GeometryError(
                f"{self.name}: the carrier DXF's {len(centres)} planet holes re-read {err:.3g} mm from the design"
            )
        res["planet_holes_readback_mm"] = significant(err)
        return res, files

    def build(self, out: Path) -> Built:
        """Agronomic metrics beside the published values, the variants, the trajectory (CSV),
        plots; with made parts, the carrier plate and the trade-off of coarser modules."""
        m = self.metrics()
        tr = self.train
        extra_files: dict[str, bytes] = {}
        objectives = None
        if self.site is not None:
            objectives, missed = self._objective_table()
            if missed and self.must_meet:
                raise GeometryError(f"{self.name}: the design misses objectives: " + "; ".join(missed))
        carrier = None
        if self.carrier is not None:
            carrier, extra_files = self._carrier_plate()
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
            "gearbox_radius_mm": rounded(
                self.gearbox_radius
                if self.module is None
                else gearbox_radius(tr.pair.driver.max_radius().value, self.module)
            ),
        }
        if self.module is not None:
            params["module_mm"] = rounded(self.module, 12)
        results = {
            "metrics": {q: {"value": rounded(v, 6), "unit": u, "published": ref.get(q)} for q, v, u in m.table()},
            "phase_error_mm": significant(tr.phase_error()),
            "trajectory_closure_mm": significant(tr.closure_error()),
            "variants": {
                label: {q: rounded(v, 6) for q, v, _ in self.metrics(variant).table()}
                for label, variant in self.variants
            },
        }
        if objectives is not None:
            results["objectives"] = objectives
        if carrier is not None:
            results["carrier_plate"] = carrier
        if self.front:
            rows, binding, made = self._front()
            results["pareto_front"] = {
                "columns": list(rows[0]),
                "rows": [list(r.values()) for r in rows],
                "binding_constraint": binding,
            }
            extra_files.update(made)
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
        files.update(extra_files)
        return Built({"kind": "planetary", "parameters": params, "results": results}, files)
