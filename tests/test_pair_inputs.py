"""``transplanter pair``'s inputs checked before anything is written (issue 43), a catalogue by class:
bad numbers for every option of full and incomplete pairs, limits derived from the sizes (the ISO
default backlash below the module, the teeth, a dwell's lock and a motion's sector at the sizes
given), a law's bad segments, ratio CSVs (one reader for full pairs and dwells: gaps, byte-order
mark, header), the transmission's path taken as given, and options that do not apply.

Every case must end in exit 2 with one ``transplanter: error:`` line naming the parameter as the
user typed it (``--centre-distance``, the law's segment), with nothing written — neither the output
folder nor ``pair.py`` — and fast: each runs under ``CASE_LIMIT_S`` (a check, not a build).
"""

from __future__ import annotations

import signal
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest

from transplanter.app import cli
from transplanter.core import inputs
from transplanter.core.errors import SpecError
from transplanter.families.pairs.pair_options import check_options
from transplanter.geometry.pitch.intermittent import MAX_SEGMENTS, IntermittentLaw

#: a check must fail within this, s (a build of the smallest pair takes longer)
CASE_LIMIT_S = 8

MOTION = "2*pi*(phi - pi/3)/(5*pi/3) - 0.35*sin(2*pi*(phi - pi/3)/(5*pi/3))"
LAW = f"0..60: dwell; 60..360: {MOTION}"
FULL = "phi - 0.08*sin(2*phi)"


@contextmanager
def _limited(seconds: float = CASE_LIMIT_S):
    def stop(signum, frame):
        raise TimeoutError

    previous = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    except TimeoutError:
        pytest.fail(f"still running after {seconds} s: the inputs were not checked before the build")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def refused(capsys, tmp_path, argv: list[str], *words: str) -> str:
    """``pair argv -o tmp_path/out``: exit 2, one error line holding every one of ``words``,
    nothing written."""
    out = tmp_path / "out"
    with _limited():
        code = cli.main(["pair", *argv, "-o", str(out)])
    std, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2, (code, std, err)
    assert len(lines) == 1 and lines[0].startswith("transplanter: error: "), err
    for w in words:
        assert w in lines[0], (w, lines[0])
    assert not out.exists() and not (out / "pair.py").exists()
    return lines[0]


# -- bad numbers, per option -------------------------------------------------------------------

