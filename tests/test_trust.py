"""Trust boundaries (issue 31): checking a folder runs no code from it and reads nothing outside it;
a build never writes, recovers or removes through a link."""

from __future__ import annotations

import json
import os

import pytest

from transplanter.app import cli
from transplanter.app.testing import SQUARE_SCRIPT as SQUARE
from transplanter.core.errors import ExportError
from transplanter.shop.export import Transaction, recover

#: a script that leaves a mark when it runs
MARKER = "import pathlib\npathlib.Path({marker!r}).write_text('ran')\n"


@pytest.fixture
def project(tmp_path, monkeypatch):
    """A project folder (the working folder) with one built family: ``(root, export folder)``."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "squares.py").write_text(SQUARE)
    assert cli.main(["build", "squares.py", "-o", "out"]) == 0
    return tmp_path, tmp_path / "out" / "squares"


def _manifest(folder):
    return json.loads((folder / "manifest.json").read_text())


def _write(folder, manifest):
    (folder / "manifest.json").write_text(json.dumps(manifest))


def test_check_runs_no_code_by_default(project, capsys):
    root, folder = project
    assert cli.main(["check", str(folder)]) == 0
    out = capsys.readouterr().out
    assert "files and digests only: no code from the folder was run" in out and out.endswith("  ok\n")
    assert cli.main(["check", "--run-script", str(folder)]) == 0
    assert "sq: " not in capsys.readouterr().err


@pytest.mark.parametrize("where", ["outside", "inside but another script", "the edited script"])
def test_check_never_runs_a_script_the_folder_names_unless_it_is_the_one_built(
    project, tmp_path_factory, capsys, where
):
    """The manifest's ``script.path`` is data from the folder: a script elsewhere, another script
    in the project, or the recorded one edited after the build is refused before it runs."""
    root, folder = project
    marker = root / "ran.txt"
    evil = MARKER.format(marker=str(marker)) + SQUARE
    manifest = _manifest(folder)
    if where == "outside":
        other = tmp_path_factory.mktemp("elsewhere") / "evil.py"
        other.write_text(evil)
        manifest["script"]["path"] = str(other)
        manifest["script"]["sha256"] = __import__("hashlib").sha256(evil.encode()).hexdigest()  # even matching
        _write(folder, manifest)
        expected = "lies outside the project"
    elif where == "inside but another script":
        (root / "evil.py").write_text(evil)
        manifest["script"]["path"] = str(root / "evil.py")
        _write(folder, manifest)
        expected = "its SHA-256 is not the one the manifest records"
    else:
        (root / "squares.py").write_text(evil)
        expected = "its SHA-256 is not the one the manifest records"
    assert cli.main(["check", str(folder)]) in (0, 1)  # the default runs nothing
    assert cli.main(["check", "--run-script", str(folder)]) == 2
    assert expected in capsys.readouterr().err
    assert not marker.exists()


@pytest.mark.parametrize("name", ["../squares.py", "/etc/hostname", "a/../../b", ".", "..", "x\\y"])
def test_manifest_file_names_are_plain_names_inside_the_folder(project, capsys, name):
    root, folder = project
    manifest = _manifest(folder)
    manifest["parts"]["sq"]["files"][name] = "0" * 64
    _write(folder, manifest)
    assert cli.main(["check", str(folder)]) == 1
    assert "not a plain file name inside the folder" in capsys.readouterr().out
    # and a build keeps no previous file by such a name
    assert cli.main(["build", "squares.py", "-o", "out"]) == 0


def test_a_hand_edited_result_is_told_apart(project, capsys):
    root, folder = project
    manifest = _manifest(folder)
    manifest["parts"]["sq"]["results"]["area"] = 10.0
    _write(folder, manifest)
    assert cli.main(["check", str(folder)]) == 1
    assert "file manifest.json: edited since the build (its seal, manifest_sha256, differs)" in capsys.readouterr().out


def test_a_deep_or_huge_manifest_is_damaged_not_a_crash(project, capsys):
    root, folder = project
    (folder / "manifest.json").write_text("[" * 200_000 + "]" * 200_000)
    assert cli.main(["check", str(folder)]) == 1
    assert "nested deeper than its reader can follow" in capsys.readouterr().out
    assert cli.main(["build", "squares.py", "-o", "out"]) == 0  # the build starts afresh


def test_links_are_never_followed(project, tmp_path_factory, capsys):
    """A family folder that is a link to another folder is neither written through, recovered
    through nor checked; a file in an export that is a link is not read."""
    root, folder = project
    outside = tmp_path_factory.mktemp("outside")
    (outside / "keep.txt").write_text("mine")
    (outside / ".x.tmp").write_text("mine too")
    link = root / "out" / "linked"
    link.symlink_to(outside, target_is_directory=True)
    with pytest.raises(ExportError, match="is a symbolic link"):
        recover(link)
    with pytest.raises(ExportError, match="is a symbolic link"), Transaction(link):
        pass
    assert sorted(p.name for p in outside.iterdir()) == [".x.tmp", "keep.txt"]
    assert cli.main(["check", str(link)]) == 2
    assert "is a symbolic link" in capsys.readouterr().err
    # a listed file replaced by a link to a file outside: not followed
    (folder / "sq.txt").unlink()
    os.symlink(outside / "keep.txt", folder / "sq.txt")
    assert cli.main(["check", str(folder)]) == 1
    assert "file sq.txt: a symbolic link: not followed" in capsys.readouterr().out
    # the family folder itself made a link: the build refuses (exit 1), the outside is untouched
    os.rename(folder, root / "moved")
    folder.symlink_to(outside, target_is_directory=True)
    assert cli.main(["build", "squares.py", "-o", "out"]) == 1
    assert "is a symbolic link" in capsys.readouterr().err
    assert sorted(p.name for p in outside.iterdir()) == [".x.tmp", "keep.txt"]
