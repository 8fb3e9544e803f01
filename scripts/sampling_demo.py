#!/usr/bin/env python3
"""The sampling demo: a 16 x 16 Hammersley set warped onto a rectangular light by each technique,
like the figures of Urena, Fajardo & King (EGSR 2013).

For one shading point, each technique's column shows
  top:    the points on the planar rectangle (the light's own coordinates), with the images of
          the iso-parameter lines u = const and v = const;
  bottom: the same on the unit sphere around the shading point, in the Lambert azimuthal
          equal-area projection centred on the direction to the light's centre: areas in this
          view are proportional to solid angle, so a solid-angle-uniform map spreads its
          points evenly here, while area sampling spreads them evenly in the top row.

    PYTHONPATH=build/python /usr/bin/python3 scripts/sampling_demo.py --out out
writes out/sampling_demo.png.
"""
import argparse
import os
import sys

import numpy as np

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

try:
    import sphrect
except ImportError:  # run from the repository without PYTHONPATH: use the default build
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "python"))
    import sphrect

TECHNIQUES = sphrect.techniques  # area, triangles, rectangle, rectangle_cosine, rectangle_projected

# One shading point (the origin) under a 3 x 2 light in the plane z = 0.5 that starts just beside
# it: the near edge subtends far more solid angle than the far one, so the techniques differ.
ORIGIN = np.array([0.0, 0.0, 0.0])
CORNER = np.array([-1.5, 0.3, 0.5])
EDGE_X = np.array([3.0, 0.0, 0.0])
EDGE_Y = np.array([0.0, 2.0, 0.0])
NORMAL = np.array([0.3, 0.2, 1.0]) / np.linalg.norm([0.3, 0.2, 1.0])   # for rectangle_cosine and _projected
ISO_LINES = 9     # u = 0, 1/8, ..., 1 and the same for v


def light_coords(points):
    """(s, t) in [0, 3] x [0, 2]: the point's position on the light along edge_x and edge_y."""
    rel = points - CORNER
    return np.stack([rel @ EDGE_X / np.linalg.norm(EDGE_X), rel @ EDGE_Y / np.linalg.norm(EDGE_Y)], axis=1)


def equal_area_projection(points):
    """Lambert azimuthal equal-area projection of the directions origin -> points, centred on
    the direction to the light's centre (a disc of radius 2 is the whole sphere)."""
    centre = CORNER + 0.5 * (EDGE_X + EDGE_Y) - ORIGIN
    w = centre / np.linalg.norm(centre)
    a = np.cross(w, [1.0, 0.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(w, a)
    d = points - ORIGIN
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    k = np.sqrt(2.0 / (1.0 + d @ w))
    # Axes chosen so that edge_x points right and the near edge is at the bottom, as in the top row.
    return np.stack([-k * (d @ b), k * (d @ a)], axis=1)


def break_jumps(xy, limit):
    """Insert NaN rows where consecutive points jump by more than `limit`, so a curve that a
    map sends to two places (the triangles technique's diagonal) is not drawn across the gap."""
    jumps = np.linalg.norm(np.diff(xy, axis=0), axis=1) > limit
    return np.insert(xy, np.nonzero(jumps)[0] + 1, np.nan, axis=0)


def warp(technique, uv):
    return sphrect.sample(technique, ORIGIN, CORNER, EDGE_X, EDGE_Y, uv, normal=NORMAL, dtype="float64")


def iso_curves(technique, samples=200):
    """Images of u = const and v = const, as lists of [samples, 3] point arrays."""
    t = np.linspace(0.0, 1.0, samples)
    curves = []
    for c in np.linspace(0.0, 1.0, ISO_LINES):
        for uv in (np.stack([np.full_like(t, c), t], 1), np.stack([t, np.full_like(t, c)], 1)):
            points, pdf = warp(technique, uv)
            curves.append(points[pdf > 0])
    return curves


def rectangle_outline(samples=400):
    t = np.linspace(0.0, 1.0, samples)
    z, o = np.zeros_like(t), np.ones_like(t)
    st = np.concatenate([np.stack(p, 1) for p in ((t, z), (o, t), (1 - t, o), (z, 1 - t))])
    return CORNER + st[:, :1] * EDGE_X + st[:, 1:] * EDGE_Y


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="out", help="output directory (default: out/)")
    parser.add_argument("--pattern", default="hammersley", choices=sphrect.patterns,
                        help="sample pattern (default: hammersley)")
    parser.add_argument("--n", type=int, default=256, help="number of points (default: 256 = 16 x 16)")
    parser.add_argument("--seed", type=int, default=0, help="pattern seed (default: 0)")
    args = parser.parse_args(argv)

    uv = sphrect.pattern(args.pattern, args.n, seed=args.seed).astype(np.float64)
    omega = sphrect.solid_angle(ORIGIN, CORNER, EDGE_X, EDGE_Y, dtype="float64")
    outline = rectangle_outline()
    colours = plt.get_cmap("viridis")(uv[:, 0])   # colour = u: shows how each map orders the points

    fig, axes = plt.subplots(2, len(TECHNIQUES), figsize=(4.2 * len(TECHNIQUES), 6.0), constrained_layout=True)
    sphere_outline = equal_area_projection(outline)
    for col, technique in enumerate(TECHNIQUES):
        points, dirs, _, pdf = sphrect.sample_directions(technique, ORIGIN, CORNER, EDGE_X, EDGE_Y, uv,
                                                         normal=NORMAL, dtype="float64")
        valid = pdf > 0
        # Per-sample estimates of the solid angle (1/pdf) and of the irradiance from a unit-radiance
        # light (cos / pdf): their relative spread is each technique's noise for these integrals
        # (0 for the solid angle with an exactly solid-angle-uniform map).
        omega_est = np.where(valid, 1.0 / np.where(valid, pdf, 1.0), 0.0)
        irradiance_est = omega_est * np.maximum(dirs @ NORMAL, 0.0)
        stats = (f"rel. sd per sample: solid angle {omega_est.std() / omega_est.mean():.3f}, "
                 f"irradiance {irradiance_est.std() / irradiance_est.mean():.3f}")
        curves = iso_curves(technique)

        top, bottom = axes[0, col], axes[1, col]
        for c in curves:
            top.plot(*break_jumps(light_coords(c), 0.3).T, color="0.75", lw=0.6, zorder=1)
            bottom.plot(*break_jumps(equal_area_projection(c), 0.1).T, color="0.75", lw=0.6, zorder=1)
        top.plot(*light_coords(outline).T, color="k", lw=1.0)
        bottom.plot(*sphere_outline.T, color="k", lw=1.0)
        top.scatter(*light_coords(points[valid]).T, s=7, c=colours[valid], zorder=2)
        bottom.scatter(*equal_area_projection(points[valid]).T, s=7, c=colours[valid], zorder=2)
        top.set_title(f"{technique}\n{stats}", fontsize=9)
        for ax in (top, bottom):
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
        # The near edge (t = 0, closest to the shading point) is at the bottom of the top row.
        top.set_xlabel("on the light (near edge at the bottom)", fontsize=8)
        bottom.set_xlabel("on the sphere (equal-area projection)", fontsize=8)

    fig.suptitle(f"{args.n} {args.pattern} points warped onto a rectangular light "
                 f"(solid angle {omega:.4f} sr; colour = u)", fontsize=12)
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "sampling_demo.png")
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")
    return path


if __name__ == "__main__":
    main()
