"""``transplanter optimise --write`` edits exactly the tuple (issue 43), and the search's own inputs
are bounded: the scheduler's address (a peer that never answers, one that answers garbage) and the
sizes (``--seed``, ``--popsize``, ``--maxiter``, ``--workers``).

The writer is tried on generated layouts × encodings directly (no search: milliseconds each); the
command on a two-variable bowl with a few generations. Every case runs under a time limit.
"""

from __future__ import annotations

import ast
import contextlib
import json
import os
import re
import signal
import socket
import struct
import threading
import time
from contextlib import contextmanager

import numpy as np
import pytest

from transplanter.app import cli
from transplanter.core.errors import PartScriptError, SpecError
from transplanter.design import cluster as design_cluster
from transplanter.design.optimise import MAX_MAXITER, MAX_POPSIZE, MAX_SEED, MAX_WORKERS, Problem, misses, optimise
from transplanter.families.builder.optimum import find_optimum, module_file, number_text, record_optimum

#: a case still running after this is a hang, s
LIMIT_S = 20


@contextmanager
def limited(seconds: float = LIMIT_S):
    class Hang(BaseException):
        pass

    def stop(signum, frame):
        raise Hang

    previous = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    except Hang:
        pytest.fail(f"hung: still running after {seconds} s")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def run(capsys, *argv) -> tuple[int, str, str]:
    with limited():
        try:
            code = cli.main([str(a) for a in argv])
        except SystemExit as exc:  # argparse's refusal
            code = exc.code
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err and "internal error" not in err, err
    return code, out, err


# -- the writer, on generated layouts and encodings --------------------------------------------

#: the tuple in the layouts a designer writes; {0} and {1} are its numbers
LAYOUTS = {
    "statement after, same line": "OPTIMUM = ({0}, {1}); KEEP = 42\n",
    "statement before, same line": "KEEP = 42; OPTIMUM = ({0}, {1})  # the design\n",
    "one per line with comments": "OPTIMUM = (  # x, y\n    {0},  # x, mm\n    {1},  # y, mm\n)  # end\nKEEP = 42\n",
    "no brackets": "OPTIMUM = {0}, {1}\nKEEP = (1,\n 2)\n",
    "annotated": "OPTIMUM: tuple[float, float] = ({0}, {1})\n",
    "CRLF": "OPTIMUM = (\r\n    {0},\r\n    {1},\r\n)\r\nKEEP = 42\r\n",
    "CR only": "KEEP = 1\rOPTIMUM = ({0},\r {1})\r",
    "text before on its line": "NOTE = 'ü ± é'; OPTIMUM = ({0}, {1}); AFTER = 'é'\n",
    "spread over lines": "OPTIMUM = (\n{0}, {1}) ; KEEP = (1,\n 2)\n",
    "a tab and a form feed": "\x0cOPTIMUM = (\t{0},\t{1})\t# tab\n",
}
#: how the module's bytes are held: (prefix, cookie line, encoding)
ENCODINGS = {
    "utf-8": (b"", "", "utf-8"),
    "utf-8 BOM": (b"\xef\xbb\xbf", "", "utf-8"),
    "latin-1 cookie": (b"", "# -*- coding: latin-1 -*-\n# café, ±\n", "latin-1"),
    "cp1252 cookie": (b"", "# vim: set fileencoding=cp1252 :\n# price € 3\n", "cp1252"),
}
HELD = ("0.5", "-1.5")


def _module(layout: str, encoding: str, numbers=HELD) -> bytes:
    prefix, cookie, codec = ENCODINGS[encoding]
    return prefix + (cookie + LAYOUTS[layout].format(*numbers)).encode(codec)


@pytest.mark.parametrize("encoding", sorted(ENCODINGS))
@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_only_the_numbers_change_whatever_the_layout_and_encoding(tmp_path, layout, encoding):
    path = tmp_path / "design.py"
    path.write_bytes(_module(layout, encoding))
    path.chmod(0o640)
    place = find_optimum(module_file(path), "OPTIMUM", 2)
    assert place.values == (0.5, -1.5)
    new = (0.1 + 0.2, -7.25e-05)
    assert record_optimum(place, new) == path
    assert path.read_bytes() == _module(layout, encoding, [repr(v) for v in new])  # byte for byte, BOM kept
    assert path.stat().st_mode & 0o777 == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["design.py"]  # no temporary file left


