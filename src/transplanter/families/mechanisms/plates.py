"""Link plates of a four-bar planting arm: frame, crank, coupler with its finger, rocker.

Each link is a flat plate of one thickness, drawn in its own frame (``linkage.fourbar``: the
crank from ``O2`` along O2->B, the coupler from ``B`` along B->C, the rocker from ``O4``
along O4->C; the frame plate in the linkage's frame, ``O2`` at the linkage origin):

- a boss (a disc of the joint's boss diameter) round every joint and a hole of the joint's
  diameter in it: the moving joints B and C and the rocker pivot O4 take ``pin``, the crank
  pivot O2 takes ``shaft`` (keyed to the crank by a DIN 6885-1 key, running in the frame);
- each plate is the convex hull of its bosses; the coupler adds its planting finger, the hull
  of the nearer joint's boss and a round nose of radius ``nose`` centred on the designed tip;
  inside corners are rounded by ``FILLET_MM`` so a wire can cut them;
- the frame plate carries the designed tip path on its ANNOTATION layer (frame coordinates),
  and the coupler a cross at the tip.

**The proof.** The shop's reading is rebuilt from the files: each hole's and the nose's centre
is the mean centre of the DXF arcs that draw it (arcs of its radius near the designed place),
the link lengths, the pivots and the tip in the coupler frame follow from those centres, the
four-bar they make is solved over a crank turn, and its tip path must match the designed one
within ``TIP_PATH_TOL_MM``. ``<name>.assembly.3mf`` stacks the plates at crank angle 0 (the
arm's angle reference), frame, crank, coupler, rocker, each a plate thickness plus ``gap``
(a washer) above the one before, and must show no two overlapping.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import shapely

from transplanter.core.errors import GeometryError, SpecError, check_number, finite_positive
from transplanter.core.precision import rounded, significant
from transplanter.core.tolerances import ARC_RADIUS_MM, TIP_PATH_TOL_MM
from transplanter.design.linkage.fourbar import FourBar, Link
from transplanter.design.linkage.planting import PlantingArm
from transplanter.families.builder.making import Making, assembly_file, check_shop_files, manufacture
from transplanter.families.builder.study import Built, Checked, StudyDefaults
from transplanter.shop import formats
from transplanter.shop.export import json_bytes
from transplanter.shop.solids import Features, circle_polygon

__all__ = ["Joint", "LinkPlatesStudy", "finger_for_centre_of_mass", "TIP_PATH_TOL_MM", "FILLET_MM"]

#: radius of the inside corners where the finger meets the coupler bar, mm
FILLET_MM = 3.0
#: crank positions of the tip-path comparison over one turn
PATH_STEPS = 3600
LINKS = ("frame", "crank", "coupler", "rocker")


@dataclass(frozen=True)
class Joint:
    """What turns in a plate's hole: ``name`` (the part to buy, the fit), the hole's diameter
    and the boss round it, mm."""

    name: str
    hole: float
    boss: float

    def __post_init__(self) -> None:
        finite_positive("joint hole", self.hole)
        check_number("joint boss", self.boss, self.hole + 2.0, 1e4, unit=f"mm (the hole {self.hole:g} mm + 2 mm wall)")


@dataclass(frozen=True)
class LinkPlatesStudy(StudyDefaults):
    """The four plates of ``arm`` (see the module docstring); ``thickness``, ``nose`` and ``gap``
    in mm; ``making`` gives the wire, DXF versions and material (its width is the plate thickness;
    by default S235JR plate, which each drawing states)."""

    cost = 3

    name: str
    arm: PlantingArm
    pin: Joint
    shaft: Joint
    thickness: float
    nose: float
    gap: float = 0.5
    making: Making = field(default_factory=lambda: Making(width=1.0, material="S235JR"))

    def __post_init__(self) -> None:
        if not isinstance(self.arm, PlantingArm):
            raise SpecError(f"{self.name}: arm must be a linkage.planting.PlantingArm, got {type(self.arm).__name__}")
        finite_positive("plate thickness", self.thickness)
        check_number("finger nose radius", self.nose, 1.0, 1e3, unit="mm")
        check_number("gap", self.gap, 0.0, 100.0, unit="mm")
        fb = self.arm.linkage
        for link, length, a, b in (
            ("crank", fb.crank, self.shaft, self.pin),
            ("coupler", fb.coupler, self.pin, self.pin),
            ("rocker", fb.rocker, self.pin, self.pin),
            ("frame", fb.ground, self.shaft, self.pin),
        ):
            wall = length - (a.hole + b.hole) / 2
            if wall < 2.0:
                raise SpecError.out_of_range(
                    f"{link} length", length, f"enough for its two holes ({a.hole:g} and {b.hole:g} mm) and a 2 mm web"
                )

    # -- geometry in each link's frame ------------------------------------------------------
    def _making(self, link: str) -> Making:
        return Making(
            self.thickness,
            self._features(link),
            wire=self.making.wire,
            dxf_versions=self.making.dxf_versions,
            material=self.making.material,
        )

    def joints(self) -> dict[str, list[tuple[str, float, float, Joint]]]:
        """Each plate's joints ``(label, u, v, joint)`` in its own frame, mm."""
        fb = self.arm.linkage
        o4 = np.subtract(fb.rocker_pivot, fb.origin)
        return {
            "frame": [("O2", 0.0, 0.0, self.shaft), ("O4", float(o4[0]), float(o4[1]), self.pin)],
            "crank": [("O2", 0.0, 0.0, self.shaft), ("B", fb.crank, 0.0, self.pin)],
            "coupler": [("B", 0.0, 0.0, self.pin), ("C", fb.coupler, 0.0, self.pin)],
            "rocker": [("O4", 0.0, 0.0, self.pin), ("C", fb.rocker, 0.0, self.pin)],
        }

    def _blank(self, link: str) -> shapely.Polygon:
        bosses = [circle_polygon(u, v, j.boss / 2) for _, u, v, j in self.joints()[link]]
        body = shapely.convex_hull(shapely.union_all(bosses))
        if link != "coupler":
            return body
        u, v = self.arm.tip
        root = min(bosses[:2], key=lambda b: b.centroid.distance(shapely.Point(u, v)))
        finger = shapely.convex_hull(shapely.union_all([root, circle_polygon(u, v, self.nose)]))
        # round the inside corners where the finger meets the bar: the pieces a closing adds there
        # (elsewhere it only moves the outline by its round-off, so the bosses and the nose stay
        # the exact circle polygons the proof reads back)
        plate = shapely.union(body, finger)
        closed = plate.buffer(FILLET_MM, quad_segs=64).buffer(-FILLET_MM, quad_segs=64)
        ring = np.asarray(shapely.geometry.polygon.orient(plate, 1.0).exterior.coords)[:-1]
        d_in, d_out = ring - np.roll(ring, 1, axis=0), np.roll(ring, -1, axis=0) - ring
        cross = d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0]
        turn = cross / (np.linalg.norm(d_in, axis=1) * np.linalg.norm(d_out, axis=1))
        corners = shapely.multipoints(ring[turn < -1e-3])  # turning clockwise by more than 0.06 deg
        added = shapely.get_parts(shapely.difference(closed, plate))
        fillets = [p for p in added if not corners.is_empty and shapely.distance(p, corners) < 1e-6]
        return shapely.union_all([plate, *fillets])

    def _features(self, link: str) -> Features:
        holes = [(u, v, j.hole) for label, u, v, j in self.joints()[link] if not (link == "crank" and label == "O2")]
        if link == "crank":  # keyed to the drive shaft
            return Features(bore=self.shaft.hole, keyway=True, holes=tuple(holes))
        return Features(holes=tuple(holes))

    def tip_path(self, n: int = PATH_STEPS) -> np.ndarray:
        """The designed tip path over a crank turn, frame coordinates (O2 at the origin), (n, 2) mm."""
        theta = self.arm.angle_reference + 2 * math.pi * np.arange(n) / n
        return self.arm.tip_motion(theta).position - np.asarray(self.arm.linkage.origin)

    # -- the files -------------------------------------------------------------------------
    def _notes(self, link: str) -> tuple[str, ...]:
        fb = self.arm.linkage
        joints = "; ".join(f"{label} dia {j.hole:g} ({j.name})" for label, _, _, j in self.joints()[link])
        length = {"frame": fb.ground, "crank": fb.crank, "coupler": fb.coupler, "rocker": fb.rocker}[link]
        shared = self.joints()
        mates = "; ".join(
            f"{label} with the "
            + " and the ".join(
                other for other in LINKS if other != link and any(lab == label for lab, _, _, _ in shared[other])
            )
            for label, _, _, _ in shared[link]
        )
        notes = [
            f"{link} plate of {self.arm.name}, {self.thickness:g} mm thick",
            f"joint centres {length:.4f} mm apart; holes: {joints}",
            f"mates: {mates}",
            "timing: assembled at crank angle 0 as placed in the assembly 3MF; joint labels on ANNOTATION",
        ]
        if link == "crank":
            notes.append("keyed to the drive shaft at O2 (DIN 6885-1)")
        if link == "coupler":
            u, v = self.arm.tip
            notes.append(f"finger tip (nose R{self.nose:g}) at ({u:.4f}, {v:.4f}) mm from B, x towards C")
        if link == "frame":
            notes.append("tip path over one crank turn drawn on ANNOTATION (frame coordinates)")
        return tuple(notes)

    def _marks(self, link: str) -> tuple:
        marks = [(u, v, label) for label, u, v, _ in self.joints()[link]]
        if link == "coupler":
            marks.append((*self.arm.tip, "TIP"))
        return tuple(marks)

    def _placed(self, parts: dict) -> list:
        """The plates at crank angle 0 (the arm's angle reference), stacked frame to rocker."""
        fb = self.arm.linkage
        m = fb.solve(np.array([self.arm.angle_reference]))
        j = {k: v[0] - np.asarray(fb.origin) for k, v in m.joints().items()}
        pitch = self.thickness + self.gap
        where = {
            "frame": (0.0, 0.0, 0.0),
            "crank": (*j["O2"], float(m.theta[Link.CRANK][0])),
            "coupler": (*j["B"], float(m.theta[Link.COUPLER][0])),
            "rocker": (*j["O4"], float(m.theta[Link.ROCKER][0])),
        }
        return [
            (f"{self.name}.{link}", parts[link], formats.placement(x, y, k * pitch, angle))
            for k, (link, (x, y, angle)) in enumerate((link, where[link]) for link in LINKS)
        ]

    def build(self, out: Path) -> Built:
        """The four plates (DXF, STL, STEP), their 3MF at crank angle 0, and the tip path of the
        four-bar rebuilt from the holes read back from the DXFs (``rebuilt``)."""
        files: dict[str, bytes] = {}
        results: dict = {}
        parts = {}
        path = self.tip_path()
        for link in LINKS:
            res, made, part = manufacture(
                f"{self.name}.{link}",
                self._blank(link),
                shapely.Polygon(),
                self._making(link),
                self._notes(link),
                lambda pt, link=link: f"({pt[0]:.1f}, {pt[1]:.1f}) on the {link}",
                marks=self._marks(link),
                paths=(np.vstack([path, path[:1]]),) if link == "frame" else (),
            )
            results[link] = res
            parts[link] = part
            files.update(made)
        results["assembly"], model = assembly_file(self.name, self._placed(parts))
        files.update(model)
        rebuilt = self.rebuilt(files)
        results["tip_path"] = rebuilt
        if rebuilt["max_deviation_mm"] > TIP_PATH_TOL_MM:
            raise GeometryError(
                f"{self.name}: the four-bar rebuilt from the plates' DXF leaves the designed tip path by "
                f"{rebuilt['max_deviation_mm'] * 1000:.3f} µm (limit {TIP_PATH_TOL_MM * 1000:g} µm)"
            )
        fb = self.arm.linkage
        params = {
            "arm": self.arm.name,
            "links_mm": {"ground": fb.ground, "crank": fb.crank, "coupler": fb.coupler, "rocker": fb.rocker},
            "tip_in_coupler_frame_mm": list(self.arm.tip),
            "thickness_mm": self.thickness,
            "nose_radius_mm": self.nose,
            "gap_mm": self.gap,
            "pin": {"name": self.pin.name, "hole_mm": self.pin.hole, "boss_mm": self.pin.boss},
            "shaft": {"name": self.shaft.name, "hole_mm": self.shaft.hole, "boss_mm": self.shaft.boss},
            "fillet_mm": FILLET_MM,
        }
        files[f"{self.name}.plates.json"] = json_bytes({"parameters": params, "results": results})
        return Built({"kind": "link_plates", "parameters": params, "results": results}, files)

    # -- the proof -------------------------------------------------------------------------
    def _centre(self, contours, u: float, v: float, radius: float, what: str) -> np.ndarray:
        """Mean centre of the DXF arcs of ``radius`` (± ``ARC_RADIUS_MM``) whose centre is within ``radius / 2``
        of (u, v), weighted by their sweep: where the shop finds a hole's or the nose's centre."""
        found, weights = [], []
        for arcs in contours:
            for cx, cy, r, sweep in arcs:
                if abs(r - radius) < ARC_RADIUS_MM and math.hypot(cx - u, cy - v) < radius / 2:
                    found.append((cx, cy))
                    weights.append(sweep)
        if not found or sum(weights) < math.pi / 2:  # a nose shows a half circle less its taper
            raise GeometryError(f"{self.name}: the DXF draws no arc of radius {radius:g} mm about {what}")
        return np.average(np.asarray(found), axis=0, weights=weights)

    def rebuilt(self, files: dict[str, bytes]) -> dict:
        """The four-bar the shop builds from the plates' DXF (see the module docstring), its tip
        path against the designed one: ``{"max_deviation_mm", link lengths, ...}``."""
        centres = {}
        for link, joints in self.joints().items():
            contours = formats.DXF.arc_centres(files[f"{self.name}.{link}.dxf"])
            for label, u, v, j in joints:
                centres[link, label] = self._centre(contours, u, v, j.hole / 2, f"{label} on the {link}")
            if link == "coupler":
                tip = self._centre(contours, *self.arm.tip, self.nose, "the finger tip")
        fb = self.arm.linkage
        b, c = centres["coupler", "B"], centres["coupler", "C"]
        e = (c - b) / np.linalg.norm(c - b)
        local = tip - b
        made = FourBar.from_pivots(
            tuple(centres["frame", "O2"] + fb.origin),
            tuple(centres["frame", "O4"] + fb.origin),
            crank=float(np.linalg.norm(centres["crank", "B"] - centres["crank", "O2"])),
            coupler=float(np.linalg.norm(c - b)),
            rocker=float(np.linalg.norm(centres["rocker", "C"] - centres["rocker", "O4"])),
            branch=fb.branch,
        )
        arm = PlantingArm(
            made,
            (float(local @ e), float(local[1] * e[0] - local[0] * e[1])),
            self.arm.crank_speed,
            angle_reference=self.arm.angle_reference,
        )
        theta = self.arm.angle_reference + 2 * math.pi * np.arange(PATH_STEPS) / PATH_STEPS
        dev = np.linalg.norm(arm.tip_motion(theta).position - self.arm.tip_motion(theta).position, axis=1)
        return {
            "steps": PATH_STEPS,
            "max_deviation_mm": significant(float(dev.max())),
            "tolerance_mm": TIP_PATH_TOL_MM,
            "links_from_holes_mm": {
                "ground": rounded(made.ground, 9),
                "crank": rounded(made.crank, 9),
                "coupler": rounded(made.coupler, 9),
                "rocker": rounded(made.rocker, 9),
            },
            "tip_from_nose_mm": [rounded(x, 9) for x in arm.tip],
        }

    def check(self, files: dict[str, bytes]) -> Checked:
        """Re-run the proof on the files as found: the tip path of the four-bar rebuilt from the
        plates' DXF, each STEP against its DXF, the 3MF assembly."""
        problems = []
        try:
            results = {"tip_path": self.rebuilt(files)}
        except (GeometryError, KeyError, ValueError) as exc:
            results, problems = {"tip_path": {"error": str(exc)}}, [f"tip path: {exc}"]
        else:
            dev = results["tip_path"]["max_deviation_mm"]
            if dev > TIP_PATH_TOL_MM:
                problems.append(
                    f"the four-bar rebuilt from the plates leaves the designed tip path by {dev * 1000:.3f} µm "
                    f"(limit {TIP_PATH_TOL_MM * 1000:g} µm)"
                )
        widths = {f"{self.name}.{link}": self.thickness for link in LINKS}
        results["made"], more = check_shop_files(
            files, widths, (f"{self.name}.assembly.3mf", [f"{self.name}.{link}" for link in LINKS])
        )
        return Checked(results, problems + more)


def finger_for_centre_of_mass(coupler: float, com: tuple[float, float]) -> tuple[float, float]:
    """The finger tip (coupler frame, mm) that puts a uniform-section coupler's centre of mass at
    ``com``: the plate is the bar B->C (length ``coupler``) and a straight finger from B to the
    tip T, of one width and thickness, so ``(c + L) com = (c²/2, 0) + (L/2) T`` with ``L = |T|``
    — for a published centre of mass when the paper gives no tip (seed 003)."""
    from scipy.optimize import brentq

    c = finite_positive("coupler", coupler)
    g = np.asarray(com, dtype=float)

    def lever(length: float) -> np.ndarray:
        return (c + length) * g - np.array([c * c / 2, 0.0])

    def gap(length: float) -> float:
        return float(np.linalg.norm(lever(length))) - length * length / 2

    hi = 4.0 * (c + float(np.linalg.norm(g))) + 10.0
    if not gap(1e-9) > 0 > gap(hi):
        raise SpecError.out_of_range("coupler centre of mass", tuple(com), "reachable by a uniform bar and finger")
    length = brentq(gap, 1e-9, hi, xtol=1e-12)
    tip = lever(length) * 2 / length
    return float(tip[0]), float(tip[1])
