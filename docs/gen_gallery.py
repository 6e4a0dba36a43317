"""Write the gallery: the part families with the pictures a build makes (mkdocs-gen-files).

Run by ``mkdocs build`` (the ``gen-files`` plugin in ``mkdocs.yml``), never by hand. The pictures
are not committed: this script reads a built export folder — ``$TRANSPLANTER_EXPORTS``, default
``exports/`` at the repository root, as ``transplanter build`` writes it — and copies every PNG and
GIF that a family's ``manifest.json`` lists into the site (``gallery/<family>/``), with the family's
description and each part's kind. A folder without a build stops the site's build, saying so: build
first (``.ci/run`` runs ``transplanter build -o exports`` before ``mkdocs build --strict``).

The two pictures that are committed, ``docs/img/seed004_ring_planet.png`` (the README's and the
home page's) and ``docs/img/seed004_machine.png`` (the README's machine section), are the build's
``exports/planetary_seed004/optimised_ring_planet.teeth.png`` — the optimised seed-004 ring and
planet as cut, in mesh at the start — and ``machine.assembly.png`` — the machine assembled at the
start, its balloons the bill of materials' items — made smaller with Pillow (matplotlib's
dependency), the same way for the second::

    transplanter build parts/planetary_seed004.py
    python -c "from PIL import Image; im = Image.open('exports/planetary_seed004/optimised_ring_planet.teeth.png'); \\
        im.resize((im.width * 3 // 5, im.height * 3 // 5), Image.LANCZOS).convert('P', palette=Image.ADAPTIVE, \\
        colors=64).save('docs/img/seed004_ring_planet.png', optimize=True)"
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import mkdocs_gen_files
from mkdocs.exceptions import PluginError

ROOT = Path(__file__).resolve().parent.parent
EXPORTS = Path(os.environ.get("TRANSPLANTER_EXPORTS", "exports"))
EXPORTS = EXPORTS if EXPORTS.is_absolute() else ROOT / EXPORTS
PICTURES = (".png", ".gif")


def families(folder: Path) -> list[tuple[Path, dict]]:
    """Every built family in ``folder``: its folder and its manifest, by name."""
    found = []
    for manifest in sorted(folder.glob("*/manifest.json")):
        try:
            found.append((manifest.parent, json.loads(manifest.read_text())))
        except (OSError, ValueError) as exc:
            raise PluginError(f"gallery: {manifest} cannot be read ({exc}): rebuild with `transplanter build`") from exc
    return found


built = families(EXPORTS)
if not built:
    raise PluginError(
        f"gallery: {EXPORTS} holds no built family (no <family>/manifest.json): the gallery shows the pictures "
        "a build makes, so build first — `transplanter build -o exports` — or set TRANSPLANTER_EXPORTS to a "
        "folder that `transplanter build` wrote"
    )

lines = [
    "# Gallery",
    "",
    "The part families, with the pictures `transplanter build` makes: plots of paths, kinematics, pitch",
    "curves, teeth in mesh, the meshing proof over the cycle and the machines' animations. They are",
    "copied from a built export folder when this site is built (`docs/gen_gallery.py`), so they are the",
    "pictures of this version of the code. Each family's `report.html` shows them beside its figures.",
    "",
]
for folder, manifest in built:
    family = manifest.get("family", folder.name)
    lines += [f"## {family}", "", manifest.get("description", ""), ""]
    for part, record in manifest.get("parts", {}).items():
        pictures = [name for name in record.get("files", {}) if name.endswith(PICTURES)]
        pictures = [name for name in pictures if (folder / name).is_file()]
        if not pictures:
            continue
        lines += [f"### {family} / {part}", "", f"*{record.get('kind', 'part')}*", ""]
        for name in pictures:
            target = Path("gallery", family, name)
            with mkdocs_gen_files.open(target, "wb") as fd:
                fd.write((folder / name).read_bytes())
            lines += [f"![{family}: {name}]({target.as_posix()})", "", f"`{name}`", ""]

with mkdocs_gen_files.open("gallery.md", "w") as fd:
    fd.write("\n".join(lines))