def test_numbers_are_the_shortest_text_that_reads_back_and_unchanged_ones_keep_theirs(tmp_path):
    path = tmp_path / "design.py"
    path.write_text("OPTIMUM = (339.996376, 1e-3, 170, 2, -37.930985)\n")
    place = find_optimum(module_file(path), "OPTIMUM", 5)
    noisy = (339.99637599999994, 0.0010000000000000002, 170.0, 2.0, -37.93098500000001)  # the search's scaling
    before = path.stat().st_mtime_ns
    assert record_optimum(place, noisy) is None  # every number the file holds: nothing written
    assert path.read_text() == "OPTIMUM = (339.996376, 1e-3, 170, 2, -37.930985)\n"
    assert path.stat().st_mtime_ns == before
    place = find_optimum(module_file(path), "OPTIMUM", 5)
    record_optimum(place, (339.99637599999994, 0.002, 171.0, 3.7, -37.93098500000001), (False, False, False, True))
    # 171.0 was an int and is whole: an int; 3.7 is a choice held as an int: its integer part
    assert path.read_text() == "OPTIMUM = (339.996376, 0.002, 171, 3, -37.930985)\n"
    place = find_optimum(module_file(path), "OPTIMUM", 5)
    record_optimum(place, (339.996376, 0.002, 170.5, 3.0, -37.930985))
    assert path.read_text() == "OPTIMUM = (339.996376, 0.002, 170.5, 3, -37.930985)\n"  # 170.5 is not whole


def test_any_float_reads_back_exactly(tmp_path):
    rng = np.random.default_rng(43)
    values = [
        *(rng.normal(0, 1, 20) * 10.0 ** rng.integers(-300, 300, 20)),
        5e-324,
        -0.0,
        1.7976931348623157e308,
        0.1,
        1 / 3,
        2.0**-1074,
    ]
    path = tmp_path / "design.py"
    path.write_text("OPTIMUM = (" + ", ".join("1.5" for _ in values) + ",)\n")
    record_optimum(find_optimum(module_file(path), "OPTIMUM", len(values)), values)
    (node,) = ast.parse(path.read_text()).body
    held = ast.literal_eval(node.value)
    assert [repr(v) for v in held] == [repr(float(v)) for v in values]  # -0.0 stays -0.0
    assert number_text(2.0, 1) == "2" and number_text(2.5, 1) == "2.5" and number_text(2.0, 1.0) == "2.0"


def test_a_link_is_written_at_its_target_and_stays_a_link(tmp_path):
    real = tmp_path / "real"
    real.mkdir()
    (real / "design.py").write_text("OPTIMUM = (0.5, -1.5)\n")
    (real / "design.py").chmod(0o600)
    link = tmp_path / "design.py"
    link.symlink_to(real / "design.py")
    assert record_optimum(find_optimum(module_file(link), "OPTIMUM", 2), (1.25, 2.5)) == real / "design.py"
    assert link.is_symlink() and os.readlink(link) == str(real / "design.py")
    assert (real / "design.py").read_text() == "OPTIMUM = (1.25, 2.5)\n"
    assert (real / "design.py").stat().st_mode & 0o777 == 0o600
    assert sorted(p.name for p in real.iterdir()) == ["design.py"]


