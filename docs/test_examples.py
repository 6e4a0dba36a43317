"""Every example of ``README.md`` and ``docs/**/*.md`` run, its output checked (CI's own step).

The convention (what a page writer needs to know):

* a fenced block whose info string is ``sh`` or ``python`` is an example: the blocks of one page
  run in order in one fresh temporary folder holding copies of the repository's ``examples/`` and
  ``parts/``; an ``sh`` block runs with ``bash -e``, a ``python`` block as a script of its own with
  the interpreter running this module (the installed package), each under ``TIMEOUT`` seconds;
* a ``text`` block right after an example (only blank lines between) is its expected output:
  stdout and stderr together must match it line by line (doctest's ``ELLIPSIS``): ``...`` within a
  line stands for any text, a line of only ``...`` for any number of lines (none too); trailing
  spaces and leading or trailing blank lines are ignored — figures a page quotes go there, so they
  cannot go stale;
* ``<!-- example: skip — REASON -->`` on the line right before a block: not run (the set-up
  commands, long-running servers); ``<!-- example: not-code -->``: not a command at all. Any other
  marker, a skip without a reason, or a shell/Python block under another name (``bash``,
  ``console``, ``py``, ...) is refused: the block fails;
* a block that fails to run (non-zero exit, time-out, refused) skips the later blocks of its page,
  naming it; an output that does not match fails only its own block (its files were made).

One test item per block, id ``PAGE:LINE`` (the opening fence's line). Not part of the main suite
(``testpaths``): ``.ci/run`` runs it as ``python -m pytest docs/test_examples.py -n 2 --dist
loadscope`` — each page is a test class, which ``loadscope`` keeps on one worker, in order (a block
selected alone, ``-k "README.md:62"``, first runs the page's earlier blocks). ``--durations=0``
gives each block's time.
"""

from __future__ import annotations

import doctest
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: seconds one block may run
TIMEOUT = 300.0
#: the repository folders every page's temporary folder holds a copy of
COPIED = ("examples", "parts")
#: lines of output a failure shows
TAIL = 40
RUN = {"sh", "python"}
#: info strings that are shell or Python under another name: refused (they would not be run)
ALIASES = {"bash", "shell", "console", "zsh", "shell-session", "sh-session", "py", "python3", "pycon", "ipython"}

_FENCE = re.compile(r"^( {0,3})(`{3,}|~{3,})\s*([^`\s]*)[^`]*$")
_MARKER = re.compile(r"<!--\s*example\b:?(.*?)-->", re.S)
_SKIP = re.compile(r"^skip\b[\s—–:-]*(.*)$", re.S)


@dataclass(frozen=True)
class Example:
    """One ``sh``/``python`` block of a page (or a block refused), with its expected output."""

    page: str
    line: int
    lang: str
    code: str
    want: str | None = None
    skip: str | None = None
    refused: str | None = None

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}"


def _fences(text: str):
    """(line of the opening fence, info word, code, marker text or None, line after the block)
    of each fenced block; an unclosed fence runs to the end."""
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence, info = len(m.group(1)), m.group(2), m.group(3).lower()
        j = i + 1
        while j < len(lines) and not re.match(rf"^ {{0,3}}{fence[0]}{{{len(fence)},}}\s*$", lines[j]):
            j += 1
        code = "\n".join(ln[indent:] if not ln[:indent].strip() else ln.lstrip() for ln in lines[i + 1 : j])
        before = lines[i - 1].strip() if i else ""
        yield i + 1, info, code + "\n" if code else "", before if _MARKER.fullmatch(before) else None, j + 2
        i = j + 1


