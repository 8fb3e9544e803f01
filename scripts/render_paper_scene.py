#!/usr/bin/env python3
"""The paper's experiment without Blender: Lambertian objects on a ground plane, lit by a two-sided
rectangular light standing perpendicular to the ground close to it (invisible to the camera),
rendered with every light-sampling technique, without and with MIS (balance heuristic), at equal
camera samples (the paper used 9 paths per pixel); RMSE against a high-sample reference.

The MIS rows are the paper's "Comparison with MIS": one light sample and one BSDF (cosine) sample at
every hit, combined by the balance heuristic. The renderer by default takes light samples alone at
purely diffuse hits (bsdf_samples_on_diffuse=False), which on this all-diffuse scene would make the
MIS rows the rows without MIS; so they are rendered with bsdf_samples_on_diffuse=True, as the paper did.

Writes to --out:
  paper_compare.png            all techniques side by side (row per MIS mode) with RMSE and times
  paper_<mis>_<technique>.png  each image (tone-mapped sRGB), and paper_reference.png
  paper_rmse_vs_light_samples.png  RMSE vs light samples per camera ray (as in the paper), half resolution
  paper_figures.json           every number in the figures

Run:  PYTHONPATH=build/python /usr/bin/python3 scripts/render_paper_scene.py --out /tmp/paper
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

import sphrect
from sphrect.study.metrics import rmse, tonemap

# area, triangles, rectangle, rectangle_cosine, rectangle_projected (rectangle_ltc follows glossy lobes: on this
# diffuse scene it samples as rectangle_projected, sample for sample).
TECHNIQUES = tuple(t for t in sphrect.techniques if t != "rectangle_ltc")
LABELS = {"area": "area", "triangles": "solid angle (two triangles)", "rectangle": "solid angle (rectangle)",
          "rectangle_cosine": "rectangle + cosine warp", "rectangle_projected": "projected solid angle (exact cosine)"}
MIS_MODES = ("none", "balance")  # the figure's rows: light sampling only, then the paper's MIS


def bsdf_samples_on_diffuse(mis):
    """The paper's MIS draws a BSDF sample at every hit; the scene is all diffuse, so it must be asked for."""
    return mis != "none"


def box(center, size, rotation_z=0.0):
    s = np.asarray(size, np.float64) / 2
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], np.float64) * s
    c, si = math.cos(rotation_z), math.sin(rotation_z)
    corners = corners @ np.array([[c, si, 0], [-si, c, 0], [0, 0, 1]]) + np.asarray(center)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for a, b, c2, d in quads for t in ((a, b, c2), (a, c2, d))]
    return corners.astype(np.float32), np.array(tris, np.int32)


def uv_sphere(center, radius, rings=48, segments=96):
    theta = np.linspace(0, np.pi, rings + 1)
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    n = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    v = (np.asarray(center) + radius * n).astype(np.float32)
    i = np.arange(rings)[:, None] * segments
    j = np.arange(segments)[None, :]
    a, b = i + j, i + (j + 1) % segments
    c, d = a + segments, b + segments
    tris = np.concatenate([np.stack([a, b, d], -1)[1:].reshape(-1, 3), np.stack([a, d, c], -1)[:-1].reshape(-1, 3)])
    return v, tris.astype(np.int32), n.astype(np.float32)


def look_at(eye, target, up=(0, 0, 1)):
    eye, target, up = (np.asarray(a, np.float64) for a in (eye, target, up))
    back = eye - target
    back /= np.linalg.norm(back)               # camera +Z points away from the view direction
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, np.cross(back, right), back, eye
    return m.tolist()