@pytest.mark.parametrize(
    ("content", "said"),
    [
        (b"KEEP = 1\n", "found 0 assignments of OPTIMUM"),
        (b"OPTIMUM = (1.0, 2.0)\nOPTIMUM = (3.0, 4.0)\n", "found 2 assignments"),
        (b"OPTIMUM = (1.0, 2.0)\nOPTIMUM += (3.0,)\n", "found 2 assignments"),
        (b"OPTIMUM = [1.0, 2.0]\n", "not a tuple of number literals"),
        (b"OPTIMUM = (1.0, X)\n", "not a tuple of number literals"),
        (b"OPTIMUM = (1.0, True)\n", "not a tuple of number literals"),
        (b"OPTIMUM = (1.0, '2')\n", "not a tuple of number literals"),
        (b"OPTIMUM = (1.0, 2.0, 3.0)\n", "holds 3 values, the problem has 2 variables"),
        (b"A = OPTIMUM = (1.0, 2.0)\n", "assigned with other names at once"),
        (b"def f():\n    OPTIMUM = (1.0, 2.0)\n", "found 0 assignments"),
        (b"OPTIMUM = (1.0, 2.0\n", "syntax error"),
        (b"# -*- coding: ascii -*-\n# caf\xe9\nOPTIMUM = (1.0, 2.0)\n", "cannot read it as Python source"),
        (b"# -*- coding: no-such-codec -*-\nOPTIMUM = (1.0, 2.0)\n", "cannot read it as Python source"),
        (b"\xef\xbb\xbf# -*- coding: latin-1 -*-\nOPTIMUM = (1.0, 2.0)\n", "cannot read it as Python source"),
    ],
)
def test_a_module_the_tuple_cannot_be_written_in_is_refused_naming_why(tmp_path, content, said):
    path = tmp_path / "design.py"
    path.write_bytes(content)
    with pytest.raises(PartScriptError, match=re.escape(said)):
        find_optimum(module_file(path), "OPTIMUM", 2)
    assert path.read_bytes() == content


def test_a_module_is_never_run_and_an_edit_during_the_search_is_not_overwritten(tmp_path):
    marker = tmp_path / "ran"
    path = tmp_path / "design.py"
    path.write_text(f"open({str(marker)!r}, 'w').close()\nraise SystemExit('ran')\nOPTIMUM = (0.5, -1.5)\n")
    place = find_optimum(module_file(path), "OPTIMUM", 2)
    path.write_text(path.read_text().replace("-1.5", "-2.5"))  # the designer edits it during the search
    with pytest.raises(PartScriptError, match=r"OPTIMUM changed during the search .* nothing written"):
        record_optimum(place, (1.0, 1.0))
    assert "-2.5)" in path.read_text() and not marker.exists()
    record_optimum(find_optimum(module_file(path), "OPTIMUM", 2), (1.0, 1.0))
    assert path.read_text().endswith("OPTIMUM = (1.0, 1.0)\n") and not marker.exists()


def test_files_that_cannot_be_replaced_are_refused(tmp_path):
    real = tmp_path / "design.py"
    real.write_text("OPTIMUM = (0.5, -1.5)\n")
    dangling = tmp_path / "gone.py"
    dangling.symlink_to(tmp_path / "nowhere.py")
    with pytest.raises(PartScriptError, match="gone.py .a link to .*nowhere.py.: --write cannot read it"):
        module_file(dangling)
    os.link(real, tmp_path / "other.py")
    with pytest.raises(PartScriptError, match="has 2 hard links"):
        module_file(real)
    (tmp_path / "other.py").unlink()
    fifo = tmp_path / "fifo.py"
    os.mkfifo(fifo)
    with limited(), pytest.raises(PartScriptError, match="not a regular file|this is not one"):
        module_file(fifo)
    real.chmod(0o444)
    with pytest.raises(PartScriptError, match=r"read-only \(mode 0444\)"):
        module_file(real)


# -- the command, on a small problem -----------------------------------------------------------

#: a bowl whose bottom is at (0.25, 1.0); ``describe`` says "margin" as seed 004's does
BOWL = """
from transplanter.design.optimise import Problem

OPTIMUM = ({x}, {y}); KEEP = 42  # the design; KEEP stays
__import__("pathlib").Path({marker!r}).touch()  # the script was loaded


def problem():
    def cost(v):
        return (v[0] - 0.25) ** 2 + (v[1] - 1.0) ** 2

    def describe(v):
        return {{"xi nutation": f"{{30 + {miss}:.4g}} deg (margin {{-{miss}:+.3g}})"}}

    return Problem("bowl", (("x", -2.0, 2.0), ("y", -1.0, 3.0)), cost, describe=describe, optimum="OPTIMUM")
"""
SEARCH = ("--seed", "3", "--maxiter", "4", "--popsize", "5")


