"""Proofs on the made parts: meshing, the train and the follower rebuilt, clearance over a cycle.

The *prove* station. Each proof states the true extreme over the continuous motion within a stated
bound — sampled, then refined where a grid could step over a narrow dip: the meshing of two made
outlines (:mod:`~transplanter.proof.meshing` with its sweep :mod:`~transplanter.proof.mesh_engine`
and refinement :mod:`~transplanter.proof.mesh_refine`), the seed-004 train rebuilt from the meshing
(:mod:`~transplanter.proof.train_rebuild`), the cam follower run on the made contour
(:mod:`~transplanter.proof.follower`), the smallest distance between two moving bodies
(:mod:`~transplanter.proof.clearance`), how deep one crosses another where they meet
(:mod:`~transplanter.proof.crossing`) and how far two files of one part lie apart, certified, so a
meshing proof made on one carries to the other (:mod:`~transplanter.proof.sameness`), gathered
in :mod:`~transplanter.proof.validate`. Under load: each tooth's radius of curvature, Hertz and ISO
6336-3 root stress measured on its own outline (:mod:`~transplanter.proof.tooth_stress`), and the
normal force, stresses and safety factors at a contact of a made pair
(:mod:`~transplanter.proof.mesh_load`), over a whole cycle with the made teeth closed against the
mesh's torque at each position (:mod:`~transplanter.proof.mesh_cycle`).

Takes
    outlines re-read from the shop files (DXF, STL sections) and the designed motion.
Gives
    figures with their bound (mm, degrees) as frozen dataclasses.
May import
    :mod:`transplanter.core`, :mod:`transplanter.geometry`, :mod:`transplanter.design` and
    :mod:`transplanter.shop`.
"""
