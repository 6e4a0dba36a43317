"""Nothing carried forward unverified (issue 43): an incremental build keeps a part only if its
key, the last manifest's seal, the build's own record of the part and every file's digest (on the
bytes taken) verify — anything else is rebuilt and the summary says which part and why; the lock,
the build record and the manifest are read by one reader (regular files only, size-limited, never
blocking); a crafted manifest is one line naming its field, in ``build`` and ``check``; the files
beside the folder go with the swap or not at all; two builds of one folder never interleave.

Every case runs under a time limit (in a thread: a FIFO that blocks fails the case instead of
hanging the run). The families are two tiny plates (a text file each), built in-process in well
under a second.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from transplanter.app import cli
from transplanter.families.builder.manifest import seal

#: a case's time limit, seconds (each takes well under one)
LIMIT_S = 30.0

#: the kind of study, in a design module beside the script: editing the script's constants
#: changes only the part whose constant changed
PLATE_KIND = """
from dataclasses import dataclass

from transplanter.families import Built, StudyDefaults


@dataclass(frozen=True)
class Plate(StudyDefaults):
    name: str
    side: float
    cost = 1

    def build(self, out):
        data = f"{self.side ** 2:.6f}\\n".encode()
        record = {"kind": "plate", "parameters": {"side": self.side}, "results": {"area": self.side ** 2}}
        return Built(record, {f"{self.name}.txt": data})
"""
PLATES = """
from _plate_kind import Plate

from transplanter.families import Family


def family():
    return Family("plates", "two plates", (Plate("a", {a}), Plate("b", {b})))
"""


def within(call, seconds: float = LIMIT_S):
    """``call()`` run in a thread: its value (or its exception, raised here); the case fails if it
    takes longer than ``seconds`` — a blocked open or read included (a signal could not be relied
    on: loading a part script sets and clears its own alarm)."""
    box: dict = {}

    def target():
        try:
            box["value"] = call()
        except BaseException as exc:  # noqa: BLE001 - handed to the test's thread
            box["error"] = exc

    worker = threading.Thread(target=target, daemon=True)
    worker.start()
    worker.join(seconds)
    if worker.is_alive():
        pytest.fail(f"did not finish within {seconds:g} s (a hang)")
    if "error" in box:
        raise box["error"]
    return box["value"]


def run(capsys, *argv) -> tuple[int, str, str]:
    code = within(lambda: cli.main([str(a) for a in argv]))
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err and "internal error" not in err, err
    return code, out, err


@pytest.fixture
def plates(tmp_path, monkeypatch, capsys):
    """A project with the two plates built into ``out``: ``(script, folder, rebuild(a, b))``."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "_plate_kind.py").write_text(PLATE_KIND)
    script = tmp_path / "plates.py"

    def rebuild(a: float = 3.0, b: float = 4.0, *more) -> tuple[int, str, str]:
        script.write_text(PLATES.format(a=a, b=b))
        return run(capsys, "build", script, "-o", tmp_path / "out", "--jobs", "1", *more)

    assert rebuild()[0] == 0
    return script, tmp_path / "out" / "plates", rebuild


def manifest_of(folder: Path) -> dict:
    return json.loads((folder / "manifest.json").read_text())


def resealed(folder: Path, manifest: dict) -> None:
    """Write ``manifest`` sealed again, with the project's own seal: a forger's edit."""
    manifest = seal({k: v for k, v in manifest.items() if k != "manifest_sha256"})
    (folder / "manifest.json").write_text(json.dumps(manifest))


def record_path(folder: Path) -> Path:
    return folder.parent / f".{folder.name}.build.json"


