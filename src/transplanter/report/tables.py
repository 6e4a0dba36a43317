"""A part's recorded figures as the tables of its report page: one row per quantity with its
value and its unit in a column of their own, parts alike compared side by side, sentences as text.

Units are read from the keys (``_mm``, ``_kg_mm``, ``_N_m``, ``_m_s2`` …, :data:`UNITS`); a key
without a suffix takes its table's unit (``links_mm: {crank: 35}``), a ``<key>_unit`` beside it, a
metric record's unit of the same name, or the unit its quantity always has (:data:`NAMED_UNITS`).
Numbers are shown to 4 significant digits (the manifest keeps the full figures).
"""

from __future__ import annotations

import html

__all__ = [
    "NAMED_UNITS",
    "POSITIONAL",
    "OPEN_ROWS",
    "ROUND_OFF",
    "UNITS",
    "Section",
    "grouped",
    "is_metric",
    "label",
    "number",
    "table",
    "value",
]

#: key suffix -> unit shown (longest first; matched ignoring case: ``_N_m`` is ``_n_m``)
UNITS = (
    ("_mm_or_deg", "mm or deg"),
    ("_kg_mm2", "kg·mm²"),
    ("_kg_mm", "kg·mm"),
    ("_m_s2", "m/s²"),
    ("_mm_s", "mm/s"),
    ("_rad_s", "rad/s"),
    ("_m_s", "m/s"),
    ("_n_m", "N·m"),
    ("_mm2", "mm²"),
    ("_mm3", "mm³"),
    ("_mm", "mm"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_rpm", "rpm"),
    ("_kg", "kg"),
    ("_n", "N"),
    ("_s", "s"),
    ("_m", "× module"),  # a gear's depths in modules (``driver_radius_below_tip_m``)
)
#: keys recorded without a suffix whose quantity always has this unit (tooth proportions are
#: multiples of the module; a cam's dimensions are mm)
NAMED_UNITS = {
    "addendum": "× module",
    "dedendum": "× module",
    "tip_fillet": "× module",
    "shift": "× module",
    "ring_addendum": "× module",
    "ring_addendum_limit": "× module",
    "arm_length": "mm",
    "base_radius": "mm",
    "pivot_distance": "mm",
    "roller_radius": "mm",
    # seed 002's synthesis: the feasible region's boxes and the extra links' points, mm
    "feasible_boxes": "mm",
    "extra_link2": "mm",
    "extra_link3": "mm",
}
#: keys recorded as a list of quantities of different units, one per place: shown as one row (or
#: column) each, named with its unit — seed 002's machine states its pose tolerance as (position mm,
#: attitude deg), its synthesis each pose as (x mm, y mm, angle deg)
POSITIONAL = {
    "tolerance": (("position tolerance", "mm"), ("attitude tolerance", "deg")),
    "poses": (("x", "mm"), ("y", "mm"), ("angle", "deg")),
}
#: keys that are the same quantity as a key recorded with its unit elsewhere in the record
_SAME_AS = {"follower_stroke": "stroke"}
#: the units a metric record may carry, written the way the page writes units
_UNIT_TEXT = {"m/s^2": "m/s²", "mm^2": "mm²", "mm^3": "mm³"}
#: a topic longer than this many rows is folded (``<details>``): the page stays short
OPEN_ROWS = 8
#: figures closer to zero than this are shown as 0 (the manifest keeps them as computed)
ROUND_OFF = 1e-6
#: a text longer than this with a space in it is a sentence: written as text, not in a value cell
_SENTENCE = 30
#: two tables of a record with this share of their keys in common are one comparison
_ALIKE = 0.5


def unit_text(unit: str) -> str:
    """A recorded unit as the page writes it (``m/s^2`` -> ``m/s²``)."""
    return _UNIT_TEXT.get(unit, unit)


def label(key: str, inherited: str = "", named: dict[str, str] | None = None) -> tuple[str, str]:
    """(name shown, unit) of a recorded key: its suffix's unit, else ``inherited`` (its table's),
    else a unit the record gives that name (``named``) or :data:`NAMED_UNITS`."""
    low = key.lower()
    for suffix, unit in UNITS:
        if low.endswith(suffix) and len(key) > len(suffix):
            return key[: -len(suffix)].replace("_", " "), unit
    name = key.replace("_", " ")
    found = (named or {}).get(key) or (named or {}).get(_SAME_AS.get(key, "")) or NAMED_UNITS.get(key, "")
    return name, inherited or found


def number(v) -> str:
    """A figure as shown: 4 significant digits, round-off as 0, yes/no, — for none."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if abs(v) < ROUND_OFF:  # no "-5.9e-08 m/s": round-off of a zero
            return "0"
        return str(round(v)) if 1e4 <= abs(v) < 1e15 else f"{v:.4g}"  # 14382, not 1.438e+04
    return str(v)


def value(v) -> str:
    """A value cell: a figure, a short list (inner lists in brackets), a small table inline."""
    if isinstance(v, list):
        if not v:
            return "none"
        if len(v) > 12:
            return f"[{len(v)} values]"
        return ", ".join(f"({value(x)})" if isinstance(x, list) else value(x) for x in v)
    if isinstance(v, dict):
        return "; ".join(f"{k.replace('_', ' ')} {value(x)}" for k, x in sorted(v.items()))
    return number(v)


def _positional(key: str, v) -> bool:
    """``v`` is ``key``'s list of quantities one per place (:data:`POSITIONAL`), or a list of them."""
    n = len(POSITIONAL.get(key, ()))
    if not n or not isinstance(v, list) or not v:
        return False
    rows = v if all(isinstance(x, list) for x in v) else [v]
    return all(len(r) == n and all(_numeric(x) for x in r) for r in rows)


def _inline(v: dict) -> bool:
    """A small table of figures in one unit (``links_mm``) is one row: ``crank 35; rocker 80``."""
    short = len(v) <= 4 and all(len(k) <= 12 for k in v)
    return short and all(_numeric(x) for x in v.values()) and all(not label(k)[1] for k in v)


def _numeric(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _sentence(v) -> bool:
    return isinstance(v, str) and " " in v and len(v) > _SENTENCE


def is_metric(v) -> bool:
    """A ``{"value": number, "unit": text}`` record (``published`` beside it when a paper gives one)."""
    if not isinstance(v, dict) or set(v) not in ({"value", "unit"}, {"value", "unit", "published"}):
        return False
    return _numeric(v["value"]) and isinstance(v["unit"], str)


def _carries_unit(v) -> bool:
    """Whether a table's unit reaches this value (a number, numbers, or a table of them)."""
    if isinstance(v, list):
        return bool(v) and all(_carries_unit(x) for x in v)
    if isinstance(v, dict):
        return bool(v) and all(_carries_unit(x) for x in v.values())
    return _numeric(v)


def _kind(v) -> str:
    return "table" if isinstance(v, dict) else "list" if isinstance(v, list) else "figure"


def _alike(a: dict, b: dict) -> bool:
    """Records of one kind: most keys shared, each shared key holding the same kind of value (the
    steps of two gears are alike; the steps and the timing marks of a pair are not)."""
    shared = set(a) & set(b)
    return len(shared) >= _ALIKE * len(set(a) | set(b)) and all(_kind(a[k]) == _kind(b[k]) for k in shared)


def _clusters(tables: dict[str, dict]) -> list[list[str]]:
    """The dict-valued entries of a record grouped by the keys they share (sorted, first-come)."""
    groups: list[list[str]] = []
    for key in sorted(tables):
        for g in groups:
            if _alike(tables[g[0]], tables[key]):
                g.append(key)
                break
        else:
            groups.append([key])
    return groups


def table(rows: list[tuple[str, str, str]], css: str = "") -> str:
    """Rows of (name, value, unit) as a three-column table."""
    body = "".join(
        f"<tr><td>{html.escape(k)}</td><td class='v'>{html.escape(v)}</td><td class='u'>{html.escape(u)}</td></tr>"
        for k, v, u in rows
    )
    head = f"<table class='{css}'>" if css else "<table>"
    return f"{head}{body}</table>" if rows else ""


def _header_table(head: list[str], rows: list[list[str]], numeric_from: int = 1) -> str:
    """A table with a header row; cells from column ``numeric_from`` on are figures."""
    top = "".join(f"<th>{html.escape(h)}</th>" for h in head)
    cell = ("<td>", "<td class='v'>")
    body = "".join(
        "<tr>" + "".join(f"{cell[k >= numeric_from]}{html.escape(c)}</td>" for k, c in enumerate(row)) + "</tr>"
        for row in rows
    )
    return f"<table><tr>{top}</tr>{body}</table>"


class Section:
    """What one topic of a record shows: its rows (name, value, unit), its sentences (name, text
    or texts) and its further tables (title, HTML), collected by :meth:`add`."""

    def __init__(self, named: dict[str, str], cells: bool = False):
        self.named = named
        #: sentences in value cells (a column of a comparison), not as text under the table
        self.cells = cells
        self.rows: list[tuple[str, str, str]] = []
        self.notes: list[tuple[str, object]] = []
        self.tables: list[tuple[str, str]] = []

    def add(self, prefix: str, record: dict, unit: str = "", depth: int = 0) -> Section:
        """Every entry of ``record`` under ``prefix`` (``a › b``), ``unit`` the table's own."""
        tables = {k: v for k, v in record.items() if isinstance(v, dict) and v and not is_metric(v) and not _inline(v)}
        compared = set()
        for group in [] if self.cells else _clusters(tables):  # a column of a comparison: its tables as rows
            if len(group) > 1:
                body = self.compare(group, tables, unit)
                names = (f"{prefix} › " if prefix else "") + ", ".join(k.replace("_", " ") for k in group)
                self.tables.append((prefix if len(group) == len(record) else names, body))  # all of it: its name
                compared.update(group)
        for key in sorted(record):
            v = record[key]
            if key in compared or (key.endswith("_unit") and key[:-5] in record):
                continue
            if _positional(key, v):  # one quantity a place: a row each, or a table of them
                self._positional(prefix, key, v)
                continue
            name, own = label(key, "", self.named)
            if isinstance(record.get(f"{key}_unit"), str):
                own = unit_text(record[f"{key}_unit"])
            u = own or (unit if _carries_unit(v) else "")
            full = f"{prefix} › {name}" if prefix else name
            if is_metric(v):
                self.rows.append((full, number(float(v["value"])), unit_text(v["unit"])))
            elif isinstance(v, dict) and not v:
                continue
            elif isinstance(v, dict) and _inline(v):
                self.rows.append((full, value(v), u))
            elif isinstance(v, dict) and _is_matrix(v):  # a table given as columns and rows (a BOM)
                self.tables.append((full, _matrix(v)))
                self.add(full, {k: x for k, x in v.items() if k not in ("columns", "rows")}, u, depth + 1)
            elif isinstance(v, dict) and depth < 4:
                said = {k: x for k, x in v.items() if isinstance(x, str)}
                if len(said) > 1 and any(map(_sentence, said.values())):  # readings in words: their own table
                    rows = [[k.replace("_", " "), x] for k, x in sorted(said.items())]
                    self.tables.append((full, _header_table([full, "reading"], rows, numeric_from=2)))
                    v = {k: x for k, x in v.items() if k not in said}
                self.add(full, v, u, depth + 1)
            elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
                self.tables.append((full, self.records([str(k + 1) for k in range(len(v))], v, "#")))
            elif (_sentence(v) and not self.cells) or (isinstance(v, list) and any(map(_sentence, v))):
                self.notes.append((full, v))
            else:
                self.rows.append((full, value(v), u))
        return self

    def _positional(self, prefix: str, key: str, v: list) -> None:
        places = POSITIONAL[key]
        full = f"{prefix} › {key.replace('_', ' ')}" if prefix else key.replace("_", " ")
        if all(_numeric(x) for x in v):
            for (name, unit), x in zip(places, v, strict=True):
                self.rows.append((f"{prefix} › {name}" if prefix else name, number(float(x)), unit))
            return
        rows = [[str(k + 1), *(number(float(x)) for x in row)] for k, row in enumerate(v)]
        self.tables.append((full, _header_table(["#", *(f"{n} ({u})" for n, u in places)], rows)))

    def _flat(self, record: dict, unit: str = "") -> Section:
        return Section(self.named, cells=True).add("", record, unit)

    def compare(self, keys: list[str], tables: dict[str, dict], unit: str = "") -> str:
        """Tables alike (the gears of a pair, the plates of a linkage, the sources of a proof)
        side by side: a quantity per row with its unit when they hold more quantities than there
        are tables, else one row each. ``unit``: theirs when their keys carry none."""
        if len({q for k in keys for q in tables[k]}) >= len(keys):
            return self._transposed(keys, tables, unit)
        return self.records(keys, [tables[k] for k in keys], "", unit)

    def _transposed(self, keys: list[str], tables: dict[str, dict], unit: str) -> str:
        flat = {k: self._flat(tables[k], unit) for k in keys}
        order: dict[str, str] = {}
        for k in keys:
            for name, _, u in flat[k].rows:
                order.setdefault(name, u)
            self.notes += [(f"{k} › {n}", t) for n, t in flat[k].notes]
            self.tables += [(f"{k} › {n}", t) for n, t in flat[k].tables]
        cells = {k: {n: v for n, v, _ in flat[k].rows} for k in keys}
        rows = [[n, u, *(cells[k].get(n, "–") for k in keys)] for n, u in order.items()]
        head = ["quantity", "unit", *(k.replace("_", " ") for k in keys)]
        return _header_table(head, rows, numeric_from=2)

    def records(self, names: list[str], records: list[dict], first: str, unit: str = "") -> str:
        """Records as rows (``names``), a column per quantity headed with its unit."""
        flat = [self._flat(r, unit) for r in records]
        order: dict[str, str] = {}
        for f in flat:
            for name, _, u in f.rows:
                order.setdefault(name, u)
        rows = [
            [n.replace("_", " "), *({q: v for q, v, _ in f.rows}.get(q, "–") for q in order)]
            for n, f in zip(names, flat, strict=True)
        ]
        texts = [(n, q, t) for n, f in zip(names, flat, strict=True) for q, t in f.notes]
        head = [first, *(f"{q} ({u})" if u else q for q, u in order.items())]
        out = _header_table(head, rows)
        if texts:
            out += "".join(
                f"<p class='note'><b>{html.escape(n)} › {html.escape(q)}</b>: {_text(t)}</p>" for n, q, t in texts
            )
        return out

    def html(self, css: str = "") -> str:
        """The rows' table, the sentences, the further tables (each under its title)."""
        out = [table(self.rows, css)]
        out += [_note(n, t) for n, t in self.notes]
        out += [(f"<h5>{html.escape(t)}</h5>" if t else "") + body for t, body in self.tables]
        return "".join(out)

    def size(self) -> int:
        return len(self.rows) + len(self.notes) + sum(body.count("<tr>") for _, body in self.tables)


def _note(name: str, t) -> str:
    """A sentence under its name; a list longer than ``OPEN_ROWS`` (an assembly order) folded."""
    if isinstance(t, list) and len(t) > OPEN_ROWS:
        head = f"<summary><b>{html.escape(name)}</b> ({len(t)} lines)</summary>"
        return f"<details class='note'>{head}{_text(t)}</details>"
    return f"<p class='note'><b>{html.escape(name)}</b>: {_text(t)}</p>"


def _text(t) -> str:
    if isinstance(t, list):
        return "<ul>" + "".join(f"<li>{html.escape(str(x))}</li>" for x in t) + "</ul>"
    return html.escape(str(t))


def named_units(record) -> dict[str, str]:
    """The units a record itself gives names: its metric records', and each ``<key>_unit``."""
    out: dict[str, str] = {}

    def walk(v):
        if isinstance(v, dict):
            for k, x in v.items():
                if is_metric(x):
                    out.setdefault(k, unit_text(x["unit"]))
                elif k.endswith("_unit") and isinstance(x, str):
                    out.setdefault(k[:-5], unit_text(x))
                else:
                    walk(x)
        elif isinstance(v, list):
            for x in v:
                walk(x)

    walk(record)
    return out


def _matrix(topic: dict) -> str:
    """A ``{"columns": [...], "rows": [[...], ...]}`` result as a table with a header row, a
    column's unit from its name (``module_mm`` -> ``module (mm)``)."""
    head = []
    for c in topic["columns"]:
        name, unit = label(str(c))
        head.append(f"{name} ({unit})" if unit else name)
    return _header_table(head, [[value(c) for c in row] for row in topic["rows"]])


def _metrics(records: list[tuple[str, dict]]) -> str:
    """Metric records in their order: name, value, unit — and the published value beside each
    when a paper gives them."""
    if not any("published" in r for _, r in records):
        return table([(k.replace("_", " "), number(float(r["value"])), unit_text(r["unit"])) for k, r in records])
    rows = [[k, number(float(r["value"])), number(r.get("published")), unit_text(r["unit"])] for k, r in records]
    return _header_table(["quantity", "value", "published", "unit"], rows)


def grouped(title: str, record: dict, folded: bool = False, order: list[str] | None = None) -> str:
    """A record's figures: its metric records as one table (in ``order``, then the rest sorted),
    its plain figures as one table, then a table per topic (a dict-valued key) — topics alike side
    by side, a topic given as columns and rows drawn as that table, a long topic folded.
    ``folded``: the whole group in a ``<details>`` a reader opens."""
    if not isinstance(record, dict) or not record:
        return ""
    named = named_units(record)
    rank = {k: i for i, k in enumerate(order or [])}
    metrics = _ranked({k: v for k, v in record.items() if is_metric(v)}, rank)
    plain = {k: v for k, v in record.items() if not isinstance(v, dict)}
    topics = {k: v for k, v in record.items() if isinstance(v, dict) and not is_metric(v)}
    head = f"<summary><b>{title}</b></summary>" if folded else f"<h3>{title}</h3>"
    out = ["<details>" if folded else "", head, Section(named).add("", plain).html()]
    out.append(_metrics(metrics) if metrics else "")
    for group in _clusters({k: v for k, v in topics.items() if v and not _is_matrix(v)}):
        if len(group) > 1:
            sec = Section(named)
            body = sec.compare(group, topics) + sec.html()
            name = ", ".join(html.escape(label(k)[0]) for k in group)
            out.append(_fold(name, body, 2 * OPEN_ROWS, folded, "made and verified" if _made(topics, group) else ""))
            continue
        (key,) = group
        topic = topics[key]
        name = html.escape(label(key)[0])
        if all(map(is_metric, topic.values())):  # a metrics table (a paper's quantities, published beside)
            out.append(_fold(name, _metrics(_ranked(topic, rank)), len(topic), folded))
            continue
        sec = Section(named).add("", topic, label(key, "", named)[1])
        out.append(_fold(name, sec.html(), sec.size(), folded, "made and verified" if _made(topics, group) else ""))
    for key in sorted(k for k, v in topics.items() if _is_matrix(v)):
        topic = topics[key]
        rest = {k: v for k, v in topic.items() if k not in ("columns", "rows")}
        body = _matrix(topic) + Section(named).add("", rest).html()
        out.append(_fold(html.escape(label(key)[0]), body, len(topic["rows"]) + len(rest), folded))
    out.append("</details>" if folded else "")
    return "".join(out)


def _ranked(records: dict, rank: dict[str, int]) -> list[tuple[str, dict]]:
    """Metric records in their table's order (``rank``), those it does not name after, sorted."""
    return sorted(
        ((k, v) for k, v in records.items() if is_metric(v)), key=lambda kv: (rank.get(kv[0], len(rank)), kv[0])
    )


def _is_matrix(v: dict) -> bool:
    """A topic given as ``{"columns": [...], "rows": [[...], ...]}`` (drawn as that table)."""
    rows = v.get("rows")
    return isinstance(v.get("columns"), list) and isinstance(rows, list) and all(isinstance(r, list) for r in rows)


def _made(topics: dict, group: list[str]) -> bool:
    """A made part's file checks (its solid's volume recorded): a click away."""
    return all("solid_volume_mm3" in topics[k] for k in group)


def _fold(name: str, body: str, rows: int, folded: bool, why: str = "") -> str:
    if folded or not (why or rows > OPEN_ROWS):
        return f"<h4>{name}</h4>{body}"
    said = f"{why}, {rows} rows" if why else f"{rows} rows"
    return f"<details><summary><b>{name}</b> ({said})</summary>{body}</details>"
