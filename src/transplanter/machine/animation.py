"""A machine's cycle to watch: an animated GIF for the report and a slider that scrubs it.

Both draw the same posed sections (``machine.Body`` re-read from their DXFs) in the machine
frame. The GIF is drawn with Pillow's ImageDraw (a frame costs milliseconds, where a matplotlib
figure costs ~0.1 s) on a fixed palette, so it stays small (:data:`GIF_LIMIT_BYTES`). The slider
is a script file beside the report: the bodies' outlines (simplified to ``OUTLINE_MM`` for the
screen) and their poses, each arm's phase and the smallest clearance at each position, drawn on
a canvas as the range input moves — it works from the folder, with no server and no network.
"""

from __future__ import annotations

import io
import json
import math

import numpy as np
import shapely

from transplanter.core.errors import ExportError
from transplanter.proof.clearance import reach

__all__ = ["GIF_FRAMES", "GIF_LIMIT_BYTES", "OUTLINE_MM", "SLIDER_POSITIONS", "gif_bytes", "slider_script"]

#: frames of the GIF per cycle (5° of driver each) and its largest size, bytes
GIF_FRAMES = 72
GIF_LIMIT_BYTES = 2_000_000
#: positions of the slider per cycle
SLIDER_POSITIONS = 360
#: outlines are simplified to this for the screen, mm (the shop files keep their precision)
OUTLINE_MM = 0.05
_SIZE = 560  # px
#: bodies drawn as outlines only (a carrier plate or a cam would hide what turns in front of it):
#: names starting with these
OUTLINED = ("carrier", "cam")
_PALETTE = {
    "fixed": (150, 110, 60),
    "ring": (70, 110, 180),
    "carrier": (150, 150, 150),
    "planet": (90, 160, 90),
    "arm": (200, 120, 40),
    "needle": (180, 40, 40),
    "trace": (40, 40, 40),
}
#: what else a name may say it is, drawn in that kind's colour
_KIND = {
    "claw": "needle",
    "gear": "planet",
    "sun": "planet",
    "sector": "planet",
    "cam": "ring",
    "lever": "ring",
    "roller": "ring",
}


def _colour(name: str, link: str) -> tuple[int, int, int]:
    for key in ("needle", "arm", "planet", "ring", "carrier", *_KIND):
        if key in name:
            return _PALETTE[_KIND.get(key, key)]
    return _PALETTE["fixed"] if link == "fixed" else _PALETTE["carrier"]


def _hex(rgb) -> str:
    return "#" + "".join(f"{int(v):02x}" for v in rgb)


def _view(bodies, poses) -> tuple[float, float, float]:
    """(scale px/mm, x0, y0) that fits the moving bodies' sweep with a margin (the fixed ones,
    the box and the soil, are drawn where they fall in it)."""
    boxes = []
    for b in bodies:
        x, y, _ = poses[b.name]
        r = reach(b.section)
        if b.link != "fixed":
            boxes.append((float(np.min(x)) - r, float(np.min(y)) - r, float(np.max(x)) + r, float(np.max(y)) + r))
    lo = np.min([bx[:2] for bx in boxes], axis=0)
    hi = np.max([bx[2:] for bx in boxes], axis=0)
    span = float(max(hi - lo)) * 1.15
    return _SIZE / span, float((lo[0] + hi[0]) / 2 - span / 2), float((lo[1] + hi[1]) / 2 + span / 2)


def _rings(section) -> list[np.ndarray]:
    polys = [section] if isinstance(section, shapely.Polygon) else list(section.geoms)
    return [np.asarray(r.coords) for p in polys for r in (p.exterior, *p.interiors)]


