"""Textured rectangle lights sampled by their blocks' power and solid angle (core/rectangle_blocks.h, the default
emission_blocks=True) against plain solid-angle sampling of the whole light (emission_blocks=False, the `rectangle`
map over the whole quad), at equal samples: MSE against a converged reference, on lights whose image is mostly
dark -- a window with bars, a logo (a ring and a bar on black) -- lighting a floor, and one fully lit image (where
the blocks cannot help).  Prints the MSE of each, their ratio and the render time per sample (a measurement, not a
test).  Run:

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_emission_blocks.py [--samples 4] [--seeds 8]
"""
import argparse
import time

import numpy as np

import sphrect

SIZE = 64


def window_with_bars():
    p = np.full((SIZE, SIZE, 3), 0.0, np.float32)
    p[8:56, 8:56] = 1.0
    for k in range(8, 56, 8):
        p[8:56, k:k + 5] = 0.0  # bars: 5 of every 8 texels across the window
    return p


def logo():
    y, x = (np.mgrid[0:SIZE, 0:SIZE] + 0.5) / SIZE - 0.5
    r = np.hypot(x, y)
    p = np.zeros((SIZE, SIZE, 3), np.float32)
    p[(r > 0.3) & (r < 0.38)] = (1.0, 0.3, 0.1)
    p[(np.abs(y) < 0.04) & (np.abs(x) < 0.25)] = (0.2, 0.6, 1.0)
    return p


def uniform():
    return np.full((SIZE, SIZE, 3), 0.5, np.float32)


def scene_of(pixels):
    floor = sphrect.Mesh(vertices=np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], np.float32),
                         triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name="floor",
                         material_ids=np.zeros(2, np.int32))
    # A 1.2 x 0.8 window 1 m above the floor, tilted 30 degrees about x.
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    quad = np.array([[-0.6, -0.4 * c, 1 - 0.4 * s], [0.6, -0.4 * c, 1 - 0.4 * s], [0.6, 0.4 * c, 1 + 0.4 * s],
                     [-0.6, 0.4 * c, 1 + 0.4 * s]], np.float32)
    panel = sphrect.Mesh(vertices=quad, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name="window",
                         uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32),
                         material_ids=np.ones(2, np.int32))
    materials = [sphrect.Material(name="floor", base_color=(0.6,) * 3),
                 sphrect.Material(name="window", base_color=(0, 0, 0), emission=(5.0,) * 3,
                                  textures={"emission": sphrect.TextureLookup(texture=0)})]
    camera = sphrect.Camera(width=64, height=64, type="orthographic", ortho_scale=4.0,
                            to_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.5], [0, 0, 0, 1]])
    return sphrect.Scene(camera=camera, meshes=[floor, panel], materials=materials,
                         textures=[sphrect.Texture(name="image", pixels=pixels, colorspace="linear")])


def render(scene, blocks, samples, seed):
    r = sphrect.Renderer(scene, techniques=["rectangle"], emission_blocks=blocks, seed=seed)
    t0 = time.perf_counter()
    assert r.render(samples)
    return r.image("rectangle")[..., :3].astype(np.float64), time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=4, help="camera samples per render (x2 light samples)")
    ap.add_argument("--seeds", type=int, default=8, help="independent renders averaged into the MSE")
    ap.add_argument("--reference", type=int, default=4096, help="samples of the reference (blocks on and off "
                    "averaged)")
    args = ap.parse_args()
    print(f"{'image':<18}{'blocks MSE':>12}{'whole MSE':>12}{'ratio':>8}{'ms/spp blocks':>15}{'ms/spp whole':>14}")
    for name, pixels in (("window with bars", window_with_bars()), ("logo", logo()), ("uniform", uniform())):
        scene = scene_of(pixels)
        reference = 0.5 * (render(scene, True, args.reference, 12345)[0] + render(scene, False, args.reference,
                                                                                  54321)[0])
        mse, cost = {}, {}
        for blocks in (True, False):
            errors, times = [], []
            for seed in range(args.seeds):
                image, seconds = render(scene, blocks, args.samples, seed)
                errors.append(np.mean((image - reference) ** 2))
                times.append(seconds / args.samples)
            mse[blocks], cost[blocks] = float(np.mean(errors)), 1e3 * float(np.median(times))
        print(f"{name:<18}{mse[True]:>12.3e}{mse[False]:>12.3e}{mse[True] / mse[False]:>8.3f}"
              f"{cost[True]:>15.2f}{cost[False]:>14.2f}")


if __name__ == "__main__":
    main()
