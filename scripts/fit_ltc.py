#!/usr/bin/python3
"""Fit linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016) to the renderer's isotropic GGX lobe.

The lobe is the cosine-weighted GGX reflection without Fresnel, f(wi) = D(h) G2(wo, wi) / (4 wo.z) for wi.z > 0
(native/render/bsdf/microfacet.h: GgxD, the height-correlated GgxG2).  In the frame with wo = (sin t, 0, cos t),
the LTC with matrix M = [[a, 0, b], [0, c, 0], [d, 0, 1]] has the density

    D(w) = D_o(w_o) |det M^-1| / |M^-1 w|^3,  w_o = M^-1 w / |M^-1 w|,  D_o(w_o) = max(0, w_o.z) / pi,

and (a, b, c, d) minimise the L3 distance between D and the normalised lobe f / |f| (|f|: the albedo), estimated
with fixed quasi-random points drawn from both (the visible-normal sampling of GGX and the LTC itself) and
combined by the balance heuristic, so that the objective is a deterministic, smooth function of the parameters
(Nelder-Mead, warm-started from the neighbouring cell).

The grid: alpha_i = max(ALPHA_MIN, (i / (N - 1))^2) and cos theta_j = 1 - (j / (N - 1))^2 (floored at COS_MIN),
i.e. uniform in sqrt(alpha) and sqrt(1 - cos theta).  Writes native/core/ltc_ggx_table.h and prints the accuracy
of every cell: the relative L1 error int |D - f / |f|| dw (0: exact, 2: disjoint) and the albedo |f|.

    /usr/bin/python3 scripts/fit_ltc.py [--size 32] [--out native/core/ltc_ggx_table.h] [--report FILE]
"""

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.optimize import minimize
from scipy.stats import qmc

ALPHA_MIN = 1e-3
COS_MIN = 1e-3


# ---------------------------------------------------------------- the GGX lobe

def ggx_d(cos_h, alpha):
    c2 = cos_h * cos_h
    a2 = alpha * alpha
    den = c2 * (a2 - 1) + 1
    return a2 / (np.pi * den * den)


def ggx_lambda(cos_w, alpha):
    c2 = np.maximum(cos_w * cos_w, 1e-300)
    tan2 = np.maximum(0.0, 1 - c2) / c2
    return 0.5 * (-1 + np.sqrt(1 + alpha * alpha * tan2))


def lobe(wo, wi, alpha):
    """f(wi) = D G2 / (4 wo.z), 0 below the horizon."""
    h = wo[None, :] + wi
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    up = wi[:, 2] > 0
    g2 = 1 / (1 + ggx_lambda(wo[2], alpha) + ggx_lambda(np.where(up, wi[:, 2], 1.0), alpha))
    return np.where(up, ggx_d(h[:, 2], alpha) * g2 / (4 * wo[2]), 0.0)


def vndf_pdf(wo, wi, alpha):
    """Solid-angle density of wi = reflect(wo, h), h from the visible normals: G1(wo) D(h) / (4 wo.z)."""
    h = wo[None, :] + wi
    n = np.linalg.norm(h, axis=1, keepdims=True)
    h = h / np.maximum(n, 1e-300)
    g1 = 1 / (1 + ggx_lambda(wo[2], alpha))
    return np.where(h[:, 2] > 0, g1 * ggx_d(h[:, 2], alpha) / (4 * wo[2]), 0.0)


def sample_vndf(wo, alpha, u):
    """Heitz 2018's visible-normal sampling, then the reflection of wo."""
    vh = np.array([alpha * wo[0], alpha * wo[1], wo[2]])
    vh /= np.linalg.norm(vh)
    lensq = vh[0] ** 2 + vh[1] ** 2
    t1 = np.array([-vh[1], vh[0], 0.0]) / np.sqrt(lensq) if lensq > 0 else np.array([1.0, 0.0, 0.0])
    t2 = np.cross(vh, t1)
    r = np.sqrt(u[:, 0])
    phi = 2 * np.pi * u[:, 1]
    p1 = r * np.cos(phi)
    p2 = r * np.sin(phi)
    s = 0.5 * (1 + vh[2])
    p2 = (1 - s) * np.sqrt(np.maximum(0.0, 1 - p1 * p1)) + s * p2
    p3 = np.sqrt(np.maximum(0.0, 1 - p1 * p1 - p2 * p2))
    nh = p1[:, None] * t1 + p2[:, None] * t2 + p3[:, None] * vh
    h = np.stack([alpha * nh[:, 0], alpha * nh[:, 1], np.maximum(1e-7, nh[:, 2])], axis=1)
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    return 2 * (h @ wo)[:, None] * h - wo[None, :]


