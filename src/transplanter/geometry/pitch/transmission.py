"""A pitch-curve pair from what a designer states: a transmission function, ratio samples, or a named curve.

Three ways in, one way out (a :class:`~transplanter.geometry.pitch.GearPair`):

* an **expression in φ** (``phi``, rad): the transmission function ψ(φ), the driven gear's
  angle as the driver turns — the convention of the peers (``ncgears "phi - 0.08*sin(2*phi)"``).
  Its ratio ω2/ω1 = ψ'(φ) is taken exactly, as a Fourier series of ψ's periodic part
  (:func:`ratio_from_expression`); allowed are numbers, ``+ - * / **``, ``pi``, ``e`` and
  ``sin cos tan exp log sqrt abs arctan sinh cosh tanh``;
* **samples** of the ratio: a CSV with a header and two columns, the driver angle in degrees
  over one turn and ω2/ω1 (:func:`ratio_from_csv`; a periodic cubic spline through them);
* a **named driver curve** ``ellipse:E[:LOBES]`` (Litvin's n-lobed ellipse of eccentricity E,
  or an ellipse about its focus for one lobe) or ``eccentric:E`` (a circle turning about a
  point E radii from its centre), whose conjugate is found with ``driven_lobes`` lobes.

**A requested ratio is built exactly, or refused** — never silently changed. A constant ratio
k = p/q (``"3*phi"``, a CSV of fives) is a pair of circles turning at that ratio, p driver
"lobes" to q driven ones, so the tooth counts keep it exactly (an irrational k, which no tooth
counts give, is refused with the nearest fraction). A law that does not close — the driven gear
must turn 1/n2 of a turn per driver lobe, for a whole n2 — is refused, naming what it turns and
the factor that would close it; only with ``scale_to_close`` (``--scale-to-close``: samples never
quite close) is the ratio scaled by that factor, and :class:`Transmission` says by how much
(``closure_scale``). A misfit below ``CLOSURE_ROUND_OFF`` (relative) is round-off, not a design
change, and is closed either way.

Examples
--------
>>> t = transmission("phi - 0.08*sin(2*phi)")
>>> t.pair.lobes, round(float(t.pair.ratio(0.0)), 12), t.closure_scale
((2, 2), 0.84, 1.0)
>>> transmission("ellipse:0.1:3", mesh="internal", driven_lobes=4).pair.lobes
(3, 4)
"""

from __future__ import annotations

import ast
import math
from dataclasses import dataclass
from fractions import Fraction
from typing import cast

import numpy as np

from transplanter.core.errors import SpecError, check_int, check_number, finite_positive
from transplanter.core.inputs import CSV_LARGEST_GAP_DEG as CSV_LARGEST_GAP_DEG  # the samples' widest gap
from transplanter.core.inputs import (
    MAX_CSV_BYTES,
    MAX_TEETH,
    is_csv_path,
    ratio_samples,
    read_data_file,
)
from transplanter.geometry.pitch.curve import PitchCurve
from transplanter.geometry.pitch.pair import GearPair, Mesh, _mesh
from transplanter.geometry.pitch.periodic import (
    Constant,
    FourierSeries,
    Periodic,
    PeriodicIntegral,
    PeriodicSpline,
    Scaled,
)

__all__ = ["Transmission", "transmission", "ratio_from_expression", "ratio_from_csv", "NAMED_CURVES", "is_named_curve"]

#: the named driver curves and what their parameter means
NAMED_CURVES = {
    "ellipse": "ellipse:E[:LOBES] — n-lobed ellipse p/(1 - E cos nφ), 0 <= E < 1",
    "eccentric": "eccentric:E — circle turning about a point E radii off its centre, 0 <= E < 1",
}

#: samples of ψ over one driver turn for its Fourier series: harmonics up to a quarter of them
#: must have died out to round-off (``SPECTRAL_TAIL``) or the expression is not smooth enough
SAMPLES = 4096
SPECTRAL_TAIL = 1e-11

#: a ratio whose closure is off by less than this (relative) closes as given: float round-off of
#: the integral, far below any machining (scaling by 1 + 1e-9 moves a 100 mm tooth 0.1 nm)
CLOSURE_ROUND_OFF = 1e-9
#: the largest numerator and denominator of a constant ratio p/q (lobes of the circle pair)
MAX_RATIO_TERMS = 1000

#: the size the curves are built at before the pair is sized by teeth and module (mm): any
#: value works, sizing scales the pair
NOMINAL_CENTRE_DISTANCE = 100.0

