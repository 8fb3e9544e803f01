#!/usr/bin/env python3
"""What a view change costs the viewport: a new Renderer (the native scene's build: BVH, lights) against
Renderer.set_camera on the one it has, and a 1/4-resolution preview (set_camera + one sample), at 1057 x 667.
Each scene file as it is, and the first one again with a 999,000-triangle sphere added.

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_view_change.py SCENE.sphrect.npz [...]

(blender_scenes' files: export them with addon/sphrect_blender/headless.py's `export` command.)"""
import argparse
import dataclasses
import time

import numpy as np

import sphrect

WIDTH, HEIGHT = 1057, 667


def sphere_mesh(rings=500, segments=1000, center=(2, 2, 1)):
    theta, phi = np.linspace(0, np.pi, rings + 1), np.linspace(0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    v = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3) + center
    i, j = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    a, b = i * segments + j, i * segments + (j + 1) % segments
    c, d = a + segments, b + segments
    tris = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([b, c, d], -1).reshape(-1, 3)])
    return sphrect.Mesh(vertices=v.astype(np.float32), triangles=tris.astype(np.int32), name="sphere")


def least(f, n):
    times = []
    for k in range(n):
        t = time.perf_counter()
        f(k)
        times.append(time.perf_counter() - t)
    return min(times)


def measure(name, scene):
    scene.camera = dataclasses.replace(scene.camera, width=WIDTH, height=HEIGHT)
    t = time.perf_counter()
    r = sphrect.Renderer(scene)
    build = time.perf_counter() - t
    shift = np.zeros((4, 4))
    shift[0, 3] = 0.05
    moved = dataclasses.replace(scene.camera, to_world=(np.asarray(scene.camera.to_world) + shift).tolist())
    quarter = dataclasses.replace(moved, width=-(-WIDTH // 4), height=-(-HEIGHT // 4))
    set_camera = least(lambda k: r.set_camera(moved if k % 2 else scene.camera), 5)
    preview = least(lambda k: (r.set_camera(quarter), r.render(1)), 3)
    triangles = sum(m.triangles.shape[0] for m in scene.meshes)
    print(f"{name}: {triangles} triangles, new renderer {build * 1e3:.0f} ms, set_camera {set_camera * 1e3:.2f} ms, "
          f"1/4 preview (set_camera + 1 sample) {preview * 1e3:.0f} ms", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+")
    a = ap.parse_args()
    for path in a.scenes:
        measure(path, sphrect.load_scene(path))
    big = sphrect.load_scene(a.scenes[0])
    big.meshes.append(sphere_mesh())
    measure(f"{a.scenes[0]} + a 999,000-triangle sphere", big)


if __name__ == "__main__":
    main()