def gif_bytes(bodies, poses: dict, tips: list[np.ndarray], frames: int = GIF_FRAMES) -> bytes:
    """An animated GIF of ``bodies`` at ``frames`` poses: ``poses[name] = (x, y, angle)`` arrays of
    that length (mm, rad); ``tips`` each arm's tip path over the same frames, traced as it goes.
    ExportError if it would exceed :data:`GIF_LIMIT_BYTES`."""
    from PIL import Image, ImageDraw

    scale, x0, y0 = _view(bodies, poses)

    def px(xy: np.ndarray) -> list[float]:
        """Pixel coordinates x, y, x, y, … of the points ``xy`` (mm; the arithmetic of a loop over
        the points, in numpy: the same values)."""
        xy = np.asarray(xy, dtype=float)
        return np.column_stack(((xy[:, 0] - x0) * scale, (y0 - xy[:, 1]) * scale)).ravel().tolist()

    shapes = {b.name: _rings(b.section.simplify(OUTLINE_MM * 4)) for b in bodies}
    # one palette for every frame, drawn in its indices (no per-frame colour quantising)
    colours = [(255, 255, 255), _PALETTE["trace"]]
    for b in bodies:
        rgb = _colour(b.name, b.link)
        colours += [rgb, tuple(int(v + (255 - v) * 0.65) for v in rgb)]
    index = {c: k for k, c in reversed(list(enumerate(colours)))}
    palette = [v for c in colours for v in c]
    images = []
    for f in range(frames):
        im = Image.new("P", (_SIZE, _SIZE), 0)
        im.putpalette(palette)
        draw = ImageDraw.Draw(im)
        for b in bodies:
            x, y, a = (float(v[f]) for v in poses[b.name])
            c, s = math.cos(a), math.sin(a)
            rgb = _colour(b.name, b.link)
            line, fill = index[rgb], index[tuple(int(v + (255 - v) * 0.65) for v in rgb)]
            for k, ring in enumerate(shapes[b.name]):
                moved = np.column_stack([c * ring[:, 0] - s * ring[:, 1] + x, s * ring[:, 0] + c * ring[:, 1] + y])
                inside = None if b.name.startswith(OUTLINED) else (fill if k == 0 else 0)
                draw.polygon(px(moved), fill=inside, outline=line)
        for path in tips:
            draw.line(px(path[: f + 1]), fill=1, width=1)
        images.append(im)
    out = io.BytesIO()
    images[0].save(out, format="GIF", save_all=True, append_images=images[1:], duration=60, loop=0, optimize=False)
    data = out.getvalue()
    if len(data) > GIF_LIMIT_BYTES:
        raise ExportError(f"the machine's animation is {len(data)} bytes (limit {GIF_LIMIT_BYTES})")
    return data


_SCRIPT = """(function () {
const M = %s;
const box = document.currentScript.previousElementSibling;
const canvas = box.querySelector("canvas"), slider = box.querySelector("input"), out = box.querySelector("output");
const g = canvas.getContext("2d");
slider.max = M.driver_deg.length - 1;
function draw() {
  const i = Number(slider.value);
  g.setTransform(1, 0, 0, 1, 0, 0);
  g.fillStyle = "#fff"; g.fillRect(0, 0, canvas.width, canvas.height);
  g.setTransform(M.scale, 0, 0, -M.scale, -M.x0 * M.scale, M.y0 * M.scale);
  for (const b of M.bodies) {
    const p = M.poses[b.name][i];
    g.save(); g.translate(p[0], p[1]); g.rotate(p[2] * Math.PI / 180);
    g.beginPath();
    for (const ring of b.rings) {
      g.moveTo(ring[0], ring[1]);
      for (let k = 2; k < ring.length; k += 2) g.lineTo(ring[k], ring[k + 1]);
      g.closePath();
    }
    g.fillStyle = b.fill; g.strokeStyle = b.stroke; g.lineWidth = 1 / M.scale;
    if (b.fill !== "none") g.fill("evenodd");
    g.stroke(); g.restore();
  }
  g.strokeStyle = "#222"; g.lineWidth = 1 / M.scale;
  for (const path of M.tips) {
    g.beginPath(); g.moveTo(path[0][0], path[0][1]);
    for (let k = 1; k <= i; k++) g.lineTo(path[k][0], path[k][1]);
    g.stroke();
  }
  const c = M.clearance[i];
  out.textContent = "driver " + M.driver_deg[i].toFixed(1) + " deg | " +
    M.phases.map((ph, k) => M.arms[k] + ": " + ph[i]).join(" | ") +
    " | smallest clearance " + c[0].toFixed(2) + " mm (" + c[1] + ")";
  box.dataset.position = String(i);
}
slider.addEventListener("input", draw);
draw();
})();
"""


def slider_script(bodies, poses: dict, tips: list[np.ndarray], driver_deg, phases, clearance, arms) -> bytes:
    """The slider's script (JavaScript, data included) for the report: ``poses`` as for
    :func:`gif_bytes` at ``len(driver_deg)`` positions; ``phases`` each arm's phase name per
    position; ``clearance`` ``(smallest distance mm, between which bodies)`` per position."""
    scale, x0, y0 = _view(bodies, poses)
    data = {
        "scale": round(scale, 6),
        "x0": round(x0, 3),
        "y0": round(y0, 3),
        "driver_deg": [round(float(v), 3) for v in driver_deg],
        "bodies": [
            {
                "name": b.name,
                "rings": [np.round(r, 2).ravel().tolist() for r in _rings(b.section.simplify(OUTLINE_MM))],
                "fill": "none"
                if b.name.startswith(OUTLINED)
                else _hex(tuple(int(v + (255 - v) * 0.65) for v in _colour(b.name, b.link))),
                "stroke": _hex(_colour(b.name, b.link)),
            }
            for b in bodies
        ],
        "poses": {
            name: np.round(np.column_stack([x, y, np.degrees(a)]), 3).tolist()
            for name, (x, y, a) in ((b.name, poses[b.name]) for b in bodies)
        },
        "tips": [np.round(t, 2).tolist() for t in tips],
        "phases": [list(p) for p in phases],
        "arms": list(arms),
        "clearance": [[round(float(d), 3), what] for d, what in clearance],
    }
    return (_SCRIPT % json.dumps(data, separators=(",", ":"), sort_keys=True)).encode()
