"""Families themselves: a part script loaded with its folder (:mod:`~.scripts`), the optimum
written into a design module's tuple (:mod:`~.optimum`), what the builder asks
of a study (the :class:`~.study.Study` protocol, :mod:`~.study`), how a prismatic part is made into
its shop files (:mod:`~.making`), the manifest a build records and the check that a manifest read
from disk has that shape (:mod:`~.manifest`), building parts in worker processes (:mod:`~.workers`),
building a family into a folder in one transaction (:mod:`~.build`) and ``transplanter check``
(:mod:`~.checking`).

May import
    the stations below :mod:`transplanter.families` (core … report); no study.
"""
