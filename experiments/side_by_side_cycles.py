#!/usr/bin/env python3
"""SPHRECT and Cycles 3.4 side by side on .blend files: each exported by the add-on and rendered by both (Cycles in
the study's direct-light settings), one row per file -- ours, Cycles', and their difference -- with the image totals'
ratio and the mean relative difference over lit 4 x 4-pixel blocks (the parity tests' measure) in the row's title.

    PYTHONPATH=build/python /usr/bin/python3 experiments/side_by_side_cycles.py --out out/side_by_side \\
        --samples 256 --cycles-samples 1024 --resolution 160x90 A.blend B.blend:clay ...

A file named with ":clay" is compared as a clay render: a copy in which every material without emission is a grey
Diffuse BSDF (0.8) in both renders (lights, emitters, world, camera, visibility as authored), which sets apart
what the lights and the world do from material features SPHRECT does not model. --reuse takes the rows already in
OUT (NAME.sphrect.npy, NAME.cycles.npy, NAME.json) instead of rendering them again, to redraw a figure.

Writes OUT/side_by_side.png, OUT/side_by_side.json (the figures) and each file's images as NAME.sphrect.npy and
NAME.cycles.npy (linear float [H, W, 4], row 0 at the top)."""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

import sphrect
from sphrect.study.cycles import export_blend, find_blender, render_cycles

HERE = os.path.dirname(os.path.abspath(__file__))
HEADLESS = os.path.join(os.path.dirname(HERE), "addon", "sphrect_blender", "headless.py")
BLOCK = 4
CLAY = """
import bpy, sys
def emissive(mat):
    if mat is None or not mat.use_nodes or mat.node_tree is None:
        return False
    for node in mat.node_tree.nodes:
        if node.type == "EMISSION" and (node.inputs["Strength"].is_linked or node.inputs["Strength"].default_value > 0):
            return True
        if node.type == "BSDF_PRINCIPLED" and node.inputs["Emission Strength"].default_value > 0 and (
                node.inputs["Emission"].is_linked or any(node.inputs["Emission"].default_value[:3])):
            return True
    return False
clay = bpy.data.materials.new("clay")
clay.use_nodes = True
nodes = clay.node_tree.nodes
nodes.clear()
diffuse = nodes.new("ShaderNodeBsdfDiffuse")
diffuse.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
diffuse.inputs["Roughness"].default_value = 0.0
out = nodes.new("ShaderNodeOutputMaterial")
clay.node_tree.links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
for obj in bpy.data.objects:
    for slot in obj.material_slots:
        if not emissive(slot.material):
            slot.material = clay
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[-1], compress=True, copy=True)
"""


def clay_copy(blend, path):
    """Write to `path` a copy of `blend` whose materials without emission are a grey Diffuse BSDF (CLAY)."""
    subprocess.run([find_blender(), "-b", "--factory-startup", blend, "--python-exit-code", "1", "--python-expr",
                    CLAY, "--", path], check=True, capture_output=True, timeout=600)


def block_difference(ours, cycles, lit_fraction=0.05):
    """Mean |ours - cycles| / cycles over the 4 x 4 blocks whose Cycles mean exceeds lit_fraction x the image's."""
    h, w = (s - s % BLOCK for s in cycles.shape[:2])

    def blocks(image):
        lum = image[:h, :w, :3].astype(np.float64).mean(axis=2)
        return lum.reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).mean(axis=(1, 3))
    a, b = blocks(ours), blocks(cycles)
    lit = b > lit_fraction * b.mean()
    return float(np.mean(np.abs(a[lit] - b[lit]) / b[lit]))


def display(image, scale):
    return np.clip(image[..., :3] / scale, 0, 1) ** (1 / 2.2)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("blends", nargs="+")
    ap.add_argument("--out", required=True)
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--cycles-samples", type=int, default=1024)
    ap.add_argument("--resolution", default="160x90")
    ap.add_argument("--reuse", action="store_true", help="take the rows already rendered in OUT")
    ap.add_argument("--technique", default="rectangle", choices=sphrect.techniques, help="our light technique")
    a = ap.parse_args()
    width, height = (int(x) for x in a.resolution.split("x"))
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for blend in a.blends:
        clay = blend.endswith(":clay")
        blend = blend[:-len(":clay")] if clay else blend
        name = os.path.splitext(os.path.basename(blend))[0] + (" (clay)" if clay else "")
        files = {k: os.path.join(a.out, name + k) for k in (".sphrect.npz", ".sphrect.npy", ".cycles.npy", ".json")}
        if a.reuse and all(os.path.exists(f) for f in files.values()):
            ours, cycles = np.load(files[".sphrect.npy"]), np.load(files[".cycles.npy"])
            with open(files[".json"]) as f:
                warnings = json.load(f)["warnings"]
        else:
            with tempfile.TemporaryDirectory() as tmp:
                if clay:
                    clay_copy(blend, os.path.join(tmp, "clay.blend"))
                    blend = os.path.join(tmp, "clay.blend")
                warnings = export_blend(blend, files[".sphrect.npz"], (width, height), blender_script=HEADLESS)
                try:
                    renderer = sphrect.Renderer(sphrect.load_scene(files[".sphrect.npz"]), techniques=[a.technique],
                                                seed=1)
                except ValueError as e:  # a scene SPHRECT cannot render (nothing it draws): said, the next file
                    print(f"{name:40} not rendered: {e}  warnings: {warnings or 'none'}", flush=True)
                    continue
                renderer.render(a.samples)
                ours = renderer.image(a.technique)
                cycles, _ = render_cycles(blend, a.cycles_samples, width, height, seed=1, threads=2,
                                          blender_script=HEADLESS)
            np.save(files[".sphrect.npy"], ours)
            np.save(files[".cycles.npy"], cycles)
            with open(files[".json"], "w") as f:
                json.dump({"warnings": warnings}, f)
        total = float(ours[..., :3].sum() / cycles[..., :3].sum())
        rows.append({"name": name, "block_difference": block_difference(ours, cycles), "total_ratio": total,
                     "warnings": warnings, "ours": ours, "cycles": cycles})
        print(f"{name:40} blocks {100 * rows[-1]['block_difference']:.2f}%  totals {total:.4f}  "
              f"warnings: {warnings or 'none'}", flush=True)
    if not rows:
        return 1
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(rows), 3, figsize=(9, 1.9 * len(rows) * height / width * 1.7 + 0.3),
                             squeeze=False)
    for r, ax in zip(rows, axes):
        scale = np.percentile(r["cycles"][..., :3], 99.5) or 1.0
        diff = np.abs(r["ours"][..., :3] - r["cycles"][..., :3]).mean(axis=2)
        panels = [(display(r["ours"], scale), "SPHRECT"), (display(r["cycles"], scale), "Cycles 3.4"),
                  (np.clip(4 * diff / scale, 0, 1), "|difference| x 4")]
        for a_, (img, label) in zip(ax, panels):
            a_.imshow(img, cmap="magma" if img.ndim == 2 else None, vmin=0, vmax=1)
            a_.set_xticks([])
            a_.set_yticks([])
            a_.set_title(label, fontsize=8)
        ax[0].set_ylabel(r["name"], fontsize=7)
        ax[2].set_title(f"|difference| x 4: blocks {100 * r['block_difference']:.2f}%, totals {r['total_ratio']:.3f}",
                        fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "side_by_side.png"), dpi=110)
    with open(os.path.join(a.out, "side_by_side.json"), "w") as f:
        json.dump([{k: v for k, v in r.items() if k not in ("ours", "cycles")} for r in rows], f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