def paper_scene(width, height):
    materials = [sphrect.Material("ground", base_color=(0.6, 0.6, 0.6)),
                 sphrect.Material("red", base_color=(0.7, 0.2, 0.15)),
                 sphrect.Material("blue", base_color=(0.15, 0.3, 0.7)),
                 sphrect.Material("white", base_color=(0.8, 0.8, 0.75))]
    meshes = [sphrect.Mesh(vertices=np.array([[-30, -30, 0], [30, -30, 0], [30, 30, 0], [-30, 30, 0]], np.float32),
                           triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), material_ids=np.zeros(2, np.int32),
                           name="ground")]
    for (center, size, rot, mat) in [((-1.7, 0.6, 0.5), (0.8, 0.8, 1.0), 0.4, 1),
                                     ((1.6, 0.1, 0.35), (0.7, 0.7, 0.7), -0.3, 2),
                                     ((0.9, 2.2, 0.6), (0.5, 0.5, 1.2), 0.1, 3)]:
        v, t = box(center, size, rot)
        meshes.append(sphrect.Mesh(vertices=v, triangles=t, material_ids=np.full(len(t), mat, np.int32), name="box"))
    for (center, r, mat) in [((-0.5, -0.9, 0.45), 0.45, 3), ((-1.0, 2.0, 0.35), 0.35, 1)]:
        v, t, n = uv_sphere(center, r)
        meshes.append(sphrect.Mesh(vertices=v, triangles=t, normals=n, material_ids=np.full(len(t), mat, np.int32),
                                   name="sphere"))
    # Two-sided light standing on the ground (bottom edge 2 cm above it), perpendicular to it, invisible.
    light = sphrect.RectLight.from_power(center=(0.0, 0.5, 0.42), edge_x=(1.6, 0, 0), edge_y=(0, 0, 0.8), power=60.0,
                                         two_sided=True, visible=False, name="panel")
    cam = sphrect.Camera(width=width, height=height, lens=30, to_world=look_at((0.3, -5.5, 4.2), (0.1, 0.6, 0.2)))
    return sphrect.Scene(camera=cam, materials=materials, meshes=meshes, lights=[light])


