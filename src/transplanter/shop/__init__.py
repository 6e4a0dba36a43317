"""What a shop receives: solids, wire-EDM paths and the files, written atomically and read back.

The *make* station: arcs fitted to outlines (:mod:`~transplanter.shop.arcs`), what a wire can reach
(:mod:`~transplanter.shop.machining`), solids by manifold3d Boolean subtraction
(:mod:`~transplanter.shop.solids`), DXF for wire EDM, binary STL, STEP (OCP) and 3MF
(:mod:`~transplanter.shop.dxf`, :mod:`~transplanter.shop.stl`, :mod:`~transplanter.shop.step`,
:mod:`~transplanter.shop.threemf`), behind one interface that writes a part, reads it back and
verifies it (:mod:`~transplanter.shop.formats`); a family's files as one atomic transaction
(:mod:`~transplanter.shop.export`). What a shop buys by name -- materials, bearings, bushes, keys,
circlips, screws, fits, each row with its standard and source -- in
:mod:`~transplanter.shop.catalogue`, and a machine's bill of materials (made and bought parts,
stable item numbers, one to one with the files) in :mod:`~transplanter.shop.bom`; a machine's
assembly STEP, every body a named solid at its place (:mod:`~transplanter.shop.assembly_step`), read
back by OCP and gmsh (:mod:`~transplanter.shop.assembly_read`), and its assembly drawing with
balloons (:mod:`~transplanter.shop.assembly_drawing`).

Takes
    outlines (shapely polygons, mm) from :mod:`transplanter.geometry` and the studies.
Gives
    bytes that are the same on every rebuild, and what each reader makes of them.
May import
    :mod:`transplanter.core`, :mod:`transplanter.geometry` and :mod:`transplanter.design`.
"""
