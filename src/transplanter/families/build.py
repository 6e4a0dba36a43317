"""A family of parts from a part script: loading, building into a folder, checking a built folder."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import re
import runpy
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from transplanter.errors import ExportError, PartScriptError, SpecError, TransplanterError
from transplanter.export import atomic_write, json_bytes
from transplanter.families.cams import CamStudy
from transplanter.families.gears import ToothedPairStudy
from transplanter.families.linkage import ArmStudy, BalancingStudy
from transplanter.families.pitch import PitchPairStudy
from transplanter.families.synthesis import SynthesisStudy
from transplanter.families.trains import PlanetaryStudy
from transplanter.report import family_report

__all__ = ["Family", "load_family", "discover", "build_family", "check_family"]


_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")


def _check_name(kind: str, name: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise SpecError.out_of_range(f"{kind} name", name, "letters, digits, '_', '-', '.' (a file name)")
    return name


Part = ArmStudy | BalancingStudy | PitchPairStudy | PlanetaryStudy | ToothedPairStudy | SynthesisStudy | CamStudy


@dataclass(frozen=True)
class Family:
    """A named set of parts defined by one part script."""

    name: str
    description: str
    parts: tuple[Part, ...] = field(default_factory=tuple)
    #: the part script it came from (set by :func:`load_family`)
    script: str | None = None

    def __post_init__(self) -> None:
        _check_name("family", self.name)
        object.__setattr__(self, "parts", tuple(self.parts))
        seen: set[str] = set()
        for p in self.parts:
            if not isinstance(p, Part):
                raise PartScriptError(
                    f"family {self.name!r}: parts must be one of ArmStudy, BalancingStudy, PitchPairStudy, "
                    f"PlanetaryStudy, ToothedPairStudy, SynthesisStudy, CamStudy; got {type(p).__name__}"
                )
            _check_name("part", p.name)
            if p.name in seen:
                raise PartScriptError(f"family {self.name!r}: part name {p.name!r} is used twice")
            seen.add(p.name)


def load_family(path: str | Path) -> Family:
    """Run a part script and return the :class:`Family` its ``family()`` builds.

    Raises
    ------
    PartScriptError
        If the file is missing, does not parse, lacks ``family()``, raises, or returns
        something that is not a Family. The message names the script (and line).
    """
    p = Path(path)
    if not p.is_file():
        raise PartScriptError(f"part script {p} does not exist")
    try:
        ns = runpy.run_path(str(p), run_name="transplanter_part_script")
    except SyntaxError as exc:
        raise PartScriptError(f"{p}:{exc.lineno}: syntax error: {exc.msg}") from exc
    except TransplanterError as exc:
        raise PartScriptError(f"{p}: {exc}") from exc
    except Exception as exc:  # a user script can raise anything; report where
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: {type(exc).__name__}: {exc}") from exc
    fn = ns.get("family")
    if not callable(fn):
        raise PartScriptError(f"{p}: a part script must define family() returning transplanter.families.Family")
    try:
        fam = fn()
    except TransplanterError as exc:
        raise PartScriptError(f"{p}: {exc}") from exc
    except Exception as exc:
        raise PartScriptError(f"{p}:{_script_line(exc, p)}: family() raised {type(exc).__name__}: {exc}") from exc
    if not isinstance(fam, Family):
        raise PartScriptError(f"{p}: family() returned {type(fam).__name__}, expected transplanter.families.Family")
    return dataclasses.replace(fam, script=str(p))


def _script_line(exc: BaseException, path: Path) -> str:
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if Path(f.filename).resolve() == path.resolve()]
    return str(frames[-1].lineno) if frames else "?"


def discover(parts_dir: str | Path) -> list[Path]:
    """Part scripts in ``parts_dir`` (``*.py`` not starting with ``_``), sorted by name."""
    d = Path(parts_dir)
    if not d.is_dir():
        raise PartScriptError(f"parts folder {d} does not exist (run from the project root or pass scripts)")
    return sorted(p for p in d.glob("*.py") if not p.name.startswith("_"))


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def build_family(family: Family, out_dir: str | Path, progress: Callable[[str], None] | None = None) -> dict:
    """Build every part of ``family`` into ``out_dir/<family.name>/``; returns the manifest.

    The manifest (also written as ``manifest.json``) lists for each part its parameters,
    results, files with SHA-256, or its error. ``manifest["ok"]`` is False if any part failed.
    """
    root = Path(out_dir) / family.name
    manifest: dict = {"family": family.name, "description": family.description, "parts": {}, "ok": True}
    if family.script is not None:
        manifest["script"] = {"path": family.script, "sha256": _sha256(Path(family.script).read_bytes())}
    for part in family.parts:
        if progress is not None:
            progress(f"{family.name}/{part.name}")
        try:
            record, files = part.build(root)
        except TransplanterError as exc:
            manifest["parts"][part.name] = {"error": f"{type(exc).__name__}: {exc}"}
            manifest["ok"] = False
            continue
        for fname, data in sorted(files.items()):
            atomic_write(root / fname, data)
        record["files"] = {fname: _sha256(data) for fname, data in sorted(files.items())}
        manifest["parts"][part.name] = record
    report = family_report(manifest)
    atomic_write(root / "report.html", report)
    manifest["report"] = {"report.html": _sha256(report)}
    atomic_write(root / "manifest.json", json_bytes(manifest))
    return manifest


def check_family(folder: str | Path, script: str | Path | None = None) -> dict:
    """Re-run the checks on a built family's files as found on disk.

    Every file the manifest lists must be there with its SHA-256; the family is loaded from
    ``script`` (default: the script recorded in the manifest) for the design it was built
    from, and every part that has checks (toothed pairs, cams) re-runs them on its files.
    Returns ``{"family", "script", "script_changed", "files": {name: problem}, "parts":
    {part: {"results", "problems", "expected"}}, "ok"}``; ``expected`` marks a part built as
    a finding (``must_mesh=False``), whose problems do not make the check fail.

    Raises
    ------
    ExportError
        If the folder has no readable manifest.
    PartScriptError
        If the script cannot be found or loaded.
    """
    root = Path(folder)
    try:
        manifest = json.loads((root / "manifest.json").read_text())
    except (OSError, ValueError) as exc:
        raise ExportError(f"{root} is not a built family folder (manifest.json: {exc})") from exc
    recorded = manifest.get("script", {})
    path = Path(script) if script is not None else Path(recorded.get("path", ""))
    if not str(path) or not path.is_file():
        raise PartScriptError(
            f"{root}: the part script {str(path) or '(not recorded)'} is not found; pass it with --script"
        )
    fam = load_family(path)
    if fam.name != manifest.get("family"):
        raise PartScriptError(f"{path} defines family {fam.name!r}, but {root} holds {manifest.get('family')!r}")
    out: dict = {
        "family": fam.name,
        "script": str(path),
        "script_changed": recorded.get("sha256") not in (None, _sha256(path.read_bytes())),
        "files": {},
        "parts": {},
        "ok": True,
    }
    for part in fam.parts:
        rec = manifest["parts"].get(part.name)
        if rec is None or "error" in rec:
            why = "it is not in the manifest" if rec is None else f"its build failed: {rec['error']}"
            out["parts"][part.name] = {"results": {}, "problems": [f"nothing to check: {why}"], "expected": False}
            out["ok"] = False
            continue
        files = {}
        for fname, digest in rec.get("files", {}).items():
            f = root / fname
            if not f.is_file():
                out["files"][fname] = "missing"
                continue
            data = f.read_bytes()
            if _sha256(data) != digest:
                out["files"][fname] = "changed since the build (SHA-256 differs)"
            files[fname] = data
        if hasattr(part, "check"):
            results, problems = part.check(files)
            expected = not getattr(part, "must_mesh", True)
        else:  # an analysis: its data files must be what the design gives now
            _, fresh = part.build(root)
            data = sorted(f for f in fresh if f.endswith((".json", ".csv")))
            problems = [f"{f} differs from what the part script gives now" for f in data if files.get(f) != fresh[f]]
            results, expected = {"data_files_reproduced": len(data) - len(problems)}, False
        out["parts"][part.name] = {"results": results, "problems": problems, "expected": expected}
        out["ok"] = out["ok"] and (expected or not problems)
    out["ok"] = out["ok"] and not out["files"]
    return out
