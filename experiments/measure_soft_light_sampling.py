#!/usr/bin/env python3
"""Uniform cone sampling of soft lights (core/cone.h, what the renderer's light samples draw for a point or spot light
with a radius and a sun with an angle) against the simplest unbiased alternatives: the MSE at equal samples of the
irradiance at a point facing +Z, estimated from N directions by

- `cone`: sphrect.sample_uniform_cone about the light's direction, L cos+ / pdf;
- `disc area`: points uniform on the light's disc (Cycles' model: a disc of radius r facing the point, at distance
  d; the sun's disc of radius tan(alpha) one unit away), L cos+ / pdf converted to solid angle (d'^2 / (A cos_l));
- `cosine`: cosine-weighted directions over the hemisphere (what a diffuse BSDF sample draws), pi L inside the cone;
- `uniform sphere`: uniform directions over the sphere, 4 pi L cos+ inside the cone;

each against the exact irradiance.  A point light's disc has uniform radiance L = I / (pi r^2) and subtends the cone
of half-angle atan(r / d): above the horizon its irradiance is L pi sin^2(alpha) cos(theta), theta the direction's
angle to the normal.  A sun's radiance is E / (pi tan^2(alpha) cos^3(t)) at t from its axis, and its irradiance at
normal incidence E (Cycles 3.4's model: docs/renderer.md); tilted, E cos(theta) when the cone is above the horizon.

    PYTHONPATH=build/python /usr/bin/python3 experiments/measure_soft_light_sampling.py [--samples 4] [--trials 20000]

Prints per light the exact irradiance, each strategy's MSE and its ratio to the cone's (how many times more samples
it needs for the cone's error; inf where it never finds the light at these samples)."""
import argparse
import math

import numpy as np

import sphrect


def frame(axis):
    """Orthonormal (t, b, axis) with axis the third column."""
    axis = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0, 1.0, 0])
    t = np.cross(helper, axis)
    t /= np.linalg.norm(t)
    return np.stack([t, np.cross(axis, t), axis], axis=1)


def lights():
    """(name, axis towards the light, half-angle alpha, radiance(cos to the axis), exact irradiance)."""
    out = []
    for r_over_d, theta_deg in [(0.01, 0), (0.1, 30), (0.5, 30), (1.0, 10), (2.0, 0)]:
        alpha = math.atan(r_over_d)
        theta = math.radians(theta_deg)
        if theta + alpha > math.pi / 2:
            continue
        L = 1.0 / (math.pi * r_over_d ** 2)  # intensity 1 at unit distance: I / (pi r^2)
        axis = np.array([math.sin(theta), 0.0, math.cos(theta)])
        out.append((f"point light r/d = {r_over_d:g}, {theta_deg} deg off the normal", axis, alpha,
                    lambda c, L=L: np.full_like(c, L), L * math.pi * math.sin(alpha) ** 2 * math.cos(theta)))
    for angle_deg, theta_deg in [(0.53, 40), (11.5, 30), (40, 20)]:
        alpha = math.radians(angle_deg) / 2
        theta = math.radians(theta_deg)
        axis = np.array([math.sin(theta), 0.0, math.cos(theta)])
        out.append((f"sun of {angle_deg:g} deg, {theta_deg} deg off the normal", axis, alpha,
                    lambda c, a=alpha: 1.0 / (math.pi * math.tan(a) ** 2 * c ** 3), math.cos(theta)))
    return out


def estimate(name, axis, alpha, radiance, n, trials, rng):
    """[trials] irradiance estimates of n directions each by strategy `name`."""
    m = n * trials
    to_world = frame(axis)
    one_minus_cos = 2 * math.sin(alpha / 2) ** 2
    cos_alpha = math.cos(alpha)
    uv = rng.random((m, 2))
    if name == "cone":
        local, pdf = sphrect.sample_uniform_cone(one_minus_cos, uv)
        w = local @ to_world.T
        value = radiance(local[:, 2]) * np.clip(w[:, 2], 0, None) / pdf
    elif name == "disc area":
        # A point of the disc of radius tan(alpha) one unit along the axis (the same cone; scale-free).
        rho, phi = math.tan(alpha) * np.sqrt(uv[:, 0]), 2 * math.pi * uv[:, 1]
        p = np.stack([rho * np.cos(phi), rho * np.sin(phi), np.ones(m)], axis=1)
        dist2 = (p ** 2).sum(axis=1)
        local = p / np.sqrt(dist2)[:, None]
        pdf = dist2 / (math.pi * math.tan(alpha) ** 2 * local[:, 2])  # area pdf to solid angle
        w = local @ to_world.T
        value = radiance(local[:, 2]) * np.clip(w[:, 2], 0, None) / pdf
    else:
        if name == "cosine":
            r, phi = np.sqrt(uv[:, 0]), 2 * math.pi * uv[:, 1]
            w = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - uv[:, 0])], axis=1)
            weight = np.full(m, math.pi)  # cos / pdf
        else:
            z = 1 - 2 * uv[:, 0]
            r, phi = np.sqrt(np.clip(1 - z * z, 0, None)), 2 * math.pi * uv[:, 1]
            w = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
            weight = 4 * math.pi * np.clip(z, 0, None)
        c = w @ (axis / np.linalg.norm(axis))
        inside = c >= cos_alpha
        value = np.where(inside, radiance(np.where(inside, c, 1.0)) * weight, 0.0)
    return value.reshape(trials, n).mean(axis=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=4, help="directions per estimate")
    ap.add_argument("--trials", type=int, default=20000)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    strategies = ["cone", "disc area", "cosine", "uniform sphere"]
    print(f"{a.samples} directions per estimate, {a.trials} estimates; MSE relative to the exact value squared, "
          "and its ratio to the cone's")
    for label, axis, alpha, radiance, exact in lights():
        rng = np.random.default_rng(a.seed)
        mse = {s: float(np.mean((estimate(s, axis, alpha, radiance, a.samples, a.trials, rng) - exact) ** 2))
               / exact ** 2 for s in strategies}
        ratios = "  ".join(f"{s} {mse[s] / mse['cone']:.3g}x" if mse["cone"] > 0 else f"{s} {mse[s]:.3g}"
                           for s in strategies[1:])
        print(f"{label:48}  E = {exact:.5g}  cone MSE {mse['cone']:.3g}  {ratios}")


if __name__ == "__main__":
    main()
