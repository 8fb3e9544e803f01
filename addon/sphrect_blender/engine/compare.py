"""The comparison image: techniques side by side with labels (name, light selection when several are compared,
samples, time, RMSE) and, when a reference exists, error heat maps on a shared scale. Pure numpy (no bpy), so
it works from the render thread and in tests; `write_png` stores it without Blender. The RMSE is the study's
(`sphrect.study.metrics.rmse`), so the add-on and the study report the same error."""
import struct
import zlib

import numpy as np

from ..native import load_sphrect

# A 3x5 bitmap font: five rows of three pixels per glyph ('#' = ink). Letters are upper case only.
_GLYPHS = {
    "A": "### #.# ### #.# #.#", "B": "##. #.# ##. #.# ##.", "C": ".## #.. #.. #.. .##", "D": "##. #.# #.# #.# ##.",
    "E": "### #.. ##. #.. ###", "F": "### #.. ##. #.. #..", "G": ".## #.. #.# #.# .##", "H": "#.# #.# ### #.# #.#",
    "I": "### .#. .#. .#. ###", "J": "..# ..# ..# #.# .#.", "K": "#.# #.# ##. #.# #.#", "L": "#.. #.. #.. #.. ###",
    "M": "#.# ### ### #.# #.#", "N": "##. #.# #.# #.# #.#", "O": ".#. #.# #.# #.# .#.", "P": "##. #.# ##. #.. #..",
    "Q": ".#. #.# #.# ##. .##", "R": "##. #.# ##. #.# #.#", "S": ".## #.. .#. ..# ##.", "T": "### .#. .#. .#. .#.",
    "U": "#.# #.# #.# #.# ###", "V": "#.# #.# #.# #.# .#.", "W": "#.# #.# ### ### #.#", "X": "#.# #.# .#. #.# #.#",
    "Y": "#.# #.# .#. .#. .#.", "Z": "### ..# .#. #.. ###", "0": "### #.# #.# #.# ###", "1": ".#. ##. .#. .#. ###",
    "2": "##. ..# .#. #.. ###", "3": "##. ..# .#. ..# ##.", "4": "#.# #.# ### ..# ..#", "5": "### #.. ##. ..# ##.",
    "6": ".## #.. ### #.# ###", "7": "### ..# .#. .#. .#.", "8": "### #.# ### #.# ###", "9": "### #.# ### ..# ##.",
    ".": "... ... ... ... .#.", ",": "... ... ... .#. #..", "_": "... ... ... ... ###", "-": "... ... ### ... ...",
    ":": "... .#. ... .#. ...", "=": "... ### ... ### ...", "/": "..# ..# .#. #.. #..", "%": "#.# ..# .#. #.. #.#",
    "(": ".#. #.. #.. #.. .#.", ")": ".#. ..# ..# ..# .#.", "+": "... .#. ### .#. ...", "?": "##. ..# .#. ... .#.",
    " ": "... ... ... ... ...",
}
GLYPH_W, GLYPH_H = 3, 5


def _glyph(ch):
    bits = _GLYPHS.get(ch.upper(), _GLYPHS["?"]).replace(" ", "")
    return np.array([c == "#" for c in bits], dtype=bool).reshape(GLYPH_H, GLYPH_W)


def text_mask(text, scale=2):
    """Boolean [5*scale, 4*scale*len] mask of `text` (one pixel of spacing between glyphs)."""
    if not text:
        return np.zeros((GLYPH_H * scale, 0), dtype=bool)
    cells = [np.pad(_glyph(c), ((0, 0), (0, 1))) for c in text]
    mask = np.concatenate(cells, axis=1)
    return np.kron(mask, np.ones((scale, scale), dtype=bool))


def draw_text(canvas, text, x, y, color=(1.0, 1.0, 1.0), scale=2, max_width=None):
    """Draw `text` into an [H, W, 3] float canvas with its top-left corner at (x, y), clipped to the
    canvas and to `max_width` pixels."""
    mask = text_mask(text, scale)
    h = min(mask.shape[0], canvas.shape[0] - y)
    w = min(mask.shape[1], canvas.shape[1] - x, max_width if max_width is not None else mask.shape[1])
    if h > 0 and w > 0:
        canvas[y:y + h, x:x + w][mask[:h, :w]] = color


