"""transplanter: from seedling-transplanting mechanism designs to parts a shop can cut.

The package is laid out by the stations a part passes through, lowest first; each imports only
from the ones before it (``tests/test_layout.py`` holds it):

``core``
    errors, tolerances, checked inputs, precision, extremes.
``geometry``
    pitch curves, cutters, teeth, tooth spaces, interference, incomplete gears, cams.
``design``
    linkages, the planetary train, agronomy, objectives, the optimiser.
``shop``
    arcs, wire machining, solids, DXF, STL, STEP, 3MF, atomic exports.
``proof``
    meshing, the train and the follower rebuilt, clearance over a cycle.
``machine``
    whole machines' bodies posed over the cycle, their parts, the animation.
``report``
    HTML reports and plots.
``families``
    part scripts and their studies, built into ``exports/``.
``app``
    the ``transplanter`` command, the pytest plugin, testing helpers.

Modules that stood at the top before 0.2 (``transplanter.teeth``, ``transplanter.pitch``,
``transplanter.families.gears`` …) are still importable under those names: each is the same
module object as its new home (``transplanter.MOVED``).
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import os
import platform
import sys

__version__ = "0.1.0"

#: numpy's dispatch groups past AVX2 (numpy >= 2.4's names), turned off by :func:`_same_kernels`
WIDER_THAN_AVX2 = "X86_V4 AVX512_ICL AVX512_SPR"


def _x86_flags() -> list[str]:
    """The CPU's feature flags where it is an x86-64 that says them (Linux's /proc/cpuinfo), else []."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return []
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as f:
            return next((line.split(":", 1)[1].split() for line in f if line.startswith("flags")), [])
    except OSError:
        return []


def _same_kernels() -> None:
    """Pick the same floating-point kernels on every x86-64 machine with AVX2, so a build's files
    are byte-identical wherever they are rebuilt (the golden record's digests too).

    numpy and OpenBLAS choose their SIMD kernels by the CPU they run on, and an AVX-512 kernel can
    round a last bit differently from an AVX2 one (a sine, a matrix product): on an AVX-512
    machine 7 of seed 000's 49 files differed from the record made on an AVX2 one, and none with
    these two settings. Set before numpy is first imported (they are read then), and only where the
    user has set neither: ``OPENBLAS_CORETYPE=Haswell`` (OpenBLAS's AVX2 kernels, numpy's and
    scipy's copies alike) and, for numpy >= 2.4, ``NPY_DISABLE_CPU_FEATURES`` = the dispatch groups
    past AVX2. A process that imported numpy before transplanter keeps its kernels."""
    if "numpy" in sys.modules or "avx2" not in _x86_flags():
        return
    os.environ.setdefault("OPENBLAS_CORETYPE", "Haswell")
    try:
        from importlib.metadata import version

        major, minor = (int(v) for v in version("numpy").split(".")[:2])
    except Exception:  # noqa: BLE001 - no numpy metadata: leave its dispatch alone
        return
    if (major, minor) >= (2, 4):
        os.environ.setdefault("NPY_DISABLE_CPU_FEATURES", WIDER_THAN_AVX2)


_same_kernels()

#: the former path of every moved module (without ``transplanter.``) -> where it lives now
MOVED = {
    **{m: f"core.{m}" for m in ("errors", "tolerances", "precision", "extrema", "inputs")},
    **{
        m: f"geometry.{m}"
        for m in (
            "pitch",
            "proportions",
            "backlash",
            "cutter",
            "cams",
            "contact",
            "interference",
            "tooth_spaces",
            "teeth",
            "pair_gate",
            "cutter_choice",
            "sweep",
            "incomplete",
        )
    },
    **{m: f"design.{m}" for m in ("linkage", "planetary", "agronomy", "objectives", "optimise")},
    **{m: f"shop.{m}" for m in ("arcs", "machining", "solids", "dxf", "stl", "step", "threemf", "export", "formats")},
    **{
        m: f"proof.{m}"
        for m in ("mesh_engine", "mesh_refine", "meshing", "train_rebuild", "follower", "validate", "clearance")
    },
    **{m: f"machine.{m}" for m in ("carriers", "arm_parts", "carrier_parts", "animation")},
    "plots": "report.plots",
    **{m: f"app.{m}" for m in ("cli", "pytest_plugin", "testing")},
    **{
        f"families.{m}": f"families.builder.{m}"
        for m in ("build", "workers", "scripts", "manifest", "checking", "study", "making")
    },
    **{
        f"families.{m}": f"families.pairs.{m}"
        for m in ("pitch", "pair_cut", "pair_proof", "pair_assembly", "gear_pair", "incomplete_pair")
    },
    "families.gears": "families.pairs.toothed",
    **{f"families.{m}": f"families.mechanisms.{m}" for m in ("linkage", "plates", "synthesis", "cams", "trains")},
    "families.machine": "families.machines.planetary_machine",
    "families.machine_record": "families.machines.record",
    **{f"families.{m}": f"families.machines.{m}" for m in ("carrier_machine", "carrier_making")},
}


class _Moved(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports a former path (``transplanter.teeth``, ``transplanter.pitch.intermittent``) as the
    module that lives at its new one — the same object, so classes and caches are shared."""

    @staticmethod
    def _target(fullname: str) -> str | None:
        """The new path of ``fullname`` if it or a package above it moved (``MOVED``), else None:
        asked of every import, so a lookup per dotted prefix, not a scan of ``MOVED``."""
        if not fullname.startswith("transplanter."):
            return None
        rest = fullname.removeprefix("transplanter.")
        old = rest
        while True:  # a moved package's submodules move with it: the longest moved prefix
            new = MOVED.get(old)
            if new is not None:
                return "transplanter." + new + rest[len(old) :]
            if "." not in old:
                return None
            old = old.rsplit(".", 1)[0]

    def find_spec(self, fullname, path=None, target=None):
        return importlib.util.spec_from_loader(fullname, self) if self._target(fullname) else None

    def create_module(self, spec):
        return importlib.import_module(self._target(spec.name))

    def exec_module(self, module) -> None:
        """The module was run at its new path; nothing to run again."""


if not any(isinstance(f, _Moved) for f in sys.meta_path):
    sys.meta_path.insert(0, _Moved())  # before the path finder, which would load a second copy
