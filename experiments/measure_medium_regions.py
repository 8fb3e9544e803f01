#!/usr/bin/env python3
"""Where in the image each medium sampling wins: the MSE of each of sphrect.medium_samplings against a finished
study's reference, split into discs around the lights' projections (point and spot positions, rectangle and disk
centres) and the rest of the image, and each region's efficiency (1 / (MSE x CPU time per sample)) of every medium
sampling relative to distance sampling.

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_medium_regions.py out/fog_stage [--samples 32]

The directory is a finished study's output (its scene.sphrect.npz and images/reference.npy, the scene at the
study's resolution).  Each medium sampling renders --replicates seeds x --samples spp (rectangle technique, MIS
power, Sobol, one thread); MSE is the mean over them, the cost per sample the least CPU time over the replicates
(the one a shared machine's load disturbs least) / samples.  A light's disc has radius --radius pixels; discs
that overlap give their pixels to the first light.  --without NAME leaves that mesh out of the scene (e.g. the pole
that hides 15_fog_stage's lamp) and renders a reference here instead (--reference-spp, all threads, the Renderer's
default medium sampling); its own RMSE, from two halves, is printed."""
import argparse
import math
import os
import time

import numpy as np

import sphrect


def light_point(light):
    """The point a light's disc is drawn around."""
    if isinstance(light, sphrect.RectLight):
        return np.add(light.corner, np.multiply(0.5, np.add(light.edge_x, light.edge_y)))
    if isinstance(light, sphrect.EllipseLight):
        return np.asarray(light.center, float)
    return np.asarray(light.position, float)


def project(camera, point):
    """Pixel (column, row) of a world point seen by a perspective camera (Blender's: looks down -Z, sensor fit
    AUTO), or None when it is behind the camera."""
    to_world = np.asarray(camera.to_world, float)
    p = np.linalg.inv(to_world) @ np.append(point, 1.0)
    if p[2] >= 0:
        return None
    w, h = camera.width, camera.height
    scale = camera.lens / camera.sensor_width * max(w, h)  # pixels per unit of image-plane distance
    return w / 2 + scale * p[0] / -p[2], h / 2 - scale * p[1] / -p[2]


def regions(scene, radius):
    """Name -> boolean mask [H, W]: a disc around each light in the frame, then the rest."""
    h, w = scene.camera.height, scene.camera.width
    rows, cols = np.mgrid[0:h, 0:w] + 0.5
    taken = np.zeros((h, w), bool)
    out = {}
    for light in scene.lights:
        at = project(scene.camera, light_point(light))
        if at is None or not (0 <= at[0] < w and 0 <= at[1] < h):
            continue
        disc = ((cols - at[0]) ** 2 + (rows - at[1]) ** 2 <= radius ** 2) & ~taken
        out[f"{type(light).__name__} {light.name} (px {at[0]:.0f}, {at[1]:.0f})"] = disc
        taken |= disc
    out["rest of the image"] = ~taken
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("study", help="a finished study's output directory")
    p.add_argument("--samples", type=int, default=32)
    p.add_argument("--replicates", type=int, default=8)
    p.add_argument("--radius", type=float, default=8.0, help="pixels")
    p.add_argument("--without", action="append", default=[], help="leave out the mesh of this name (repeatable)")
    p.add_argument("--reference-spp", type=int, default=4096, help="with --without: the reference's samples")
    args = p.parse_args()
    scene = sphrect.load_scene(os.path.join(args.study, "scene.sphrect.npz"))
    if args.without:
        scene.meshes = [m for m in scene.meshes if m.name not in args.without]
        halves = []
        for seed in (1, 2):
            r = sphrect.Renderer(scene, techniques=["rectangle"], mis="power", pattern="sobol", seed=seed, threads=0)
            r.render(args.reference_spp // 2)
            halves.append(r.image("rectangle")[..., :3].astype(np.float64))
        reference = 0.5 * (halves[0] + halves[1])
        print(f"reference without {', '.join(args.without)}: {args.reference_spp} spp, its own RMSE "
              f"{0.5 * math.sqrt(np.mean((halves[0] - halves[1]) ** 2)):.3g}")
    else:
        reference = np.load(os.path.join(args.study, "images", "reference.npy"))[..., :3].astype(np.float64)
    masks = regions(scene, args.radius)
    mse, cost = {}, {}
    for medium in sphrect.medium_samplings:
        squared, times = 0.0, []
        for seed in range(args.replicates):
            r = sphrect.Renderer(scene, techniques=["rectangle"], mis="power", pattern="sobol",
                                 medium_sampling=medium, seed=1000 + seed, threads=1)
            start = time.process_time()
            r.render(args.samples)
            times.append(time.process_time() - start)
            squared = squared + np.mean((r.image("rectangle")[..., :3] - reference) ** 2, axis=2)
        mse[medium] = squared / args.replicates
        cost[medium] = min(times) / args.samples
    names = list(sphrect.medium_samplings)
    print(f"{args.study}: {args.replicates} x {args.samples} spp, rectangle / power / sobol; "
          f"CPU ms per spp: " + ", ".join(f"{m} {1e3 * cost[m]:.3g}" for m in names))
    print("| region | pixels | share of distance's squared error | "
          + " | ".join(f"RMSE {m}" for m in names) + " | "
          + " | ".join(f"efficiency {m} / distance" for m in names if m != "distance") + " |")
    print("|---" * (3 + 2 * len(names) - 1) + "|")
    total = float(np.sum(mse["distance"]))
    for name, mask in masks.items():
        region = {m: float(np.mean(mse[m][mask])) for m in names}
        efficiency = [region["distance"] * cost["distance"] / (region[m] * cost[m]) for m in names
                      if m != "distance"]
        print(f"| {name} | {int(mask.sum())} | {float(np.sum(mse['distance'][mask])) / total:.0%} | "
              + " | ".join(f"{math.sqrt(region[m]):.3g}" for m in names) + " | "
              + " | ".join(f"{e:.3g}" for e in efficiency) + " |")


if __name__ == "__main__":
    main()