def files_of(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def assert_consistent(folder: Path) -> None:
    """The folder holds exactly what its manifest lists, each file with its digest."""
    manifest = manifest_of(folder)
    listed = {"manifest.json", *manifest["report"]}
    for rec in manifest["parts"].values():
        for fname, digest in rec.get("files", {}).items():
            assert hashlib.sha256((folder / fname).read_bytes()).hexdigest() == digest, fname
            listed.add(fname)
    assert {p.name for p in folder.iterdir()} == listed


def assert_full_rebuild(capsys, folder: Path, script: Path) -> None:
    """The folder is byte for byte what a build from nothing makes, and ``check`` passes it."""
    full = folder.parent.parent / "full"
    assert run(capsys, "build", script, "-o", full, "--force", "--jobs", "1")[0] == 0
    assert files_of(folder) == files_of(full / folder.name)
    assert run(capsys, "check", folder)[0] == 0


# -- what a forger with write access to the export folder can do -------------------------------


def _edit_file_and_digest(folder):  # the hand edit of the issue: a file, its digest, resealed
    manifest = manifest_of(folder)
    (folder / "b.txt").write_text("99.000000\n")
    manifest["parts"]["b"]["files"]["b.txt"] = hashlib.sha256(b"99.000000\n").hexdigest()
    manifest["parts"]["b"]["results"]["area"] = 99.0
    resealed(folder, manifest)


def _edit_results(folder):
    manifest = manifest_of(folder)
    manifest["parts"]["b"]["results"]["area"] = 99.0
    resealed(folder, manifest)


def _edit_results_unsealed(folder):
    manifest = manifest_of(folder)
    manifest["parts"]["b"]["results"]["area"] = 99.0
    (folder / "manifest.json").write_text(json.dumps(manifest))


def _drop_seal(folder):
    manifest = manifest_of(folder)
    del manifest["manifest_sha256"]
    (folder / "manifest.json").write_text(json.dumps(manifest))


def _edit_file(folder):
    (folder / "b.txt").write_text("99.000000\n")


def _delete_file(folder):
    (folder / "b.txt").unlink()


def _link_file(folder):  # a link to a copy with the right bytes: still not followed
    copy = folder.parent.parent / "copy.txt"
    copy.write_bytes((folder / "b.txt").read_bytes())
    (folder / "b.txt").unlink()
    (folder / "b.txt").symlink_to(copy)


def _fifo_file(folder):
    (folder / "b.txt").unlink()
    os.mkfifo(folder / "b.txt")


def _forge_a_with_bs_files(folder):  # part a given b's files, a.txt gone, resealed
    manifest = manifest_of(folder)
    manifest["parts"]["a"]["files"] = dict(manifest["parts"]["b"]["files"])
    (folder / "a.txt").unlink()
    resealed(folder, manifest)


def _forge_both_records(folder):  # the manifest and the build record agree on a file that is not there
    manifest = manifest_of(folder)
    manifest["parts"]["a"]["files"]["c.txt"] = "0" * 64
    resealed(folder, manifest)
    record = json.loads(record_path(folder).read_text())
    record["parts"]["a"] = manifest["parts"]["a"]
    record_path(folder).write_text(json.dumps(seal({k: v for k, v in record.items() if k != "manifest_sha256"})))


def _drop_part(folder):
    manifest = manifest_of(folder)
    del manifest["parts"]["a"]
    resealed(folder, manifest)


def _edit_record_unsealed(folder):
    record = json.loads(record_path(folder).read_text())
    record["parts"]["b"]["results"]["area"] = 99.0
    record_path(folder).write_text(json.dumps(record))


def _manifest_a_folder(folder):
    (folder / "manifest.json").unlink()
    (folder / "manifest.json").mkdir()


def _manifest_a_fifo(folder):
    (folder / "manifest.json").unlink()
    os.mkfifo(folder / "manifest.json")


def _manifest_a_socket(folder):
    (folder / "manifest.json").unlink()
    with socket.socket(socket.AF_UNIX) as s:
        s.bind(str(folder / "manifest.json"))


#: (label, edit, the part edited, words in why it is rebuilt, every part rebuilt)
FORGERIES = [
    ("file and digest, resealed", _edit_file_and_digest, "b", "differs from the one the build made", False),
    ("results only, resealed", _edit_results, "b", "differs from the one the build made", False),
    ("results only, seal left", _edit_results_unsealed, "b", "seal, manifest_sha256, does not verify", True),
    ("seal removed", _drop_seal, "b", "carries no seal", True),
    ("file only", _edit_file, "b", "b.txt: changed since the build (SHA-256 differs)", False),
    ("file deleted", _delete_file, "b", "b.txt: missing", False),
    ("file a link", _link_file, "b", "b.txt: a symbolic link: not followed", False),
    ("file a FIFO", _fifo_file, "b", "b.txt: a FIFO (a named pipe), not a regular file", False),
    ("a given b's files", _forge_a_with_bs_files, "a", "differs from the one the build made", False),
    ("both records name a missing file", _forge_both_records, "a", "c.txt: missing", False),
    ("part dropped from the manifest", _drop_part, "a", "is missing from .plates.build.json", False),
    ("build record edited", _edit_record_unsealed, "b", ".plates.build.json was edited since the build", True),
    ("manifest a folder", _manifest_a_folder, "b", "a folder, not a regular file", True),
    ("manifest a FIFO", _manifest_a_fifo, "b", "a FIFO (a named pipe), not a regular file", True),
    ("manifest a socket", _manifest_a_socket, "b", "a socket, not a regular file", True),
]


@pytest.mark.parametrize(("label", "edit", "edited", "words", "all_rebuilt"), FORGERIES, ids=[f[0] for f in FORGERIES])
def test_an_edited_part_is_rebuilt_and_the_summary_says_why(plates, capsys, label, edit, edited, words, all_rebuilt):
    script, folder, rebuild = plates
    edit(folder)
    other = "b" if edited == "a" else "a"
    code, out, _ = rebuild(*((3.0, 5.0) if other == "b" else (5.0, 4.0)))  # another part changed
    assert code == 0
    build = json.loads(record_path(folder).read_text())
    assert words in build["unverified"][edited], build["unverified"]
    assert sorted(build["unverified"]) == (["a", "b"] if all_rebuilt else [edited])
    assert build["kept"] == [] and sorted(build["rebuilt"]) == ["a", "b"]
    line = next(x for x in out.splitlines() if x.startswith(f"  rebuilt plates/{edited}: "))
    assert words in line
    assert_consistent(folder)
    assert_full_rebuild(capsys, folder, script)


def test_with_nothing_else_changed_the_edited_part_alone_is_rebuilt(plates, capsys):
    script, folder, rebuild = plates
    _edit_file_and_digest(folder)
    code, out, _ = rebuild()
    build = json.loads(record_path(folder).read_text())
    assert code == 0 and build["kept"] == ["a"] and list(build["unverified"]) == ["b"]
    assert "  rebuilt plates/b: its record in manifest.json differs" in out
    assert (folder / "b.txt").read_text() == "16.000000\n"
    assert_full_rebuild(capsys, folder, script)
    assert rebuild()[1].count("rebuilt plates/") == 0  # and then nothing is said: all kept, verified


def test_the_build_record_holds_what_the_build_made_and_is_sealed(plates):
    _, folder, rebuild = plates
    record = json.loads(record_path(folder).read_text())
    assert record["parts"] == manifest_of(folder)["parts"]
    assert (
        record["manifest_sha256"]
        == seal({k: v for k, v in record.items() if k != "manifest_sha256"})["manifest_sha256"]
    )
    del record["parts"]  # an older build's record: it says nothing of what was made — rebuilt, no alarm
    record_path(folder).write_text(json.dumps(record))
    code, out, _ = rebuild()
    record = json.loads(record_path(folder).read_text())
    assert code == 0 and record["kept"] == [] and record["unverified"] == {} and "rebuilt plates/" not in out
    assert set(record["rebuilt"].values()) == {"new, or no record of its last build"}


def test_a_failing_part_keeps_only_previous_files_that_verify(plates, capsys):
    script, folder, rebuild = plates
    (folder / "b.txt").write_text("99.000000\n")
    assert rebuild(3.0, None)[0] == 1  # b fails now: its previous file is edited, not carried
    manifest = manifest_of(folder)
    assert "previous_files" not in manifest["parts"]["b"] and not (folder / "b.txt").exists()
    assert rebuild()[0] == 0
    assert rebuild(3.0, None)[0] == 1  # one that verifies is carried
    assert manifest_of(folder)["parts"]["b"]["previous_files"] == {"b.txt": hashlib.sha256(b"16.000000\n").hexdigest()}
    assert run(capsys, "check", folder)[0] == 1  # (a failed part fails the check)


# -- one reader: what is not a regular file is never opened ------------------------------------


@pytest.mark.parametrize("kind", ["fifo", "folder", "link"])
@pytest.mark.parametrize("where", ["build record", "lock"])
def test_a_build_record_or_lock_that_is_not_a_file_is_refused_at_once(plates, capsys, where, kind):
    script, folder, rebuild = plates
    path = record_path(folder) if where == "build record" else folder.parent / ".plates.lock"
    before = files_of(folder)
    path.unlink()
    {"fifo": os.mkfifo, "folder": os.mkdir, "link": lambda p: p.symlink_to(folder / "a.txt")}[kind](path)
    code, out, err = rebuild(5.0)
    assert code == 1 and err.count("\n") == 1 and "transplanter: error:" in err, err
    said = {"fifo": "a FIFO (a named pipe)", "folder": "a folder", "link": "symbolic link"}[kind]
    assert said in err and "not seekable" not in err
    assert files_of(folder) == before and not (folder.parent / ".plates.previous").exists()


@pytest.mark.parametrize("target", ["manifest.json", "a.txt"])
def test_check_never_opens_a_fifo(plates, capsys, target):
    _, folder, _ = plates
    (folder / target).unlink()
    os.mkfifo(folder / target)
    code, out, _ = run(capsys, "check", folder)
    assert code == 1 and f"file {target}: " in out and "a FIFO (a named pipe), not a regular file" in out


def test_the_reader_refuses_what_is_not_a_regular_file(tmp_path):
    from transplanter.core.errors import SpecError
    from transplanter.core.files import FileRefused, open_regular, read_regular

    (tmp_path / "f").write_bytes(b"12345")
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "dir").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "f")
    with socket.socket(socket.AF_UNIX) as s:
        s.bind(str(tmp_path / "sock"))
    cases = {
        "fifo": "a FIFO (a named pipe), not a regular file: not opened",
        "dir": "a folder, not a regular file: not opened",
        "link": "a symbolic link: not followed",
        "sock": "a socket, not a regular file: not opened",
        "missing": "cannot be read: No such file or directory",
        "f/x": "cannot be read: Not a directory",
        "x" * 300: "cannot be read: File name too long",
    }
    for name, reason in cases.items():
        with pytest.raises(FileRefused) as caught:
            within(lambda n=name: read_regular(tmp_path / n, "the file", 10))
        assert caught.value.reason == reason and isinstance(caught.value, SpecError)
        assert "\n" not in str(caught.value)
    assert read_regular(tmp_path / "f", "the file", 5) == b"12345"
    assert read_regular(tmp_path / "link", "the file", 5, follow_links=True) == b"12345"
    assert read_regular(tmp_path / "missing", "the file", 5, missing_ok=True) is None
    with pytest.raises(FileRefused, match=r"larger than 4 bytes \(5\): not read"):
        read_regular(tmp_path / "f", "the file", 4)
    for name in ("fifo", "dir", "link", "sock"):
        with pytest.raises(FileRefused):
            within(lambda n=name: os.close(open_regular(tmp_path / n, "the lock", os.O_RDWR | os.O_CREAT)))
    os.close(open_regular(tmp_path / "new.lock", "the lock", os.O_RDWR | os.O_CREAT))