def _bowl(tmp_path, x="0.5", y="-1.5", miss=0.0):
    path = tmp_path / "bowl.py"
    marker = tmp_path / "loaded"
    path.write_text(BOWL.format(x=x, y=y, miss=miss, marker=str(marker)))
    return path, marker


def test_write_records_only_the_tuple_and_keeps_the_statements_beside_it(tmp_path, capsys):
    path, _ = _bowl(tmp_path)
    before = path.read_text()
    code, out, err = run(capsys, "optimise", path, *SEARCH, "--write")
    assert code == 0, err
    result = json.loads(out)
    assert result["written"] == f"OPTIMUM in {path}"
    after = path.read_text()
    line = next(x for x in after.splitlines() if x.startswith("OPTIMUM"))
    x, y = re.fullmatch(r"OPTIMUM = \((\S+), (\S+)\); KEEP = 42  # the design; KEEP stays", line).groups()
    assert after == before.replace("OPTIMUM = (0.5, -1.5)", f"OPTIMUM = ({x}, {y})")
    assert round(float(x), 6) == result["parameters"]["x"] and repr(float(x)) == x  # shortest round trip
    assert (float(x) - 0.25) ** 2 + (float(y) - 1) ** 2 == pytest.approx(result["cost"], abs=1e-15)


def test_nothing_is_written_when_the_optimum_is_no_better_than_the_file(tmp_path, capsys):
    path, _ = _bowl(tmp_path, x="0.25", y="1.0")  # the bottom of the bowl: nothing beats it
    before, stamp = path.read_bytes(), path.stat().st_mtime_ns
    code, out, err = run(capsys, "optimise", path, *SEARCH, "--write")
    assert code == 0 and json.loads(out)["written"] is None
    assert "no better than OPTIMUM in" in err and "(cost 0): nothing written" in err
    assert path.read_bytes() == before and path.stat().st_mtime_ns == stamp


def test_a_design_that_misses_an_objective_is_written_only_when_asked(tmp_path, capsys):
    path, _ = _bowl(tmp_path, miss=0.282)
    before = path.read_bytes()
    code, out, err = run(capsys, "optimise", path, *SEARCH, "--write")
    assert code == 0 and path.read_bytes() == before
    said = json.loads(out)["not_written"]
    assert "it misses xi nutation: 30.28 deg (margin -0.282)" in said and "--write-infeasible" in said
    assert said in err
    code, out, err = run(capsys, "optimise", path, *SEARCH, "--write-infeasible")
    assert code == 0 and path.read_bytes() != before
    assert json.loads(out)["misses"] == "it misses xi nutation: 30.28 deg (margin -0.282)"
    assert "written as asked (--write-infeasible), though it misses xi nutation: 30.28 deg (margin -0.282)" in err
    assert misses({"a": "1 mm (margin +0.5)", "b": "no margin", "c": "2 (margin -1e-3)"}) == [
        ("c", "2 (margin -1e-3)", -0.001)
    ]


@pytest.mark.parametrize(
    ("case", "said"),
    [
        ("read-only", "read-only (mode 0444)"),
        ("no tuple", "found 0 assignments of OPTIMUM"),
        ("latin-1 undeclared", "cannot read it as Python source"),
        pytest.param(
            "folder not writable",
            "is not writable: --write replaces the file atomically",
            marks=pytest.mark.skipif(os.geteuid() == 0, reason="root may write in any folder"),
        ),
    ],
)
def test_a_module_that_cannot_take_the_optimum_is_refused_before_the_first_generation(tmp_path, capsys, case, said):
    path, marker = _bowl(tmp_path)
    if case == "read-only":
        path.chmod(0o444)
    elif case == "no tuple":
        path.write_text(path.read_text().replace("OPTIMUM = (0.5, -1.5); ", ""))
    elif case == "latin-1 undeclared":
        path.write_bytes(path.read_bytes() + "# café\n".encode("latin-1"))
    else:
        os.chmod(tmp_path, 0o555)
    before = path.read_bytes()
    try:
        code, out, err = run(capsys, "optimise", path, *SEARCH, "--write")
    finally:
        os.chmod(tmp_path, 0o755)
    assert code == 2 and said in err and "generation" not in err, err
    assert path.read_bytes() == before
    if case in ("read-only", "latin-1 undeclared", "folder not writable"):
        assert not marker.exists()  # refused before the script was even loaded


