#!/usr/bin/env python3
"""Light selection "ris" against "tree": relative variance at equal samples and time per sample for ris_candidates
M in 1..32, on synthetic many-light scenes (docs/light_selection_ris.md).

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_ris_candidates.py [--samples 16] [--lights 2000]

Scenes: a 12 m floor seen from above at an angle, four boxes on it, lit by --lights small rectangles (random sizes
4-12 cm, heights 0.3-2.3 m, tilts and colours; a third two-sided), the floor "diffuse" (grey Lambert) or "glossy"
(metallic GGX, roughness 0.25); and "four", the diffuse floor under four rectangles of different sizes and powers.
Variance: two renders of seeds 1 and 2; mean over pixels and RGB of (a - b)^2 / 2 over the mean of ((a + b) / 2)^2
(as measure_light_selection.py).  Time: the render's wall time with one thread, per camera sample.  Efficiency:
1 / (variance x time), relative to the tree's."""
import argparse

import numpy as np

import sphrect

BOXES = [((-3, -2, 0), (-2, -1, 0.8)), ((1, -3, 0), (2.5, -1.5, 0.5)), ((-1, 2, 0), (0, 3, 1.0)),
         ((2, 1, 0), (3, 2.5, 0.6))]


def box_mesh(lo, hi, name):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], np.float32)
    t = np.array([[4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6],
                  [3, 0, 4], [3, 4, 7]], np.int32)
    return sphrect.Mesh(vertices=v, triangles=t, name=name)


def scene(kind: str, lights: int, width: int) -> sphrect.Scene:
    rng = np.random.default_rng(17)
    floor = np.array([[-6, -6, 0], [6, -6, 0], [6, 6, 0], [-6, 6, 0]], np.float32)
    meshes = [sphrect.Mesh(vertices=floor, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name="floor")]
    meshes += [box_mesh(lo, hi, f"box{i}") for i, (lo, hi) in enumerate(BOXES)]
    if kind == "glossy":
        floor_material = sphrect.Material(kind="glossy", base_color=(0.8, 0.8, 0.8), roughness=0.25, metallic=1.0)
    else:
        floor_material = sphrect.Material(base_color=(0.6, 0.6, 0.6))
    if kind == "four":
        rects = [((-2, -1, 1.5), 1.0, 4.0), ((1, 1, 2.5), 0.4, 40.0), ((0.5, -2, 0.8), 0.2, 60.0),
                 ((-1, 2, 2.0), 1.5, 1.5)]
        ls = [sphrect.RectLight(corner=c, edge_x=(0, s, 0), edge_y=(s, 0, 0), radiance=(r, r, r), visible=False)
              for c, s, r in rects]
    else:
        ls = []
        for i in range(lights):
            c = (-5 + 10 * rng.random(), -5 + 10 * rng.random(), 0.3 + 2 * rng.random())
            s = 0.08 * (0.5 + rng.random())
            tilt = rng.random() - 0.5
            radiance = tuple(float(x) for x in (0.2 + rng.random(3)) * 2000.0 / lights / 0.0064)
            ls.append(sphrect.RectLight(corner=c, edge_x=(0, s, s * tilt), edge_y=(s, 0, 0), radiance=radiance,
                                        two_sided=i % 3 == 0, visible=False))
    camera = sphrect.Camera(width=width, height=width * 3 // 4,
                            to_world=[[1, 0, 0, 0], [0, 0.8, -0.6, -9], [0, 0.6, 0.8, 8], [0, 0, 0, 1]])
    return sphrect.Scene(camera=camera, meshes=meshes, lights=ls,
                         materials=[floor_material, sphrect.Material(base_color=(0.5, 0.5, 0.5))])


def measure(sc, samples, **kw):
    images, seconds = [], 0.0
    for seed in (1, 2):
        r = sphrect.Renderer(sc, techniques=["rectangle"], seed=seed, threads=1, **kw)
        assert r.render(samples)
        images.append(r.image()[..., :3].astype(np.float64))
        seconds += r.stats()["wall_time"]
    a, b = images
    variance = float(np.mean((a - b) ** 2) / 2 / np.mean(((a + b) / 2) ** 2))
    pixels = a.shape[0] * a.shape[1]
    return variance, seconds / 2 / (pixels * samples)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--lights", type=int, default=2000)
    p.add_argument("--width", type=int, default=96)
    p.add_argument("--scenes", nargs="+", default=["diffuse", "glossy", "four"])
    p.add_argument("--candidates", type=int, nargs="+", default=[1, 2, 4, 8, 16, 32])
    p.add_argument("--mis", nargs="+", default=["power", "none"])
    args = p.parse_args()
    print("| scene | mis | selection | M | rel. variance | us / sample | variance / tree's | efficiency / tree's |")
    print("|---|---|---|---|---|---|---|---|")
    for kind in args.scenes:
        sc = scene(kind, args.lights, args.width)
        for mis in args.mis:
            tree_var, tree_time = measure(sc, args.samples, mis=mis, light_selection="tree")
            print(f"| {kind} | {mis} | tree | | {tree_var:.4g} | {tree_time * 1e6:.2f} | 1 | 1 |", flush=True)
            for m in args.candidates:
                var, t = measure(sc, args.samples, mis=mis, light_selection="ris", ris_candidates=m)
                print(f"| {kind} | {mis} | ris | {m} | {var:.4g} | {t * 1e6:.2f} | {var / tree_var:.3f} | "
                      f"{tree_var * tree_time / (var * t):.2f} |", flush=True)


if __name__ == "__main__":
    main()
