#!/usr/bin/env python3
"""Light samples per camera sample at equal light-sample budget: MSE against a reference, CPU time and MSE x time for
1, 2 and 4 light samples (budget / light_samples camera samples, so each run shades ~budget light samples per pixel),
rectangle technique (--technique for another), tree selection (--selections to add power) and power-heuristic MIS
(--mis to add others; and --bsdf-on-diffuse false,true for Renderer(bsdf_samples_on_diffuse=...)) at the Renderer's
other defaults.  Then, over all the scenes given, the geometric mean and the worst of each configuration's
MSE x time relative to the best configuration of its scene.

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_light_samples.py out/many_lights/08_disk_room
    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_light_samples.py DIR/*.sphrect.npz --reference-spp 4096

A directory is a finished study's output (its scene.sphrect.npz and images/reference.npy); a scene file gets a
reference rendered here (rectangle, mis power, sobol, 1 light sample, --reference-spp camera samples, all threads;
its own MSE, from two halves, is printed so that it can be compared with the MSEs measured).  MSE is the mean over
two seeds; time is the least CPU time of --repeats renders (one thread), which a shared machine's load disturbs
least."""
import argparse
import math
import os
import time

import numpy as np

import sphrect

LIGHT_SAMPLE_COUNTS = (1, 2, 4)


def load(source, reference_spp):
    if os.path.isdir(source):
        ref = np.load(os.path.join(source, "images", "reference.npy"))[..., :3]
        scene = sphrect.load_scene(os.path.join(source, "scene.sphrect.npz"))
        scene.camera.width, scene.camera.height = ref.shape[1], ref.shape[0]
        return scene, ref
    scene = sphrect.load_scene(source)
    halves = []
    for seed in (1001, 1002):
        r = sphrect.Renderer(scene, techniques=["rectangle"], light_samples=1, seed=seed)
        r.render(max(1, reference_spp // 2))
        halves.append(r.image("rectangle")[..., :3])
    print(f"reference: {reference_spp} spp, its own MSE ~{float(((halves[0] - halves[1]) ** 2).mean()) / 4:.3g}")
    return scene, 0.5 * (halves[0] + halves[1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sources", nargs="+", help="study output directories or .sphrect.npz scenes")
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--budget", type=int, default=64, help="camera samples x light samples per pixel")
    ap.add_argument("--repeats", type=int, default=5, help="renders timed per count (the least time is kept)")
    ap.add_argument("--selections", default="tree", help=f"comma list of {','.join(sphrect.light_selections)}")
    ap.add_argument("--mis", default="power", help=f"comma list of {','.join(sphrect.mis_modes)}")
    ap.add_argument("--bsdf-on-diffuse", default="false", help="comma list of false, true")
    ap.add_argument("--technique", default="rectangle", help=f"one of {','.join(sphrect.techniques)}")
    ap.add_argument("--light-samples", default=",".join(map(str, LIGHT_SAMPLE_COUNTS)),
                    help="comma list of light samples per camera sample")
    a = ap.parse_args()
    counts = [int(v) for v in a.light_samples.split(",")]
    flags = [{"false": False, "true": True}[v.strip().lower()] for v in a.bsdf_on_diffuse.split(",")]
    configs = [(s, m, b) for s in a.selections.split(",") for m in a.mis.split(",") for b in flags
               if m != "none" or b == flags[0]]  # without MIS the flag changes nothing
    relative = {(s, m, b, n): [] for s, m, b in configs for n in counts}
    for source in a.sources:
        print(f"== {source}")
        scene, ref = load(source, a.reference_spp)
        print(f"{'light samples':>13} {'selection':9} {'mis':6} {'diffuse':7} {'spp':>4} {'MSE':>10} {'time s':>7} "
              f"{'MSE x time':>11}")
        products = {}
        for selection, mis, on_diffuse in configs:
            for light_samples in counts:
                spp = max(1, a.budget // light_samples)
                mses, times = [], []
                for seed in range(max(2, a.repeats)):
                    r = sphrect.Renderer(scene, techniques=[a.technique], light_samples=light_samples,
                                         light_selection=selection, mis=mis, bsdf_samples_on_diffuse=on_diffuse,
                                         seed=11 + seed, threads=1)
                    start = time.process_time()
                    r.render(spp)
                    times.append(time.process_time() - start)
                    if seed < 2:
                        mses.append(float(((r.image(a.technique)[..., :3] - ref) ** 2).mean()))
                m, t = float(np.mean(mses)), min(times)
                products[selection, mis, on_diffuse, light_samples] = m * t
                print(f"{light_samples:>13} {selection:9} {mis:6} {'bsdf' if on_diffuse else 'alone':7} {spp:>4} "
                      f"{m:>10.3g} {t:>7.3f} {m * t:>11.3g}", flush=True)
        best = min(products.values())
        for key, p in products.items():
            relative[key].append(p / best)
    print("MSE x time relative to each scene's best configuration: geometric mean (worst)")
    for (selection, mis, on_diffuse, n), values in relative.items():
        geo = math.exp(sum(math.log(v) for v in values) / len(values))
        diffuse = "" if mis == "none" else (", BSDF samples on diffuse" if on_diffuse else ", light alone on diffuse")
        print(f"  {selection:6s} mis {mis}{diffuse}, {n} light samples: {geo:.2f} ({max(values):.2f})")


if __name__ == "__main__":
    main()
