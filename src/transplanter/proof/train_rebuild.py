"""The train rebuilt from the made parts: the seed-004 train with the planet attitude taken from the
geometric meshing of the parts (the design contact angle plus the measured ``driven_error``)
instead of the pitch curves; the report is the needle-tip distance from the designed trajectory
at every meshing step.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from transplanter.core.precision import significant
from transplanter.geometry.pitch import GearPair
from transplanter.proof.meshing import MeshReport

__all__ = ["TrainReport", "measured_error", "meshed_train", "train_check", "turned_within_play"]


def measured_error(angle, error, phi1) -> np.ndarray:
    """The driven gear's rotation beyond its design angle at driver angles ``phi1`` (rad), from a
    meshing measured at ``angle`` → ``error`` (rad, one driver turn), interpolated periodically."""
    return np.interp(np.mod(phi1, 2 * math.pi), angle, error, period=2 * math.pi)


@dataclass(frozen=True)
class _MeshedPair:
    """A pair whose driven contact angle comes from the parts' geometric meshing."""

    pair: GearPair
    angle: np.ndarray
    error: np.ndarray

    @property
    def centre_distance(self) -> float:
        return self.pair.centre_distance

    @property
    def lobes(self) -> tuple[int, int]:
        return self.pair.lobes

    @property
    def driver(self):
        return self.pair.driver

    @property
    def ring(self) -> str | None:
        return self.pair.ring

    def ratio(self, phi1):
        return self.pair.ratio(phi1)

    def driven_contact_angle(self, phi1):
        phi1 = np.asarray(phi1, dtype=float)
        return self.pair.driven_contact_angle(phi1) + self.pair.contact_sense * measured_error(
            self.angle, self.error, phi1
        )


@dataclass(frozen=True)
class TrainReport:
    """Needle-tip path of the train rebuilt from the parts against the designed one."""

    theta: np.ndarray = field(repr=False)
    deviation: np.ndarray = field(repr=False)
    attitude_error: np.ndarray = field(repr=False)
    #: the train as rebuilt from the parts (its planets turned by the parts' meshing)
    made: object = field(default=None, repr=False, compare=False)

    @property
    def max_deviation(self) -> float:
        return float(self.deviation.max())

    def summary(self) -> dict:
        return {
            "samples": len(self.theta),
            "carrier_turns": round(float(np.ptp(self.theta)) / (2 * math.pi), 3),
            "max_tip_deviation_mm": significant(self.max_deviation),
            "rms_tip_deviation_mm": significant(np.sqrt(np.mean(self.deviation**2))),
            "max_needle_attitude_error_deg": significant(math.degrees(np.max(np.abs(self.attitude_error)))),
        }


def train_check(train, report: MeshReport) -> TrainReport:
    """Rebuild ``train`` (a ``planetary.DifferentialTrain``) with the planet attitude from the
    parts' meshing in ``report`` (from :func:`mesh_check` of its ring and planet) and compare the
    needle tip with the designed one at every meshing step (ring body angle → carrier angle)."""
    meshed = meshed_train(train, report.driver_angle, report.driven_error)
    # arm I's contact is at ring body angle -(1 - ω1/ω2) θ
    theta = (2 * math.pi - report.driver_angle) / (1.0 - train.speed_ratio)
    design, made = train.state(theta), meshed.state(theta)
    dev = np.linalg.norm(made.tip - design.tip, axis=1)
    att = np.angle(np.exp(1j * (made.attitude - design.attitude)))
    return TrainReport(theta, dev, att, meshed)


def meshed_train(train, driver_angle, driven_error):
    """``train`` with its planets turned by the measured meshing: ``driven_error`` (rad, the
    driven gear's rotation beyond the design angle at driving-flank contact) at ring body angles
    ``driver_angle`` (rad), interpolated periodically between them."""
    angle, error = np.asarray(driver_angle, dtype=float), np.asarray(driven_error, dtype=float)
    return dataclasses.replace(train, pair=_MeshedPair(train.pair, angle, error))


def turned_within_play(train, report: MeshReport, turn: float):
    """``train`` rebuilt from the parts' meshing in ``report`` with every planet turned a further
    ``turn`` rad (its attitude where the play lets it sit: ± half the free play over the planet's
    pitch radius), for judging the objectives at the worst place the play allows."""
    error = np.asarray(report.driven_error, dtype=float) + float(turn)
    return dataclasses.replace(train, pair=_MeshedPair(train.pair, report.driver_angle, error))
