"""A family's HTML report: what was built, the figures that matter, the plots, the files.

The page is written next to the parts' files and refers to their PNG plots by name, so the
folder can be zipped or served as is. It is deterministic (sorted keys, no timestamps).

Each part opens with its status — **built** (with its shop files), **withheld** (a finding:
figures and plots, no shop files, and why) or **failed** (the error) — and its results and
parameters follow as tables grouped by topic, with the unit in its own column (read from the
key's suffix: ``_mm``, ``_mm2``, ``_deg``, ...) and numbers to 4 significant digits (the
manifest keeps the full figures).
"""

from __future__ import annotations

import html
import json

__all__ = ["family_report", "part_status"]

_STYLE = """
body { font-family: sans-serif; max-width: 70em; margin: 2em auto; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; border-bottom: 1px solid #ccc; margin-top: 2em; }
h4 { margin: 0.8em 0 0.2em 0; font-size: 0.95em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.3em 0; }
td, th { border: 1px solid #ddd; padding: 0.2em 0.6em; text-align: left; vertical-align: top; }
td.v { font-family: monospace; text-align: right; } td.u { color: #666; }
.error { color: #b00; font-weight: bold; } .withheld { color: #a60; font-weight: bold; }
.built { color: #070; font-weight: bold; }
img { max-width: 49%; border: 1px solid #eee; margin: 0.5em 0.2em; vertical-align: top; }
details { margin: 0.4em 0; } summary { cursor: pointer; }
"""

#: key suffix -> unit shown (longest first)
_UNITS = (
    ("_mm2", "mm²"),
    ("_mm3", "mm³"),
    ("_mm", "mm"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_rpm", "rpm"),
    ("_m_s2", "m/s²"),
    ("_m_s", "m/s"),
    ("_n_m", "N m"),
    ("_n", "N"),
    ("_kg", "kg"),
    ("_s", "s"),
)
_SHOP = (".dxf", ".stl", ".step", ".3mf")
#: a machine's slider script (``animation.slider_script``): the page gives it a canvas and a range
SLIDER_SUFFIX = ".slider.js"
_SLIDER = (
    "<div class='machine'><canvas width='560' height='560'></canvas><br>"
    "<input type='range' min='0' max='0' value='0' style='width:560px' aria-label='driver angle'>"
    "<br><output></output></div><script src='{src}'></script>"
)
#: a results topic longer than this many rows is folded (``<details>``), mm of page saved
OPEN_ROWS = 8
#: figures closer to zero than this are shown as 0 (the manifest keeps them as computed)
ROUND_OFF = 1e-6
#: the units a metric record may carry, written the way the page writes units
_UNIT_TEXT = {"m/s^2": "m/s²", "mm^2": "mm²", "mm^3": "mm³"}


#: DXFs beside the parts that no shop cuts: obstacles, bought parts
_NOT_CUT = (".obstacle.dxf", ".bought.dxf")


def _label(key: str) -> tuple[str, str]:
    for suffix, unit in _UNITS:
        if key.endswith(suffix):
            return key[: -len(suffix)].replace("_", " "), unit
    return key.replace("_", " "), ""


def _number(v) -> str:
    if isinstance(v, bool) or v is None:
        return json.dumps(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "0" if abs(v) < ROUND_OFF else f"{v:.4g}"  # no "-5.9e-08 m/s": round-off of a zero
    return str(v)


def _value(v) -> str:
    if isinstance(v, list):
        if len(v) > 12:
            return f"[{len(v)} values]"
        return ", ".join(_value(x) for x in v)
    if isinstance(v, dict):
        return "; ".join(f"{k} {_value(x)}" for k, x in sorted(v.items()))
    return _number(v)


def _rows(prefix: str, value: dict, depth: int = 0) -> list[tuple[str, str, str]]:
    rows = []
    for key in sorted(value):
        v = value[key]
        name, unit = _label(key)
        name = f"{prefix} › {name}" if prefix else name
        if isinstance(v, dict) and depth < 4 and v and not all(isinstance(x, int | float) for x in v.values()):
            rows.extend(_rows(name, v, depth + 1))
        else:
            rows.append((name, _value(v), unit))
    return rows


def _table(rows: list[tuple[str, str, str]]) -> str:
    body = "".join(
        f"<tr><td>{html.escape(k)}</td><td class='v'>{html.escape(v)}</td><td class='u'>{html.escape(u)}</td></tr>"
        for k, v, u in rows
    )
    return f"<table>{body}</table>" if rows else ""


def _matrix(value: dict) -> str:
    """A ``{"columns": [...], "rows": [[...], ...]}`` result as a table with a header row."""
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in value["columns"])
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(_value(c))}</td>" for c in row) + "</tr>" for row in value["rows"]
    )
    return f"<table><tr>{head}</tr>{body}</table>"


