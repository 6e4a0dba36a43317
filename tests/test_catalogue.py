"""The user-input catalogue (issue 31): what a user hands the command line or the API, grown by
class — the pair expression, ratio CSVs, sizes, output paths, part scripts, manifests and checked
folders, the optimiser, the Python API. Every case must end clearly: done (exit 0), a part that
failed said as such (exit 1), or bad input named (exit 2, "transplanter: error: ..." naming the
parameter or the file) — never a traceback, never a silently different design, never a hang (each
case runs under a time limit). The project's older cases are in ``test_robustness.py``; the
generated ones (hypothesis) are at the end.
"""

from __future__ import annotations

import json
import os
import signal
from contextlib import contextmanager

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from transplanter.app import cli
from transplanter.app.testing import SQUARE_SCRIPT as SQUARE
from transplanter.core import inputs
from transplanter.core.errors import PartScriptError, SpecError, TransplanterError
from transplanter.geometry.pitch.transmission import ratio_from_csv, transmission

#: a case that takes longer than this is a hang, s
CASE_LIMIT_S = 60


class _Hang(BaseException):
    pass


@contextmanager
def _limited(seconds: float = CASE_LIMIT_S):
    def stop(signum, frame):
        raise _Hang

    previous = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    except _Hang:
        pytest.fail(f"hung: still running after {seconds} s")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def run(capsys, *argv) -> tuple[int, str, str]:
    with _limited():
        try:
            code = cli.main([str(a) for a in argv])
        except SystemExit as exc:  # argparse's own refusal: usage and "error: ..." on stderr, exit 2
            code = exc.code
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err and "internal error" not in err, err
    return code, out, err


def refused(capsys, words: str, *argv) -> None:
    """Exit 2 with one ``transplanter: error:`` line that contains ``words``."""
    code, out, err = run(capsys, *argv)
    assert code == 2, (code, out, err)
    assert "error:" in err and words in err, err


# -- the pair expression -----------------------------------------------------------------------

PAIR = ("pair", "--teeth", "24", "--module", "1.5")

EXPRESSIONS = [
    ("phi +", "not an expression"),
    ("phi ** ", "not an expression"),
    ("(phi", "not an expression"),
    ("phi)", "not an expression"),
    ("", "the transmission must be"),
    ("   ", "the transmission must be"),
    ("__import__('os').system('true')", "calls something other than"),
    ("open('/etc/passwd')", "calls something other than"),
    ("phi.real", "uses Attribute"),
    ("[phi][0]", "uses"),
    ("phi if phi else 0", "uses"),
    ("lambda: phi", "uses"),
    ("phi * x", "uses 'x'"),
    ("theta + 0.1*sin(theta)", "uses 'theta'"),
    ("arctan(sin(phi), cos(phi)) + phi", "takes exactly one"),
    ("sin() + phi", "takes exactly one"),
    ("sin(phi=1) + phi", "calls something other than"),
    ("phi + 0*2**2**2**2**2**2", "not finite"),
    ("phi + " + "sin(" * 150 + "phi" + ")" * 150, "nested deeper than 100"),
    ("phi + " + "0.001*sin(phi) + " * 20_000 + "0", "<= 200000 characters"),
    ("sqrt(phi) + phi", "not smooth and periodic"),
    ("phi + abs(sin(phi))", "not smooth and periodic"),
    ("-phi", "the driven gear turns on"),
    ("phi - 2*sin(phi)", "> 0"),
    ("2*phi + 0.3*sin(phi)", "does not close"),
    ("1.5*phi + 0.1*sin(phi)", "does not close"),
    ("2.718281828459045*phi", "not a fraction p/q"),
    ("phi + sqrt(0*phi - 1)", "is not finite"),
    ("phi + log(0*phi)", "is not finite"),
    ("phi + 1/(phi - phi)", "is not finite"),
    ("phi + 1e308*1e308*sin(phi)", "is not finite"),
    ("0*phi", "> 0"),
    ("phi + sin", "uses sin without calling it"),
    ("phi + 0.1*cos*phi", "uses cos without calling it"),
]


@pytest.mark.parametrize(("spec", "words"), EXPRESSIONS, ids=range(len(EXPRESSIONS)))
def test_a_bad_expression_is_named(capsys, tmp_path, spec, words):
    refused(capsys, words, *PAIR, spec, "-o", tmp_path)
    assert not any(tmp_path.iterdir())  # nothing written