def to_display(rgb):
    """Linear radiance -> sRGB-encoded [0, 1] (Blender's Standard view transform, no exposure)."""
    c = np.clip(np.nan_to_num(rgb, nan=0.0, posinf=1.0), 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def heat(values):
    """[0, 1] -> black, red, yellow, white."""
    t = np.clip(values, 0.0, 1.0)[..., None]
    stops = np.array([[0, 0, 0], [0.8, 0.05, 0.05], [1.0, 0.85, 0.1], [1, 1, 1]], dtype=np.float32)
    pos = t * (len(stops) - 1)
    i = np.minimum(pos.astype(int), len(stops) - 2)[..., 0]
    f = pos - i[..., None]
    return stops[i] * (1 - f) + stops[i + 1] * f


def _study_rmse():
    """sphrect.study.metrics.rmse, imported when first needed: the add-on registers without the module."""
    load_sphrect()
    from sphrect.study.metrics import rmse
    return rmse


def _label_lines(entry):
    lines = [f"LIGHTS BY {entry['light_selection']}"] if entry.get("light_selection") else []
    if entry.get("ellipse_technique"):
        lines.append(f"DISKS BY {entry['ellipse_technique']}")
    lines.append(f"{entry.get('samples', '?')} SPP {entry.get('time', 0.0):.2f}S")
    if entry.get("light_time"):
        lines.append(f"LIGHT {entry['light_time']:.2f}S")
    if "rmse" in entry:
        lines.append(f"RMSE {entry['rmse']:.3g}")
    return lines


def comparison_image(entries, reference=None, reference_label="reference", scale=None):
    """The comparison image, [H, W, 3] float in [0, 1] (row 0 = top).

    entries: list of dict(name, image [h, w, >=3] linear, samples, time, light_time) in display order; an entry's
    panel shows its `label` instead of its name if it has one, and a line naming its `light_selection` and one its
    `ellipse_technique` if given.
    reference: [h, w, >=3] linear or None. With a reference, each entry also gets its RMSE (stored back
    in the entry as 'rmse') and a heat map of |image - reference| (mean over RGB) on one scale shared
    by all entries (the 99th percentile of all errors), so the maps compare directly."""
    h, w = entries[0]["image"].shape[:2]
    if scale is None:
        scale = 1 if w < 160 else 2
    errors = []
    if reference is not None:
        rmse = _study_rmse()
        for e in entries:
            e["rmse"] = rmse(e["image"], reference)
            errors.append(np.mean(np.abs(e["image"][..., :3] - reference[..., :3]), axis=-1))
        err_scale = max(float(np.percentile(np.concatenate([x.ravel() for x in errors]), 99)), 1e-12)
    pad = 4 * scale
    line = (GLYPH_H + 2) * scale
    label_h = (1 + max(len(_label_lines(e)) for e in entries)) * line + pad
    columns = [(e.get("label", e["name"]), e["image"]) for e in entries]
    if reference is not None:
        columns.append((reference_label, reference))
    rows = 2 if reference is not None else 1
    canvas_w = pad + len(columns) * (w + pad)
    canvas_h = pad + rows * (h + label_h + pad)
    canvas = np.full((canvas_h, canvas_w, 3), 0.12, dtype=np.float32)
    for col, (name, img) in enumerate(columns):
        x = pad + col * (w + pad)
        y = pad + h + scale
        canvas[pad:pad + h, x:x + w] = to_display(img[..., :3])
        draw_text(canvas, name, x, y, scale=scale, max_width=w + pad // 2)
        if col < len(entries):
            for i, text in enumerate(_label_lines(entries[col])):
                draw_text(canvas, text, x, y + (i + 1) * line, color=(0.8, 0.8, 0.8), scale=scale,
                          max_width=w + pad // 2)
        if reference is not None and col < len(entries):
            y = pad + h + label_h + pad
            canvas[y:y + h, x:x + w] = heat(errors[col] / err_scale)
            draw_text(canvas, "ABS ERROR", x, y + h + scale, scale=scale, max_width=w + pad // 2)
            draw_text(canvas, f"WHITE={err_scale:.2g}", x, y + h + scale + line, color=(0.8, 0.8, 0.8),
                      scale=scale, max_width=w + pad // 2)
    return canvas


def write_png(path, rgb):
    """Write an [H, W, 3] float [0, 1] image (row 0 = top) as an 8-bit PNG, without Blender."""
    data = (np.clip(rgb[..., :3], 0, 1) * 255 + 0.5).astype(np.uint8)
    h, w = data.shape[:2]
    raw = np.concatenate([np.zeros((h, 1), dtype=np.uint8), data.reshape(h, w * 3)], axis=1).tobytes()

    def chunk(kind, payload):
        return (struct.pack(">I", len(payload)) + kind + payload
                + struct.pack(">I", zlib.crc32(kind + payload) & 0xffffffff))

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 1)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(png)
