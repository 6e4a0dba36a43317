"""Names a module gave before issue 41 split it, still found there: a module ``__getattr__`` that
looks each one up, on first use, in the module it moved to.

Examples
--------
>>> getattr_ = forward("old", {"pi": "math"})
>>> getattr_("pi")
3.141592653589793
>>> getattr_("tau")
Traceback (most recent call last):
...
AttributeError: module 'old' has no attribute 'tau'
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

__all__ = ["forward"]


def forward(module: str, moved: dict[str, str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``module``: each name of ``moved`` is taken from the module
    named beside it (imported when first asked for, so no import circle), any other name is the
    usual ``AttributeError``."""

    def __getattr__(name: str) -> Any:
        if name in moved:
            return getattr(importlib.import_module(moved[name]), name)
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__
