"""A family's HTML report: what was built, the figures that matter, the plots, the files.

The page is written next to the parts' files and refers to their PNG plots by name, so the
folder can be zipped or served as is. It is deterministic (sorted keys, no timestamps).

It opens with every part's verdict, then each part opens with its status — **built** (with its
shop files), **withheld** (a finding: figures and plots, no shop files, and why) or **failed**
(the error) — what its proofs found, and the few figures the part is made to
(:mod:`~transplanter.report.headlines`: a pair's module, teeth, centre distance and backlash
band; a four-bar's in its seed table's order). Its plots follow, each opening full size on a
click, then its results and parameters as tables grouped by topic, with the unit in its own
column (:mod:`~transplanter.report.tables`) and numbers to 4 significant digits (the manifest
keeps the full figures).
"""

from __future__ import annotations

import html

from transplanter.report.figure import SHOWN_PX
from transplanter.report.headlines import headline, table_order
from transplanter.report.tables import grouped, table

__all__ = ["family_report", "part_status"]

_STYLE = """
body { font-family: sans-serif; max-width: 70em; margin: 2em auto; padding: 0 0.5em; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; border-bottom: 1px solid #ccc; margin-top: 1.6em; }
h4, h5 { margin: 0.8em 0 0.2em 0; font-size: 0.95em; } h5 { font-weight: normal; font-style: italic; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.3em 0; }
td, th { border: 1px solid #ddd; padding: 0.2em 0.6em; text-align: left; vertical-align: top; }
th { background: #f4f4f4; font-weight: normal; }
td.v { font-family: monospace; text-align: right; } td.u { color: #555; }
div.key { display: flex; flex-wrap: wrap; gap: 0 1.5em; align-items: flex-start; }
table.key { font-size: 0.95em; } table.key td.v { font-weight: bold; }
.error { color: #b00; font-weight: bold; } .withheld { color: #a60; font-weight: bold; }
.built { color: #070; font-weight: bold; } p.note { font-size: 0.9em; }
p.state { font-weight: normal; font-size: 0.85em; margin: 0.3em 0; } p.proof { font-weight: bold; margin: 0.3em 0; }
.figs a, .figs div.machine { display: inline-block; margin: 0.3em 0.2em; vertical-align: top; }
.figs img, .figs canvas { width: SHOWNpx; max-width: 100%; border: 1px solid #eee; }
.figs div.machine { width: SHOWNpx; max-width: 100%; }
details { margin: 0.4em 0; } summary { cursor: pointer; } p.files { font-size: 0.85em; }
""".replace("SHOWN", str(SHOWN_PX))

_SHOP = (".dxf", ".stl", ".step", ".3mf")
#: a machine's slider script (``animation.slider_script``): the page gives it a canvas and a range
SLIDER_SUFFIX = ".slider.js"
#: what a machine's page links under its files instead of showing (:func:`_shown`)
LINKED_ON_MACHINES = (".gif", ".assembly.png")
#: a part with more shop files than this counts them in its verdict and folds its list of files
_LISTED = 12
_SLIDER = (
    "<div class='machine'><canvas width='560' height='560'></canvas><br>"
    "<input type='range' min='0' max='0' value='0' style='width:SHOWNpx' aria-label='driver angle'>"
    "<br><output></output></div><script src='{src}'></script>"
).replace("SHOWN", str(SHOWN_PX))
#: a part's key figures longer than this many rows are set in two tables side by side
_KEY_ROWS = 5
#: DXFs beside the parts that no shop cuts: obstacles, bought parts
_NOT_CUT = (".obstacle.dxf", ".bought.dxf")
#: what a page calls each state, and its style
_CSS = {"built": "built", "withheld": "withheld", "failed": "error"}


def _shade(proof: str, state: str) -> str:
    """The style of a part's proof line: a finding is not a proof passed — it reads as one withheld
    does, whatever the part's state (on its section and, said first, in the verdicts table)."""
    return _CSS["withheld" if proof.startswith("finding") else state]


def part_status(rec: dict) -> tuple[str, str]:
    """("built" | "withheld" | "failed", the sentence a reader sees) for a manifest part record."""
    if "error" in rec:
        return "failed", f"failed: {rec['error']}"
    results = rec.get("results")
    shop = results.get("shop_files") if isinstance(results, dict) else None
    if isinstance(shop, str) and shop.startswith("withheld"):
        return "withheld", f"withheld as a finding — {shop.removeprefix('withheld: ')}; no shop files were written"
    # obstacles and bought parts are drawn for the machine's judge, not cut
    made = sorted(f for f in rec.get("files", {}) if f.endswith(_SHOP) and not f.endswith(_NOT_CUT))
    if len(made) > _LISTED:  # a machine's tens of files: counted here, listed under "files"
        return "built", f"built — {len(made)} shop files (listed under its files)"
    if made:
        return "built", f"built — shop files: {', '.join(made)}"
    return "built", "built — analysis only (no shop files for this kind of part)"