# -- a crafted manifest: one line naming the field, in check and in build -----------------------

_D = "0" * 64
#: (field, a wrong value, words of the one line that names it): each field of the schema with
#: the wrong types and values a crafted manifest can give it
_TOP_CASES = [
    *[("family", v, "'family' must be a plain name") for v in (1, ["plates"], None, "../x", "a\x1bb", "x" * 300)],
    *[("description", v, "'description' must be text") for v in (1, [], None, {})],
    *[("ok", v, "'ok' must be true or false") for v in ("yes", 1, None)],
    *[("report", v, "'report' must be a table") for v in ([], "report.html", 3)],
    ("report", {"../x": _D}, "not a plain file name"),
    ("report", {"report.html": "zz"}, "must be a SHA-256"),
    *[("script", v, "'script' must be a record") for v in ("x.py", ["x.py"], 1)],
    *[("manifest_sha256", v, "'manifest_sha256' must be a SHA-256") for v in (1, "abc", "A" * 64)],
    *[("parts", v, "no 'parts' table") for v in ([1], None, "a")],
]
_SCRIPT_CASES = [
    *[({"path": v, "sha256": _D}, "'script'.path must be a path") for v in (1, "", None, "x" * 5000)],
    *[({"path": "p.py", "sha256": v}, "'script'.sha256 must be a SHA-256") for v in (1, None, "x" * 64, _D[1:])],
    *[({"path": "p.py", "sha256": _D, "modules": v}, "'script'.modules must be a table") for v in (["_m.py"], "m", 1)],
    ({"path": "p.py", "sha256": _D, "modules": {"../_m.py": _D}}, "not a plain file name"),
    ({"path": "p.py", "sha256": _D, "modules": {"_m.py": 1}}, "must be a SHA-256"),
]
_PART_CASES = [
    *[({"files": v}, "files must be a table") for v in ([1], "a.txt", None)],
    *[({"files": {v: _D}}, "not a plain file name") for v in ("x" * 304, "a\nb", "a\x1b[2Jb", "../a", "", "é" * 128)],
    *[({"files": {"a.txt": v}}, "must be a SHA-256") for v in (1, None, "0" * 63, "G" * 64, [])],
    *[({"error": "e", "previous_files": v}, "previous_files must be a table") for v in ([1], 2)],
    *[({"error": v}, "error must be text") for v in (1, {}, None)],
    *[({"files": {}, "kind": v}, "kind must be text") for v in (1, [])],
    *[({"files": {}, "parameters": v}, "parameters must be a table") for v in ([1, 2], "side=3", 3, None)],
    *[({"files": {}, "results": v}, "results must be a table") for v in ([1], "ok", 1.5)],
    ({"kind": "plate"}, "neither 'files' nor 'error'"),
]


