#!/usr/bin/env python3
"""Importance sampling of image worlds (render/environment_light.h) against directions that ignore the image:
the MSE at equal samples of the irradiance at a point facing +Z, estimated from N directions by

- `environment`: SampleEnvironment (the image's luminance x solid angle, what the renderer's light samples draw),
  L cos+ / pdf;
- `cosine`: cosine-weighted directions over the hemisphere (what a diffuse BSDF sample draws), pi L;
- `uniform`: uniform directions over the sphere, 4 pi L cos+;
- `mis`: half the directions from each of `environment` and `cosine`, combined by the balance heuristic (the
  renderer's light sample and diffuse BSDF sample with MIS);

each against the exact irradiance (closest interpolation: per pixel its radiance times the integral of cos over its
cell above the horizon), over worlds from a uniform sky to a small sun in a dark sky.

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_environment_sampling.py [--samples 16] [--trials 4000]

Prints per world the exact irradiance, each strategy's MSE and the ratio of the cosine and uniform MSE to the
environment's (how many times more samples they need for its error)."""
import argparse

import numpy as np

import sphrect


def exact_irradiance(image):
    """E at a point facing +Z under `image` [H, W] (red channel, closest interpolation, identity to_world)."""
    h, w = image.shape
    theta_top = np.pi * (1 - (np.arange(h) + 1) / h)   # each row's edges, theta = pi (1 - v)
    theta_bottom = np.pi * (1 - np.arange(h) / h)
    a, b = np.minimum(theta_top, np.pi / 2), np.minimum(theta_bottom, np.pi / 2)
    per_row = (2 * np.pi / w) * (np.sin(b) ** 2 - np.sin(a) ** 2) / 2  # integral of cos over one cell
    return float((image * per_row[:, None]).sum())


def worlds(h=64, w=128):
    v, u = np.meshgrid((np.arange(h) + 0.5) / h, (np.arange(w) + 0.5) / w, indexing="ij")
    sky = 0.05 + 0.2 * np.clip(2 * v - 1, 0, 1)
    out = {"uniform sky": np.full((h, w), 0.3)}
    out["sky gradient"] = sky
    blob = np.exp(-(((u - 0.3) * 2) ** 2 + (v - 0.75) ** 2) / (2 * 0.04 ** 2))
    out["sky + broad sun (x50)"] = sky + 50 * blob
    sun = sky.copy()
    sun[int(0.8 * h), int(0.3 * w)] = 5000.0  # one pixel: a ~2.8 x 2.8 degree sun
    out["sky + one-pixel sun"] = sun
    return out


def cosine_directions(u):
    r, phi = np.sqrt(u[:, 0]), 2 * np.pi * u[:, 1]
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0, 1 - u[:, 0]))], axis=1)


def uniform_directions(u):
    z = 1 - 2 * u[:, 0]
    r, phi = np.sqrt(np.maximum(0, 1 - z * z)), 2 * np.pi * u[:, 1]
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=16, help="directions per estimate")
    ap.add_argument("--trials", type=int, default=4000, help="estimates per strategy")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    n = args.samples * args.trials
    print(f"{args.samples} directions per estimate, {args.trials} estimates; MSE of the irradiance at a point "
          "facing +Z")
    print(f"{'world':24s} {'exact E':>10s} {'environment':>12s} {'cosine':>12s} {'uniform':>12s} "
          f"{'mis':>12s} {'cos/env':>9s} {'unif/env':>9s} {'cos/mis':>9s}")
    for name, red in worlds().items():
        image = np.repeat(red[..., None], 3, axis=2).astype(np.float32)
        sampler = sphrect.EnvironmentSampler(image, interpolation="closest")
        exact = exact_irradiance(image[..., 0].astype(np.float64))
        u = rng.random((n, 2))
        dirs, pdf = sampler.sample(u)
        radiance = sampler.radiance(dirs)[:, 0]
        env = np.where(pdf > 0, radiance * np.maximum(dirs[:, 2], 0) / np.where(pdf > 0, pdf, 1), 0.0)
        cos_dirs = cosine_directions(rng.random((n, 2)))
        cos = np.pi * sampler.radiance(cos_dirs)[:, 0]
        uni_dirs = uniform_directions(rng.random((n, 2)))
        uni = 4 * np.pi * sampler.radiance(uni_dirs)[:, 0] * np.maximum(uni_dirs[:, 2], 0)
        # MIS: pairs of an environment and a cosine direction (the first half of each set), balance heuristic.
        half = n // 2
        pdf_cos_at_env = np.maximum(dirs[:half, 2], 0) / np.pi
        pdf_env_at_cos = sampler.pdf(cos_dirs[:half])[:, 0]
        cos_at_env = np.maximum(dirs[:half, 2], 0)
        mis = radiance[:half] * cos_at_env / np.maximum(pdf[:half] + pdf_cos_at_env, 1e-30) + \
            cos[:half] / np.pi * cos_dirs[:half, 2] / np.maximum(pdf_env_at_cos + cos_dirs[:half, 2] / np.pi, 1e-30)
        mse = {}
        for key, values, per in (("environment", env, args.samples), ("cosine", cos, args.samples),
                                 ("uniform", uni, args.samples), ("mis", mis, args.samples // 2)):
            estimates = values[:args.trials * per].reshape(args.trials, per).mean(axis=1)
            mse[key] = float(np.mean((estimates - exact) ** 2))
        ratio = lambda k: mse[k] / mse["environment"] if mse["environment"] > 0 else float("inf")
        print(f"{name:24s} {exact:10.4g} {mse['environment']:12.4g} {mse['cosine']:12.4g} {mse['uniform']:12.4g} "
              f"{mse['mis']:12.4g} {ratio('cosine'):9.3g} {ratio('uniform'):9.3g} "
              f"{mse['cosine'] / mse['mis']:9.3g}")


if __name__ == "__main__":
    main()
