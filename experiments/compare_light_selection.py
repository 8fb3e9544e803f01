"""Power vs light-tree selection on the multi-light blend_scenes, at the Renderer's other defaults
(rectangle, MIS power, sobol, 4 light samples), lights hidden from the camera, and Cycles 3.4 as the peer
(direct light only): relative variance at equal samples (two seeds, experiments/measure_light_selection.py's
measure), CPU time per render (one thread) and variance x time relative to Cycles (below 1/3: we reach
Cycles' error in less than a third of its time).

    PYTHONPATH=build/python python3 experiments/compare_light_selection.py --out /tmp/cmp [--scenes 07_studio ...]
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import sphrect  # noqa: E402
from measure_light_selection import SEEDS, measure_cycles, relative_variance, blend_file, scene_file  # noqa: E402


def measure(scene, samples, light_selection):
    images, time = [], 0.0
    for seed in SEEDS:
        r = sphrect.Renderer(scene, techniques=["rectangle"], seed=seed, threads=1, light_selection=light_selection)
        r.render(samples)
        s = r.stats("rectangle")
        images.append(r.image("rectangle"))
        time += s["shading_time"] + s["camera_time"]
    return relative_variance(*images), time / len(SEEDS)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", nargs="*", default=["07_studio", "08_disk_room", "09_hall", "10_night_street"])
    ap.add_argument("--resolution", default="96x72")
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--no-cycles", action="store_true")
    a = ap.parse_args()
    resolution = tuple(int(x) for x in a.resolution.split("x"))
    print(f"{'scene':16} {'selection':9} {'variance':>10} {'time s':>8} {'var x time / Cycles':>20}")
    for name in a.scenes:
        scene = sphrect.load_scene(scene_file(a.out, name, resolution))
        cycles = None if a.no_cycles else measure_cycles(blend_file(a.out, name), a.samples, resolution)
        if cycles:
            print(f"{name:16} {'cycles':9} {cycles['variance']:10.4g} {cycles['time']:8.3f} {1.0:20.3f}")
        for selection in sphrect.light_selections:
            v, t = measure(scene, a.samples, selection)
            rel = f"{v * t / (cycles['variance'] * cycles['time']):20.3f}" if cycles else ""
            print(f"{name:16} {selection:9} {v:10.4g} {t:8.3f} {rel}", flush=True)


if __name__ == "__main__":
    main()
