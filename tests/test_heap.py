"""``core.heap``: the memory a stage freed, handed back to the system (issue 46: a part's stages
stacked their peaks — the meshing proofs' thread arenas and the 3MF re-read under the STEP)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from transplanter.core import heap

CHURN = """
import os, threading
from transplanter.core import heap
def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
kept = []
def churn():
    blocks = [bytearray(16_000) for _ in range(8_000)]  # ~128 MB from this thread's malloc arena
    kept.extend(blocks[1::2])  # every other block outlives the thread: the freed ones are holes
t = threading.Thread(target=churn); t.start(); t.join()
before = rss()
if {trim}:
    heap.trim()
print(before - rss())
"""


def _given_back(trim: bool) -> float:
    run = subprocess.run([sys.executable, "-c", CHURN.format(trim=trim)], capture_output=True, text=True, check=True)
    return float(run.stdout)


@pytest.mark.skipif(heap._malloc_trim() is None or not os.path.exists("/proc/self/statm"), reason="glibc on Linux")
def test_trim_hands_a_threads_freed_heap_back_to_the_system():
    """64 MB freed in holes of a worker thread's arena stay resident until trimmed; trimmed, most
    of it goes back (whole pages only)."""
    assert _given_back(False) < 5
    assert _given_back(True) > 30


def test_trim_and_released_change_nothing_they_are_given():
    """They only collect garbage and return free memory: what the block computes is the same."""
    data = [bytearray(b"x" * 1000) for _ in range(100)]
    with heap.released():
        total = sum(len(d) for d in data)
    heap.trim(0)
    assert total == 100_000 and all(d == b"x" * 1000 for d in data)