def scan(text: str, page: str) -> list[Example]:
    """The examples of a page's markdown ``text`` (see the module docstring), in order."""
    found: list[Example] = []
    blocks = list(_fences(text))
    lines = text.splitlines()
    marked = {line - 1 for line, *_, marker, _end in blocks if marker}
    inside = {n for line, *_, end in blocks for n in range(line, end)}
    for n, ln in enumerate(lines, 1):  # a marker line that stands before no block is refused too
        if _MARKER.fullmatch(ln.strip()) and n not in marked and n not in inside:
            why = "an example marker not on the line right before a block"
            found.append(Example(page, n, "marker", ln.strip(), refused=why))
    for k, (line, info, code, marker, end) in enumerate(blocks):
        skip = refused = None
        body = _MARKER.fullmatch(marker).group(1).strip() if marker else None
        if body == "not-code":
            skip = "not code (marked <!-- example: not-code -->)"
        elif body is not None and _SKIP.match(body):
            reason = _SKIP.match(body).group(1).strip()
            skip = f"not run: {reason}" if reason else None
            refused = None if reason else "a skip without a reason: <!-- example: skip — REASON -->"
        elif body is not None:
            refused = f"unknown example marker {marker!r}: only 'skip — REASON' and 'not-code'"
        if info in ALIASES and skip is None and refused is None:
            refused = f"a {info!r} block is not run: name it 'sh' or 'python' (or 'text' if it is no command)"
        if info not in RUN and not refused:
            if skip and body != "not-code":
                refused = "a skip marker on a block that is not sh or python: nothing would run"
            else:
                continue
        want = None
        nxt = blocks[k + 1] if k + 1 < len(blocks) else None
        if nxt and nxt[1] == "text" and nxt[3] is None and not any(s.strip() for s in lines[end - 1 : nxt[0] - 1]):
            want = nxt[2]
        found.append(Example(page, line, info, code, want, skip, refused))
    return sorted(found, key=lambda e: e.line)


def collect(root: Path = ROOT) -> list[Example]:
    """The examples of ``README.md`` and ``docs/**/*.md`` under ``root``, page by page."""
    pages = [root / "README.md", *sorted((root / "docs").rglob("*.md"))]
    pages = [p for p in pages if p.is_file()]
    return [e for p in pages for e in scan(p.read_text(encoding="utf-8"), p.relative_to(root).as_posix())]


@dataclass(frozen=True)
class Run:
    """What running a block gave: exit status (None: timed out), stdout and stderr together, time."""

    status: int | None
    output: str
    seconds: float


