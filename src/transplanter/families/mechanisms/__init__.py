"""Mechanism studies: four-bar planting arms and their balancing (:mod:`~.linkage`), their link plates
(:mod:`~.plates`), Burmester synthesis and seed 002's open 3R chain (:mod:`~.synthesis`), disc cams
(:mod:`~.cams`) and planetary trains with their objectives and carrier plate (:mod:`~.trains`).

May import
    :mod:`transplanter.families.builder` and the stations below the families.
"""
