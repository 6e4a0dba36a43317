"""What the command line prints and leaves behind when the text or the folders come from someone
else (issue 43): text from data is printed as text (control characters escaped, never obeyed by
the terminal), and the internal-error log is written where no planted link can redirect it.
"""

from __future__ import annotations

import json
import os
import stat
import tempfile
import time
from pathlib import Path

import pytest

from transplanter.app import cli
from transplanter.app.testing import SQUARE_SCRIPT
from transplanter.core.text import CONTROLS, shown

#: the characters a terminal obeys, by kind, and a name for each case
OBEYED = {
    "clear screen": "\x1b[2J",
    "carriage return": "\r",
    "set title (OSC)": "\x1b]0;pwned\x07",
    "newline": "\n",
    "backspace": "\b",
    "C1 CSI": "\x9b2J",
    "DEL": "\x7f",
    "NUL": "\x00",
    "right-to-left override": "\u202e",
    "left-to-right isolate": "\u2066",
    "pop directional isolate": "\u2069",
    "bell": "\x07",
}


def raw(text: str) -> list[str]:
    """The characters of CONTROLS ``text`` holds (a printed line holds none but its own newlines)."""
    return sorted({c for c in text if c in CONTROLS and c != "\n"})


@pytest.mark.parametrize("code", sorted(ord(c) for c in CONTROLS))
def test_every_control_character_is_escaped_and_readable(code):
    c = chr(code)
    out = shown(f"a{c}b")
    assert c not in out and out.startswith("a\\") and out.endswith("b") and out.isprintable()
    assert shown(out) == out  # idempotent: an escape is text


def test_printable_text_of_any_script_is_kept():
    text = "ring µm ² – ü 齿轮 שלום \\x1b (already an escape)"
    assert shown(text) == text and shown(3) == "3"


def _report(name: str) -> dict:
    """A check report quoting ``name`` everywhere a manifest's text reaches the printed lines."""
    return {
        "family": f"fam{name}",
        "script": f"parts/x{name}.py",
        "script_run": True,
        "ok": False,
        "files": {f"f{name}.dxf": f"missing{name}"},
        "parts": {
            f"part{name}": {
                "expected": False,
                "problems": [f"error from a file{name}"],
                "results": {
                    "shop_files_reread": 1,
                    f"src{name}": {
                        "pairs_judged": 2,
                        "smallest_mm": 1.0,
                        "between": f"a{name}b",
                        "at_driver_deg": 3.0,
                        "required_mm": 0.5,
                    },
                    "made": {
                        f"m{name}.step": {
                            "solids": 1,
                            "faces": 6,
                            "valid": True,
                            "volume_rel_error": 0.0,
                            "checked_by": f"ocp{name}",
                        }
                    },
                },
            }
        },
    }


@pytest.mark.parametrize("kind", sorted(OBEYED))
def test_check_prints_names_paths_and_errors_from_a_manifest_as_text(tmp_path, capsys, monkeypatch, kind):
    import transplanter.families as families

    name = OBEYED[kind] + "ok"
    folder = tmp_path / f"fam{OBEYED[kind].replace(chr(0), '')}"  # a path holds no NUL
    folder.mkdir()
    (folder / "manifest.json").write_text("{}")
    monkeypatch.setattr(families, "check_families", lambda folders, *a, **k: [_report(name)])
    assert cli.main(["check", str(folder)]) == 1
    out, err = capsys.readouterr()
    assert raw(out + err) == [], (out, err)
    escaped = shown(OBEYED[kind])
    for said in (
        f"fam{escaped}ok",
        f"file f{escaped}ok.dxf: missing{escaped}ok",
        f"error from a file{escaped}ok",
        f"a{escaped}okb",
        f"ocp{escaped}ok",
        f"part{escaped}ok",
    ):
        assert said in out, (said, out)
    assert len(out.splitlines()) == 7  # one line each: nothing a name holds starts another


@pytest.mark.parametrize("kind", sorted(OBEYED))
def test_an_error_quoting_a_path_is_printed_as_text(tmp_path, capsys, kind):
    if "\x00" in OBEYED[kind]:
        pytest.skip("a path cannot hold NUL")
    bad = tmp_path / f"no{OBEYED[kind]}such"
    code = cli.main(["check", str(bad)])
    out, err = capsys.readouterr()
    assert code == 2 and "transplanter: error:" in err and raw(out + err) == [], err
    assert f"no{shown(OBEYED[kind])}such" in err and len(err.splitlines()) == 1


@pytest.mark.parametrize("kind", sorted(OBEYED))
def test_argparse_quotes_the_arguments_as_text(capsys, kind):
    with pytest.raises(SystemExit) as exc:
        cli.main(["check", f"--bo{OBEYED[kind]}gus"])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and raw(err) == [] and f"--bo{shown(OBEYED[kind])}gus" in err, err


