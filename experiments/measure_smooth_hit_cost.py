#!/usr/bin/env python3
"""What a smooth hit's ensure_valid_reflection test costs: a smooth UV sphere (N x 2N quads, its vertex normals)
filling most of a 128 x 96 view under a rectangle light, 32 spp, one thread, the least CPU time of five renders.
Run it with two builds and compare (docs/renderer.md, smooth normals):

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_smooth_hit_cost.py [N=64]
"""
import sys
import time

import numpy as np

import sphrect


def sphere(n=64):
    theta, phi = np.meshgrid(np.linspace(0, np.pi, n + 1), np.linspace(0, 2 * np.pi, 2 * n + 1), indexing="ij")
    v = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    v = v.reshape(-1, 3).astype(np.float32)
    tris = []
    w = 2 * n + 1
    for i in range(n):
        for j in range(2 * n):
            a, b, c, d = i * w + j, i * w + j + 1, (i + 1) * w + j, (i + 1) * w + j + 1
            tris += [[a, c, b], [b, c, d]]
    return v, np.array(tris, np.int32)


v, t = sphere(int(sys.argv[1]) if len(sys.argv) > 1 else 64)
mesh = sphrect.Mesh(vertices=v, triangles=t, normals=v.copy(), name="ball")
light = sphrect.RectLight(corner=(-1.0, -1.0, 3.0), edge_x=(0.0, 2.0, 0.0), edge_y=(2.0, 0.0, 0.0),
                          radiance=(5, 5, 5))  # facing down
# The camera 3 units along -Y, looking along +Y (right +X, up +Z, Blender's camera looking down its -Z).
to_world = [[1, 0, 0, 0], [0, 0, -1, -3], [0, 1, 0, 0], [0, 0, 0, 1]]
scene = sphrect.Scene(camera=sphrect.Camera(width=128, height=96, to_world=to_world, lens=35), meshes=[mesh],
                      lights=[light])
best = 1e9
for r in range(5):
    rend = sphrect.Renderer(scene, techniques=["rectangle"], threads=1, seed=r)
    c0 = time.process_time()
    rend.render(32)
    best = min(best, time.process_time() - c0)
print(f"{best * 1e3:.1f} ms per render (image mean {float(rend.image('rectangle')[..., :3].mean()):.6f})")