# ---------------------------------------------------------------- the LTC

def matrix(params):
    log_a, b, log_c, d = params
    return np.array([[np.exp(log_a), 0, b], [0, np.exp(log_c), 0], [d, 0, 1.0]])


def ltc_pdf(m_inv, det_inv, w):
    wo = w @ m_inv.T
    length = np.linalg.norm(wo, axis=1)
    return np.maximum(0.0, wo[:, 2] / length) / np.pi * det_inv / length ** 3


def cosine_directions(u):
    r = np.sqrt(u[:, 0])
    phi = 2 * np.pi * u[:, 1]
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1 - u[:, 0]))], axis=1)


class Cell:
    """One (alpha, theta): the lobe's fixed samples and the LTC's fixed quasi-random numbers."""

    def __init__(self, alpha, cos_theta, u_lobe, u_ltc):
        self.alpha = alpha
        self.wo = np.array([np.sqrt(1 - cos_theta * cos_theta), 0.0, cos_theta])
        self.w1 = sample_vndf(self.wo, alpha, u_lobe)
        self.q1_w1 = vndf_pdf(self.wo, self.w1, alpha)
        f = lobe(self.wo, self.w1, alpha)
        self.albedo = float(np.mean(np.where(self.q1_w1 > 0, f / np.maximum(self.q1_w1, 1e-300), 0.0)))
        self.p_w1 = f / self.albedo
        self.cos_ltc = cosine_directions(u_ltc)

    def parts(self, params):
        """The samples of both techniques with the lobe's and the LTC's densities and the balance weights' sum."""
        m = matrix(params)
        m_inv = np.linalg.inv(m)
        det_inv = abs(np.linalg.det(m_inv))
        w2 = self.cos_ltc @ m.T
        w2 /= np.linalg.norm(w2, axis=1, keepdims=True)
        n1, n2 = len(self.w1), len(w2)
        g_w1 = ltc_pdf(m_inv, det_inv, self.w1)
        g_w2 = ltc_pdf(m_inv, det_inv, w2)
        p_w2 = lobe(self.wo, w2, self.alpha) / self.albedo
        q1_w2 = vndf_pdf(self.wo, w2, self.alpha)
        p = np.concatenate([self.p_w1, p_w2])
        g = np.concatenate([g_w1, g_w2])
        mix = np.concatenate([n1 * self.q1_w1 + n2 * g_w1, n1 * q1_w2 + n2 * g_w2])
        return p, g, mix

    def l3(self, params):
        p, g, mix = self.parts(params)
        ok = mix > 0
        return float(np.sum(np.abs(p[ok] - g[ok]) ** 3 / mix[ok]))

    def l1(self, params):
        p, g, mix = self.parts(params)
        ok = mix > 0
        return float(np.sum(np.abs(p[ok] - g[ok]) / mix[ok]))


def quasi_random(n, seed):
    return qmc.Sobol(2, scramble=True, seed=seed).random(n)


def fit(size, samples):
    alphas = np.maximum(ALPHA_MIN, (np.arange(size) / (size - 1)) ** 2)
    cosines = np.maximum(COS_MIN, 1 - (np.arange(size) / (size - 1)) ** 2)
    u_lobe, u_ltc = quasi_random(samples, 1), quasi_random(samples, 2)
    # The accuracy is measured on other, larger point sets than the fit's.
    check_lobe, check_ltc = quasi_random(4 * samples, 3), quasi_random(4 * samples, 4)
    table = np.zeros((size, size, 4))
    albedo = np.zeros((size, size))
    rel_l1 = np.zeros((size, size))
    previous_row = None
    # From the roughest lobe (near a cosine) down, each cell started from the better of its fitted neighbours
    # (rougher, same theta; same alpha, previous theta).
    for i in reversed(range(size)):
        row = []
        for j in range(size):
            cell = Cell(alphas[i], cosines[j], u_lobe, u_ltc)
            starts = []
            if previous_row is not None:
                rougher = previous_row[j].copy()
                rougher[0] += np.log(alphas[i] / alphas[i + 1])
                rougher[2] += np.log(alphas[i] / alphas[i + 1])
                starts.append(rougher)
            if j > 0:
                starts.append(row[j - 1].copy())
            if not starts:
                starts.append(np.array([np.log(alphas[i]), 0.0, np.log(alphas[i]), 0.0]))
            start = min(starts, key=cell.l3)
            best = minimize(cell.l3, start, method="Nelder-Mead",
                            options={"xatol": 1e-6, "fatol": 1e-10, "maxiter": 2000, "maxfev": 4000})
            params = best.x
            row.append(params)
            m = matrix(params)
            table[i, j] = [m[0, 0], m[0, 2], m[1, 1], m[2, 0]]
            check = Cell(alphas[i], cosines[j], check_lobe, check_ltc)
            albedo[i, j] = check.albedo
            rel_l1[i, j] = check.l1(params)
        previous_row = row
        print(f"alpha {alphas[i]:.4g}: relative L1 error min {min(rel_l1[i]):.3g} max {max(rel_l1[i]):.3g}",
              flush=True)
    return alphas, cosines, table, albedo, rel_l1


