"""The same floating-point kernels on every x86-64 machine with AVX2 (``transplanter._same_kernels``):
exports byte-identical wherever they are rebuilt (docs/cli.md, build); one OpenBLAS thread per
process of the command (``transplanter.app.one_blas_thread``)."""

import os
import subprocess
import sys

import pytest

import transplanter

avx2 = pytest.mark.skipif(
    "avx2" not in transplanter._x86_flags(), reason="the pin applies to x86-64 machines with AVX2"
)

SHOW = "import os; print(os.environ.get('OPENBLAS_CORETYPE'), os.environ.get('NPY_DISABLE_CPU_FEATURES'))"


def _run(code: str, **env: str) -> str:
    pinned = ("OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES", "OPENBLAS_NUM_THREADS")
    clean = {k: v for k, v in os.environ.items() if k not in pinned}
    out = subprocess.run(
        [sys.executable, "-W", "error::ImportWarning", "-c", code], env={**clean, **env}, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


@avx2
def test_importing_transplanter_pins_the_kernels_before_numpy():
    from importlib.metadata import version

    wide = "X86_V4 AVX512_ICL AVX512_SPR" if tuple(int(v) for v in version("numpy").split(".")[:2]) >= (2, 4) else None
    assert _run(f"import transplanter, numpy; {SHOW}") == f"Haswell {wide}"
    # numpy reads them when first imported, and takes them without a warning (-W error above)
    cpu = _run("import transplanter; from numpy._core._multiarray_umath import __cpu_features__ as f; print(f['AVX2'])")
    assert cpu == "True"


@avx2
def test_a_users_settings_and_an_earlier_numpy_are_left_alone():
    assert _run(f"import transplanter; {SHOW}", OPENBLAS_CORETYPE="Zen").startswith("Zen ")
    assert _run(f"import numpy, transplanter; {SHOW}") == "None None"


#: numpy's OpenBLAS asked how many threads it runs, once ``MODULE`` is imported (its symbols carry
#: scipy-openblas's prefix and suffix in numpy's wheels, none in a system OpenBLAS); "none" where
#: numpy runs on another BLAS
BLAS_THREADS = """
import ctypes, sys
import MODULE, numpy
found = [line.split()[-1] for line in open('/proc/self/maps') if 'openblas' in line.lower() and '.so' in line]
blas = ctypes.CDLL(found[0]) if found else None
names = ('scipy_openblas_get_num_threads64_', 'scipy_openblas_get_num_threads', 'openblas_get_num_threads')
print(next((getattr(blas, n)() for n in names if hasattr(blas, n)), 'none'))
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/self/maps")
def test_the_command_runs_one_blas_thread_unless_the_user_says_otherwise():
    """The command works in parallel with processes, each with one OpenBLAS thread (issue 46: the
    threads' spinning cost a pair call 3 % of its CPU); a user's setting is numpy's, and a program
    that only imports transplanter keeps its BLAS threads."""
    command = BLAS_THREADS.replace("MODULE", "transplanter.app.cli")
    if _run(command) == "none":
        pytest.skip("numpy does not run on OpenBLAS here")
    assert _run(command) == "1"
    if (os.cpu_count() or 1) >= 2:  # OpenBLAS runs no more threads than there are cores
        assert _run(command, OPENBLAS_NUM_THREADS="2") == "2"
    assert _run("import transplanter.families, os; print(os.environ.get('OPENBLAS_NUM_THREADS'))") == "None"
