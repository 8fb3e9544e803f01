#!/usr/bin/env python3
"""Cost of emissive meshes against their number of triangles: a ceiling of N small emissive triangles
(a grid of sheared quads, so no pair is a rectangle: N triangle lights) over a ground plane.

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_mesh_lights.py [--counts 100 10000 1000000]

Prints per N: the scene's build time (sphrect.Renderer: validation, Embree BVH, N area lights and their
power CDF) and its memory (growth of the process' peak RSS), and the time per camera sample of a 64 x 64
render at 4 spp (one light sample, --mis power by default: every BSDF ray is one Embree ray into the
ceiling, so it grows with the BVH's depth, not with N; --mis none traces no BSDF rays)."""
import argparse
import resource
import time

import numpy as np

import sphrect


def peak_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def ceiling(n_triangles, size=4.0, height=2.0):
    """n_triangles (rounded to an even square count) emissive triangles covering [-size/2, size/2]^2 at `height`."""
    k = max(1, int(round(np.sqrt(n_triangles / 2))))
    step = size / k
    i, j = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
    x0, y0 = (-size / 2 + i * step).ravel(), (-size / 2 + j * step).ravel()
    w, shear = 0.8 * step, 0.2 * step
    corners = np.stack([np.stack([x0, y0], -1), np.stack([x0 + w, y0], -1),
                        np.stack([x0 + w + shear, y0 + w], -1), np.stack([x0 + shear, y0 + w], -1)], 1)
    v = np.concatenate([corners, np.full(corners.shape[:2] + (1,), height)], -1).reshape(-1, 3).astype(np.float32)
    q = 4 * np.arange(k * k)[:, None]
    t = np.concatenate([q + [0, 1, 2], q + [0, 2, 3]], 1).reshape(-1, 3).astype(np.int32)
    return sphrect.Mesh(vertices=v, triangles=t, name="ceiling", material_ids=np.ones(len(t), np.int32))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--counts", type=int, nargs="+", default=[100, 10_000, 1_000_000])
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--samples", type=int, default=4)
    ap.add_argument("--mis", default="power", choices=sphrect.mis_modes)
    args = ap.parse_args()
    ground = sphrect.Mesh(vertices=np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], np.float32),
                          triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name="ground",
                          material_ids=np.zeros(2, np.int32))
    materials = [sphrect.Material(base_color=(0.5,) * 3),
                 sphrect.Material(name="emitter", base_color=(0, 0, 0), emission=(1, 1, 1))]
    cam = sphrect.Camera(width=args.size, height=args.size, type="orthographic", ortho_scale=3.0,
                         to_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1.0], [0, 0, 0, 1]])
    print(f"{'triangles':>10} {'lights':>10} {'build s':>8} {'peak RSS +MB':>12} {'B/triangle':>10} "
          f"{'us/camera sample':>16}")
    for n in args.counts:
        mesh = ceiling(n)
        scene = sphrect.Scene(camera=cam, meshes=[ground, mesh], materials=materials)
        rss0 = peak_rss_mb()
        t0 = time.perf_counter()
        r = sphrect.Renderer(scene, techniques=["rectangle"], mis=args.mis, seed=1)
        build = time.perf_counter() - t0
        grown = peak_rss_mb() - rss0
        n_lights = r._scene.num_area_lights
        assert r.render(args.samples)
        st = r.stats("rectangle")
        per_sample = st["wall_time"] / (args.size * args.size * args.samples) * 1e6
        print(f"{len(mesh.triangles):>10} {n_lights:>10} {build:>8.3f} {grown:>12.1f} "
              f"{grown * 2**20 / len(mesh.triangles):>10.0f} {per_sample:>16.3f}")
        del r


if __name__ == "__main__":
    main()