def _verdicts(manifest: dict) -> str:
    """The page's first table: each part, its kind and its verdict, linked to its section."""
    rows = []
    for part in sorted(manifest["parts"]):
        rec = manifest["parts"][part]
        state, sentence = part_status(rec)
        proofs = headline(rec)[1] if state != "failed" else []
        shop = sum(f.endswith(_SHOP) and not f.endswith(_NOT_CUT) for f in rec.get("files", {}))
        if proofs:
            said = f"{state} — {proofs[0]}"
        elif state == "built":
            said = f"built — {shop} shop files" if shop else "built — analysis only"
        else:
            said = sentence
        name = html.escape(part)
        shade = _shade(proofs[0], state) if proofs else _CSS[state]  # as the part's first line reads
        rows.append(
            f"<tr><td><a href='#{name}'>{name}</a></td><td>{html.escape(str(rec.get('kind', '')))}</td>"
            f"<td class='{shade}'>{html.escape(said)}</td></tr>"
        )
    return "<table class='parts'><tr><th>part</th><th>kind</th><th>verdict</th></tr>" + "".join(rows) + "</table>"


def _scrubbed(files) -> bool:
    """A machine whose cycle the page's slider scrubs: its animation (GIF) is linked, not shown."""
    return any(f.endswith(SLIDER_SUFFIX) for f in files)


def _shown(files) -> list[str]:
    """The files the part's page shows, in order: its pictures and its slider. A machine whose cycle
    the slider scrubs shows the slider first and its pictures but the animation (GIF) and the
    assembly picture (:data:`LINKED_ON_MACHINES`: linked under its files, beside the assembly
    drawing it is the picture of) — the cycle and what it carries side by side, the page short."""
    scrubbed = _scrubbed(files)
    linked = LINKED_ON_MACHINES if scrubbed else ()
    out = [f for f in sorted(files) if f.endswith((".png", ".gif")) and not f.endswith(linked)]
    slider = [f for f in sorted(files) if f.endswith(SLIDER_SUFFIX)]
    return [*slider, *out] if scrubbed else [*out, *slider]


def _figures(rec: dict) -> str:
    """The part's plots, each a link to itself (a click opens it full size), and its slider."""
    out = []
    for fname in _shown(rec.get("files", {})):
        name = html.escape(fname)
        if fname.endswith(SLIDER_SUFFIX):  # a machine's cycle to scrub (animation.slider_script)
            out.append(_SLIDER.format(src=name))
        else:
            out.append(f"<a href='{name}'><img src='{name}' alt='{name}'></a>")
    return f"<div class='figs'>{''.join(out)}</div>" if out else ""


def _part(part: str, rec: dict) -> list[str]:
    state, sentence = part_status(rec)
    name = html.escape(part)
    out = [f"<a id='{name}'></a><h2>{name}</h2>"]  # the verdicts link here
    if state == "failed":
        return [*out, f"<p class='{_CSS[state]}'>{html.escape(sentence)}</p>"]
    rows, proofs = headline(rec)
    out += [f"<p class='proof {_shade(p, state)}'>{html.escape(p)}</p>" for p in proofs]
    out.append(f"<p class='state {_CSS[state]}'>{html.escape(sentence)}</p>")
    half = -(-len(rows) // 2) if len(rows) > _KEY_ROWS else len(rows)
    out.append(f"<div class='key'>{table(rows[:half], 'key')}{table(rows[half:], 'key')}</div>" if rows else "")
    out.append(_figures(rec))
    order = list(table_order(str(rec.get("kind"))))
    # a machine's results are the shop's and the judge's detail (its verdicts are the key above): folded
    out.append(grouped("results", rec.get("results", {}), folded=rec.get("kind") == "machine", order=order))
    out.append(grouped("parameters", rec.get("parameters", {}), folded=True))
    files = rec.get("files", {})
    shown = set(_shown(files))
    shown |= {f for f in files if f.endswith(".svg") and f.removesuffix(".svg") + ".png" in shown}  # its SVG twin
    links = " ".join(f"<a href='{html.escape(f)}'>{html.escape(f)}</a>" for f in sorted(files) if f not in shown)
    count = links.count("<a ")
    if count > _LISTED:
        out.append(f"<details class='files'><summary>files ({count})</summary><p class='files'>{links}</p></details>")
    else:
        out.append(f"<p class='files'>files: {links}</p>")
    return out


def family_report(manifest: dict) -> bytes:
    """HTML page for a family manifest (as written by ``families.build_family``)."""
    name = html.escape(manifest["family"])
    states = [part_status(manifest["parts"][p])[0] for p in manifest["parts"]]
    counts = ", ".join(f"{states.count(s)} {s}" for s in ("built", "withheld", "failed") if states.count(s))
    # a part built with a finding (a machine missing a requirement) is counted apart, amber
    found = sum(
        state == "built" and any(_shade(p, state) != _CSS[state] for p in headline(manifest["parts"][part])[1])
        for part, state in zip(manifest["parts"], states, strict=True)
    )
    counts += f" ({found} with a finding)" if found else ""
    summary = f"{len(states)} part{'s' if len(states) != 1 else ''}: {counts}"
    cls = "error" if "failed" in states else ("withheld" if "withheld" in states or found else "built")
    out = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{name}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{name}</h1><p>{html.escape(manifest['description'])}</p><p class='{cls}'>{summary}</p>",
        _verdicts(manifest),
    ]
    for part in sorted(manifest["parts"]):
        out += _part(part, manifest["parts"][part])
    out.append("</body></html>\n")
    return "\n".join(out).encode()
