"""The report pages as a designer sees them (issue 30): every family's report.html opened from its
folder in headless Chromium — no script error, every picture loads, every results table has its
name, value and unit columns, long topics folded so the page stays short."""

from __future__ import annotations

import pytest

FAMILIES = ("fourbar_seed000", "fourbar_seed001", "fourbar_seed003", "planetary_seed004", "potseedling_seed002")
#: the longest page, px at 1200 px wide (the pages were 4 000-22 000 px with every topic open)
MAX_PAGE_PX = 10_000


@pytest.mark.parametrize("family", FAMILIES)
def test_a_report_page_reads_in_headless_chromium(built, browser, family):
    browser.get((built / family / "report.html").as_uri())
    broken = browser.execute_script(
        "return Array.from(document.images).filter(i => !i.complete || i.naturalWidth === 0).map(i => i.src)"
    )
    # a table is a header-row matrix or a name | value | unit table (the unit in its own column)
    odd = browser.execute_script(
        "return Array.from(document.querySelectorAll('table')).filter(t => !t.querySelector('th'))"
        ".filter(t => Array.from(t.rows).some(r => r.cells.length !== 3)).length"
    )
    height = browser.execute_script("return document.body.scrollHeight")
    images = browser.execute_script("return document.images.length")
    errors = [e for e in browser.get_log("browser") if e.get("level") == "SEVERE"]
    assert not broken and not errors and odd == 0
    assert images >= 2 and height <= MAX_PAGE_PX, f"{family}: {height} px"