BAD = ["0", "-1", "nan", "inf", "1e300"]
INT_BAD = ["0", "-1", "1000000000"]
FULL_SIZED = [FULL, "--teeth", "24", "--module", "1.5"]
INC_SIZED = [LAW, "--module", "2", "--centre-distance", "64"]
NUMBERS = (
    [(f"full --module {v}", [FULL, "--teeth", "24", "--module", v], "--module") for v in BAD]
    + [(f"incomplete --module {v}", [LAW, "--teeth", "30", "--module", v], "--module") for v in BAD]
    + [
        (f"{kind} --centre-distance {v}", [spec, "--module", m, "--centre-distance", v], "--centre-distance")
        for kind, spec, m in (("full", FULL, "1.5"), ("incomplete", LAW, "2"))
        for v in [*BAD, "1e9"]
    ]
    + [
        (f"{kind} --teeth {v}", [spec, "--module", m, "--teeth", v], "--teeth")
        for kind, spec, m in (("full", FULL, "1.5"), ("incomplete", LAW, "2"))
        for v in INT_BAD
    ]
    + [("full --teeth 25", [FULL, "--module", "1.5", "--teeth", "25"], "--teeth")]  # not a multiple of 2 lobes
    + [(f"full {o} {v}", [*FULL_SIZED, o, v], o) for o in ("--backlash",) for v in ["-1", "nan", "inf", "1e300", "2"]]
    + [(f"incomplete --backlash {v}", [*INC_SIZED, "--backlash", v], "--backlash") for v in [*BAD, "2"]]
    + [
        (f"{kind} --width {v}", [*base, "--width", v], "--width")
        for kind, base in (("full", FULL_SIZED), ("incomplete", INC_SIZED))
        for v in [*BAD, "1e-9"]
    ]
    + [
        (f"{kind} --addendum {v}", [*base, "--addendum", v], "--addendum")
        for kind, base in (("full", FULL_SIZED), ("incomplete", INC_SIZED))
        for v in [*BAD, "2.5", "1,nan", "0,1"]
    ]
    + [(f"full --shift {v}", [*FULL_SIZED, "--shift", v], "--shift") for v in ["nan", "inf", "1e300", "1.7", "-3"]]
    + [
        (f"{kind} --cutter-teeth {v}", [*base, "--cutter-teeth", v], "--cutter-teeth")
        for kind, base in (("full", FULL_SIZED), ("incomplete", INC_SIZED))
        for v in [*INT_BAD, "7"]
    ]
    + [
        (
            f"named --driven-lobes {v}",
            ["ellipse:0.1:2", "--teeth", "24", "--module", "1.5", "--driven-lobes", v],
            "--driven-lobes",
        )
        for v in INT_BAD
    ]
    + [
        (f"incomplete --lock-clearance {v}", [*INC_SIZED, "--lock-clearance", v], "--lock-clearance")
        for v in [*BAD, "2"]
    ]
    + [(f"incomplete --lock-depth {v}", [*INC_SIZED, "--lock-depth", v], "--lock-depth") for v in [*BAD, "2"]]
    + [(f"incomplete --locking-play {v}", [*INC_SIZED, "--locking-play", v], "--locking-play") for v in [*BAD, "50"]]
)


@pytest.mark.parametrize(("label", "argv", "flag"), NUMBERS, ids=[c[0] for c in NUMBERS])
def test_a_bad_number_is_refused_naming_its_option(capsys, tmp_path, label, argv, flag):
    line = refused(capsys, tmp_path, argv, flag)
    assert "must" in line or "give" in line


# -- limits derived from the sizes ---------------------------------------------------------------

DERIVED = [
    # the ISO/TR 10064-2 default backlash grows with the centre distance: below the module, or --backlash
    ("full ISO backlash", [FULL, "--module", "1.5", "--centre-distance", "5000"], ["--centre-distance", "--backlash"]),
    ("full ISO backlash by teeth", [FULL, "--module", "1.5", "--teeth", "5000"], ["--teeth", "--backlash"]),
    ("incomplete ISO backlash", [LAW, "--module", "2", "--teeth", "5000"], ["--teeth", "below 5398"]),
    ("full too few teeth", [FULL, "--module", "1.5", "--centre-distance", "1"], ["--centre-distance", "6 to"]),
    ("full too many teeth", [FULL, "--module", "0.05", "--centre-distance", "9000"], ["--module", "make gears"]),
    ("lock radius", [LAW, "--module", "2", "--centre-distance", "1"], ["segment 1 '0..60: dwell'", "not > 0"]),
    ("lock depth past the addenda", [*INC_SIZED, "--addendum", "0.1"], ["--addendum = 0.1", "--lock-depth"]),
    ("lock depth past given addenda", [*INC_SIZED, "--addendum", "0.5", "--lock-depth", "1.2"], ["--lock-depth"]),
    ("driven's sector at module 4", [LAW, "--module", "4", "--centre-distance", "80"], ["segment 2", "--module = 4"]),
    ("a small pair's dwell", [LAW, "--module", "2", "--centre-distance", "12"], ["segment 2", "about 73"]),
    ("teeth no law carries", [LAW, "--module", "2", "--teeth", "3"], ["--teeth = 3"]),
    (
        "internal ratio >= 1",
        [LAW, "--internal", "--module", "2", "--centre-distance", "64"],
        ["segment 2", "--internal"],
    ),
]


