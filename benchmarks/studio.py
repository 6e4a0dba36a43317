"""The design studio's latency: a variable moved 50 times, timed three ways in the same run.

For each page (a part script, one of its variables, the step it is moved by: 50 values within two
steps of the opening one, never the same twice, so no cache of the view answers a change):

* **the library's call** — the problem's ``view(x)`` in this process, for the same 50 designs
  (the floor: what any front end must wait for);
* **the server's answer** — from the change reaching the studio's server to the drawing handed to
  Bokeh (the page prints it: ``server-ms``);
* **the browser** — from the slider's value set in headless Chromium to the page redrawn (the
  design's results and its plots received, two animation frames after).

Goals (issue 45): the server ≤ 100 ms and the browser ≤ 250 ms, medians of 50 changes. The
library's call is the baseline; the ratios say what the server and the browser add to it.

Run: python benchmarks/studio.py [SCRIPT VARIABLE STEP ...]  (default: the four pages of issue 45)
"""

from __future__ import annotations

import math
import re
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CHANGES = 50
#: (part script, variable, step): the pages issue 45 names
PAGES = (
    ("parts/planetary_seed004.py", "carrier_start_deg", 5.0),
    ("parts/potseedling_seed002.py", "pivot_mm", 2.0),
    ("parts/potseedling_seed002.py", "beta2_offset_gap1", 0.002),
    ("parts/fourbar_seed000.py", "a2_crank_mm", 2.0),
    ("parts/picking_dwell.py", "amplitude", 0.05),
)

_MOVE = """
const done = arguments[arguments.length - 1];
const doc = Bokeh.documents[0], slider = doc.get_model_by_name('slider-' + arguments[0]);
const results = doc.get_model_by_name('results'), step = arguments[1], count = arguments[2];
const base = slider.value;
const out = [];
function serial() { const m = /data-serial="(\\d+)"/.exec(results.text); return m ? +m[1] : 0; }
function one(i) {
  const before = serial(), t0 = performance.now();
  slider.value = base + step * Math.sin(0.7 * (i + 1)) * (1 + (i + 1) / 50);
  const wait = () => {
    if (serial() > before) {
      requestAnimationFrame(() => requestAnimationFrame(() => {
        const m = /class="server-ms">([0-9.]+)</.exec(results.text);
        out.push([performance.now() - t0, m ? +m[1] : NaN]);
        if (i + 1 < count) setTimeout(() => one(i + 1), 300); else done(out);
      }));
    } else setTimeout(wait, 1);
  };
  wait();
}
one(0);
"""


def _offset(i: int, step: float) -> float:
    """The i-th change's offset from the opening value: within ±2 steps, never the same twice (a
    view's cache cannot answer it), as the page's script moves the slider."""
    return step * math.sin(0.7 * (i + 1)) * (1 + (i + 1) / 50)


def _browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--window-size=1500,1200",
    ):
        options.add_argument(arg)
    return webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)


def _library_ms(script: str, variable: str, step: float) -> list[float]:
    from transplanter.app.optimise import script_problem

    problem, _ = script_problem(ROOT / script, {}, None)
    names = [n for n, _, _ in problem.variables]
    x = np.array(problem.design or problem.x0, dtype=float)
    k = names.index(variable)
    problem.view(x)  # what the page computed when it opened
    out = []
    base = x[k]
    for i in range(CHANGES):
        x[k] = base + _offset(i, step)
        t = time.perf_counter()
        problem.view(x)
        out.append((time.perf_counter() - t) * 1e3)
    return out


def page(script: str, variable: str, step: float, driver) -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "transplanter", "design", str(ROOT / script), "--no-browser"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        url = re.search(r"(http://\S+)", proc.stdout.readline()).group(1)
        driver.get(url)
        t = time.time()
        while time.time() - t < 120 and "data-serial" not in (
            driver.execute_script(
                "const d = window.Bokeh && Bokeh.documents[0]; const m = d && d.get_model_by_name('results');"
                "return m ? m.text : '';"
            )
            or ""
        ):
            time.sleep(0.2)
        time.sleep(1.0)  # the first design's slow judgement out of the way
        driver.set_script_timeout(600)
        measured = np.array(driver.execute_async_script(_MOVE, variable, step, CHANGES))
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    library = statistics.median(_library_ms(script, variable, step))
    server = float(np.nanmedian(measured[:, 1]))
    browser = float(np.median(measured[:, 0]))
    print(
        f"{script} {variable} ±{step:g}: library {library:.1f} ms; server {server:.1f} ms "
        f"({server / library:.2f}x the library, goal 100 ms: {'met' if server <= 100 else 'NOT met'}); "
        f"browser {browser:.0f} ms ({browser / library:.2f}x, goal 250 ms: {'met' if browser <= 250 else 'NOT met'}); "
        f"browser p90 {np.percentile(measured[:, 0], 90):.0f} ms",
        flush=True,
    )


def main(argv: list[str]) -> None:
    pages = [(argv[i], argv[i + 1], float(argv[i + 2])) for i in range(0, len(argv), 3)] if argv else PAGES
    driver = _browser()
    try:
        for script, variable, step in pages:
            if variable is None:
                print(f"{script}: no page variable named in PAGES", flush=True)
                continue
            page(script, variable, step, driver)
    finally:
        driver.quit()


if __name__ == "__main__":
    main(sys.argv[1:])