def _crafted():
    for field, value, words in _TOP_CASES:
        yield f"{field}={value!r:.20}", lambda m, f=field, v=value: m.__setitem__(f, v), words
    for value, words in _SCRIPT_CASES:
        yield f"script={value!r:.40}", lambda m, v=value: m.__setitem__("script", v), words
    for value, words in _PART_CASES:
        yield f"part={value!r:.40}", lambda m, v=value: m["parts"].__setitem__("a", v), words
    for name in ("", "a/b", "x" * 300, "\x1b[2J", "a\tb"):
        yield f"part name {name!r:.20}", lambda m, n=name: m.__setitem__("parts", {n: {"files": {}}}), "a part name"
    for value in (1, [], "x", None):
        yield f"part record {value!r}", lambda m, v=value: m["parts"].__setitem__("a", v), "must be a record"


CRAFTED = list(_crafted())


def test_the_crafted_cases_cover_every_field():
    from transplanter.families.builder.manifest import _MANIFEST_FIELDS, _PART_FIELDS

    assert {c[0] for c in _TOP_CASES} >= set(_MANIFEST_FIELDS) | {"parts"}
    assert {k for value, _ in _PART_CASES for k in value} >= set(_PART_FIELDS)
    assert len(CRAFTED) >= 70


@pytest.fixture(scope="module")
def built_once(tmp_path_factory):
    """One built family, copied for each crafted case (building is the costly part)."""
    root = tmp_path_factory.mktemp("crafted")
    (root / "_plate_kind.py").write_text(PLATE_KIND)
    (root / "plates.py").write_text(PLATES.format(a=3.0, b=4.0))
    assert within(lambda: cli.main(["build", str(root / "plates.py"), "-o", str(root / "out"), "--jobs", "1"])) == 0
    return root


