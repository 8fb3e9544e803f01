#!/usr/bin/env python3
"""Variance at equal samples on the blend_scenes: sphrect (every technique x MIS x pattern, light samples) and
Cycles 3.4, for issue 11's stratified light selection and the defaults.

    # 1. our renderer (run once per build; --label names the build's results):
    PYTHONPATH=BUILD/python /usr/bin/python3 experiments/measure_light_selection.py --out out/lightsel --label after
    PYTHONPATH=OLD_BUILD/python /usr/bin/python3 experiments/measure_light_selection.py \\
        --out out/lightsel --label before --scenes 07_studio 08_disk_room --mis balance --patterns sobol
    # 2. Cycles 3.4 (direct light only, as the study's peer):
    PYTHONPATH=BUILD/python /usr/bin/python3 experiments/measure_light_selection.py --out out/lightsel --cycles
    # 3. the tables (reads every <label>.json and cycles.json in --out):
    PYTHONPATH=BUILD/python /usr/bin/python3 experiments/measure_light_selection.py --out out/lightsel --report

Variance: two renders of different seeds a, b at the same samples; Var = mean over pixels and RGB of
(a - b)^2 / 2 (each pixel's variance, unbiased, no reference needed), divided by the mean of ((a + b) / 2)^2:
the relative variance, comparable between renderers whose images agree (Cycles and sphrect to ~1 %) and
between scenes.  Seeds 1 and 2 in both renderers.  Lights are hidden from the camera (blend_file), and the
scenes are exported once (cached in OUT/scenes) so every build renders the same scene files.  The light-samples
table is at equal time: variance x CPU time per pixel (the technique's shading and light time plus its share of the
camera rays)."""
import argparse
import glob
import itertools
import json
import math
import os
import subprocess
import sys

import numpy as np

import sphrect

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
BLEND_DIR = os.path.join(REPO, "blend_scenes")
HEADLESS = os.path.join(REPO, "addon", "sphrect_blender", "headless.py")
SEEDS = (1, 2)


def relative_variance(a: np.ndarray, b: np.ndarray) -> float:
    a, b = a[..., :3].astype(np.float64), b[..., :3].astype(np.float64)
    return float(np.mean((a - b) ** 2) / 2 / np.mean(((a + b) / 2) ** 2))


def blend_file(out: str, name: str) -> str:
    """The scene's .blend with its lights hidden from the camera (cached: OUT/scenes/NAME.blend): the variance
    measured is the lighting's, not that of the pixels a bright light's edge crosses (the same for every
    configuration, and in a room with visible ceiling lights most of the image's variance)."""
    from sphrect.study.cycles import find_blender
    path = os.path.abspath(os.path.join(out, "scenes", name + ".blend"))
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        hide = ("import bpy\nfor o in bpy.data.objects:\n    if o.type == 'LIGHT': o.visible_camera = False\n"
                f"bpy.ops.wm.save_as_mainfile(filepath={path!r}, compress=True)")
        subprocess.run([find_blender(), "-b", "--factory-startup", os.path.join(BLEND_DIR, name + ".blend"),
                        "--python-exit-code", "1", "--python-expr", hide], check=True, capture_output=True)
    return path


def scene_file(out: str, name: str, resolution, blender_script=HEADLESS) -> str:
    """The exported scene (cached): OUT/scenes/NAME_WxH.sphrect.npz."""
    from sphrect.study.cycles import export_blend
    path = os.path.join(out, "scenes", f"{name}_{resolution[0]}x{resolution[1]}.sphrect.npz")
    if not os.path.exists(path):
        export_blend(blend_file(out, name), path, resolution, blender_script=blender_script)
    return path


