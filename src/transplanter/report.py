"""A family's HTML report: what was built, the figures that matter, the plots, the files.

The page is written next to the parts' files and refers to their PNG plots by name, so the
folder can be zipped or served as is. It is deterministic (sorted keys, no timestamps).
"""

from __future__ import annotations

import html
import json

__all__ = ["family_report"]

_STYLE = """
body { font-family: sans-serif; max-width: 70em; margin: 2em auto; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }
td, th { border: 1px solid #ddd; padding: 0.2em 0.6em; text-align: left; vertical-align: top; }
td.v { font-family: monospace; } .error { color: #b00; font-weight: bold; }
img { max-width: 100%; border: 1px solid #eee; margin: 0.5em 0; }
"""


def _flat(prefix: str, value, rows: list[tuple[str, str]], depth: int = 0) -> None:
    if isinstance(value, dict) and depth < 3:
        for k in sorted(value):
            _flat(f"{prefix}.{k}" if prefix else str(k), value[k], rows, depth + 1)
    elif isinstance(value, list) and len(value) > 12:
        rows.append((prefix, f"[{len(value)} values]"))
    else:
        text = value if isinstance(value, str) else json.dumps(value, sort_keys=True)
        rows.append((prefix, text))


def _table(title: str, value) -> str:
    rows: list[tuple[str, str]] = []
    _flat("", value, rows)
    body = "".join(f"<tr><td>{html.escape(k)}</td><td class='v'>{html.escape(v)}</td></tr>" for k, v in rows)
    return f"<h3>{title}</h3><table>{body}</table>" if rows else ""


def family_report(manifest: dict) -> bytes:
    """HTML page for a family manifest (as written by ``families.build_family``)."""
    name = html.escape(manifest["family"])
    status = "all parts built" if manifest["ok"] else "<span class='error'>some parts failed</span>"
    out = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{name}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{name}</h1><p>{html.escape(manifest['description'])}</p><p>{status}</p>",
    ]
    for part in sorted(manifest["parts"]):
        rec = manifest["parts"][part]
        out.append(f"<h2>{html.escape(part)}</h2>")
        if "error" in rec:
            out.append(f"<p class='error'>{html.escape(rec['error'])}</p>")
            continue
        out.append(f"<p>kind: {html.escape(rec.get('kind', ''))}</p>")
        for fname in sorted(rec.get("files", {})):
            if fname.endswith(".png"):
                out.append(f"<img src='{html.escape(fname)}' alt='{html.escape(fname)}'>")
        out.append(_table("results", rec.get("results", {})))
        out.append(_table("parameters", rec.get("parameters", {})))
        links = " ".join(
            f"<a href='{html.escape(f)}'>{html.escape(f)}</a>"
            for f in sorted(rec.get("files", {}))
            if not f.endswith((".png", ".svg"))
        )
        out.append(f"<p>files: {links}</p>")
    out.append("</body></html>\n")
    return "\n".join(out).encode()
