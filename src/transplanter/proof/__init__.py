"""Proofs on the made parts: meshing, the train and the follower rebuilt, clearance over a cycle.

The *prove* station. Each proof states the true extreme over the continuous motion within a stated
bound — sampled, then refined where a grid could step over a narrow dip: the meshing of two made
outlines (:mod:`~transplanter.proof.meshing` with its sweep :mod:`~transplanter.proof.mesh_engine`
and refinement :mod:`~transplanter.proof.mesh_refine`), the seed-004 train rebuilt from the meshing
(:mod:`~transplanter.proof.train_rebuild`), the cam follower run on the made contour
(:mod:`~transplanter.proof.follower`), the smallest distance between two moving bodies
(:mod:`~transplanter.proof.clearance`), gathered in :mod:`~transplanter.proof.validate`.

Takes
    outlines re-read from the shop files (DXF, STL sections) and the designed motion.
Gives
    figures with their bound (mm, degrees) as frozen dataclasses.
May import
    :mod:`transplanter.core`, :mod:`transplanter.geometry`, :mod:`transplanter.design` and
    :mod:`transplanter.shop`.
"""