@pytest.mark.parametrize("k", range(len(CRAFTED)), ids=[c[0] for c in CRAFTED])
def test_a_crafted_manifest_is_one_line_naming_its_field(built_once, tmp_path, monkeypatch, capsys, k):
    label, craft, words = CRAFTED[k]
    shutil.copytree(built_once, tmp_path / "p", symlinks=True)
    monkeypatch.chdir(tmp_path / "p")
    folder = Path("out") / "plates"
    manifest = manifest_of(folder)
    craft(manifest)  # (sealed or not: the schema is checked first)
    (folder / "manifest.json").write_text(json.dumps(manifest))
    for args in (("check", folder), ("check", "--run-script", folder)):
        code, out, err = run(capsys, *args)
        line = next(x for x in out.splitlines() if x.startswith("  file manifest.json: "))
        assert code == 1 and "damaged" in line and words in line, (line, words)
    code, out, err = run(capsys, "build", "plates.py", "-o", "out", "--jobs", "1")
    build = json.loads(record_path(folder).read_text())
    assert code == 0 and sorted(build["unverified"]) == ["a", "b"] and build["kept"] == []
    assert sum(words in x for x in out.splitlines() if x.startswith("  rebuilt plates/")) == 2
    assert_consistent(folder)


# -- the files beside the folder go with the swap ----------------------------------------------


