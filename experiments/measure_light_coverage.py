#!/usr/bin/env python3
"""What the analytic coverage of lights seen by the camera (Renderer(analytic_light_coverage=...)) buys:
per scene file, RMSE at equal samples with and without it against one reference rendered without it,
and the CPU time per render (one thread; the machine's noise applies).

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_light_coverage.py out/many_lights/*/scene.sphrect.npz
    ... --pixel-filter blackman_harris:1.5     # the scenes' camera with another pixel filter (name:width)

(The study writes each scene's scene.sphrect.npz into its output folder.)"""
import argparse
import time

import numpy as np

import sphrect


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+", help=".sphrect.npz scene files")
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--reference-samples", type=int, default=1024)
    ap.add_argument("--pixel-filter", metavar="NAME:WIDTH", help=f"one of {', '.join(sphrect.pixel_filters)}")
    a = ap.parse_args()
    for path in a.scenes:
        scene = sphrect.load_scene(path)
        if a.pixel_filter:
            name, _, width = a.pixel_filter.partition(":")
            scene.camera.pixel_filter, scene.camera.filter_width = name, float(width or 1)
        ref = sphrect.Renderer(scene, seed=999, threads=0, analytic_light_coverage=False)
        ref.render(a.reference_samples)
        reference = ref.image()[..., :3].astype(np.float64)
        line = [path]
        for coverage in (False, True):
            mse, secs = [], []
            for seed in range(a.seeds):
                r = sphrect.Renderer(scene, seed=seed, threads=1, analytic_light_coverage=coverage)
                t = time.process_time()
                r.render(a.samples)
                secs.append(time.process_time() - t)
                mse.append(np.mean((r.image()[..., :3] - reference) ** 2))
            line.append(f"coverage={coverage}: RMSE {np.mean(mse) ** 0.5:.4g}, {np.median(secs):.3f} s/render")
        print("  ".join(line), flush=True)


if __name__ == "__main__":
    main()