HEADER = """\
// Generated by scripts/fit_ltc.py ({command}); do not edit.
// Linearly transformed cosines fitted to the renderer's isotropic GGX lobe D G2 / (4 wo.z) (no Fresnel): per
// (alpha, cos theta_o), M = [[a, 0, b], [0, c, 0], [d, 0, 1]] in the frame with wo = (sin theta_o, 0, cos theta_o),
// and the lobe's albedo (its integral).  The grid (kLtcGgxSize^2 cells) is uniform in sqrt(alpha) and in
// sqrt(1 - cos theta_o): alpha_i = max(kLtcGgxAlphaMin, (i / (kLtcGgxSize - 1))^2),
// cos theta_j = max(kLtcGgxCosMin, 1 - (j / (kLtcGgxSize - 1))^2).  The fit's accuracy: docs/rectangle_ltc.md.
#pragma once

namespace sphrect {{

constexpr int kLtcGgxSize = {size};
constexpr double kLtcGgxAlphaMin = {alpha_min!r};
constexpr double kLtcGgxCosMin = {cos_min!r};

struct LtcGgxEntry {{
    double a, b, c, d;  // M's entries m00, m02, m11, m20
    double albedo;
}};

// kLtcGgxTable[i * kLtcGgxSize + j]: alpha_i, cos theta_j.
constexpr LtcGgxEntry kLtcGgxTable[kLtcGgxSize * kLtcGgxSize] = {{
{rows}
}};

}}  // namespace sphrect
"""


def write_header(path, command, alphas, cosines, table, albedo):
    size = len(alphas)
    lines = []
    for i in range(size):
        for j in range(size):
            a, b, c, d = table[i, j]
            lines.append(f"    {{{a:.12g}, {b:.12g}, {c:.12g}, {d:.12g}, {albedo[i, j]:.12g}}},")
    Path(path).write_text(HEADER.format(command=command, size=size, alpha_min=ALPHA_MIN, cos_min=COS_MIN,
                                        rows="\n".join(lines)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=32, help="grid points per axis")
    parser.add_argument("--samples", type=int, default=2048, help="points per technique in the fit's objective")
    parser.add_argument("--out", default=str(Path(__file__).resolve().parent.parent / "native/core/ltc_ggx_table.h"))
    parser.add_argument("--report", help="also write the per-cell accuracy here (text)")
    args = parser.parse_args()
    start = time.time()
    alphas, cosines, table, albedo, rel_l1 = fit(args.size, args.samples)
    command = f"scripts/fit_ltc.py --size {args.size} --samples {args.samples}"
    write_header(args.out, command, alphas, cosines, table, albedo)
    print(f"fit of {args.size}x{args.size} cells in {time.time() - start:.0f} s; wrote {args.out}")
    print(f"relative L1 error: median {np.median(rel_l1):.3g}, 90th percentile {np.percentile(rel_l1, 90):.3g},"
          f" max {rel_l1.max():.3g}")
    for lo, hi in [(0, 0.1), (0.1, 0.3), (0.3, 0.6), (0.6, 1.01)]:
        sel = (alphas >= lo) & (alphas < hi)
        for name, cols in [("cos>=0.5", cosines >= 0.5), ("cos<0.5", cosines < 0.5)]:
            block = rel_l1[np.ix_(sel, cols)]
            print(f"  alpha in [{lo}, {min(hi, 1)}), {name}: median {np.median(block):.3g} max {block.max():.3g}")
    if args.report:
        with open(args.report, "w") as out:
            out.write("alpha cos_theta a b c d albedo relative_L1\n")
            for i in range(len(alphas)):
                for j in range(len(cosines)):
                    a, b, c, d = table[i, j]
                    out.write(f"{alphas[i]:.6g} {cosines[j]:.6g} {a:.6g} {b:.6g} {c:.6g} {d:.6g} "
                              f"{albedo[i, j]:.6g} {rel_l1[i, j]:.4g}\n")


if __name__ == "__main__":
    main()
