"""The same floating-point kernels on every x86-64 machine with AVX2 (``transplanter._same_kernels``):
exports byte-identical wherever they are rebuilt (docs/cli.md, build)."""

import os
import subprocess
import sys

import pytest

import transplanter

pytestmark = pytest.mark.skipif(
    "avx2" not in transplanter._x86_flags(), reason="the pin applies to x86-64 machines with AVX2"
)

SHOW = "import os; print(os.environ.get('OPENBLAS_CORETYPE'), os.environ.get('NPY_DISABLE_CPU_FEATURES'))"


def _run(code: str, **env: str) -> str:
    clean = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES")}
    out = subprocess.run(
        [sys.executable, "-W", "error::ImportWarning", "-c", code], env={**clean, **env}, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


def test_importing_transplanter_pins_the_kernels_before_numpy():
    from importlib.metadata import version

    wide = "X86_V4 AVX512_ICL AVX512_SPR" if tuple(int(v) for v in version("numpy").split(".")[:2]) >= (2, 4) else None
    assert _run(f"import transplanter, numpy; {SHOW}") == f"Haswell {wide}"
    # numpy reads them when first imported, and takes them without a warning (-W error above)
    cpu = _run("import transplanter; from numpy._core._multiarray_umath import __cpu_features__ as f; print(f['AVX2'])")
    assert cpu == "True"


def test_a_users_settings_and_an_earlier_numpy_are_left_alone():
    assert _run(f"import transplanter; {SHOW}", OPENBLAS_CORETYPE="Zen").startswith("Zen ")
    assert _run(f"import numpy, transplanter; {SHOW}") == "None None"