@pytest.mark.parametrize("failing", [".plates.build.json", "plates.py"])
def test_a_file_beside_that_cannot_be_written_undoes_the_swap(plates, monkeypatch, failing):
    from transplanter.families import build_family, load_family

    script, folder, _ = plates
    script.write_text(PLATES.format(a=5.0, b=4.0))
    family = load_family(script)
    parent = folder.parent
    (parent / "plates.py").write_text("# the part script of an earlier build\n")
    before = {p.name: p.read_bytes() for p in parent.iterdir() if p.is_file()}
    folder_before = files_of(folder)
    real = os.replace

    def refuse(src, dst, *args, **kw):
        if Path(dst).name == failing:
            raise OSError(28, "No space left on device")
        return real(src, dst, *args, **kw)

    monkeypatch.setattr(os, "replace", refuse)
    from transplanter.core.errors import ExportError

    with pytest.raises(ExportError, match="No space left on device"):
        within(lambda: build_family(family, parent, beside={"plates.py": b"# written with the export\n"}))
    monkeypatch.setattr(os, "replace", real)
    assert files_of(folder) == folder_before  # the old export, whole
    assert {p.name: p.read_bytes() for p in parent.iterdir() if p.is_file()} == before  # and beside it
    assert sorted(p.name for p in parent.iterdir()) == sorted([*before, "plates"])  # no .previous, .beside


def test_a_file_beside_that_cannot_be_written_exits_1_with_the_old_export(plates, capsys, monkeypatch):
    script, folder, rebuild = plates
    before = files_of(folder)
    real = os.replace

    def refuse(src, dst, *args, **kw):
        if Path(dst).name.endswith(".build.json"):
            raise PermissionError(13, "Permission denied")
        return real(src, dst, *args, **kw)

    monkeypatch.setattr(os, "replace", refuse)
    code, _, err = rebuild(5.0)
    assert code == 1 and "Permission denied" in err
    assert files_of(folder) == before and not (folder.parent / ".plates.previous").exists()


# -- two builds of one folder ------------------------------------------------------------------

SLOW_KIND = """
import os
import time
from dataclasses import dataclass

from transplanter.families import Built, StudyDefaults


@dataclass(frozen=True)
class Slow(StudyDefaults):
    name: str
    side: float
    cost = 1

    def build(self, out):
        flag = os.environ["PLATES_FLAG"]
        open(flag + ".started", "w").close()
        for _ in range(600):  # until the test lets it go (at most 30 s)
            if os.path.exists(flag):
                break
            time.sleep(0.05)
        return Built({"kind": "slow", "results": {}}, {f"{self.name}.txt": f"{self.side:.6f}\\n".encode()})
"""
SLOW = """
from _slow_kind import Slow

from transplanter.families import Family


def family():
    return Family("plates", "two plates", (Slow("a", 1.0), Slow("b", {b})))
"""


def test_two_builds_of_one_folder_do_not_interleave(tmp_path, monkeypatch, capsys):
    """While one build (another process, ``--jobs 2``) rebuilds a part, a second build of the same
    folder is refused at once — before it decides anything — and the folder ends consistent."""
    monkeypatch.chdir(tmp_path)
    flag = tmp_path / "go"
    monkeypatch.setenv("PLATES_FLAG", str(flag))
    (tmp_path / "_slow_kind.py").write_text(SLOW_KIND)
    script = tmp_path / "plates.py"
    script.write_text(SLOW.format(b=2.0))
    flag.touch()
    assert run(capsys, "build", script, "-o", "out", "--jobs", "1")[0] == 0
    flag.unlink()
    Path(f"{flag}.started").unlink()
    script.write_text(SLOW.format(b=3.0))  # b changes: the first build waits in it, holding the lock
    cmd = [sys.executable, "-m", "transplanter", "build", str(script), "-o", "out", "--jobs", "2"]
    first = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while not Path(f"{flag}.started").exists():
            assert time.monotonic() < deadline and first.poll() is None, first.communicate()
            time.sleep(0.05)
        second: list = []
        worker = threading.Thread(target=lambda: second.append(cli.main(["build", str(script), "-o", "out"])))
        worker.daemon = True
        worker.start()
        worker.join(20)
        assert not worker.is_alive(), "the second build waited for the first"
    finally:
        flag.touch()
        out, err = first.communicate(timeout=60)
    worker.join(30)
    _, second_err = capsys.readouterr()
    assert first.returncode == 0, err
    assert second == [1] and "another build is writing" in second_err
    assert_consistent(tmp_path / "out" / "plates")
    assert (tmp_path / "out" / "plates" / "b.txt").read_text() == "3.000000\n"
    assert run(capsys, "check", tmp_path / "out" / "plates")[0] == 0


