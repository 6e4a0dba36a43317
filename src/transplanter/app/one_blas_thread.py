"""One OpenBLAS thread per process for the ``transplanter`` command, unless the user sets
``OPENBLAS_NUM_THREADS``: imported by :mod:`~transplanter.app.cli` before anything imports numpy.

transplanter's arrays are small (thousands of points), and where the command works in parallel
it does so with processes: a build's parts, a search's workers, a pair's STEP and plots. Its BLAS
calls gain nothing from more threads. OpenBLAS (numpy's copy and scipy's) starts one thread per
core, and those threads spin: that cost a ``transplanter pair`` call 0.18 s of CPU on 2 cores, 3 %,
for the same files (issue 46). Only the command does this: a program that imports transplanter
keeps the BLAS threads it chose (``tests/conftest.py`` imports this module, so the tests run
as the command does).
"""

import os
import sys

if "numpy" not in sys.modules:  # numpy's OpenBLAS reads it once, when numpy is first imported
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
