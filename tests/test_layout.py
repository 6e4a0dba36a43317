"""The shape of the code, read from the source (nothing is imported or run): imports one way, in
layers, no circle; modules small; the families reach the shop formats only through ``formats``;
the gear study knows no paper; the maths layer free of adapters (issue 28, ``../shared/STYLE.md``).
"""

from __future__ import annotations

import ast
import functools

import pytest

from layout_graph import LAYERS, MODULES, SRC, imports

#: the maths: numpy and scipy only, no geometry kernel, no file format (ezdxf keeps its math/ so)
MATHS = (
    "design.linkage",
    "geometry.pitch",
    "geometry.cutter",
    "geometry.cutter_tooth",
    "geometry.rack_cutter",
    "geometry.cams",
    "design.planetary",
    "design.agronomy",
    "design.objectives",
    "design.views",
    "design.train_view",
    "geometry.backlash",
    "geometry.proportions",
)
ADAPTERS = {"shapely", "manifold3d", "ezdxf", "trimesh", "OCP", "matplotlib"}
#: the package's top level: the stations, the package's own files, nothing else
MAX_TOP_ENTRIES = 12
#: largest module, lines
MAX_LINES = 500


@functools.cache
def graph() -> dict:
    """Every module's imports (read when a test first asks, not when the suite is collected: ~1 s
    in each worker)."""
    return {name: imports(name, path) for name, path in MODULES.items()}


def _within(name: str, entry: str) -> bool:
    return name == entry or name.startswith(entry + ".")


def _layer(name: str) -> int:
    found = [(len(e), k) for k, layer in enumerate(LAYERS) for e in layer if _within(name, e)]
    if not found:
        raise AssertionError(f"{name} is in no layer: add it to LAYERS (and to docs/layout.md)")
    return max(found)[1]


def test_every_module_is_in_a_layer_and_imports_only_below():
    upward = [
        f"{name} (layer {_layer(name)}) imports {dep} (layer {_layer(dep)})"
        for name, (deps, _) in graph().items()
        for dep in deps
        if dep in MODULES and _layer(dep) > _layer(name)
    ]
    assert not upward


def test_no_import_circle():
    state: dict[str, int] = {}
    circles = []

    def visit(node, path):
        state[node] = 1
        for dep in sorted(graph()[node][0]):
            if dep not in graph() or dep == node:
                continue
            if state.get(dep) == 1:
                circles.append(" -> ".join([*path[path.index(dep) :], dep]))
            elif dep not in state:
                visit(dep, [*path, dep])
        state[node] = 2

    for node in graph():
        if node not in state and not node.endswith("__init__"):
            visit(node, [node])
    # a package's __init__ re-exports its modules: a circle only through an __init__ is not one
    assert [c for c in circles if "__init__" not in c] == []


@pytest.mark.parametrize("name", sorted(MODULES))
def test_no_module_is_large(name):
    assert len(MODULES[name].read_text().splitlines()) <= MAX_LINES


def test_the_top_level_shows_the_stations():
    entries = sorted(p.name for p in SRC.iterdir() if p.name != "__pycache__" and "egg-info" not in p.name)
    assert len(entries) <= MAX_TOP_ENTRIES, entries
    packages = [p for p in SRC.iterdir() if p.is_dir() and p.name != "__pycache__"]
    assert {p.name for p in packages} == {e for layer in LAYERS for e in layer if "." not in e and "_" not in e}


@pytest.mark.parametrize("package", sorted(str(p.parent.relative_to(SRC)) for p in SRC.rglob("__init__.py")))
def test_every_package_says_what_it_holds_and_may_import(package):
    """A newcomer finds a file by its concern: each package's docstring names its modules and
    (for a station) the stations it may import from."""
    init = SRC / package / "__init__.py"
    doc = ast.get_docstring(ast.parse(init.read_text())) or ""
    assert len(doc) > 80, f"{package}/__init__.py says too little of what it holds"
    if package != "." and package.count("/") == 0:
        assert "May import" in doc, f"{package}/__init__.py does not say what it may import"


def test_the_gear_pair_stations():
    lines = {n: len(p.read_text().splitlines()) for n, p in MODULES.items()}
    assert lines["families.pairs.toothed"] <= 300 and lines["geometry.teeth"] <= MAX_LINES
    assert not graph()["families.pairs.toothed"][0] & {"design.objectives", "design.planetary"}  # no paper
    assert not graph()["geometry.teeth"][0] & {"geometry.interference", "geometry.backlash"}  # one gear


def test_families_reach_the_shop_formats_through_formats_only():
    formats = {"shop.dxf", "shop.stl", "shop.step", "shop.threemf"}
    direct = {
        name: sorted(deps & formats | outer & {"ezdxf", "OCP", "lib3mf"})
        for name, (deps, outer) in graph().items()
        if name.startswith("families.")
    }
    assert {n: d for n, d in direct.items() if d} == {}


def test_the_maths_imports_no_adapter():
    found = {
        name: sorted(outer & ADAPTERS) for name, (_, outer) in graph().items() if any(_within(name, m) for m in MATHS)
    }
    assert {n: a for n, a in found.items() if a} == {}
    assert all(any(_within(n, m) for n in MODULES) for m in MATHS)  # every name still a module
