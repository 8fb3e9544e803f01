#!/usr/bin/env python3
"""Light samples per camera sample at equal camera-sample budget: MSE against a study's reference, CPU time and
MSE x time for 1, 2 and 4 light samples (64 / light_samples camera samples, so each run shades ~64 light samples
per pixel), both light selections, two seeds, rectangle technique at the Renderer's other defaults.

    PYTHONPATH=build/python /usr/bin/python3 scripts/measure_light_samples.py out/many_lights/08_disk_room
    PYTHONPATH=build/python /usr/bin/python3 scripts/measure_light_samples.py scene.sphrect.npz --reference-spp 4096

A directory is a finished study's output (its scene.sphrect.npz and images/reference.npy); a scene file gets a
reference rendered here (rectangle, mis power, sobol, 1 light sample, --reference-spp camera samples, all threads;
its own MSE, from two halves, is printed so that it can be compared with the MSEs measured)."""
import argparse
import os

import numpy as np

import sphrect


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", help="a study's output directory or a .sphrect.npz scene")
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--budget", type=int, default=64, help="camera samples x light samples per pixel")
    a = ap.parse_args()
    if os.path.isdir(a.source):
        ref = np.load(os.path.join(a.source, "images", "reference.npy"))[..., :3]
        scene = sphrect.load_scene(os.path.join(a.source, "scene.sphrect.npz"))
        scene.camera.width, scene.camera.height = ref.shape[1], ref.shape[0]
    else:
        scene = sphrect.load_scene(a.source)
        halves = []
        for seed in (1001, 1002):
            r = sphrect.Renderer(scene, techniques=["rectangle"], light_samples=1, seed=seed)
            r.render(max(1, a.reference_spp // 2))
            halves.append(r.image("rectangle")[..., :3])
        ref = 0.5 * (halves[0] + halves[1])
        print(f"reference: {a.reference_spp} spp, its own MSE ~{float(((halves[0] - halves[1]) ** 2).mean()) / 4:.3g}")
    print(f"{'light samples':>13} {'selection':9} {'spp':>4} {'MSE':>10} {'time s':>7} {'MSE x time':>11}")
    for light_samples in (1, 2, 4):
        for selection in sphrect.light_selections:
            spp = max(1, a.budget // light_samples)
            mses, times = [], []
            for seed in (11, 12):
                r = sphrect.Renderer(scene, techniques=["rectangle"], light_samples=light_samples,
                                     light_selection=selection, seed=seed, threads=1)
                r.render(spp)
                st = r.stats("rectangle")
                mses.append(float(((r.image("rectangle")[..., :3] - ref) ** 2).mean()))
                times.append(st["shading_time"] + st["camera_time"])
            m, t = np.mean(mses), np.mean(times)
            print(f"{light_samples:>13} {selection:9} {spp:>4} {m:>10.3g} {t:>7.3f} {m * t:>11.3g}")


if __name__ == "__main__":
    main()