def test_a_crafted_manifest_prints_nothing_a_terminal_obeys(tmp_path, capsys, monkeypatch):
    """End to end: a built family whose manifest a hand filled with escape sequences."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "squares.py").write_text(SQUARE_SCRIPT)
    assert cli.main(["build", "squares.py", "-o", "out", "--jobs", "1"]) == 0
    capsys.readouterr()
    path = tmp_path / "out" / "squares" / "manifest.json"
    manifest = json.loads(path.read_text())
    manifest["family"] = "squares\x1b[2J\x1b]0;title\x07"
    manifest["parts"]["sq"] = {"error": "GeometryError: \x1b[1A\x1b[2K\rok \u202etxt.exe"}
    path.write_text(json.dumps(manifest))
    code = cli.main(["check", str(tmp_path / "out" / "squares")])
    out, err = capsys.readouterr()
    assert code in (1, 2) and raw(out + err) == [], (out, err)
    assert "Traceback" not in err and "internal error" not in err


# -- the internal-error log --------------------------------------------------------------------


@pytest.fixture
def crash(monkeypatch, tmp_path):
    """A bug in ``check`` (the command raises KeyError), the state folder and temp folder in tmp_path."""
    monkeypatch.setattr(cli, "_cmd_check", lambda args: {}["no such key"])
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    (tmp_path / "tmp").mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "tmp"))
    victim = tmp_path / "victim.txt"
    victim.write_text("precious\n")
    return victim


def _logged(capsys) -> str:
    err = capsys.readouterr().err
    assert "transplanter: internal error — please report it: KeyError" in err and "Traceback" not in err
    return err.rsplit("the traceback is in ", 1)[1].strip()


def test_the_log_is_written_in_a_private_folder_of_ours(tmp_path, capsys, crash):
    for second in range(3):  # links planted at the old predictable names, for this second and the next
        t = time.strftime("%Y%m%d-%H%M%S", time.localtime(time.time() + second))
        (tmp_path / "tmp" / f"transplanter-internal-error-{t}-{os.getpid()}.log").symlink_to(crash)
    assert cli.main(["check", str(tmp_path / "elsewhere")]) == 1
    log = _logged(capsys)
    assert crash.read_text() == "precious\n"
    assert os.path.dirname(log) == str(tmp_path / "state" / "transplanter")
    assert "no such key" in Path(log).read_text(encoding="utf-8")
    assert stat.S_IMODE(os.stat(log).st_mode) == 0o600
    assert stat.S_IMODE(os.stat(tmp_path / "state" / "transplanter").st_mode) == 0o700


@pytest.mark.parametrize("attack", ["state folder is a link", "state folder open to others", "link at the name"])
def test_a_planted_link_is_never_followed(tmp_path, capsys, crash, monkeypatch, attack):
    planted = tmp_path / "attacker"
    planted.mkdir(mode=0o700)
    (tmp_path / "state").mkdir()
    if attack == "state folder is a link":
        (tmp_path / "state" / "transplanter").symlink_to(planted)
    elif attack == "state folder open to others":
        (tmp_path / "state" / "transplanter").mkdir()
        os.chmod(tmp_path / "state" / "transplanter", 0o777)
    else:  # a link at whatever name the log is given: the name made foreseeable for the test
        monkeypatch.setattr(os, "urandom", lambda n: b"\x00" * n)
        monkeypatch.setattr(time, "strftime", lambda fmt, *a: "20260101-000000")
        (tmp_path / "state" / "transplanter").mkdir(mode=0o700)
        name = f"internal-error-20260101-000000-{os.getpid()}-00000000.log"
        (tmp_path / "state" / "transplanter" / name).symlink_to(crash)
    assert cli.main(["check", str(tmp_path / "elsewhere")]) == 1
    log = _logged(capsys)
    assert crash.read_text() == "precious\n" and list(planted.iterdir()) == []
    assert os.path.dirname(os.path.dirname(log)) == str(tmp_path / "tmp")  # a fresh private folder instead
    assert stat.S_IMODE(os.stat(os.path.dirname(log)).st_mode) == 0o700


def test_the_log_is_never_written_inside_or_beside_a_checked_folder(tmp_path, capsys, crash, monkeypatch):
    checked = tmp_path / "checked"
    checked.mkdir()
    monkeypatch.setenv("XDG_STATE_HOME", str(checked))  # the state folder would be inside it
    assert cli.main(["check", str(checked)]) == 1
    log = _logged(capsys)
    assert list(checked.iterdir()) == [] and log.startswith(str(tmp_path / "tmp"))
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))  # a fresh folder would be beside it
    assert cli.main(["check", str(checked)]) == 1
    err = capsys.readouterr().err
    assert "its traceback could not be written to a private folder" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["checked", "tmp", "victim.txt"]
