"""The shape of the code, read from the source (nothing is imported or run): imports one way, in
layers, no circle; modules small; the families reach the shop formats only through ``formats``;
the gear study knows no paper; the maths layer free of adapters (issue 28, ``../shared/STYLE.md``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "transplanter"

#: the layers, lowest first: a module imports only from its own layer or below (README, Layout)
LAYERS = (
    ("errors", "tolerances", "precision", "extrema", "proportions", "inputs"),
    ("contact", "linkage", "pitch", "planetary", "agronomy", "objectives", "backlash", "cutter", "cams", "optimise"),
    (
        "arcs",
        "machining",
        "interference",
        "tooth_spaces",
        "teeth",
        "pair_gate",
        "cutter_choice",
        "solids",
        "sweep",
        "incomplete",
    ),
    ("clearance", "arm_parts", "carrier_parts"),
    ("mesh_engine", "mesh_refine", "meshing", "train_rebuild", "follower", "validate", "machine", "carriers"),
    ("dxf", "stl", "step", "threemf", "export", "plots", "report", "animation"),
    ("formats",),
    ("families",),
    ("cli", "pytest_plugin", "testing", "__init__", "__main__"),
)
#: the maths: numpy and scipy only, no geometry kernel, no file format (ezdxf keeps its math/ so)
MATHS = ("linkage", "pitch", "cutter", "cams", "planetary", "agronomy", "objectives", "backlash", "proportions")
ADAPTERS = {"shapely", "manifold3d", "ezdxf", "trimesh", "OCP", "matplotlib"}
#: largest module, lines
MAX_LINES = 650


def _modules() -> dict[str, Path]:
    return {
        ".".join(p.relative_to(SRC).with_suffix("").parts): p
        for p in sorted(SRC.rglob("*.py"))
        if "egg-info" not in str(p)
    }


MODULES = _modules()


def _imports(name: str, path: Path) -> tuple[set[str], set[str]]:
    """(project modules, outside top-level packages) that ``name`` imports."""
    tree = ast.parse(path.read_text())
    inner, outer = set(), set()
    package = name.rsplit(".", 1)[0] if "." in name and not path.name == "__init__.py" else name
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                (inner if a.name.startswith("transplanter") else outer).add(a.name)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                mod = ".".join(["transplanter", *base, *([node.module] if node.module else [])])
            else:
                mod = node.module or ""
            if not mod.startswith("transplanter"):
                outer.add(mod)
                continue
            for a in node.names:  # `from transplanter import dxf` imports the module dxf
                sub = f"{mod}.{a.name}"
                inner.add(sub if sub.removeprefix("transplanter.") in MODULES else mod)
    inner = {m.removeprefix("transplanter.").removeprefix("transplanter") for m in inner}
    return {m for m in inner if m}, {m.split(".")[0] for m in outer}


GRAPH = {name: _imports(name, path) for name, path in MODULES.items()}


def _layer(name: str) -> int:
    top = name.split(".")[0]
    for k, layer in enumerate(LAYERS):
        if top in layer or name in layer:
            return k
    raise AssertionError(f"{name} is in no layer: add it to LAYERS (and to the README's layout)")


def test_every_module_is_in_a_layer_and_imports_only_below():
    upward = [
        f"{name} (layer {_layer(name)}) imports {dep} (layer {_layer(dep)})"
        for name, (deps, _) in GRAPH.items()
        for dep in deps
        if dep in MODULES and _layer(dep) > _layer(name)
    ]
    assert not upward


def test_no_import_circle():
    state: dict[str, int] = {}
    circles = []

    def visit(node, path):
        state[node] = 1
        for dep in sorted(GRAPH[node][0]):
            if dep not in GRAPH or dep == node:
                continue
            if state.get(dep) == 1:
                circles.append(" -> ".join([*path[path.index(dep) :], dep]))
            elif dep not in state:
                visit(dep, [*path, dep])
        state[node] = 2

    for node in GRAPH:
        if node not in state and not node.endswith("__init__"):
            visit(node, [node])
    # a package's __init__ re-exports its modules: a circle only through an __init__ is not one
    assert [c for c in circles if "__init__" not in c] == []


@pytest.mark.parametrize("name", sorted(MODULES))
def test_no_module_is_large(name):
    assert len(MODULES[name].read_text().splitlines()) <= MAX_LINES


def test_the_gear_pair_stations():
    lines = {n: len(p.read_text().splitlines()) for n, p in MODULES.items()}
    assert lines["families.gears"] <= 300 and lines["teeth"] <= 650
    assert not GRAPH["families.gears"][0] & {"objectives", "planetary"}  # no paper in the gear study
    assert not GRAPH["teeth"][0] & {"interference", "backlash"}  # one gear


def test_families_reach_the_shop_formats_through_formats_only():
    direct = {
        name: sorted(deps & {"dxf", "stl", "step", "threemf"} | outer & {"ezdxf", "OCP", "lib3mf"})
        for name, (deps, outer) in GRAPH.items()
        if name.startswith("families.")
    }
    assert {n: d for n, d in direct.items() if d} == {}


def test_the_maths_imports_no_adapter():
    found = {name: sorted(outer & ADAPTERS) for name, (_, outer) in GRAPH.items() if name.split(".")[0] in MATHS}
    assert {n: a for n, a in found.items() if a} == {}