_FUNCTIONS = {
    name: getattr(np, name)
    for name in ("sin", "cos", "tan", "exp", "log", "sqrt", "abs", "arctan", "sinh", "cosh", "tanh")
}
_CONSTANTS = {"pi": math.pi, "e": math.e}
_ALLOWED: tuple[type[ast.AST], ...] = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Load)
_ALLOWED += (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd)


#: the longest expression taken, characters (a 2000-term Fourier series with 6-digit
#: coefficients is ~60 000)
MAX_EXPRESSION = 200_000
#: the deepest nesting of parentheses and calls taken (sums and products of many terms are flat)
MAX_NESTING = 100

_OPERATORS = {
    ast.Add: np.add,
    ast.Sub: np.subtract,
    ast.Mult: np.multiply,
    ast.Div: np.divide,
    ast.Pow: np.power,
}


def _compile(expr: str):
    """The expression as a function of φ (numpy arrays), or SpecError naming what is not allowed.

    Evaluated by walking its checked syntax tree with numpy, never by Python's ``eval``: numbers
    are float64 (a power of integer constants overflows to inf at once instead of growing without
    end), every function takes exactly one argument, and chains of ``+ - * /`` of any length are
    evaluated flat (a long Fourier series needs no deep recursion); the length and the nesting
    are bounded (``MAX_EXPRESSION``, ``MAX_NESTING``)."""
    if not isinstance(expr, str) or not expr.strip():
        raise SpecError(f"the transmission function must be an expression in phi, got {expr!r}")
    if len(expr) > MAX_EXPRESSION:
        raise SpecError.out_of_range("the transmission function's length", len(expr), f"<= {MAX_EXPRESSION} characters")
    try:
        tree = ast.parse(expr.strip(), mode="eval")
    except SyntaxError as exc:
        raise SpecError(f"the transmission function {expr!r} is not an expression: {exc.msg}") from exc
    except (RecursionError, MemoryError) as exc:
        raise SpecError(f"the transmission function is nested too deeply (limit {MAX_NESTING} levels)") from exc
    short = expr if len(expr) <= 80 else expr[:77] + "..."
    called = {id(n.func) for n in ast.walk(tree) if isinstance(n, ast.Call)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            if node.id != "phi" and node.id not in _FUNCTIONS and node.id not in _CONSTANTS:
                raise SpecError(
                    f"the transmission function {short!r} uses {node.id!r}: only phi, pi, e and "
                    f"{', '.join(_FUNCTIONS)} are allowed"
                )
            if node.id in _FUNCTIONS and id(node) not in called:
                raise SpecError(
                    f"the transmission function {short!r} uses {node.id} without calling it: {node.id}(...)"
                )
        elif isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name) or node.func.id not in _FUNCTIONS or node.keywords:
                allowed = ", ".join(_FUNCTIONS)
                raise SpecError(f"the transmission function {short!r} calls something other than {allowed}")
            if len(node.args) != 1 or isinstance(node.args[0], ast.Starred):
                raise SpecError(
                    f"the transmission function {short!r} calls {node.func.id} with {len(node.args)} arguments: "
                    "each function takes exactly one"
                )
        elif isinstance(node, ast.Constant):
            if not isinstance(node.value, int | float) or isinstance(node.value, bool):
                raise SpecError(f"the transmission function {short!r} holds {node.value!r}: only numbers are allowed")
        elif not isinstance(node, _ALLOWED):
            what = type(node).__name__
            raise SpecError(f"the transmission function {short!r} uses {what}: only arithmetic is allowed")
    _depth(tree.body, short)

    def psi(phi: np.ndarray) -> np.ndarray:
        with np.errstate(all="ignore"):
            out = _evaluate(tree.body, phi)
        return np.broadcast_to(np.asarray(out, dtype=float), np.shape(phi))

    return psi


def _chain(node) -> list:
    """The operands and operators of a left-leaning chain of binary operations of one precedence
    (``a + b - c + ...`` or ``a * b / c ...``), first operand first, without recursion."""
    group = (ast.Add, ast.Sub) if isinstance(node.op, ast.Add | ast.Sub) else (ast.Mult, ast.Div)
    out: list[tuple[ast.operator | None, ast.expr]] = []
    while isinstance(node, ast.BinOp) and isinstance(node.op, group):
        out.append((node.op, node.right))
        node = node.left
    out.append((None, node))
    return out[::-1]