# -- what a build makes is what a manifest can hold ---------------------------------------------

ODD_KIND = """
from dataclasses import dataclass

from transplanter.families import Built, StudyDefaults


@dataclass(frozen=True)
class Odd(StudyDefaults):
    name: str
    files: tuple
    parameters: object = None
    cost = 1

    def build(self, out):
        return Built({"kind": "odd", "parameters": self.parameters or {}, "results": {}}, dict(self.files))
"""


@pytest.mark.parametrize(
    ("files", "parameters", "words"),
    [
        ((("../escaped.txt", b"x"),), None, "not a plain file name"),
        ((("a\x1b[2J.txt", b"x"),), None, "not a plain file name"),
        ((("x" * 300, b"x"),), None, "not a plain file name"),
        ((("ok.txt", b"x"),), [1, 2], "parameters must be a table"),
    ],
)
def test_a_part_whose_record_no_manifest_could_hold_fails(tmp_path, monkeypatch, capsys, files, parameters, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "_odd_kind.py").write_text(ODD_KIND)
    (tmp_path / "odd.py").write_text(
        "from _odd_kind import Odd\nfrom transplanter.families import Family\n"
        f"def family():\n    return Family('odd', 'odd', (Odd('p', {files!r}, {parameters!r}),))\n"
    )
    code, out, err = run(capsys, "build", "odd.py", "-o", "out", "--jobs", "1")
    assert code == 1 and words in manifest_of(tmp_path / "out" / "odd")["parts"]["p"]["error"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["_odd_kind.py", "odd.py", "out"]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [".odd.build.json", ".odd.lock", "odd"]


MEDDLER_KIND = (
    PLATE_KIND
    + """

@dataclass(frozen=True)
class Meddler(Plate):
    def build(self, out):  # edits another part's file in the export while the build runs
        (out / "b.txt").write_text("99.000000\\n")
        return super().build(out)
"""
)


def test_a_kept_file_changed_while_the_build_runs_is_not_taken(tmp_path, monkeypatch, capsys):
    """The digest is checked on the bytes taken, not only when the keep was decided: a kept part
    whose file changes in between is rebuilt there and then."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "_plate_kind.py").write_text(MEDDLER_KIND)
    script = tmp_path / "plates.py"
    script.write_text(PLATES.format(a=3.0, b=4.0))
    assert run(capsys, "build", script, "-o", "out", "--jobs", "1")[0] == 0
    script.write_text(
        PLATES.format(a=5.0, b=4.0).replace('Plate("a"', 'Meddler("a"').replace("import Plate", "import Meddler, Plate")
    )
    code, out, _ = run(capsys, "build", script, "-o", "out", "--jobs", "1")
    build = json.loads(record_path(tmp_path / "out" / "plates").read_text())
    why = "its files changed while the build ran: b.txt: changed since the build (SHA-256 differs)"
    assert code == 0 and build["unverified"] == {"b": why} and f"rebuilt plates/b: {why}" in out
    assert (tmp_path / "out" / "plates" / "b.txt").read_text() == "16.000000\n"
    assert_consistent(tmp_path / "out" / "plates")


def test_a_parts_key_follows_every_package_of_the_code(tmp_path, monkeypatch):
    """The key's code digest covers every module of transplanter — the proofs, the shop's writers,
    the geometry — not only the builder's own package: a change to how a DXF is written or a pair
    is proved rebuilds the parts (it hashed ``families/`` alone from the move into packages, issue
    41, to issue 46's twelfth pass). Here on a copy of the package, one module of each kind edited."""
    import shutil

    import transplanter
    from transplanter.families.builder import manifest

    copy = tmp_path / "transplanter"
    shutil.copytree(Path(transplanter.__file__).parent, copy, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(transplanter, "__file__", str(copy / "__init__.py"))
    digest = manifest.package_digest.__wrapped__  # (the package's own is cached for the process)
    seen = {digest()}
    for module in ("shop/dxf.py", "proof/meshing.py", "geometry/contact.py", "families/builder/build.py"):
        with open(copy / module, "a") as f:
            f.write("\n# edited\n")
        seen.add(digest())
    assert len(seen) == 5