def test_an_expression_starting_with_a_minus_is_not_an_option(capsys, tmp_path):
    refused(capsys, "the driven gear turns on", *PAIR, "-phi + 0*sin(phi)", "-o", tmp_path)


# -- ratio CSVs --------------------------------------------------------------------------------


def _rows(n=36, f=lambda d: 1 + 0.1 * __import__("math").cos(__import__("math").radians(d))):
    return "".join(f"{360 * k / n:g},{f(360 * k / n)!r}\n" for k in range(n))


CSVS = [
    ("empty", b"", "2 columns"),
    ("header only", b"phi_deg,ratio\n", "2 columns"),
    ("one column", "".join(f"{d}\n" for d in range(0, 360, 10)).encode(), "2 columns"),
    ("three columns", "".join(f"{d},1,2\n" for d in range(0, 360, 10)).encode(), "2 columns"),
    ("text", b"a,b\nc,d\ne,f\n", "cannot be read as numbers"),
    ("nan", _rows(f=lambda d: float("nan")).encode(), "must be finite"),
    ("inf", _rows(f=lambda d: float("inf")).encode(), "must be finite"),
    ("negative ratio", _rows(f=lambda d: -1.0).encode(), "> 0"),
    # a zero row marks a dwell (an incomplete pair): all zeros is a dwell without a motion
    ("zero ratio", _rows(f=lambda d: 0.0).encode(), "rows with a positive ratio (a motion)"),
    ("decreasing", "".join(f"{d},1\n" for d in range(350, -1, -10)).encode(), "increase within"),
    ("duplicate angle", ("0,1\n" + _rows()).encode(), "increase within"),
    ("radians", "".join(f"{k * 0.2},1\n" for k in range(31)).encode(), "look like radians"),
    ("beyond 360", "".join(f"{d},1\n" for d in range(0, 720, 20)).encode(), "within [0, 360)"),
    ("a gap", "".join(f"{d},1\n" for d in range(0, 200, 10)).encode(), "without a sample"),
    ("too few rows", "".join(f"{d},1\n" for d in range(0, 360, 60)).encode(), "at least 8 rows"),
    ("binary", bytes(range(256)) * 4, "cannot be read as numbers"),
    ("not closing", _rows(f=lambda d: 1.5).encode().replace(b"1.5", b"1.5"), "> 0"),  # replaced below
    ("utf-16", _rows().encode("utf-16"), "cannot be read as numbers"),
    ("too many rows", b"".join(b"%d,1\n" % k for k in range(inputs.MAX_CSV_ROWS + 5)), "rows"),
]
CSVS[16] = (
    "not closing",
    _rows(f=lambda d: 1.3 + 0.1 * __import__("math").cos(__import__("math").radians(d))).encode(),
    "does not close",
)


@pytest.mark.parametrize(("label", "data", "words"), CSVS, ids=[c[0] for c in CSVS])
def test_a_bad_ratio_csv_is_named(capsys, tmp_path, label, data, words):
    path = tmp_path / "ratio.csv"
    path.write_bytes(data)
    refused(capsys, words, *PAIR, path, "-o", tmp_path / "out")


@pytest.mark.parametrize(
    ("label", "words"),
    [("fifo", "not a regular file"), ("folder", "is a folder"), ("missing", "cannot be read"), ("huge", "size")],
)
def test_a_ratio_csv_that_is_not_a_small_regular_file_is_refused_at_once(capsys, tmp_path, label, words):
    path = tmp_path / "run:2.csv"  # a colon in the name: still a file, not a curve named 'run'
    if label == "fifo":
        os.mkfifo(path)  # reading it would block for ever
    elif label == "folder":
        path.mkdir()
    elif label == "huge":
        with open(path, "wb") as f:
            f.truncate(inputs.MAX_CSV_BYTES + 1)
    refused(capsys, words, *PAIR, path, "-o", tmp_path / "out")


# -- sizes and options -------------------------------------------------------------------------

