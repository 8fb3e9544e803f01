#!/usr/bin/env python3
"""Fingerprints of everything a behaviour-preserving change must leave bit-identical: rendered images
(scenes covering every kernel specialisation and light type x techniques x MIS x patterns x light
samples), the sampling core's samples, pdfs, inverses and solid angles (float and double, random and
hard configurations) and the sample patterns.

    PYTHONPATH=build/python /usr/bin/python3 scripts/fingerprint.py > before.json
    ... change ...
    PYTHONPATH=build/python /usr/bin/python3 scripts/fingerprint.py --compare before.json

With --compare it prints the entries that differ and exits 1 if any does.  Blender-exported scenes:
--scenes DIR adds the images of every *.sphrect.npz in DIR.
"""
import argparse
import glob
import hashlib
import json
import math
import os
import sys

import numpy as np

import sphrect


def digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(str(a.dtype).encode() + str(a.shape).encode())
        h.update(a.tobytes())
    return h.hexdigest()[:16]


def box(lo, hi, name):
    """An axis-aligned box mesh (12 triangles)."""
    lo, hi = np.asarray(lo, np.float32), np.asarray(hi, np.float32)
    v = np.array([[x, y, z] for z in (lo[2], hi[2]) for y in (lo[1], hi[1]) for x in (lo[0], hi[0])], np.float32)
    f = [[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
         [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]]
    return sphrect.Mesh(vertices=v, triangles=np.array(f, np.int32), name=name)


def sphere(center, radius, n=10, name="sphere"):
    th = np.linspace(0, np.pi, n + 1)
    ph = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    v = [[center[0] + radius * math.sin(t) * math.cos(p), center[1] + radius * math.sin(t) * math.sin(p),
          center[2] + radius * math.cos(t)] for t in th for p in ph]
    m = 2 * n
    f = []
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, i * m + (j + 1) % m
            c, d = a + m, b + m
            f += [[a, c, b], [b, c, d]]
    v = np.array(v, np.float32)
    return sphrect.Mesh(vertices=v, triangles=np.array(f, np.int32), normals=(v - np.float32(center)) / radius,
                        name=name)


def base_scene(width=32, height=24):
    ground = np.array([[-10, -10, 0], [10, -10, 0], [10, 10, 0], [-10, 10, 0]], np.float32)
    meshes = [sphrect.Mesh(vertices=ground, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name="ground"),
              box([-1.5, -0.5, 0], [-0.5, 0.5, 1.2], "box"), sphere([1.0, 0.3, 0.6], 0.6)]
    meshes[1].material_ids = np.full(12, 1, np.int32)
    cam = sphrect.Camera(width=width, height=height, lens=35,
                         to_world=[[1, 0, 0, 0], [0, 0.5, -0.866, -6], [0, 0.866, 0.5, 3.5], [0, 0, 0, 1]])
    return sphrect.Scene(camera=cam, meshes=meshes,
                         materials=[sphrect.Material(name="a"), sphrect.Material(name="b", base_color=(0.7, 0.3, 0.2))])


def scenes():
    out = {}
    s = base_scene()
    s.lights = [sphrect.RectLight(corner=(-1, 1.5, 0.2), edge_x=(2, 0, 0), edge_y=(0, 0, 1.5), radiance=(5, 5, 5),
                                  two_sided=True)]
    out["diffuse_two_sided"] = s
    s = base_scene()
    s.materials = [sphrect.Material(name="g", kind="glossy", roughness=0.3, metallic=0.0),
                   sphrect.Material(name="m", kind="glossy", base_color=(0.9, 0.6, 0.2), roughness=0.5, metallic=1)]
    s.lights = [sphrect.RectLight(corner=(-1, -1, 3), edge_x=(0, 2, 0), edge_y=(2, 0, 0), radiance=(4, 3, 2)),
                sphrect.EllipseLight(center=(2, -1, 2), axis_x=(0.5, 0, 0), axis_y=(0, 0.3, 0.3), radiance=(2, 4, 2),
                                     two_sided=True, visible=False)]
    out["glossy_rect_ellipse"] = s
    s = base_scene()
    s.world = sphrect.World(background=(0.05, 0.08, 0.1), medium=sphrect.Medium(sigma_s=(0.08, 0.1, 0.12),
                                                                                 sigma_a=(0.01, 0, 0), g=0.3))
    s.lights = [sphrect.RectLight(corner=(-1, -1, 3), edge_x=(0, 2, 0), edge_y=(2, 0, 0), radiance=(4, 4, 4)),
                sphrect.PointLight(position=(2, 2, 2), intensity=(3, 3, 3)),
                sphrect.SpotLight(position=(-2, -2, 3), direction=(0.4, 0.4, -0.82), intensity=(10, 8, 6))]
    out["fog_point_spot_sky"] = s
    s = base_scene()
    s.camera.aperture_radius, s.camera.focus_distance = 0.15, 6.0
    s.world = sphrect.World(background=(0.2, 0.2, 0.25))
    s.lights = [sphrect.SunLight(direction=(0.3, 0.2, -0.93), irradiance=(2, 2, 2)),
                sphrect.RectLight(corner=(1, -1, 0.01), edge_x=(0.5, 0, 0), edge_y=(0, 0.5, 2), radiance=(6, 6, 6))]
    out["dof_sun_sky_grazing"] = s
    s = base_scene()
    s.camera.type, s.camera.ortho_scale = "orthographic", 8.0
    s.lights = [sphrect.RectLight(corner=(-3 + 1.5 * i, 2, 2.5), edge_x=(0, 0.6, 0), edge_y=(1, 0, 0),
                                  radiance=(1 + i, 2, 3 - 0.5 * i)) for i in range(4)]
    out["ortho_four_lights"] = s
    return out


def image_fingerprints(scene_items):
    out = {}
    techniques = list(sphrect.techniques)
    for name, scene in scene_items:
        for mis in sphrect.mis_modes:
            for pattern, light_samples in (("sobol", 1), ("independent", 1), ("stratified", 2), ("sobol", 3)):
                r = sphrect.Renderer(scene, techniques=techniques, mis=mis, pattern=pattern,
                                     light_samples=light_samples, seed=7, threads=2, light_selection="power")
                r.render(3)
                r.render(2)  # progressive continuation
                for t in techniques:
                    out[f"image/{name}/{mis}/{pattern}/{light_samples}/{t}"] = digest(r.image(t))
        # The light tree (one light sample, and several, where its per-point memo works).
        for light_samples in (1, 3):
            r = sphrect.Renderer(scene, techniques=techniques, mis="power", pattern="sobol",
                                 light_samples=light_samples, seed=5, threads=2, light_selection="tree")
            r.render(4)
            for t in techniques:
                out[f"image/{name}/tree/{light_samples}/{t}"] = digest(r.image(t))
        if "fog" in name:
            for ms in ("distance", "equiangular"):
                # The settings pinned (the Renderer's defaults when these entries were made), so that a change
                # of defaults does not read as a change of the kernel.
                r = sphrect.Renderer(scene, techniques=techniques, medium_sampling=ms, seed=3, mis="balance",
                                     pattern="sobol", light_samples=1, light_selection="power")
                r.render(4)
                for t in techniques:
                    out[f"image/{name}/medium_{ms}/{t}"] = digest(r.image(t))
    return out


def core_configs(rng):
    """(origin, corner, edge_x, edge_y, normal) sets: random, and hard ones (distant, tiny, grazing, beside)."""
    n = 512
    o = rng.uniform(-3, 3, (n, 3))
    corner = np.array([-0.5, -0.5, 1.0])
    ex, ey = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    normal = rng.normal(size=(n, 3))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    yield "random", o, corner, ex, ey, normal
    for d in (1e2, 1e4, 1e6):
        yield f"distant{d:g}", np.array([0.3, -0.2, 1.0 - d]) + 0 * o, corner, ex, ey, np.array([0, 0, 1.0])
    for h in (1e-9, 1e-5, 1e-2):
        yield f"grazing{h:g}", np.column_stack([o[:, 0] * 2, o[:, 1] * 2, np.full(n, 1.0 - h)]), corner, ex, ey, \
            np.array([0, 0, 1.0])
    yield "thin", o, corner, np.array([1e-4, 0, 0]), np.array([0, 3.0, 0]), normal


def core_fingerprints():
    out = {}
    rng = np.random.default_rng(12345)
    for name in sphrect.patterns:
        for n, seed in ((1, 0), (7, 3), (256, 1), (1000, 99)):
            out[f"pattern/{name}/{n}/{seed}"] = digest(sphrect.pattern(name, n, seed=seed))
    uv_sets = {"sobol": sphrect.pattern("sobol", 512, seed=5).astype(np.float64),
               "edges": np.array([[u, v] for u in (0, 1e-7, 0.5, 1 - 1e-7, 1) for v in (0, 0.5, 1)] * 35)[:512]}
    for cname, o, corner, ex, ey, normal in core_configs(rng):
        for dtype in ("float32", "float64"):
            for two_sided in (True, False):
                key = f"{cname}/{dtype}/{'two' if two_sided else 'one'}"
                out[f"solid_angle/{key}"] = digest(sphrect.solid_angle(o, corner, ex, ey, dtype=dtype,
                                                                       two_sided=two_sided))
                for uname, uv in uv_sets.items():
                    for t in sphrect.techniques:
                        p, d, dist, pdf = sphrect.sample_directions(t, o, corner, ex, ey, uv, normal=normal,
                                                                    dtype=dtype, two_sided=two_sided)
                        out[f"sample/{key}/{uname}/{t}"] = digest(p, d, dist, pdf)
                        out[f"pdf/{key}/{uname}/{t}"] = digest(
                            sphrect.pdf(t, o, corner, ex, ey, p, normal=normal, dtype=dtype, two_sided=two_sided))
                    pts, _ = sphrect.sample("rectangle", o, corner, ex, ey, uv, dtype=dtype, two_sided=two_sided)
                    out[f"invert/{key}/{uname}"] = digest(sphrect.invert(o, corner, ex, ey, pts, dtype=dtype,
                                                                         two_sided=two_sided))
    if hasattr(sphrect._native, "_study_textbook_rectangle"):
        uv = uv_sets["sobol"]
        for cname, o, corner, ex, ey, normal in core_configs(np.random.default_rng(1)):
            o = np.broadcast_to(o, (len(uv), 3))
            res = sphrect._native._study_textbook_rectangle(o[0], corner, ex, ey, uv)
            out[f"textbook/{cname}"] = digest(*[np.asarray(r) for r in (res if isinstance(res, tuple) else (res,))])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--compare", help="a JSON file written by an earlier run")
    ap.add_argument("--scenes", help="a folder of .sphrect.npz scenes to render too")
    ap.add_argument("--skip-images", action="store_true")
    args = ap.parse_args()
    fp = core_fingerprints()
    if not args.skip_images:
        items = list(scenes().items())
        if args.scenes:
            items += [(os.path.basename(p), sphrect.load_scene(p))
                      for p in sorted(glob.glob(os.path.join(args.scenes, "*.sphrect.npz")))]
        fp.update(image_fingerprints(items))
    if not args.compare:
        json.dump(fp, sys.stdout, indent=0, sort_keys=True)
        print()
        return 0
    with open(args.compare) as f:
        old = json.load(f)
    differ = sorted(k for k in old.keys() & fp.keys() if old[k] != fp[k])
    missing, new = sorted(old.keys() - fp.keys()), sorted(fp.keys() - old.keys())
    for k in differ:
        print("DIFFERS", k)
    for k in missing:
        print("MISSING", k)
    print(f"{len(old.keys() & fp.keys()) - len(differ)} identical, {len(differ)} differ, {len(missing)} missing, "
          f"{len(new)} new ({sum(k.startswith('image/') for k in fp)} images)")
    return 1 if differ or missing else 0


if __name__ == "__main__":
    sys.exit(main())
