"""The Denavit-Hartenberg loop of seed 000 and its conversion to the vector loop.

Seed 000 (Kim & Chung) numbers the links 1 = frame, 2 = crank, 3 = coupler, 4 = rocker and
writes the loop as a product of 3x3 displacement matrices ``A2 A3 A4 A1 = I`` with::

    A_i = [[1, 0, 0],
           [a_i cos t_i, cos t_i, -sin t_i],
           [a_i sin t_i, sin t_i,  cos t_i]]

where ``t_i`` is the *relative* angle from X_(i-1) to X_i. Reading the chain: the crank
pivot is the origin of the frame system X1Y1, ``t2`` is the crank angle from X1, the crank
pin sits at ``a2 e(t2)``, the rocker pin at ``+ a3 e(t2+t3)``, the rocker pivot at
``+ a4 e(t2+t3+t4)`` and ``A1`` brings the chain back along +X1, so the rocker pivot is at
``(-a1, 0)`` in the frame system. The drawing (reference) system XY is X1Y1 turned by ``phi``
counter-clockwise (matrix D of eq. 8-3).

The coupler point is given as (X3P, Y3P) in the system X3Y3 obtained after ``A2 A3``: origin
at the *rocker pin*, x axis along crank pin -> rocker pin. In the vector-loop coupler frame
(origin at the crank pin) the same point is ``(a3 + X3P, Y3P)``.

Examples
--------
>>> import numpy as np
>>> from transplanter.design.linkage.dh import DHFourBar
>>> mech_b = DHFourBar(a1=125.0, a2=40.0, a3=100.0, a4=85.0, phi=np.radians(322.0))
>>> fb = mech_b.to_fourbar()
>>> round(fb.ground, 6), round(float(np.degrees(fb.ground_angle)) % 360, 6)
(125.0, 142.0)
>>> mech_b.coupler_point(-273.8, 63.3)
(-173.8, 63.3)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from transplanter.design.linkage.fourbar import FourBar, FourBarMotion, Link

__all__ = ["DHFourBar", "displacement_matrix"]


def displacement_matrix(a: float | np.ndarray, theta: float | np.ndarray) -> np.ndarray:
    """Seed 000's 3x3 homogeneous displacement matrix A(a, theta), shape (..., 3, 3)."""
    a = np.asarray(a, dtype=float)
    th = np.asarray(theta, dtype=float)
    a, th = np.broadcast_arrays(a, th)
    c, s = np.cos(th), np.sin(th)
    m = np.zeros(a.shape + (3, 3))
    m[..., 0, 0] = 1.0
    m[..., 1, 0] = a * c
    m[..., 2, 0] = a * s
    m[..., 1, 1] = c
    m[..., 1, 2] = -s
    m[..., 2, 1] = s
    m[..., 2, 2] = c
    return m


def _rotation_matrix(phi: float) -> np.ndarray:
    """Matrix D of seed 000 eq. 8-3 (a pure rotation in homogeneous form)."""
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


@dataclass(frozen=True)
class DHFourBar:
    """A crank-rocker described as in seed 000 (lengths in mm, ``phi`` in rad).

    ``branch`` has the meaning of :class:`~transplanter.design.linkage.fourbar.FourBar.branch`.
    """

    a1: float
    a2: float
    a3: float
    a4: float
    phi: float = 0.0
    branch: int = 1

    def to_fourbar(self) -> FourBar:
        """The same linkage in the vector-loop convention, crank pivot at the origin."""
        return FourBar(
            ground=self.a1,
            crank=self.a2,
            coupler=self.a3,
            rocker=self.a4,
            ground_angle=self.phi + math.pi,
            branch=self.branch,
        )

    def crank_angle(self, theta2_dh: float | np.ndarray) -> np.ndarray:
        """Absolute crank angle (vector loop) for seed 000's ``theta2`` (from X1)."""
        return np.asarray(theta2_dh, dtype=float) + self.phi

    def coupler_point(self, x3: float, y3: float) -> tuple[float, float]:
        """(X3P, Y3P) in the rocker-pin frame -> (u, v) in the crank-pin coupler frame."""
        return (self.a3 + float(x3), float(y3))

    def relative_angles(self, motion: FourBarMotion) -> dict[int, np.ndarray]:
        """Seed 000's pair variables t1..t4 (rad, wrapped to [0, 2 pi)) from a solved motion."""
        t2 = motion.theta[Link.CRANK] - self.phi
        t3 = motion.theta[Link.COUPLER] - motion.theta[Link.CRANK]
        # direction rocker pin -> rocker pivot is the rocker angle + pi
        t4 = motion.theta[Link.ROCKER] + math.pi - motion.theta[Link.COUPLER]
        t1 = -(t2 + t3 + t4)
        return {k: np.mod(v, 2 * math.pi) for k, v in {1: t1, 2: t2, 3: t3, 4: t4}.items()}

    def loop_product(self, motion: FourBarMotion) -> np.ndarray:
        """``A2 A3 A4 A1`` at every crank angle, (n, 3, 3); the identity when the loop closes."""
        t = self.relative_angles(motion)
        return (
            displacement_matrix(self.a2, t[2])
            @ displacement_matrix(self.a3, t[3])
            @ displacement_matrix(self.a4, t[4])
            @ displacement_matrix(self.a1, t[1])
        )

    def point_by_matrices(self, motion: FourBarMotion, x3: float, y3: float) -> np.ndarray:
        """Coupler point by seed 000 eq. 8-3, ``D A2 A3 [1, X3, Y3]^T``, as (n, 2) mm."""
        t = self.relative_angles(motion)
        chain = _rotation_matrix(self.phi) @ displacement_matrix(self.a2, t[2]) @ displacement_matrix(self.a3, t[3])
        h = chain @ np.array([1.0, x3, y3])
        return h[:, 1:]