def to_srgb8(img, exposure):
    return (tonemap(img, white=1 / exposure) * 255 + 0.5).astype(np.uint8)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--samples", type=int, default=9, help="camera samples per pixel (the paper: 9)")
    ap.add_argument("--reference-samples", type=int, default=512)
    ap.add_argument("--sweep", default="1,2,4,8,16", help="light samples per camera ray for the RMSE curve ('' = none)")
    ap.add_argument("--pattern", default="sobol")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene = paper_scene(args.width, args.height)
    n_tris = sum(len(m.triangles) for m in scene.meshes)
    print(f"scene: {n_tris} triangles, {args.width}x{args.height}", flush=True)

    t0 = time.perf_counter()
    ref_r = sphrect.Renderer(scene, techniques=["rectangle"], mis="power", pattern=args.pattern,
                             seed=10_000 + args.seed, threads=args.threads)
    ref_r.render(args.reference_samples)
    ref = ref_r.image("rectangle")
    print(f"reference: {args.reference_samples} spp (rectangle, the renderer's defaults otherwise) in "
          f"{time.perf_counter() - t0:.1f} s",
          flush=True)
    lum = ref[:, :, :3] @ np.array([0.2126, 0.7152, 0.0722])
    exposure = 0.9 / max(float(np.percentile(lum, 98)), 1e-8)
    plt.imsave(os.path.join(args.out, "paper_reference.png"), to_srgb8(ref, exposure))

    figures = {"scene": {"triangles": n_tris, "width": args.width, "height": args.height, "samples": args.samples,
                         "reference_samples": args.reference_samples, "pattern": args.pattern,
                         "light": "two-sided rectangle perpendicular to the ground, invisible"},
               "images": {}, "sweep": {}}
    images = {}
    ref_rms = float(np.sqrt(np.mean(ref[:, :, :3] ** 2)))
    for mis in MIS_MODES:
        r = sphrect.Renderer(scene, techniques=TECHNIQUES, mis=mis, pattern=args.pattern, seed=args.seed,
                             threads=args.threads, bsdf_samples_on_diffuse=bsdf_samples_on_diffuse(mis))
        r.render(args.samples)
        for t in TECHNIQUES:
            img = r.image(t)
            images[(mis, t)] = img
            st = r.stats(t)
            error = rmse(img, ref)
            entry = {"rmse": error, "relative_rmse": error / ref_rms,
                     "light_time": st["light_time"], "shading_time": st["shading_time"],
                     "camera_time": st["camera_time"], "rays": st["rays"], "samples": st["samples"],
                     "bsdf_samples_on_diffuse": bsdf_samples_on_diffuse(mis)}
            figures["images"][f"{mis}/{t}"] = entry
            plt.imsave(os.path.join(args.out, f"paper_{mis}_{t}.png"), to_srgb8(img, exposure))
            print(f"  mis={mis:8s} {t:17s} RMSE {entry['rmse']:.5f}  light {entry['light_time']:.3f} s  "
                  f"shading {entry['shading_time']:.3f} s", flush=True)

    # Side-by-side comparison.
    fig, axes = plt.subplots(2, len(TECHNIQUES) + 1, figsize=(3.2 * (len(TECHNIQUES) + 1), 2.0 * 2 + 0.8), dpi=110)
    for row, mis in enumerate(MIS_MODES):
        for col, t in enumerate(TECHNIQUES):
            ax = axes[row, col]
            ax.imshow(to_srgb8(images[(mis, t)], exposure))
            e = figures["images"][f"{mis}/{t}"]
            ax.set_title(f"{LABELS[t]}{' + BSDF' if mis != 'none' else ''}\nRMSE {e['rmse']:.4f}, "
                         f"{e['light_time'] + e['shading_time']:.2f} s", fontsize=7)
            ax.axis("off")
        axes[row, -1].imshow(to_srgb8(ref, exposure))
        axes[row, -1].set_title(f"reference ({args.reference_samples} spp)", fontsize=7)
        axes[row, -1].axis("off")
    fig.suptitle(f"{args.samples} camera samples per pixel, 1 light sample each; top: light sampling only, "
                 f"bottom: MIS (balance) with a BSDF sample at every hit, diffuse ones included, as in the paper",
                 fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "paper_compare.png"))
    plt.close(fig)

    # RMSE vs light samples per camera ray, at half resolution (cheaper; same scene).
    sweep = [int(s) for s in args.sweep.split(",") if s.strip()]
    if sweep:
        small = paper_scene(max(8, args.width // 2), max(8, args.height // 2))
        rr = sphrect.Renderer(small, techniques=["rectangle"], mis="power", pattern=args.pattern,
                              seed=20_000 + args.seed, threads=args.threads)
        rr.render(args.reference_samples)
        small_ref = rr.image("rectangle")
        fig, axs = plt.subplots(1, 2, figsize=(9, 3.4), dpi=110)
        for ax, mis in zip(axs, MIS_MODES):
            curves = {t: [] for t in TECHNIQUES}
            for n in sweep:
                r = sphrect.Renderer(small, techniques=TECHNIQUES, mis=mis, light_samples=n, pattern=args.pattern,
                                     seed=args.seed, threads=args.threads,
                                     bsdf_samples_on_diffuse=bsdf_samples_on_diffuse(mis))
                r.render(args.samples)
                for t in TECHNIQUES:
                    curves[t].append(rmse(r.image(t), small_ref))
            figures["sweep"][mis] = {"light_samples": sweep, **curves}
            for t in TECHNIQUES:
                ax.loglog(sweep, curves[t], "o-", label=LABELS[t])
            ax.set_xlabel("light samples per camera ray")
            ax.set_ylabel("RMSE")
            ax.set_title("light sampling only" if mis == "none" else
                         "MIS (balance), BSDF samples on diffuse hits", fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
        axs[0].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "paper_rmse_vs_light_samples.png"))
        plt.close(fig)

    figures["total_seconds"] = time.perf_counter() - t0
    with open(os.path.join(args.out, "paper_figures.json"), "w") as f:
        json.dump(figures, f, indent=2)
    print(f"wrote {args.out} in {figures['total_seconds']:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