@pytest.mark.parametrize(("label", "argv", "words"), DERIVED, ids=[c[0] for c in DERIVED])
def test_a_size_that_does_not_fit_is_refused_before_the_build(capsys, tmp_path, label, argv, words):
    refused(capsys, tmp_path, argv, *words)


def test_the_python_api_names_its_keywords():
    with pytest.raises(SpecError, match=r"^addendum = 0\.1 is out of range.*lock_depth's default"):
        check_options(LAW, module=2.0, centre_distance=64.0, addendum=0.1)
    with pytest.raises(SpecError, match=r"^centre_distance = -1"):
        check_options(FULL, module=1.5, centre_distance=-1.0)


# -- the law's segments --------------------------------------------------------------------------


def _many(n: int) -> str:
    """A law of ``n`` dwells and ``n`` motions, each motion a 1/n turn at constant speed."""
    step, segs = 360 / (2 * n), []
    for i in range(n):
        a, b, c = 2 * i * step, (2 * i + 1) * step, (2 * i + 2) * step
        segs += [
            f"{a:.12g}..{b:.12g}: dwell",
            f"{b:.12g}..{c:.12g}: {2 / n!r}*pi*(phi - {b!r}*pi/180)/({c - b!r}*pi/180)",
        ]
    return "; ".join(segs)