SIZES = [
    (("--teeth", "0", "--module", "1.5"), "teeth"),
    (("--teeth", "-4", "--module", "1.5"), "teeth"),
    (("--teeth", "25", "--module", "1.5"), "multiple of the driver's 2 lobes"),
    (("--teeth", "24.5", "--module", "1.5"), "invalid int value"),
    (("--teeth", "24", "--module", "0"), "module"),
    (("--teeth", "24", "--module", "-1"), "module"),
    (("--teeth", "24", "--module", "nan"), "module"),
    (("--teeth", "24", "--module", "inf"), "module"),
    (("--teeth", "24", "--module", "abc"), "invalid float value"),
    (
        (
            "--teeth",
            "24",
        ),
        "give two of --teeth, --module and --centre-distance",
    ),
    (("--teeth", "24", "--module", "1.5", "--centre-distance", "40"), "give two of"),
    (("--module", "1.5", "--centre-distance", "0"), "--centre-distance = 0.0"),
    (("--module", "1.5", "--centre-distance", "-40"), "--centre-distance = -40.0"),
    (("--teeth", "24", "--module", "1.5", "--width", "0"), "width"),
    (("--teeth", "24", "--module", "1.5", "--width", "nan"), "width"),
    (("--teeth", "24", "--module", "1.5", "--width", "1e9"), "width"),
    (("--teeth", "24", "--module", "1.5", "--width", "1e-9"), "--width = 1e-09"),
    (("--teeth", "24", "--module", "1.5", "--backlash", "-0.1"), "backlash"),
    (("--teeth", "24", "--module", "1.5", "--backlash", "nan"), "backlash"),
    (("--teeth", "24", "--module", "1.5", "--cutter-teeth", "3"), "--cutter-teeth = 3"),
    (("--teeth", "24", "--module", "1.5", "--cutter-teeth", "100000"), "--cutter-teeth = 100000"),
    (("--teeth", "24", "--module", "1.5", "--driven-lobes", "3"), "--driven-lobes is for named curves"),
    (("--teeth", "24", "--module", "1.5", "--ring", "both"), "invalid choice"),
    (("--teeth", "24", "--module", "1.5", "--rack", "--cutter-teeth", "12"), "either --rack or --cutter-teeth"),
    (("--teeth", "240000", "--module", "1.5"), "teeth = 240000"),
    (("--module", "0.05", "--centre-distance", "9000"), "make gears of"),
]


@pytest.mark.parametrize(("options", "words"), SIZES, ids=range(len(SIZES)))
def test_a_bad_size_or_option_is_named(capsys, tmp_path, options, words):
    refused(capsys, words, "pair", "phi - 0.08*sin(2*phi)", *options, "-o", tmp_path)


NAMED = [
    ("ellipse:1.2", "ellipse eccentricity E = 1.2"),
    ("ellipse:0.1:2.5", "ellipse LOBES = 2.5"),
    ("ellipse:0.1:0", "ellipse LOBES"),
    ("ellipse:0.1:1000", "ellipse LOBES"),
    ("ellipse:", "does not match"),
    ("ellipse:a", "must be numbers"),
    ("ellipse:0.1:2:3", "does not match"),
    ("eccentric:-0.1", "eccentric eccentricity E"),
    ("hyperbola:1", "unknown curve 'hyperbola'"),
]


@pytest.mark.parametrize(("spec", "words"), NAMED, ids=range(len(NAMED)))
def test_a_bad_named_curve_is_named(capsys, tmp_path, spec, words):
    refused(capsys, words, *PAIR, spec, "-o", tmp_path)


# -- output paths ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "words"),
    [("a/b", "name"), ("..", "name"), ("", "name"), (" x", "name"), ("x y", "name"), ("-", "name"), (".x", "first")],
)
def test_a_bad_name_is_named(capsys, tmp_path, name, words):
    refused(capsys, words, *PAIR, "phi - 0.08*sin(2*phi)", "--name", name, "-o", tmp_path)


def test_an_output_folder_that_is_a_file_is_said(capsys, tmp_path):
    (tmp_path / "file").write_text("x")
    code, _, err = run(capsys, *PAIR, "phi - 0.08*sin(2*phi)", "-o", tmp_path / "file")
    assert code in (1, 2) and "error:" in err and "file" in err


