"""The mechanism as designed: four-bar and open-chain linkages, the seed-004 differential planetary
train, agronomic metrics of the tip's path, the seed's twelve objectives and the optimiser.

Analysis and synthesis: four-bar kinematics and dynamics, Denavit–Hartenberg chains, Burmester
four-pose synthesis and seed 002's open 3R chain (:mod:`~transplanter.design.linkage`); the planetary
train of non-circular gears (:mod:`~transplanter.design.planetary`), what its tip does in the soil
(:mod:`~transplanter.design.agronomy`), seed 004's objectives i–xii
(:mod:`~transplanter.design.objectives`) and differential evolution over a problem's variables
(:mod:`~transplanter.design.optimise`; its generations on many workers by dask.distributed,
:mod:`~transplanter.design.cluster`).

Takes
    link dimensions and pitch curves (:mod:`transplanter.geometry.pitch`).
Gives
    trajectories and attitudes as numpy arrays, metrics and objectives as frozen dataclasses.
May import
    :mod:`transplanter.core` and :mod:`transplanter.geometry`; the maths (``linkage``,
    ``planetary``, ``agronomy``, ``objectives``) numpy and scipy only.
"""