SEGMENTS = [
    ("dwel", f"0..60: dwel; 60..360: {MOTION}", ["segment 1 '0..60: dwel'", "unknown segment kind 'dwel'"]),
    ("Dwelling", f"0..60: Dwelling; 60..360: {MOTION}", ["segment 1", "unknown segment kind 'Dwelling'"]),
    ("no colon", f"0..60 dwell; 60..360: {MOTION}", ["segment 1 '0..60 dwell'", "no ':'"]),
    ("bad second", f"0..60: dwell; 60..360 {MOTION}", ["segment 2", "no ':'"]),
    ("comma", f"0..60: dwell, 60..360: {MOTION}", ["segment 1", "a ',' is no separator"]),
    ("empty body", f"0..60: ; 60..360: {MOTION}", ["segment 1 '0..60:'", "expected 'dwell'"]),
    ("no body", "0..60: dwell; 60..360", ["segment 2 '60..360'", "no ':'"]),
    ("word angle", f"a..60: dwell; 60..360: {MOTION}", ["segment 1", "start angle 'a'"]),
    ("nan angle", f"nan..60: dwell; 60..360: {MOTION}", ["segment 1", "start angle 'nan'"]),
    ("inf angle", f"0..inf: dwell; inf..360: {MOTION}", ["segment 1", "end angle 'inf'"]),
    ("unknown name", f"0..60: dwell; 60..360: {MOTION} + x", ["segment 2", "uses 'x'"]),
    ("syntax", "0..60: dwell; 60..360: sin(", ["segment 2 '60..360: sin('", "not an expression"]),
    ("gap", f"0..60: dwell; 70..360: {MOTION}", ["segment 1 ends at 60 deg, segment 2 starts at 70"]),
    ("backwards", f"60..0: dwell; 0..360: {MOTION}", ["segment 1 (60..0 deg)"]),
    ("too many", _many(MAX_SEGMENTS // 2 + 1), [f"number of segments = {MAX_SEGMENTS + 2}", f"<= {MAX_SEGMENTS}"]),
    ("2000 segments", _many(1000), ["number of segments = 2000"]),
    ("dwell of 1e-9 deg", "0..1e-9: dwell; 1e-9..360: 2*pi*(phi-1e-9*pi/180)/(2*pi-1e-9*pi/180)", ["segment 2"]),
    ("dwell of 2 deg", "0..2: dwell; 2..360: 2*pi*(phi-2*pi/180)/(2*pi-2*pi/180)", ["segment 2", "about 6.61 deg"]),
    ("motion of 1 deg", "0..359: dwell; 359..360: 2*pi*(phi-359*pi/180)/(pi/180)", ["segment 2", "too short"]),
    ("30 motions", _many(30), ["segment 2", "too short"]),
]


@pytest.mark.parametrize(("label", "law", "words"), SEGMENTS, ids=[c[0] for c in SEGMENTS])
def test_a_bad_segment_is_named(capsys, tmp_path, label, law, words):
    refused(capsys, tmp_path, [law, "--module", "2", "--centre-distance", "64"], *words)


@pytest.mark.parametrize(
    "text",
    [
        f"0..60: dwell\n60..360: {MOTION}",
        f"0..60: dwell;\r\n60..360: {MOTION};",
        f"\n0..60: dwell;;  60..360: {MOTION}\n",
        f"0..60: DWELL; 60..360: {MOTION}",
    ],
    ids=["newline", "crlf and trailing", "blank segments", "upper case"],
)
def test_segments_are_separated_by_semicolons_or_new_lines(text):
    law, same = IntermittentLaw.parse(text), IntermittentLaw.parse(LAW)
    assert law.describe() == same.describe() == "dwell 0..60 deg, motion 60..360 deg"
    assert law.motions[0].law == MOTION


# -- ratio CSVs: one reader ----------------------------------------------------------------------


#: examples/dwells.csv: stands 0..60 deg, then one turn at 1.2 (1 - 0.35 cos 2 pi s), every 5 deg
DWELLS = (Path(__file__).resolve().parents[1] / "examples" / "dwells.csv").read_bytes()


def _dwell_rows() -> list[tuple[float, float]]:
    deg, ratio = inputs.ratio_samples(DWELLS)
    return list(zip(deg.tolist(), ratio.tolist(), strict=True))


def _csv(rows, header=True) -> bytes:
    return (("phi_deg,ratio\n" if header else "") + "".join(f"{a:g},{r!r}\n" for a, r in rows)).encode()


def test_a_byte_order_mark_is_no_header_and_the_first_row_is_kept():
    rows = _dwell_rows()
    plain = inputs.ratio_samples(_csv(rows, header=False))
    for data in (b"\xef\xbb\xbf" + _csv(rows, header=False), b"\xef\xbb\xbf" + _csv(rows), _csv(rows)):
        deg, ratio = inputs.ratio_samples(data)
        assert len(deg) == len(rows) and deg[0] == 0.0 and ratio[0] == plain[1][0]
    crlf = _csv(rows).replace(b"\n", b"\r\n")
    assert np.array_equal(inputs.ratio_samples(crlf)[0], plain[0])


def test_full_and_dwell_csvs_are_read_alike(tmp_path):
    """The law of a dwell CSV with a BOM and no header is the law of the CSV as written."""
    laws = []
    for name, data in (("plain.csv", _csv(_dwell_rows())), ("bom.csv", b"\xef\xbb\xbf" + _csv(_dwell_rows(), False))):
        (tmp_path / name).write_bytes(data)
        with _limited():
            laws.append(check_options(str(tmp_path / name), module=3.0, centre_distance=100.0).law)
    assert laws[0].describe() == laws[1].describe() == "motion 60..360 deg, dwell 360..420 deg"


def _gap_in_motion() -> bytes:
    """A dwell CSV whose motion leaves 275 deg unsampled (75..350): a spline there is a guess."""
    rows = [(a, r) for a, r in _dwell_rows() if a <= 75 or a >= 350]
    return _csv(rows)


CSVS = [
    ("full gap", _csv([(a, 1.0) for a in range(0, 270, 10)]), ["without a sample", "limit 90 deg"]),
    ("dwell gap in a motion", _gap_in_motion(), ["275 deg of the turn without a sample, from 75 to 350"]),
    ("dwell gap in a dwell", _csv([(a, r) for a, r in _dwell_rows() if not 5 <= a <= 55 or a == 30]), []),
    ("latin-1", _csv(_dwell_rows()).replace(b"phi_deg", b"\xe9phi"), ["not UTF-8"]),
    ("three columns", _csv(_dwell_rows()).replace(b"\n10,", b"\n10,1,"), ["row 4", "3 columns"]),
    ("a word", _csv(_dwell_rows()).replace(b"\n10,", b"\nten,"), ["row 4 'ten,"]),
    ("hex", _csv(_dwell_rows()).replace(b"\n10,", b"\n0x10,"), ["row 4"]),
    ("underscore", _csv(_dwell_rows()).replace(b"\n100,", b"\n1_00,"), ["row 22"]),
    ("nan ratio", _csv(_dwell_rows()).replace(b"\n10,", b"\n10,nan\n#"), ["must be finite: row 4"]),
    ("header only", b"\xef\xbb\xbfphi_deg,ratio\n", ["0 rows"]),
]


@pytest.mark.parametrize(("label", "data", "words"), CSVS, ids=[c[0] for c in CSVS])
def test_a_csv_is_read_by_one_set_of_rules(capsys, tmp_path, label, data, words):
    path = tmp_path / "law.csv"
    path.write_bytes(data)
    argv = [str(path), "--module", "3", "--centre-distance", "100"]
    if not words:  # zero rows far apart in a dwell are fine: it is the stretch between its ends
        with _limited():
            assert check_options(str(path), module=3.0, centre_distance=100.0).law is not None
        return
    refused(capsys, tmp_path, argv, "ratio CSV", *words)


@pytest.mark.parametrize(
    ("given", "shown"),
    [("r.csv ", "'r.csv '"), (" r.csv", "' r.csv'"), ("r.csv\x1b[2J.csv", "'r.csv\\x1b[2J.csv'")],
    ids=["trailing blank", "leading blank", "escape"],
)
def test_a_csv_path_is_taken_exactly_as_given(capsys, tmp_path, monkeypatch, given, shown):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "r.csv").write_bytes(_csv(_dwell_rows()))  # what a stripped path would read
    line = refused(capsys, tmp_path, [given, "--module", "3", "--centre-distance", "100"], shown, "cannot be read")
    assert "\x1b" not in line


# -- options that do not apply -------------------------------------------------------------------

NOT_APPLYING = [
    ("--ring driver, external", [*FULL_SIZED, "--ring", "driver"], "--ring"),
    ("--ring driven, external", [*FULL_SIZED, "--ring", "driven"], "--ring"),
    (
        "--ring on a named curve",
        ["ellipse:0.05:2", "--internal", "--driven-lobes", "4", "--teeth", "24", "--module", "1.5", "--ring", "driver"],
        "--ring",
    ),
    ("--ring, incomplete", [*INC_SIZED, "--internal", "--ring", "driver"], "--ring"),
    ("--driven-lobes, expression", [*FULL_SIZED, "--driven-lobes", "2"], "--driven-lobes"),
    ("--driven-lobes, incomplete", [*INC_SIZED, "--driven-lobes", "2"], "--driven-lobes"),
    (
        "--scale-to-close, named curve",
        ["ellipse:0.1:2", "--teeth", "24", "--module", "1.5", "--scale-to-close"],
        "--scale-to-close",
    ),
    ("--scale-to-close, incomplete", [*INC_SIZED, "--scale-to-close"], "--scale-to-close"),
    ("--no-trim-ring-tips, external", [*FULL_SIZED, "--no-trim-ring-tips"], "--no-trim-ring-tips"),
    ("--no-trim-ring-tips, incomplete", [*INC_SIZED, "--no-trim-ring-tips"], "--no-trim-ring-tips"),
    (
        "--rack for a ring",
        ["ellipse:0.05:2", "--internal", "--driven-lobes", "4", "--teeth", "24", "--module", "1.5", "--rack"],
        "--rack",
    ),
    ("--rack and --cutter-teeth", [*FULL_SIZED, "--rack", "--cutter-teeth", "12"], "--cutter-teeth"),
    ("--shift, incomplete", [*INC_SIZED, "--shift", "0.1"], "--shift"),
    ("--allow-undercut, incomplete", [*INC_SIZED, "--allow-undercut"], "--allow-undercut"),
    ("--lock-depth, full", [*FULL_SIZED, "--lock-depth", "0.5"], "--lock-depth"),
    ("--lock-clearance, full", [*FULL_SIZED, "--lock-clearance", "0.05"], "--lock-clearance"),
    ("--locking-play, full", [*FULL_SIZED, "--locking-play", "1"], "--locking-play"),
    ("three sizes", [*FULL_SIZED, "--centre-distance", "40"], "give two of --teeth, --module and --centre-distance"),
    ("incomplete sized by teeth and centre distance", [*INC_SIZED, "--teeth", "30"], "--centre-distance"),
]


@pytest.mark.parametrize(("label", "argv", "flag"), NOT_APPLYING, ids=[c[0] for c in NOT_APPLYING])
def test_an_option_that_does_not_apply_is_refused(capsys, tmp_path, label, argv, flag):
    refused(capsys, tmp_path, argv, flag)


# -- a made outline stays one valid polygon (the GEOS class) --------------------------------------


@pytest.mark.parametrize(
    ("csv", "module", "centre_distance", "failure"),
    [("data/dwells_speck.csv", 4.0, 80.0, "speck"), ("../examples/dwells.csv", 4.0, 120.0, "empty")],
    ids=["a speck beside it", "an empty erosion"],
)
def test_a_wire_closing_that_fails_in_geos_still_gives_one_valid_outline_on_the_grid(
    csv, module, centre_distance, failure
):
    """Regression (issue 43): GEOS's closing of these dwell CSVs' drivers fails — an invalid
    MultiPolygon with a 1.2e-8 mm² speck beside the body, or an empty erosion — and the body was then
    passed on as it was, off the grid: its outline CSV's nine decimals made it cross itself
    ("driver_polygon must be a valid ... polygon", exit 1; uniting the pieces back raised a GEOS
    TopologyException). Now a closing is taken only if it holds the body (offset again otherwise)
    and the outline is snapped: one valid polygon, the wire's corners closed, whose nine-decimal
    rounding is the same polygon."""
    import shapely

    import transplanter.geometry.incomplete as incomplete
    from transplanter.geometry.sector_outline import CORNER_RADIUS_MM, GRID_MM, wire_cut

    class Stop(Exception):
        pass

    bodies = []

    def first(body, radius):
        bodies.append(body)
        raise Stop

    spec = str(Path(__file__).parent / csv)
    with _limited(), pytest.MonkeyPatch.context() as mp:
        mp.setattr(incomplete, "_wire_cut", first)
        with pytest.raises(Stop):
            _ = check_options(spec, module=module, centre_distance=centre_distance).study.gears
    (body,) = bodies  # the driver as cut, before the wire
    closed = body.buffer(CORNER_RADIUS_MM, quad_segs=64).buffer(-CORNER_RADIUS_MM, quad_segs=64)
    if failure == "speck":
        assert isinstance(closed, shapely.MultiPolygon) and not closed.is_valid
    else:
        assert closed.is_empty
    assert not shapely.Polygon(np.round(body.exterior.coords, 9)).is_valid  # the body as the CSV held it
    made = wire_cut(body, CORNER_RADIUS_MM)
    coords = np.asarray(made.exterior.coords)
    assert isinstance(made, shapely.Polygon) and made.is_valid
    assert shapely.difference(body, made).area < 1e-3 and made.area > body.area  # holds it, corners filled
    assert np.abs(coords / GRID_MM - np.round(coords / GRID_MM)).max() < 1e-3  # on the grid
    assert shapely.Polygon(np.round(coords, 9)).equals(made)
