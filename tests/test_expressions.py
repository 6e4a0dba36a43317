"""The ``pair`` expression ψ(φ) ends in a value or a SpecError naming what is wrong — never a hang,
a traceback from Python's evaluator, or a silently different function (issue 31's classes:
unbounded integer powers, functions given extra arguments that numpy takes as ``out=``, deep
or long input)."""

import re
import time

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from transplanter.core.errors import SpecError
from transplanter.geometry.pitch.transmission import MAX_EXPRESSION, _compile, ratio_from_expression


@pytest.mark.parametrize(
    "expr, says",
    [
        ("phi + 0*2**2**2**2**2**2", "not finite"),  # hung: Python integer powers without end
        ("phi + 0*9**9**9", "not finite"),
        ("arctan(sin(phi), cos(phi))", "exactly one"),  # was arctan(sin(phi)): numpy's out= slot
        ("sin()", "exactly one"),
        ("sin(*phi)", "exactly one"),
        ("phi" + " + phi" * (MAX_EXPRESSION // 6), "length"),
        ("(" * 300 + "phi" + ")" * 300, "not an expression"),
        ("-" * 5000 + "phi", "nested"),
        ("sqrt(-1) + phi", "not finite"),
    ],
)
def test_bad_expressions_end_in_a_named_error_at_once(expr, says):
    start = time.perf_counter()
    with pytest.raises(SpecError, match=says):
        ratio_from_expression(expr)
    assert time.perf_counter() - start < 2.0


def test_a_2000_term_fourier_series_is_taken():
    coefficients = [f"{1e-4 / (k * k):.6g}" for k in range(1, 2001)]
    psi = _compile("phi + " + " + ".join(f"{c}*sin({k}*phi)" for k, c in enumerate(coefficients, 1)))
    phi = np.linspace(0.0, 2 * np.pi, 7)
    want = phi
    for k, c in enumerate(coefficients, 1):  # summed in the expression's order
        want = want + float(c) * np.sin(k * phi)
    np.testing.assert_allclose(psi(phi), want, rtol=0, atol=1e-12)


_numbers = st.floats(0.01, 5.0).map(lambda x: f"{x:.3g}")
_atoms = st.one_of(st.just("phi"), _numbers, st.just("pi"))
_terms = st.recursive(
    _atoms,
    lambda inner: st.one_of(
        st.tuples(inner, st.sampled_from("+-*/"), inner).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        st.tuples(st.sampled_from(["sin", "cos", "exp", "tanh"]), inner).map(lambda t: f"{t[0]}({t[1]})"),
        st.tuples(inner, _numbers).map(lambda t: f"({t[0]})**{t[1]}"),
    ),
    max_leaves=12,
)


@settings(max_examples=60, deadline=None, derandomize=True)
@example("sin(((0.5 - 1))**0.5)")
@given(_terms)
def test_generated_expressions_agree_with_numpy_or_name_their_error(expr):
    """Our evaluator against numpy evaluating the same text (trusted here: the text is generated)."""
    phi = np.linspace(0.1, 6.0, 9)
    namespace = {"phi": phi, "pi": np.pi, "sin": np.sin, "cos": np.cos, "exp": np.exp, "tanh": np.tanh}
    # the reference with every number as numpy float64, as ours: a negative number to a fraction
    # is NaN (Python's floats go complex), an overflow inf (Python's raise)
    reference = re.sub(r"\d+(?:\.\d*)?", lambda m: f"F({m.group(0)})", expr)
    with np.errstate(all="ignore"):
        want = eval(reference, {"__builtins__": {}}, {**namespace, "F": np.float64})  # noqa: S307
    want = np.broadcast_to(np.asarray(want, dtype=float), phi.shape)
    got = _compile(expr)(phi)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12, equal_nan=True)