def execute(example: Example, folder: Path, timeout: float = TIMEOUT) -> Run:
    """Run ``example`` in ``folder`` (``bash -e`` or this interpreter), its whole process group
    killed at ``timeout`` seconds and when it ends (nothing it started in the background lives on)."""
    work = folder.parent / f"{folder.name}.blocks"
    work.mkdir(exist_ok=True)
    name = re.sub(r"[^\w.-]", "_", example.id)
    script = work / f"{name}.{'py' if example.lang == 'python' else 'sh'}"
    script.write_text(example.code, encoding="utf-8")
    cmd = [sys.executable, str(script)] if example.lang == "python" else ["bash", "-e", str(script)]
    env = dict(os.environ, PYTHONUNBUFFERED="1", MPLBACKEND="Agg")
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    start = time.perf_counter()
    with open(work / f"{name}.out", "w+b") as out:
        proc = subprocess.Popen(
            cmd,
            cwd=folder,
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        try:
            status: int | None = proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            status = None
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        proc.wait()
        out.seek(0)
        output = out.read().decode("utf-8", "replace")
    return Run(status, output, time.perf_counter() - start)


def _normal(text: str) -> str:
    """Trailing spaces, leading and trailing blank lines gone, one final newline."""
    return "\n".join(ln.rstrip() for ln in text.splitlines()).strip("\n") + "\n"


def _marked(text: str, want: bool) -> str:
    """``text`` with each line opened by a NUL, so that doctest's ``...`` between two lines may stand
    for no line at all and a line of the page must match a whole line; in ``want`` a line of only
    ``...`` stays bare."""
    return "".join("..." if want and ln == "..." else f"\0{ln}\n" for ln in _normal(text).splitlines())


def matches(want: str, got: str) -> bool:
    """Whether output ``got`` matches the expected ``want`` (see the module docstring)."""
    return doctest.OutputChecker().check_output(_marked(want, True), _marked(got, False), doctest.ELLIPSIS)


def judge(example: Example, run: Run, timeout: float = TIMEOUT) -> str | None:
    """Why ``run`` fails ``example`` (the command, exit status and last lines), or None."""
    command = "\n".join(f"    {ln}" for ln in example.code.rstrip().splitlines())
    tail = "\n".join(f"    {ln}" for ln in run.output.rstrip().splitlines()[-TAIL:]) or "    (no output)"
    if run.status is None:
        return f"{example.id}: timed out after {timeout:g} s\n  command:\n{command}\n  last output:\n{tail}"
    if run.status != 0:
        took = f"exit status {run.status} after {run.seconds:.1f} s"
        return f"{example.id}: {took}\n  command:\n{command}\n  last output:\n{tail}"
    if example.want is not None:
        if not matches(example.want, run.output):
            want, got = _normal(example.want), _normal(run.output)
            diff = doctest.OutputChecker().output_difference(doctest.Example("", want), got, doctest.ELLIPSIS)
            return f"{example.id}: the output does not match the page's expected output\n  command:\n{command}\n{diff}"
    return None


class Page:
    """One page's temporary folder (copies of ``COPIED`` from ``root``) and whether a block failed."""

    def __init__(self, folder: Path, root: Path = ROOT) -> None:
        self.folder = folder
        folder.mkdir(parents=True, exist_ok=True)
        for name in COPIED:
            if (root / name).is_dir():
                shutil.copytree(root / name, folder / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        self.failed: str | None = None
        self.times: dict[str, float] = {}
        self.done: set[str] = set()

    def catch_up(self, earlier: list[Example], timeout: float = TIMEOUT) -> None:
        """Run those of the page's ``earlier`` blocks that did not run here yet (a block selected
        alone, or a page split over workers), so that the next block finds what they make."""
        for e in earlier:
            if e.id not in self.done and not self.failed:
                self.run(e, timeout)

    def run(self, example: Example, timeout: float = TIMEOUT) -> tuple[str, str]:
        """("passed" | "failed" | "skipped", why) of ``example``, run here after the page's earlier blocks."""
        self.done.add(example.id)
        if example.refused:
            self.failed = self.failed or example.id
            return "failed", f"{example.id}: refused: {example.refused}"
        if example.skip:
            return "skipped", f"{example.id}: {example.skip}"
        if self.failed:
            return "skipped", f"{example.id}: not run — an earlier block of {example.page} failed: {self.failed}"
        run = execute(example, self.folder, timeout)
        self.times[example.id] = run.seconds
        why = judge(example, run, timeout)
        if why and run.status != 0:
            self.failed = example.id
        return ("failed", why) if why else ("passed", "")


EXAMPLES = collect()
_PAGES: dict[str, Page] = {}


def _page_test(examples: list[Example]):
    """The test of one page's blocks, one item per block (``PAGE:LINE``), run in order."""

    @pytest.mark.parametrize("example", [pytest.param(e, id=e.id) for e in examples])
    def test_example(self, example: Example, tmp_path_factory: pytest.TempPathFactory) -> None:
        page = _PAGES.get(example.page)
        if page is None:
            page = _PAGES[example.page] = Page(tmp_path_factory.mktemp(re.sub(r"\W", "_", example.page)))
        page.catch_up(examples[: examples.index(example)])
        status, why = page.run(example)
        if status == "skipped":
            pytest.skip(why)
        if status == "failed":
            pytest.fail(why, pytrace=False)

    return test_example


# one class per page: ``--dist loadscope`` keeps a class on one worker, in order (``--dist loadgroup``
# would be the natural choice, but pytest-xdist's grouping is silently lost on pytest >= 9.2:
# pytest-dev/pytest-xdist#1386)
for _page in dict.fromkeys(e.page for e in EXAMPLES):
    _name = "Test_" + re.sub(r"\W", "_", _page)
    while _name in globals():
        _name += "_"
    _doc = f"The examples of {_page}, in order in one folder."
    globals()[_name] = type(
        _name, (), {"__doc__": _doc, "test_example": _page_test([e for e in EXAMPLES if e.page == _page])}
    )
