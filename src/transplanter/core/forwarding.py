"""Names a module gave before issue 41 split it, still found there: a module ``__getattr__`` that
looks each one up, on first use, in the module it moved to.

A forwarded name can also be a former module path: ``transplanter.families.gear_pair`` is the
one-call function and the old path of :mod:`transplanter.families.pairs.gear_pair`. Importing
that path set the package's attribute to the module, so from then on ``from
transplanter.families import gear_pair`` gave the module, in that process, and a test
elsewhere broke depending on the order. A forwarding module therefore keeps its names:
an import of a submodule of the same name leaves the attribute alone (:class:`Forwarding`). The
module stays in ``sys.modules`` under its path, so ``from transplanter.families.gear_pair import
pair_family`` still works; only ``import transplanter.families.gear_pair as m`` and the dotted
``transplanter.families.gear_pair.pair_family`` now give the function's side, which one name
cannot avoid: use ``transplanter.families.pairs.gear_pair`` for the module.

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
import sys
import types
from collections.abc import Callable
from typing import Any

__all__ = ["Forwarding", "forward"]


class Forwarding(types.ModuleType):
    """A module that forwards names (:func:`forward`): a submodule imported under one of them does
    not replace it as the module's attribute. Pickled (cloudpickle: a part's build key, a search's
    cost function) as a module is, by its name."""

    def __setattr__(self, name: str, value: Any) -> None:
        if isinstance(value, types.ModuleType) and name in self.__dict__.get("_FORWARDED", ()):
            return
        super().__setattr__(name, value)

    def __reduce__(self):
        return importlib.import_module, (self.__name__,)


def forward(module: str, moved: dict[str, str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``module``: each name of ``moved`` is taken from the module
    named beside it (imported when first asked for, so no import circle), any other name is the
    usual ``AttributeError``."""

    here = sys.modules.get(module)
    if here is not None and type(here) is types.ModuleType:  # a module being run: keep its names
        here.__class__ = Forwarding
        here.__dict__["_FORWARDED"] = frozenset(moved)

    def __getattr__(name: str) -> Any:
        if name in moved:
            return getattr(importlib.import_module(moved[name]), name)
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__