def test_a_users_own_script_and_another_familys_export_are_not_replaced(capsys, tmp_path):
    (tmp_path / "mine.py").write_text("# my own script\n")
    refused(capsys, "was not written by transplanter pair", *PAIR, "phi", "--name", "mine", "-o", tmp_path)
    assert (tmp_path / "mine.py").read_text() == "# my own script\n"
    (tmp_path / "theirs").mkdir()
    (tmp_path / "theirs" / "manifest.json").write_text(json.dumps({"parts": {}, "script": {"path": "/x/other.py"}}))
    refused(capsys, "not of an earlier transplanter pair", *PAIR, "phi", "--name", "theirs", "-o", tmp_path)
    (tmp_path / "plain").mkdir()
    refused(capsys, "is not an export of transplanter pair", *PAIR, "phi", "--name", "plain", "-o", tmp_path)


# -- part scripts ------------------------------------------------------------------------------

SCRIPTS = [
    ("def family(:\n", 2, "syntax error"),
    ("x = 1\n", 2, "must define family()"),
    ("def family():\n    return 42\n", 2, "returned int"),
    ("def family():\n    return 1 / 0\n", 2, "family() raised ZeroDivisionError"),
    ("import _nowhere\n", 2, "No module named '_nowhere'"),
    ("import sys\nsys.exit(0)\n", 2, "called sys.exit(0)"),
    ("def family():\n    return family()\n", 2, "recursed too deep"),
    ("while True:\n    pass\n", 2, "ran longer than its time limit of 1 s"),
    ("import time\ndef family():\n    time.sleep(30)\n", 2, "family() ran longer than its time limit"),
    ("import pathlib\npathlib.Path(__file__).unlink()\ndef family():\n    return None\n", 2, "returned NoneType"),
    (
        "import pathlib\nfrom transplanter.families import Family\npathlib.Path(__file__).unlink()\n"
        "def family():\n    return Family('f', 'gone')\n",
        2,
        "the part script is gone after it ran",
    ),
    (
        "from transplanter.families import Family, ArmStudy\ndef family():\n    return Family('f', 'd', (1,))\n",
        2,
        "parts must be studies",
    ),
    ("from transplanter.families import Family\ndef family():\n    return Family('a/b', 'd')\n", 2, "family name"),
    ("raise KeyError('k')\n", 2, "KeyError"),
    ("def family():\n    raise MemoryError\n", 2, "family() raised MemoryError"),
]


