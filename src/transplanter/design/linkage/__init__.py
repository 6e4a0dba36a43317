"""Linkage analysis and synthesis: four-bar kinematics, conventions, planting metrics, dynamics.

:mod:`~transplanter.design.linkage.fourbar` (closed-form positions, speeds and accelerations of a
four-bar on either branch), :mod:`~transplanter.design.linkage.dh` (seed 000's Denavit–Hartenberg
description), :mod:`~transplanter.design.linkage.planting` (the tip's path to frame and ground and
seed 000's Table 2 metrics), :mod:`~transplanter.design.linkage.dynamics` (shaking force, crank
torque, balancing; seed 003), :mod:`~transplanter.design.linkage.burmester` (four-pose synthesis)
and :mod:`~transplanter.design.linkage.open_chain` (seed 002's open 3R chain).

Takes
    link lengths (mm), angles (rad), speeds (rad/s) and masses.
Gives
    positions and their derivatives as numpy arrays, metrics as frozen dataclasses.
May import
    :mod:`transplanter.core` only; numpy and scipy, no geometry kernel or file format.
"""