def _metric(v) -> bool:
    """A ``{"value": number, "unit": text}`` record (a row of a metrics table, e.g. seed 000's Table 2)."""
    return isinstance(v, dict) and set(v) == {"value", "unit"} and isinstance(v["value"], int | float)


def _grouped(title: str, value: dict, folded: bool = False) -> str:
    """One table of the scalars and of the metric records (name, value, unit columns: one table,
    not one per metric), then one per topic (a dict-valued key); a topic given as columns and rows
    is drawn as that table. ``folded``: the whole group in a ``<details>`` a reader opens."""
    if not value:
        return ""
    scalars = {k: v for k, v in value.items() if not isinstance(v, dict)}
    metrics = [
        (k.replace("_", " "), _number(float(v["value"])), _UNIT_TEXT.get(v["unit"], v["unit"]))
        for k, v in sorted(value.items())
        if _metric(v)
    ]
    head = f"<summary><b>{title}</b></summary>" if folded else f"<h3>{title}</h3>"
    out = ["<details>" if folded else "", head, _table(_rows("", scalars)), _table(metrics)]
    for key in sorted(k for k, v in value.items() if isinstance(v, dict) and not _metric(v)):
        topic = value[key]
        if "columns" in topic and "rows" in topic:
            rest = {k: v for k, v in topic.items() if k not in ("columns", "rows")}
            body, n = _matrix(topic) + _table(_rows("", rest)), len(topic["rows"]) + len(rest)
        else:
            rows = _rows("", topic)
            body, n = _table(rows), len(rows)
        name = html.escape(_label(key)[0])
        if "solid_volume_mm3" in topic and not folded:  # a made part's file checks: a click away
            head = f"<summary><b>{name}</b> (made: its files verified, {n} rows)</summary>"
            out.append(f"<details>{head}{body}</details>")
        elif n > OPEN_ROWS and not folded:  # a long topic folded: the page stays short, the figures a click away
            out.append(f"<details><summary><b>{name}</b> ({n} rows)</summary>{body}</details>")
        else:
            out.append(f"<h4>{name}</h4>{body}")
    out.append("</details>" if folded else "")
    return "".join(out)


def part_status(rec: dict) -> tuple[str, str]:
    """("built" | "withheld" | "failed", the sentence a reader sees) for a manifest part record."""
    if "error" in rec:
        return "failed", f"failed: {rec['error']}"
    shop = rec.get("results", {}).get("shop_files")
    if isinstance(shop, str) and shop.startswith("withheld"):
        return "withheld", f"withheld as a finding — {shop.removeprefix('withheld: ')}; no shop files were written"
    # obstacles and bought parts are drawn for the machine's judge, not cut
    made = sorted(f for f in rec.get("files", {}) if f.endswith(_SHOP) and not f.endswith(_NOT_CUT))
    if made:
        return "built", f"built — shop files: {', '.join(made)}"
    return "built", "built — analysis only (no shop files for this kind of part)"


def family_report(manifest: dict) -> bytes:
    """HTML page for a family manifest (as written by ``families.build_family``)."""
    name = html.escape(manifest["family"])
    states = [part_status(manifest["parts"][p])[0] for p in manifest["parts"]]
    counts = ", ".join(f"{states.count(s)} {s}" for s in ("built", "withheld", "failed") if states.count(s))
    headline = f"{len(states)} part{'s' if len(states) != 1 else ''}: {counts}"
    cls = "error" if "failed" in states else ("withheld" if "withheld" in states else "built")
    out = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{name}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{name}</h1><p>{html.escape(manifest['description'])}</p><p class='{cls}'>{headline}</p>",
    ]
    for part in sorted(manifest["parts"]):
        rec = manifest["parts"][part]
        state, sentence = part_status(rec)
        out.append(f"<h2>{html.escape(part)}</h2>")
        css = "error" if state == "failed" else state
        out.append(f"<p class='{css}'>{html.escape(sentence)}</p>")
        if state == "failed":
            continue
        out.append(f"<p>kind: {html.escape(rec.get('kind', ''))}</p>")
        for fname in sorted(rec.get("files", {})):
            if fname.endswith((".png", ".gif")):
                out.append(f"<img src='{html.escape(fname)}' alt='{html.escape(fname)}'>")
            elif fname.endswith(SLIDER_SUFFIX):  # a machine's cycle to scrub (animation.slider_script)
                out.append(_SLIDER.format(src=html.escape(fname)))
        out.append(_grouped("results", rec.get("results", {})))
        out.append(_grouped("parameters", rec.get("parameters", {}), folded=True))
        links = " ".join(
            f"<a href='{html.escape(f)}'>{html.escape(f)}</a>"
            for f in sorted(rec.get("files", {}))
            if not f.endswith((".png", ".svg", ".gif", SLIDER_SUFFIX))
        )
        out.append(f"<p>files: {links}</p>")
    out.append("</body></html>\n")
    return "\n".join(out).encode()
