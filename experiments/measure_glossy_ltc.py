#!/usr/bin/env python3
"""Technique rectangle_ltc against rectangle and rectangle_projected on a Principled floor at several roughnesses:
MSE at equal samples, time per camera sample and efficiency at equal time (docs/rectangle_ltc.md, "In the renderer").

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_glossy_ltc.py [--samples 16] [--roughness 0.1 0.3]

The scene: a 12 m Principled floor (base colour 0.8; --metallic 1: a metal, 0: a dielectric with specular 0.5)
seen at 45 degrees, a 1 x 0.6 m two-sided light 1.5 m above it where the camera sees its highlight, a grey box
beside it.  Reference: rectangle_projected with MIS power at --reference-samples.  Each configuration renders
--samples per pixel with one thread, twice (seeds 1, 2); MSE: the mean over pixels and RGB of the squared error of
each render against the reference, averaged; time: the renders' wall time per camera sample (one thread).  Efficiency:
1 / (MSE x time), relative to rectangle_projected with MIS power (above 1: better at equal time)."""
import argparse

import numpy as np

import sphrect
from measure_ris_candidates import box_mesh  # (this folder: the script's own)

TECHNIQUES = ("rectangle", "rectangle_projected", "rectangle_ltc")
BASELINE = ("rectangle_projected", "power")


def scene(roughness: float, metallic: float, width: int) -> sphrect.Scene:
    floor = np.array([[-6, -6, 0], [6, -6, 0], [6, 6, 0], [-6, 6, 0]], np.float32)
    meshes = [sphrect.Mesh(vertices=floor, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32),
                           material_ids=np.zeros(2, np.int32), name="floor"),
              box_mesh((0.8, 0.5, 0.0), (1.4, 1.1, 0.6), "box")]
    meshes[1].material_ids = np.ones(len(meshes[1].triangles), np.int32)
    materials = [sphrect.Material(kind="principled", base_color=(0.8, 0.8, 0.8), roughness=roughness,
                                  metallic=metallic, specular=0.5),
                 sphrect.Material(base_color=(0.5, 0.5, 0.5))]
    light = sphrect.RectLight(corner=(-0.5, 2.7, 1.5), edge_x=(1.0, 0.0, 0.0), edge_y=(0.0, 0.6, 0.0),
                              radiance=(10.0, 10.0, 10.0), two_sided=True, visible=False)
    camera = sphrect.Camera(width=width, height=width * 3 // 4, lens=35,
                            to_world=[[1, 0, 0, 0], [0, 0.7071, -0.7071, -3.0], [0, 0.7071, 0.7071, 3.0],
                                      [0, 0, 0, 1]])
    return sphrect.Scene(camera=camera, meshes=meshes, lights=[light], materials=materials)


def render(sc, technique, samples, seed, **kw):
    r = sphrect.Renderer(sc, techniques=[technique], seed=seed, threads=1, **kw)
    assert r.render(samples)
    return r.image()[..., :3].astype(np.float64), r.stats()["wall_time"]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--reference-samples", type=int, default=4096)
    p.add_argument("--width", type=int, default=96)
    p.add_argument("--roughness", type=float, nargs="+", default=[0.05, 0.1, 0.2, 0.3, 0.5])
    p.add_argument("--metallic", type=float, nargs="+", default=[1.0, 0.0])
    p.add_argument("--mis", nargs="+", default=["power", "none"])
    args = p.parse_args()
    print("| metallic | roughness | technique | mis | MSE | ns / sample | MSE / baseline's | efficiency / baseline's |")
    print("|---|---|---|---|---|---|---|---|")
    for metallic in args.metallic:
        for roughness in args.roughness:
            sc = scene(roughness, metallic, args.width)
            reference, _ = render(sc, BASELINE[0], args.reference_samples, 99, mis=BASELINE[1])
            rows = {}
            for technique in TECHNIQUES:
                for mis in args.mis:
                    errors, seconds = [], 0.0
                    for seed in (1, 2):
                        image, cpu = render(sc, technique, args.samples, seed, mis=mis)
                        errors.append(np.mean((image - reference) ** 2))
                        seconds += cpu
                    pixels = reference.shape[0] * reference.shape[1]
                    rows[technique, mis] = (float(np.mean(errors)), seconds / 2 / (pixels * args.samples))
            base_mse, base_time = rows[BASELINE]
            for (technique, mis), (mse, t) in rows.items():
                print(f"| {metallic:g} | {roughness:g} | {technique} | {mis} | {mse:.3g} | {t * 1e9:.0f} | "
                      f"{mse / base_mse:.3f} | {base_mse * base_time / (mse * t):.2f} |", flush=True)


if __name__ == "__main__":
    main()
