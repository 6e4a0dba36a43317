"""The runner of the README's and docs' examples (``docs/test_examples.py``, CI's own step) on a
tiny page: what it collects, refuses, runs, matches and skips."""

import importlib.util
import sys
from pathlib import Path

import pytest

RUNNER = Path(__file__).resolve().parents[1] / "docs" / "test_examples.py"

PAGE = """\
# A page

```sh
mkdir -p out && cp examples/law.csv out/  # the page's blocks share one folder
echo "ratio $(cat out/law.csv)"
```

```text
ratio ...
```

```python
import sys
print(open("out/law.csv").read().strip(), sys.version_info >= (3,))
```
```text
0.9 ...True<3 spaces>
```

Transitions, as the page says:

```sh
echo "transitions 0.689 deg"
echo "entry +0.09 deg"
```

```text
transitions 0.59 deg
...
```

```sh
false  # fails: bash -e
echo never
```

```sh
cat out/law.csv
```

<!-- example: skip — a set-up command, run by .ci/run -->
```sh
pip install .
```

<!-- example: skip -->
```sh
echo no reason
```

<!-- example: frobnicate -->
```python
print(1)
```

```console
$ transplanter --help
```

```text
not an example
```
<!-- example: not-code -->
```sh
exports/pair/
```

<!-- example: skip — stray -->

```sh
sleep 30
```
""".replace("<3 spaces>", "   ")  # trailing spaces in the output are ignored


@pytest.fixture(scope="module")
def runner():
    spec = importlib.util.spec_from_file_location("doc_examples_runner", RUNNER)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    yield module
    sys.modules.pop(spec.name, None)


def test_a_page_is_scanned_into_its_examples_with_their_expected_output(runner):
    found = {e.line: e for e in runner.scan(PAGE, "page.md")}
    assert sorted(found) == [3, 12, 22, 32, 37, 42, 47, 52, 56, 64, 68, 70]
    assert found[3].id == "page.md:3" and found[3].lang == "sh" and found[3].want == "ratio ...\n"
    assert found[12].lang == "python" and found[12].code.startswith("import sys\n")
    assert found[22].want == "transitions 0.59 deg\n...\n"
    assert found[32].want is None and found[37].want is None  # the next block is an example, not output
    assert found[42].skip.endswith("a set-up command, run by .ci/run") and not found[42].refused
    assert "without a reason" in found[47].refused
    assert "unknown example marker" in found[52].refused
    assert "'console'" in found[56].refused
    assert found[64].skip.startswith("not code")  # a not-code block: not run
    assert "not on the line right before a block" in found[68].refused


def test_a_page_runs_in_order_in_its_folder_and_each_failure_says_why(runner, tmp_path):
    root = tmp_path / "repo"
    (root / "examples").mkdir(parents=True)
    (root / "examples" / "law.csv").write_text("0.9\n")
    page = runner.Page(tmp_path / "page", root)
    results = {}
    for example in runner.scan(PAGE, "page.md"):
        results[example.line] = page.run(example, timeout=0.5 if example.line == 70 else 30)
    assert results[3] == ("passed", "")
    assert results[12] == ("passed", "")  # ELLIPSIS inside a line, trailing spaces ignored
    status, why = results[22]  # the figure the page quotes went stale: the block fails, with both
    assert status == "failed" and "transitions 0.59 deg" in why and "transitions 0.689 deg" in why
    status, why = results[32]
    assert status == "failed" and "exit status 1" in why and "false  # fails: bash -e" in why
    assert results[37] == ("skipped", "page.md:37: not run — an earlier block of page.md failed: page.md:32")
    assert results[42][0] == "skipped" and results[47][0] == "failed" and results[52][0] == "failed"
    assert set(page.times) == {"page.md:3", "page.md:12", "page.md:22", "page.md:32"}  # nothing ran after
    fresh = runner.Page(tmp_path / "other", root)
    (sleep,) = [e for e in runner.scan(PAGE, "page.md") if e.line == 70]
    status, why = fresh.run(sleep, timeout=0.5)
    assert status == "failed" and "timed out after 0.5 s" in why and "sleep 30" in why
    assert fresh.times["page.md:70"] < 10


def test_a_block_run_alone_first_runs_the_blocks_before_it(runner, tmp_path):
    blocks = runner.scan(PAGE, "page.md")
    page = runner.Page(tmp_path / "page", tmp_path)
    (out_cat,) = [e for e in blocks if e.line == 12]  # reads what page.md:3 makes
    page.catch_up(blocks[: blocks.index(out_cat)])
    # no examples/ in this root: page.md:3 fails as it is caught up, and names itself
    assert page.run(out_cat) == ("skipped", "page.md:12: not run — an earlier block of page.md failed: page.md:3")
    (root := tmp_path / "repo" / "examples").mkdir(parents=True)
    (root / "law.csv").write_text("0.9\n")
    page = runner.Page(tmp_path / "again", root.parent)
    page.catch_up(blocks[: blocks.index(out_cat)])
    assert set(page.times) == {"page.md:3"} and page.run(out_cat) == ("passed", "")


@pytest.mark.parametrize(
    ("want", "got", "ok"),
    [
        ("a = 35.88... mm\nok", "a = 35.8842 mm\nok\n", True),
        ("...\nplanetary / train\n...", "planetary / train\n  height 283.18\n", True),  # a '...' line: 0 lines too
        ("a\n...\nb", "a\nb\n", True),
        ("a\n...\nb", "a\nx\ny\nb\n", True),
        ("...\n  ok", "  not ok\n", False),  # a line of the page matches a whole line
        ("transitions 0.59 deg\n...", "transitions 0.689 deg\nentry +0.09 deg\n", False),
        ("\n\nx  \n\n", "x\n", True),  # blank lines around and trailing spaces ignored
        ("x\ny", "x\n", False),
    ],
)
def test_expected_output_matches_with_doctest_ellipsis_a_line_of_dots_any_lines(runner, want, got, ok):
    assert runner.matches(want, got) is ok


def test_the_readme_and_docs_examples_are_well_formed(runner):
    """No block of README.md or docs/ that the runner (CI's own step) would refuse: an unknown
    marker, a skip without a reason, a shell or Python block under another name."""
    assert [f"{e.id}: {e.refused}" for e in runner.collect() if e.refused] == []
