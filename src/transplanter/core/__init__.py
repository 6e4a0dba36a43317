"""The vocabulary every station shares: one exception hierarchy, named tolerances, checked user
input, the precision figures are written with, and the search for a function's true extremes.

Takes
    nothing from the rest of the package (numpy and scipy only).
Gives
    :mod:`~transplanter.core.errors` (``TransplanterError`` and its subclasses, each naming the
    parameter, its value and its limit), :mod:`~transplanter.core.tolerances` (each tolerance with
    the reason for its value), :mod:`~transplanter.core.inputs` (numbers, booleans, folders and files
    a user hands in, checked in one place), :mod:`~transplanter.core.precision`, :mod:`~transplanter.core.extrema` and
    :mod:`~transplanter.core.text` (text from data printed as text) and :mod:`~transplanter.core.files`
    (the one reader of every file build and check open: regular files only, size-limited, never
    blocking on a FIFO or following a link), :mod:`~transplanter.core.heap` (the memory a stage
    freed handed back to the system before the next).
May import
    nothing of transplanter: this is the lowest layer (``tests/test_layout.py``).
"""