def test_a_linked_module_is_written_through_the_link(tmp_path, capsys):
    real = tmp_path / "real"
    real.mkdir()
    path, _ = _bowl(real)
    link = tmp_path / "bowl.py"
    link.symlink_to(path)
    code, out, err = run(capsys, "optimise", link, *SEARCH, "--write")
    assert code == 0, err
    assert link.is_symlink() and "OPTIMUM = (0.5, -1.5)" not in path.read_text()
    assert json.loads(out)["written"] == f"OPTIMUM in {link} (a link: written at its target {path})"


# -- the search's sizes ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("option", "value", "said"),
    [
        ("--seed", str(2**32), f"--seed = {2**32} is out of range: must be an integer from 0 to {MAX_SEED}"),
        ("--seed", "-1", "--seed = -1 is out of range: must be an integer from 0 to"),
        ("--seed", "1.5", "--seed = '1.5' is not an integer"),
        ("--popsize", str(MAX_POPSIZE + 1), f"--popsize = {MAX_POPSIZE + 1} is out of range"),
        ("--popsize", "0", "--popsize = 0 is out of range: must be an integer from 1 to 1000"),
        ("--maxiter", str(MAX_MAXITER + 1), f"--maxiter = {MAX_MAXITER + 1} is out of range"),
        ("--workers", str(MAX_WORKERS + 1), f"--workers = {MAX_WORKERS + 1} is out of range"),
        ("--workers", "10" * 400, "is out of range"),
    ],
)
def test_the_search_sizes_are_limited_when_parsed(tmp_path, capsys, option, value, said):
    path, marker = _bowl(tmp_path)
    code, out, err = run(capsys, "optimise", path, option, value)
    assert code == 2 and said in err and not marker.exists(), err


def test_the_limits_themselves_are_accepted(tmp_path, capsys):
    path, _ = _bowl(tmp_path)
    code, out, err = run(capsys, "optimise", path, "--seed", str(MAX_SEED), "--maxiter", "1", "--popsize", "2")
    assert code == 0 and json.loads(out)["seed"] == MAX_SEED
    bowl = Problem("b", (("x", 0.0, 1.0),), lambda v: float(v[0]))
    for kwargs in ({"seed": 2**32}, {"seed": -1}, {"popsize": MAX_POPSIZE + 1}, {"maxiter": 0}, {"workers": 999}):
        with pytest.raises(SpecError, match=f"{next(iter(kwargs))} = .* is out of range"):
            optimise(bowl, **kwargs)


# -- the scheduler -----------------------------------------------------------------------------