def _depth(node, expr: str) -> None:
    """SpecError where the nesting (chains counted once) is deeper than MAX_NESTING."""
    stack = [(node, 1)]
    while stack:
        node, level = stack.pop()
        if level > MAX_NESTING:
            raise SpecError(f"the transmission function {expr!r} is nested deeper than {MAX_NESTING} levels")
        if isinstance(node, ast.BinOp) and not isinstance(node.op, ast.Pow):
            stack.extend((operand, level + 1) for _, operand in _chain(node))
        else:
            stack.extend((child, level + 1) for child in ast.iter_child_nodes(node))


def _evaluate(node, phi: np.ndarray):
    """The value of a checked expression node at ``phi`` (float64 numpy throughout)."""
    if isinstance(node, ast.Constant):
        return np.float64(cast(float, node.value))  # a number: the syntax check admits no other constant
    if isinstance(node, ast.Name):
        return phi if node.id == "phi" else np.float64(_CONSTANTS[node.id])
    if isinstance(node, ast.UnaryOp):
        value = _evaluate(node.operand, phi)
        return -value if isinstance(node.op, ast.USub) else +value
    if isinstance(node, ast.Call):
        return _FUNCTIONS[cast(ast.Name, node.func).id](_evaluate(node.args[0], phi))
    if isinstance(node.op, ast.Pow):
        return np.power(_evaluate(node.left, phi), _evaluate(node.right, phi))
    (_, first), *rest = _chain(node)
    value = _evaluate(first, phi)
    for op, operand in rest:
        value = _OPERATORS[type(op)](value, _evaluate(operand, phi))
    return value