@pytest.mark.parametrize(("source", "code", "words"), SCRIPTS, ids=range(len(SCRIPTS)))
def test_a_bad_part_script_is_named(capsys, tmp_path, monkeypatch, source, code, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.py").write_text(source)
    got, out, err = run(capsys, "build", "bad.py", "-o", "out", "--timeout", "1")
    assert got == code and words in err, err
    assert os.getcwd() == str(tmp_path)


def test_a_script_that_changes_the_working_folder_leaves_it_as_it_was(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "moving.py").write_text(
        "import os\nfrom transplanter.families import Family\nos.chdir('sub')\n"
        "def family():\n    os.chdir('/')\n    return Family('moving', 'no parts')\n"
    )
    code, out, err = run(capsys, "build", "moving.py", "-o", "out")
    assert code == 0 and (tmp_path / "out" / "moving" / "manifest.json").is_file()
    assert os.getcwd() == str(tmp_path)


@pytest.mark.parametrize(("value", "words"), [("0", "timeout = 0"), ("-1", "timeout"), ("abc", "not a number")])
def test_a_bad_timeout_is_named(capsys, tmp_path, value, words):
    refused(capsys, words, "build", "x.py", "--timeout", value)


# -- checked folders and their manifests -------------------------------------------------------


@pytest.fixture
def square(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "squares.py").write_text(SQUARE)
    assert cli.main(["build", "squares.py", "-o", "out"]) == 0
    capsys.readouterr()
    return tmp_path / "out" / "squares"


MANIFESTS = [
    ("not json", "{", "damaged"),
    ("a list", "[1, 2]", "damaged"),
    ("parts a list", '{"parts": [1]}', "damaged"),
    ("part a number", '{"parts": {"sq": 3}}', "damaged"),
    ("files a list", '{"parts": {"sq": {"files": [1]}}}', "damaged"),
    ("digest a number", '{"parts": {"sq": {"files": {"sq.txt": 1}}}}', "damaged"),
    ("absolute name", '{"parts": {"sq": {"files": {"/etc/hostname": "0"}}}}', "not a plain file name"),
    ("climbing name", '{"parts": {"sq": {"files": {"../squares.py": "0"}}}}', "not a plain file name"),
    ("script a string", '{"parts": {}, "script": "x.py"}', "damaged"),
    ("deep", "[" * 100_000 + "]" * 100_000, "nested deeper"),
    ("not utf-8", '{"parts": {}, "x": "\xff"}', "not UTF-8 text"),
    ("report names out", '{"parts": {}, "report": {"../x": "0"}}', "plain file names"),
]


@pytest.mark.parametrize(("label", "text", "words"), MANIFESTS, ids=[m[0] for m in MANIFESTS])
def test_a_damaged_manifest_is_said_and_nothing_outside_is_read(capsys, square, label, text, words):
    (square / "manifest.json").write_bytes(text.encode("latin-1"))
    code, out, err = run(capsys, "check", square)
    assert code == 1 and "file manifest.json:" in out and words in out, out
    code, out, err = run(capsys, "check", "--run-script", square)
    assert code in (1, 2)


def test_check_of_a_file_or_a_missing_folder_is_named(capsys, square):
    refused(capsys, "is not a built family folder", "check", square / "sq.txt")
    refused(capsys, "is not a built family folder", "check", square / "nowhere")


def test_check_run_script_without_a_recorded_script(capsys, square):
    manifest = json.loads((square / "manifest.json").read_text())
    del manifest["script"]
    (square / "manifest.json").write_text(json.dumps(manifest))
    refused(capsys, "is not found; pass it with --script", "check", "--run-script", square)


# -- the optimiser -----------------------------------------------------------------------------

PROBLEM = """
from transplanter.design.optimise import Problem
def problem():
    return Problem("p", (("x", -1.0, 1.0),), lambda v: {cost})
"""


@pytest.mark.parametrize(
    ("cost", "words"),
    [
        ("1 / 0", "its cost function raised ZeroDivisionError"),
        ("'cheap'", "its cost function returned 'cheap'"),
        ("float('nan')", "no feasible design"),
        ("float('inf')", "no feasible design"),
        ("[1, 2]", "not a number"),
    ],
)
def test_a_bad_cost_function_is_named(capsys, tmp_path, cost, words):
    (tmp_path / "opt.py").write_text(PROBLEM.format(cost=cost))
    refused(capsys, words, "optimise", tmp_path / "opt.py", "--maxiter", "2", "--popsize", "3")


@pytest.mark.parametrize(
    ("options", "words"),
    [
        (("--maxiter", "0"), "--maxiter = 0"),
        (("--popsize", "0"), "--popsize = 0"),
        (("--workers", "0"), "--workers = 0"),
        (("--seed", "-1"), "--seed = -1"),
        (("--scheduler", "not an address"), "scheduler"),
    ],
)
def test_a_bad_optimiser_option_is_named(capsys, tmp_path, options, words):
    (tmp_path / "opt.py").write_text(PROBLEM.format(cost="v[0] ** 2"))
    refused(capsys, words, "optimise", tmp_path / "opt.py", "--maxiter", "2", "--popsize", "3", *options)


# -- the Python API ----------------------------------------------------------------------------


def _api_cases():
    from transplanter.families import PlanetaryStudy, ToothedPairStudy, gear_pair, pair_family
    from transplanter.geometry.cutter import ShaperCutter
    from transplanter.geometry.pitch import GearPair, PitchCurve

    pair = GearPair.from_driver(PitchCurve.ellipse(20.0, 0.1, 2), "external", 2)
    return [
        ("out None", lambda t: gear_pair("phi", None, teeth=24, module=1.5), "out"),
        ("spec a number", lambda t: gear_pair(3, t, teeth=24, module=1.5), "the transmission must be"),
        ("rack 'no'", lambda t: pair_family("phi", teeth=24, module=1.5, rack="no"), "rack = 'no'"),
        ("internal 1", lambda t: pair_family("phi", teeth=24, module=1.5, internal=1), "internal = 1"),
        ("scale 'yes'", lambda t: pair_family("phi", teeth=24, module=1.5, scale_to_close="yes"), "scale_to_close"),
        ("teeth and module", lambda t: ToothedPairStudy("p", pair, ShaperCutter(12), 30, module=2.0), "exactly one"),
        ("neither", lambda t: ToothedPairStudy("p", pair, ShaperCutter(12)), "exactly one"),
        ("train a string", lambda t: ToothedPairStudy("p", pair, ShaperCutter(12), 30, train="x"), "proof hook"),
        (
            "depth '40'",
            lambda t: PlanetaryStudy("t", None, (0, 0), 100.0, "40", gearbox_radius=50.0),
            "planting_depth",
        ),
        ("box text", lambda t: PlanetaryStudy("t", None, ("a", 0), 100.0, 40.0, gearbox_radius=50.0), "seedling_box"),
        ("no radius", lambda t: PlanetaryStudy("t", None, (0, 0), 100.0, 40.0), "gearbox_radius"),
        ("transmission 3", lambda t: transmission(3), "the transmission must be"),
        ("csv text", lambda t: ratio_from_csv("0,1\n"), "at least 8 rows"),
        ("csv a number", lambda t: ratio_from_csv(3), "must be bytes or text"),
    ]


@pytest.mark.parametrize("k", range(14))
def test_the_api_names_bad_input(tmp_path, k):
    label, call, words = _api_cases()[k]
    with _limited(), pytest.raises(TransplanterError, match=words):
        call(tmp_path)


# -- generated cases ---------------------------------------------------------------------------

_numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=32).map(repr),
    st.integers(-1000, 1000).map(str),
    st.sampled_from(["", "x", "1e999", "-0", "0x10", " 1", "1,2"]),
)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    rows=st.lists(st.tuples(_numbers, _numbers), min_size=0, max_size=40),
    header=st.booleans(),
    sep=st.sampled_from([",", ";", "\t"]),
)
def test_any_ratio_csv_is_taken_or_refused_by_name(rows, header, sep):
    data = ("phi_deg,ratio\n" if header else "") + "".join(f"{a}{sep}{b}\n" for a, b in rows)
    with _limited(30):
        try:
            ratio_from_csv(data.encode())
        except TransplanterError:
            pass