def measure_sphrect(scene, samples, mis_modes, patterns, light_samples, passes=1):
    """{(mis, pattern, light_samples, technique): {"variance", "time"}} for all techniques at once."""
    out = {}
    techniques = list(sphrect.techniques)
    for mis, pattern, ls in itertools.product(mis_modes, patterns, light_samples):
        images, times = {t: [] for t in techniques}, {t: 0.0 for t in techniques}
        for seed in SEEDS:
            r = sphrect.Renderer(scene, techniques=techniques, mis=mis, pattern=pattern, light_samples=ls, seed=seed,
                                 threads=1)
            for _ in range(passes):  # progressive passes, as the add-on renders (its "Progressive Passes")
                r.render(samples // passes)
            for t in techniques:
                s = r.stats(t)
                images[t].append(r.image(t))
                times[t] += s["shading_time"] + s["camera_time"] / len(techniques)
        for t in techniques:
            out[f"{mis}/{pattern}/{ls}/{t}"] = {"variance": relative_variance(*images[t]),
                                                "time": times[t] / len(SEEDS)}
    return out


def measure_cycles(blend, samples, resolution, blender_script=HEADLESS):
    from sphrect.study.cycles import render_cycles
    images, times = [], []
    for seed in SEEDS:
        image, timing = render_cycles(blend, samples, resolution[0], resolution[1], seed=seed, threads=1,
                                      blender_script=blender_script)
        images.append(image)
        times.append(timing["cpu_time"])
    return {"variance": relative_variance(*images), "time": float(np.mean(times))}


def load(path):
    with open(path) as f:
        return json.load(f)


def save(path, data):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
    os.replace(tmp, path)


def geomean(values):
    values = [v for v in values if v > 0 and math.isfinite(v)]
    return math.exp(sum(map(math.log, values)) / len(values)) if values else float("nan")


def report(out):
    runs = {os.path.basename(p)[:-5]: load(p) for p in sorted(glob.glob(os.path.join(out, "*.json")))}
    cycles = runs.pop("cycles", {})
    techniques = list(sphrect.techniques)
    for label, data in runs.items():
        print(f"\n## {label}: relative variance at {data['samples']} spp in {data.get('passes', 1)} pass(es), "
              f"{data['resolution']}, seeds {SEEDS}")
        for scene, res in data["scenes"].items():
            keys = sorted({k.rsplit("/", 1)[0] for k in res})
            print(f"\n{scene}\n| MIS/pattern/light samples | " + " | ".join(techniques) + " |")
            print("|---" * (len(techniques) + 1) + "|")
            for k in keys:
                print(f"| {k} | " + " | ".join(f"{res[k + '/' + t]['variance']:.3g}" for t in techniques) + " |")
        # MIS x pattern at one light sample: geometric mean over scenes and techniques of the variance relative
        # to each (scene, technique)'s best configuration.
        configs = sorted({k.rsplit("/", 1)[0] for res in data["scenes"].values() for k in res if "/1/" in k + "/"})
        configs = [c for c in configs if c.endswith("/1")]
        if len(configs) > 1:
            print(f"\n{label}: variance / best configuration of the (scene, technique), geometric mean "
                  f"(and worst) over {len(data['scenes'])} scenes x {len(techniques)} techniques, 1 light sample")
            print("| MIS/pattern | geomean | worst |\n|---|---|---|")
            rows = []
            for c in configs:
                ratios = []
                for scene, res in data["scenes"].items():
                    for t in techniques:
                        best = min(res[k + "/" + t]["variance"] for k in configs if k + "/" + t in res)
                        if c + "/" + t in res:
                            ratios.append(res[c + "/" + t]["variance"] / best)
                rows.append((geomean(ratios), max(ratios), c))
            for g, w, c in sorted(rows):
                print(f"| {c} | {g:.3g} | {w:.3g} |")
        ls_values = sorted({int(k.split("/")[2]) for res in data["scenes"].values() for k in res})
        if len(ls_values) > 1:
            print(f"\n{label}: light samples, variance x time relative to 1 light sample (geomean over scenes and "
                  f"techniques; < 1: more efficient)")
            for mp in sorted({k.rsplit("/", 2)[0] for res in data["scenes"].values() for k in res}):
                cells = []
                for ls in ls_values:
                    ratios = [res[f"{mp}/{ls}/{t}"]["variance"] * res[f"{mp}/{ls}/{t}"]["time"] /
                              (res[f"{mp}/1/{t}"]["variance"] * res[f"{mp}/1/{t}"]["time"])
                              for res in data["scenes"].values() for t in techniques
                              if f"{mp}/{ls}/{t}" in res and f"{mp}/1/{t}" in res]
                    cells.append(f"{ls}: {geomean(ratios):.3g}" if ratios else f"{ls}: -")
                print(f"| {mp} | " + " | ".join(cells) + " |")
    # Before / after and Cycles, per scene and technique, at the configurations both builds measured.
    for scene in sorted({s for d in runs.values() for s in d["scenes"]}):
        # One pass, one light sample: the builds measured alike ("after", "before"), or whatever label there is.
        labels = [l for l in ("after", "before") if l in runs] or list(runs)
        have = {l: runs[l]["scenes"][scene] for l in labels if scene in runs[l]["scenes"]}
        common = set.intersection(*(set(r) for r in have.values()))
        cyc = cycles.get(scene)
        if not common or (len(have) < 2 and not cyc):
            continue
        print(f"\n{scene}: relative variance" + (f"; Cycles 3.4 {cyc['variance']:.3g}" if cyc else ""))
        labels = list(have)
        head = " | ".join(labels) + (" | " + " | ".join(f"{l} / Cycles" for l in labels) if cyc else "")
        if len(labels) == 2:
            head += f" | {labels[0]} / {labels[1]}"
        print(f"| configuration | {head} |\n" + "|---" * (1 + head.count("|") + 1) + "|")
        for k in sorted(common):
            v = [have[l][k]["variance"] for l in labels]
            cells = [f"{x:.3g}" for x in v]
            if cyc:
                cells += [f"{x / cyc['variance']:.3g}" for x in v]
            if len(labels) == 2:
                cells.append(f"{v[0] / v[1]:.3g}")
            print(f"| {k} | " + " | ".join(cells) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--label", help="measure this build's sphrect and store it as OUT/LABEL.json")
    ap.add_argument("--cycles", action="store_true", help="measure Cycles 3.4 (OUT/cycles.json)")
    ap.add_argument("--report", action="store_true", help="print the tables from OUT/*.json")
    ap.add_argument("--scenes", nargs="*",
                    default=sorted(os.path.basename(p)[:-6] for p in glob.glob(os.path.join(BLEND_DIR, "*.blend"))))
    ap.add_argument("--resolution", default="96x72")
    ap.add_argument("--blender-script", default=HEADLESS, help="the add-on's headless.py for export and Cycles")
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--mis", nargs="*", default=list(sphrect.mis_modes))
    ap.add_argument("--patterns", nargs="*", default=list(sphrect.patterns))
    ap.add_argument("--passes", type=int, default=1, help="render the samples in this many progressive passes")
    ap.add_argument("--light-samples", nargs="*", type=int, default=[1],
                    help="light samples per camera sample (measured with every --mis and --patterns)")
    args = ap.parse_args()
    resolution = tuple(int(x) for x in args.resolution.split("x"))
    os.makedirs(args.out, exist_ok=True)
    if args.label:
        path = os.path.join(args.out, args.label + ".json")
        data = load(path) if os.path.exists(path) else {"samples": args.samples, "resolution": args.resolution,
                                                        "passes": args.passes, "scenes": {}}
        for name in args.scenes:
            scene = sphrect.load_scene(scene_file(args.out, name, resolution, args.blender_script))
            res = measure_sphrect(scene, args.samples, args.mis, args.patterns, args.light_samples, args.passes)
            data["scenes"].setdefault(name, {}).update(res)
            save(path, data)
            print(f"{args.label}: {name} done", file=sys.stderr)
    if args.cycles:
        path = os.path.join(args.out, "cycles.json")
        data = load(path) if os.path.exists(path) else {}
        for name in args.scenes:
            data[name] = measure_cycles(blend_file(args.out, name), args.samples, resolution,
                                        args.blender_script)
            save(path, data)
            print(f"cycles: {name} {data[name]}", file=sys.stderr)
    if args.report:
        report(args.out)


if __name__ == "__main__":
    main()