@contextmanager
def peer(send: bytes | None):
    """A TCP server on localhost that accepts and sends ``send`` (None: never answers)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held = []

    def serve():
        while True:
            try:
                conn, _ = server.accept()
            except OSError:
                return
            held.append(conn)
            if send is not None:
                try:
                    conn.sendall(send)
                except OSError:
                    pass

    serving = threading.Thread(target=serve, daemon=True)
    serving.start()
    try:
        yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    finally:  # accept() woken and ended before the lines it took are closed: none taken after
        with contextlib.suppress(OSError):  # (Linux wakes accept() so; others may refuse it)
            server.shutdown(socket.SHUT_RDWR)
        server.close()
        serving.join(10.0)
        for conn in held:
            conn.close()


def test_a_scheduler_that_accepts_and_never_answers_fails_within_the_timeout(tmp_path, capsys, monkeypatch):
    assert design_cluster.SCHEDULER_TIMEOUT_S == 10.0  # the stated bound; tried here at 1 s
    monkeypatch.setattr(design_cluster, "SCHEDULER_TIMEOUT_S", 1.0)
    path, _ = _bowl(tmp_path)
    with peer(None) as address:
        start = time.monotonic()
        code, out, err = run(capsys, "optimise", path, *SEARCH, "--scheduler", address)
        took = time.monotonic() - start
    assert code == 2 and f"scheduler = '{address}': no Dask scheduler answered within 1 s" in err, err
    assert took < 1.0 + 4.0, took  # the timeout, and a load of the script and of dask


@pytest.mark.parametrize(
    "reply",
    [
        b"\xff" * 64,  # a frame count numpy cannot even shape
        struct.pack("<Q", int(3.07 * 2**60)) + b"x" * 16,  # "Unable to allocate 3.07 EiB"
        b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n",
        b"SSH-2.0-OpenSSH_9.6\r\n",
        b"\x00" * 64,
        struct.pack("<Q", 16) + b"\x01" * 16,
        b"",  # accepts, says nothing, keeps the line open
    ],
    ids=["0xff", "a 3 EiB frame", "HTTP", "SSH", "zeros", "a short frame", "silence"],
)
def test_a_scheduler_that_answers_garbage_is_refused_clearly(tmp_path, capsys, monkeypatch, reply):
    monkeypatch.setattr(design_cluster, "SCHEDULER_TIMEOUT_S", 1.0)
    path, _ = _bowl(tmp_path)
    with peer(reply) as address:
        code, out, err = run(capsys, "optimise", path, *SEARCH, "--scheduler", address)
    assert code == 2 and f"scheduler = '{address}': " in err, err
    # a reply is refused for what it is; only silence waits for the timeout
    said = "no Dask scheduler answered within 1 s" if reply == b"" else "not a Dask scheduler"
    assert said in err, err
    assert "EiB" not in err and "allocate" not in err and len(err.strip().splitlines()) == 1, err


def test_a_probe_that_fails_oddly_once_its_time_is_up_says_the_time(tmp_path, capsys, monkeypatch):
    """A reader cancelled in the middle of its wait may raise anything (a silent peer was once said
    to send garbage, the suite run under a sampling profiler): what fails once the time is up is
    said as the time, whatever it raised."""
    import asyncio

    import distributed.comm

    async def connect(address, timeout):
        try:
            await asyncio.sleep(60.0)
        except asyncio.CancelledError:
            raise RuntimeError("a reader cancelled mid-frame") from None

    monkeypatch.setattr(distributed.comm, "connect", connect)
    monkeypatch.setattr(design_cluster, "SCHEDULER_TIMEOUT_S", 0.3)
    path, _ = _bowl(tmp_path)
    code, out, err = run(capsys, "optimise", path, *SEARCH, "--scheduler", "tcp://127.0.0.1:9")
    assert code == 2 and "scheduler = 'tcp://127.0.0.1:9': no Dask scheduler answered within 0.3 s" in err, err


@pytest.mark.parametrize(
    ("address", "said"),
    [
        ("not an address", "not an address like 'tcp://host:8786'"),
        ("tcp://127.0.0.1:99999", "port 99999 is not 1..65535"),
        ("tcp://[::1", "not an address"),
    ],
)
def test_a_scheduler_address_that_is_not_one_is_named(tmp_path, capsys, address, said):
    path, _ = _bowl(tmp_path)
    code, out, err = run(capsys, "optimise", path, *SEARCH, "--scheduler", address)
    assert code == 2 and said in err, err


PORT_TAKEN = """
import socket
import warnings

from transplanter.design.cluster import _evaluator

if __name__ == "__main__":
    held = socket.socket()
    try:
        held.bind(("127.0.0.1", 8787))
        held.listen()
    except OSError:
        pass  # dask's port is taken already: the same case
    warnings.simplefilter("error")  # here, where the local scheduler runs
    with _evaluator(2, None) as run:
        print(run.workers())
    held.close()
"""


def test_a_local_search_starts_beside_another_cluster_without_a_word(tmp_path):
    """The local cluster's scheduler keeps an HTTP server for its metrics; on dask's 8787, taken by
    any other cluster (the design studio's search, a notebook's), it warns before moving to another
    port — said on the user's console, an error in a suite. It binds a free port of loopback."""
    import subprocess
    import sys

    script = tmp_path / "beside.py"
    script.write_text(PORT_TAKEN)
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and proc.stdout.strip() == "2", proc.stderr[-2000:]
    assert "already in use" not in proc.stderr