def ratio_from_expression(expr: str) -> Periodic:
    """ω2/ω1 = ψ'(φ) of the transmission function ``expr`` (see the module docstring), exactly: ψ's
    secular part T φ / 2π plus the derivative of the Fourier series of the rest."""
    psi = _compile(expr)
    phi = 2 * math.pi * np.arange(SAMPLES) / SAMPLES
    values = psi(phi)
    end = float(psi(np.array([2 * math.pi]))[0])
    if not (np.all(np.isfinite(values)) and math.isfinite(end)):
        bad = float(np.degrees(phi[np.argmax(~np.isfinite(values))])) if not np.all(np.isfinite(values)) else 360.0
        raise SpecError(f"the transmission function {expr!r} is not finite at phi = {bad:g} deg")
    turn = end - float(values[0])  # what the driven gear turns per driver turn, rad
    if turn <= 0:
        raise SpecError.out_of_range(f"psi(2 pi) - psi(0) of {expr!r}", turn, "> 0 rad (the driven gear turns on)")
    c = np.fft.rfft(values - turn * phi / (2 * math.pi)) / SAMPLES
    a, b = 2 * c.real[1:], -2 * c.imag[1:]
    size = max(float(np.max(np.abs(c[1:]))), turn)
    tail = float(np.max(np.abs(c[SAMPLES // 4 :])))
    if tail > SPECTRAL_TAIL * size:
        raise SpecError(
            f"the transmission function {expr!r} is not smooth and periodic over a driver turn (its Fourier "
            f"series has not converged at {SAMPLES // 4} harmonics: {tail:.2g}); psi(phi) - psi(0) must be a "
            "smooth function of phi plus (psi(2 pi) - psi(0)) phi / 2 pi"
        )
    k = np.arange(1, len(a) + 1)
    keep = np.flatnonzero(np.hypot(a, b) > SPECTRAL_TAIL * size)
    mean = turn / (2 * math.pi)
    if not keep.size:
        return Constant(mean)
    lobes = int(np.gcd.reduce(k[keep]))
    top = int(k[keep].max())
    harmonics = np.arange(lobes, top + 1, lobes)
    # d/dφ (a_j cos jφ + b_j sin jφ) = j b_j cos jφ - j a_j sin jφ
    return FourierSeries(mean, harmonics * b[harmonics - 1], -harmonics * a[harmonics - 1], lobes=lobes)


def csv_table(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """(driver angle in deg, ratio) of a ratio CSV: :func:`transplanter.core.inputs.ratio_samples`,
    the one reader of full pairs' and of dwells' samples (header optional, a byte-order mark
    dropped, no stretch over ``CSV_LARGEST_GAP_DEG`` without a sample); the ratios are the
    caller's to judge."""
    return ratio_samples(data)


def ratio_from_csv(data: bytes) -> Periodic:
    """ω2/ω1 from a CSV of samples over one driver turn (:func:`csv_table`), every ratio positive;
    a periodic cubic spline through them."""
    deg, ratio = csv_table(data)
    if np.any(ratio <= 0):
        i = int(np.argmax(ratio <= 0))
        raise SpecError.out_of_range(f"ratio at {deg[i]:g} deg", float(ratio[i]), "> 0")
    return PeriodicSpline(np.radians(deg), ratio, period=2 * math.pi)


@dataclass(frozen=True)
class Transmission:
    """The pair a spec gives (at ``NOMINAL_CENTRE_DISTANCE``), what the spec was, and the factor
    its ratio was scaled by to close a whole number of driven lobes (1.0: it closed as given)."""

    pair: GearPair
    spec: str
    closure_scale: float = 1.0


def _constant(ratio: Periodic) -> Periodic | None:
    """A constant ``ratio`` k as the circle pair's ratio: period 2π/p for k = p/q (p driver lobes
    to q driven ones); None when the ratio is not constant. SpecError when k is no fraction of
    terms up to ``MAX_RATIO_TERMS``: no tooth counts give it."""
    x = np.linspace(0.0, ratio.period, 64, endpoint=False)
    values = ratio(x)
    k = float(values.mean())
    if not np.all(np.abs(values - k) <= 1e-12 * abs(k)):
        return None
    near = Fraction(k).limit_denominator(MAX_RATIO_TERMS)
    if near.numerator == 0 or near.numerator > MAX_RATIO_TERMS or abs(float(near) - k) > CLOSURE_ROUND_OFF * k:
        raise SpecError(
            f"the constant ratio {k!r} is not a fraction p/q with p, q <= {MAX_RATIO_TERMS}: no tooth counts z1/z2 "
            f"give it exactly (the nearest is {near.numerator}/{near.denominator} = {float(near)!r}); state the "
            "ratio as that fraction"
        )
    return Constant(float(near), period=2 * math.pi / near.numerator)


def _closing(ratio: Periodic, scale_to_close: bool) -> tuple[Periodic, float]:
    """``ratio`` as it closes a whole number of driven lobes per driver lobe (see the module
    docstring): as given, a constant as its circle pair, or scaled when ``scale_to_close``."""
    circles = _constant(ratio)
    if circles is not None:
        return circles, 1.0
    turn = PeriodicIntegral(ratio, ratio.period, ratio.breakpoints).total
    lobes = max(1, round(2 * math.pi / turn))
    scale = 2 * math.pi / lobes / turn
    if abs(scale - 1) < 1e-12:  # the integral's own round-off: as given
        return ratio, 1.0
    if abs(scale - 1) <= CLOSURE_ROUND_OFF:
        return Scaled(ratio, scale), scale
    if not scale_to_close:
        per_lobe = turn / (2 * math.pi)
        raise SpecError(
            f"the ratio does not close: it turns the driven gear {per_lobe:.9g} turns per driver lobe ("
            f"{ratio.lobes} driver lobe{'s' if ratio.lobes != 1 else ''}), and a closed driven gear turns 1/n2 of a "
            f"turn per driver lobe for a whole number n2 of its own lobes (1, 1/2, 1/3, ...); scaled by "
            f"{scale:.9g} it would close with n2 = {lobes} — state that law, or ask for it with scale_to_close "
            "(--scale-to-close)"
        )
    return Scaled(ratio, scale), scale


def _named(spec: str, mesh: Mesh, driven_lobes: int | None) -> GearPair:
    name, _, rest = spec.partition(":")
    args = rest.split(":") if rest else []
    if name not in NAMED_CURVES:
        raise SpecError(f"unknown curve {name!r}: the named curves are " + "; ".join(NAMED_CURVES.values()))
    try:
        numbers = [float(x) for x in args]
    except ValueError as exc:
        raise SpecError(f"{spec!r}: the curve's parameters must be numbers ({NAMED_CURVES[name]})") from exc
    if not numbers or len(numbers) > (2 if name == "ellipse" else 1):
        raise SpecError(f"{spec!r} does not match {NAMED_CURVES[name]}")
    e = check_number(f"{name} eccentricity E", numbers[0], 0.0, 1.0, high_open=True)
    if name == "ellipse":
        lobes = numbers[1] if len(numbers) > 1 else 1
        if lobes != int(lobes) or not 1 <= lobes <= 100:
            raise SpecError.out_of_range("ellipse LOBES", lobes, "a whole number from 1 to 100")
        driver = PitchCurve.ellipse(1.0, e, int(lobes))
    else:
        driver = PitchCurve.eccentric_circle(1.0, e)
    n1 = driver.lobes
    n2 = driven_lobes if driven_lobes is not None else (n1 if mesh is Mesh.EXTERNAL else n1 + 1)
    n2 = check_int("driven_lobes", n2, 1, 100)
    pair = GearPair.from_driver(driver, mesh, n2)
    return pair.scaled(NOMINAL_CENTRE_DISTANCE / pair.centre_distance)


def is_named_curve(spec) -> bool:
    """Whether ``spec`` names a driver curve (``NAME:PARAMS``) rather than an expression or a CSV
    file: ``'run:2.csv'`` is a file, ``'lambda: phi'`` an expression (refused as one),
    ``'hyperbola:1'`` an unknown curve."""
    if not isinstance(spec, str) or is_csv_path(spec):
        return False
    spec = spec.strip()
    head = spec.partition(":")[0]
    params = spec.partition(":")[2].replace(":", "").replace(".", "").replace("-", "").replace("e", "").strip()
    return head in NAMED_CURVES or (":" in spec and head.isidentifier() and (params.isdigit() or not params))


def transmission(
    spec: str,
    mesh: Mesh | str = Mesh.EXTERNAL,
    *,
    driven_lobes: int | None = None,
    ring: str = "driven",
    scale_to_close: bool = False,
) -> Transmission:
    """The pitch pair of ``spec`` (see the module docstring): an expression in ``phi``, the path of
    a ratio CSV (``*.csv``), or a named curve ``NAME:PARAMS``.

    ``mesh`` is ``"external"`` or ``"internal"``; internal pairs from a ratio have the ring as
    ``ring`` (``"driven"``: ratio < 1, or ``"driver"``); a named curve is the driver (the planet
    of an internal pair) and its mate has ``driven_lobes`` lobes (default: as many for an
    external pair, one more for a ring). A ratio that does not close is refused unless
    ``scale_to_close`` (see the module docstring).
    """
    mesh = _mesh(mesh)
    if not isinstance(scale_to_close, bool):
        raise SpecError.out_of_range("scale_to_close", scale_to_close, "True or False")
    if not isinstance(spec, str) or not spec.strip():
        raise SpecError(f"the transmission must be an expression in phi, a CSV file or a named curve, got {spec!r}")
    csv = is_csv_path(spec)  # a file first: 'run:2.csv' is a file, not a curve named 'run'
    path = spec  # a file is read at the path exactly as given: 'r.csv ' is not 'r.csv'
    spec = spec.strip()
    if is_named_curve(spec):
        return Transmission(_named(spec, mesh, driven_lobes), spec)
    if driven_lobes is not None:
        raise SpecError("driven_lobes is for named curves: a ratio fixes the driven gear's lobes itself")
    if csv:
        ratio = ratio_from_csv(read_data_file("ratio CSV", path, MAX_CSV_BYTES))
    else:
        ratio = ratio_from_expression(spec)
    ratio, scale = _closing(ratio, scale_to_close)
    pair = GearPair.from_ratio(ratio, NOMINAL_CENTRE_DISTANCE, mesh, ring=ring)
    return Transmission(pair, spec, scale)


def size_pair(pair: GearPair, teeth: int | None, module: float | None, centre_distance: float | None):
    """The pair sized by two of driver ``teeth``, ``module`` (mm) and ``centre_distance`` (mm);
    returns ``(pair, sizing)`` as :meth:`GearPair.sized`."""
    given = [v is not None for v in (teeth, module, centre_distance)]
    if sum(given) != 2:
        raise SpecError(
            "give two of teeth, module and centre distance (teeth and module fix the size; with the centre "
            "distance, the other follows)"
        )
    if teeth is not None:
        check_int("teeth", teeth, 1, MAX_TEETH)
    if centre_distance is not None:
        pair = pair.scaled(finite_positive("centre distance", centre_distance) / pair.centre_distance)
        pair, sizing = pair.sized(teeth=teeth) if teeth is not None else pair.sized(module=module)
        check_int("teeth", int(sizing.teeth[0]), 1, MAX_TEETH)
        return pair, sizing
    n1 = pair.lobes[0]
    if not isinstance(teeth, int) or teeth < n1 or teeth % n1 or teeth > MAX_TEETH:
        raise SpecError.out_of_range("teeth", teeth, f"a positive multiple of the driver's {n1} lobes, <= {MAX_TEETH}")
    m = finite_positive("module", cast(float, module))  # two of three are given: here teeth and module
    pair = pair.scaled(teeth * math.pi * m / pair.driver.perimeter)
    return pair.sized(teeth=teeth)