@settings(max_examples=60, deadline=None)
@given(
    st.recursive(
        st.none() | st.booleans() | st.integers() | st.text(max_size=8),
        lambda c: st.lists(c) | st.dictionaries(st.text(max_size=8), c),
        max_leaves=30,
    )
)
def test_any_manifest_is_checked_without_a_crash(tmp_path_factory, tree):
    from transplanter.families import check_family

    folder = tmp_path_factory.mktemp("fam")
    (folder / "manifest.json").write_text(json.dumps(tree))
    with _limited(30):
        report = check_family(folder)
    # a manifest with parts is checked; anything else is said to be damaged
    assert report["ok"] is False or (isinstance(tree, dict) and isinstance(tree.get("parts"), dict))
    if not (isinstance(tree, dict) and isinstance(tree.get("parts"), dict)):
        assert "damaged" in report["files"]["manifest.json"]


@settings(max_examples=40, deadline=None)
@given(st.text(alphabet="phisncotaxelrq0123456789.+-*/() ", max_size=40))
def test_any_short_expression_is_taken_or_refused_by_name(expr):
    with _limited(30):
        try:
            transmission(expr)
        except TransplanterError:
            pass


@settings(max_examples=40, deadline=None)
@given(st.text(max_size=20))
def test_any_name_is_a_folder_name_or_refused(name):
    from transplanter.families import Family

    try:
        Family(name, "d")
    except (SpecError, PartScriptError):
        return
    assert "/" not in name and name not in ("", ".", "..")


def test_a_bug_is_said_as_one_with_its_log(monkeypatch, capsys, tmp_path):
    """Anything unexpected is "internal error — please report" with the traceback in a log, exit
    1: never a bare traceback."""
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))  # the log's private folder (issue 43)
    monkeypatch.setattr(cli, "_cmd_check", lambda args: {}["no such key"])
    assert cli.main(["check", str(tmp_path / "checked")]) == 1
    err = capsys.readouterr().err
    assert "transplanter: internal error — please report it: KeyError" in err and "Traceback" not in err
    (log,) = tmp_path.glob("state/transplanter/internal-error-*.log")
    assert "Traceback" in log.read_text() and "no such key" in log.read_text()
