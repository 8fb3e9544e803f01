"""Chi-square goodness-of-fit test of a light-sampling technique against its own pdf: the project's
one chi-square harness (the C++ tests have none; it checks the core through the bindings, i.e.
LightSampler<K, T> as the renderer calls it, in both precisions).

In the manner of Mitsuba 3's ``chi2`` warp tests: draw ``sample_count`` independent samples with
``sphrect.sample``, histogram the points over a grid of cells on the light, compute each cell's
expected count by integrating the technique's *own* ``sphrect.pdf`` over the cell (adaptive
Gauss-Legendre quadrature in the light's (s, t) coordinates, converted to solid angle), pool cells expecting fewer
than 5 samples, and compare with Pearson's chi-square statistic.

The grid's lines along each edge are half uniform, half at equal solid angle of the strip they cut
off, so that cells stay small where any technique concentrates its samples (near the shading
point in grazing configurations) and where the area technique does (everywhere).  Samples with
pdf 0 (invalid) form one more cell whose expected probability is the pdf's missing mass.

False failures: each call uses a fixed seed, so results are reproducible; a correct technique
fails a test with probability ``alpha`` where ``alpha`` is the Sidak-corrected share of a
suite-wide ``significance`` spread over ``test_count`` tests: 1 - (1 - alpha)^test_count
= significance.
"""
from __future__ import annotations

import dataclasses
from typing import Callable, Optional, Sequence

import numpy as np
from scipy import special, stats

import sphrect

MIN_EXPECTED = 5.0


@dataclasses.dataclass
class LightConfig:
    """A shading point and a rectangular light, as sphrect's functions take them."""
    name: str
    origin: Sequence[float]
    corner: Sequence[float]
    edge_x: Sequence[float]
    edge_y: Sequence[float]
    normal: Optional[Sequence[float]] = None
    two_sided: bool = True

    def light_args(self):
        return (np.asarray(self.origin, float), np.asarray(self.corner, float), np.asarray(self.edge_x, float),
                np.asarray(self.edge_y, float))

    def __str__(self):
        return self.name


@dataclasses.dataclass
class Chi2Result:
    technique: str
    config: str
    dtype: str
    statistic: float
    dof: int
    p_value: float
    alpha: float
    cells: int
    pooled_cells: int
    invalid_samples: int
    off_light_samples: int
    total_probability: float   # integral of the pdf over the light (1 for a normalised pdf)
    worst: str                 # the cells that contribute most, for the failure message

    @property
    def passed(self) -> bool:
        return self.off_light_samples == 0 and self.p_value >= self.alpha

    def __str__(self):
        return (f"chi2 {self.technique} [{self.config}, {self.dtype}]: statistic {self.statistic:.1f} "
                f"dof {self.dof} p-value {self.p_value:.3g} (alpha {self.alpha:.2g}); {self.cells} cells, "
                f"{self.pooled_cells} pooled; invalid samples {self.invalid_samples}; samples off the light "
                f"{self.off_light_samples}; integral of pdf {self.total_probability:.6f}; worst cells: {self.worst}")


def sidak_alpha(significance: float, test_count: int) -> float:
    """Per-test significance so that test_count independent tests together fail with `significance`."""
    return 1.0 - (1.0 - significance) ** (1.0 / test_count)


def grid_edges(config: LightConfig, resolution: int, axis: int) -> np.ndarray:
    """Cell boundaries in [0, 1] along edge_x (axis 0) or edge_y (axis 1): resolution/2 uniform
    and resolution/2 at equal solid angle of the strip [0, s] x [0, 1]."""
    origin, corner, ex, ey = config.light_args()
    edge, other = (ex, ey) if axis == 0 else (ey, ex)
    half = max(resolution // 2, 1)
    uniform = np.linspace(0.0, 1.0, resolution - half + 1)

    def strip(s):
        e_s = edge * s
        return sphrect.solid_angle(origin, corner, e_s, other, dtype="float64") if axis == 0 else \
            sphrect.solid_angle(origin, corner, other, e_s, dtype="float64")

    total = strip(1.0)
    lines = []
    if np.isfinite(total) and total > 0:
        for i in range(1, half):
            target, lo, hi = total * i / half, 0.0, 1.0
            for _ in range(48):
                mid = 0.5 * (lo + hi)
                if strip(mid) < target:
                    lo = mid
                else:
                    hi = mid
            lines.append(0.5 * (lo + hi))
    # Equal-angle lines that nearly coincide with uniform ones would only add sliver cells.
    lines = [x for x in lines if np.min(np.abs(uniform - x)) > 0.05 / resolution]
    edges = np.unique(np.concatenate([uniform, lines]))
    keep = np.concatenate([[True], np.diff(edges) > 1e-12])
    edges = edges[keep]
    edges[-1] = 1.0
    return edges


def adaptive_cell_integrals(integrand: Callable, s_edges: np.ndarray, t_edges: np.ndarray, nodes: int = 6,
                            rtol: float = 1e-5, atol: float = 1e-10, max_depth: int = 12) -> np.ndarray:
    """Integral of integrand(s, t) (arrays in, array out) over each cell of the grid,
    [len(s_edges)-1, len(t_edges)-1]: Gauss-Legendre (nodes x nodes) on the cell against the sum over
    its four quarters, splitting the cells where they disagree by more than rtol (or atol)."""
    x, w = special.roots_legendre(nodes)
    x, w = 0.5 * (x + 1.0), 0.5 * w                      # on [0, 1]
    wx = (w[:, None] * w[None, :]).reshape(-1)

    def gauss(cells):                                     # cells [K, 4] = (s0, s1, t0, t1)
        ds, dt = cells[:, 1] - cells[:, 0], cells[:, 3] - cells[:, 2]
        s = cells[:, 0, None, None] + ds[:, None, None] * x[None, :, None]
        t = cells[:, 2, None, None] + dt[:, None, None] * x[None, None, :]
        s, t = np.broadcast_arrays(s, t)
        f = integrand(s.reshape(-1), t.reshape(-1)).reshape(len(cells), nodes * nodes)
        return (f * wx).sum(axis=1) * ds * dt

    def quarters(cells):
        sm, tm = 0.5 * (cells[:, 0] + cells[:, 1]), 0.5 * (cells[:, 2] + cells[:, 3])
        s0, s1, t0, t1 = cells.T
        return np.stack([np.stack(q, axis=1) for q in ((s0, sm, t0, tm), (sm, s1, t0, tm),
                                                        (s0, sm, tm, t1), (sm, s1, tm, t1))], axis=1).reshape(-1, 4)

    S0, T0 = np.meshgrid(s_edges[:-1], t_edges[:-1], indexing="ij")
    S1, T1 = np.meshgrid(s_edges[1:], t_edges[1:], indexing="ij")
    cells = np.stack([S0.ravel(), S1.ravel(), T0.ravel(), T1.ravel()], axis=1)
    owner = np.arange(len(cells))
    result = np.zeros(len(cells))
    coarse = gauss(cells)
    for depth in range(max_depth):
        sub = quarters(cells)
        fine_each = gauss(sub)
        fine = fine_each.reshape(-1, 4).sum(axis=1)
        done = np.abs(fine - coarse) <= rtol * np.abs(fine) + atol
        if depth == max_depth - 1 or len(sub) > 400_000:
            done[:] = True
        np.add.at(result, owner[done], fine[done])
        keep = np.repeat(~done, 4)
        cells, coarse, owner = sub[keep], fine_each[keep], np.repeat(owner, 4)[keep]
        if not len(cells):
            break
    return result.reshape(len(s_edges) - 1, len(t_edges) - 1)


def cell_probabilities(technique: str, config: LightConfig, s_edges: np.ndarray, t_edges: np.ndarray,
                       dtype: str, nodes: int = 6, rtol: float = 1e-5, atol: float = 1e-10,
                       max_depth: int = 12, pdf_factor: Optional[Callable] = None,
                       pdf_fn: Optional[Callable] = None) -> np.ndarray:
    """Integral of the technique's solid-angle pdf over each cell, [len(s_edges)-1, len(t_edges)-1].

    With P(s, t) = corner + s ex + t ey, the solid angle element is
    d omega = h |ex x ey| / |P - origin|^3 ds dt, h the origin's distance to the light's plane;
    near a shading point close to the light that factor is sharply peaked, so each cell is
    integrated adaptively (adaptive_cell_integrals).
    `pdf_factor(points)`, when given, multiplies the pdf (how the tests make a wrong one); `pdf_fn(points)`, when
    given, replaces sphrect.pdf (a sampler outside sphrect.techniques)."""
    origin, corner, ex, ey = config.light_args()
    n = np.cross(ex, ey)
    area = np.linalg.norm(n)
    h = abs(np.dot(n / area, origin - corner))

    def integrand(s, t):
        P = corner + s[:, None] * ex + t[:, None] * ey
        d = np.linalg.norm(P - origin, axis=1)
        if pdf_fn is not None:
            pdf = np.asarray(pdf_fn(P), np.float64)
        else:
            pdf = sphrect.pdf(technique, config.origin, config.corner, config.edge_x, config.edge_y, P,
                              normal=config.normal, dtype=dtype, two_sided=config.two_sided).astype(np.float64)
        if pdf_factor is not None:
            pdf = pdf * pdf_factor(P)
        return pdf * h * area / d ** 3

    return adaptive_cell_integrals(integrand, s_edges, t_edges, nodes, rtol, atol, max_depth)


def light_coordinates(points: np.ndarray, config: LightConfig):
    """(s, t) of points on the light: P = corner + s ex + t ey."""
    _, corner, ex, ey = config.light_args()
    rel = np.asarray(points, np.float64) - corner
    return rel @ ex / np.dot(ex, ex), rel @ ey / np.dot(ey, ey)


def pearson(observed: np.ndarray, probability: np.ndarray, invalid: int, sample_count: int):
    """Pearson's statistic of observed cell counts against the cells' probabilities (plus one cell of
    the invalid samples, expecting the probability the cells miss), pooling cells expecting fewer
    than MIN_EXPECTED: (statistic, dof, p_value, pooled_cells, worst cells)."""
    total = float(probability.sum())
    obs = np.concatenate([observed.reshape(-1), [invalid]])
    exp = np.concatenate([probability.reshape(-1), [max(0.0, 1.0 - total)]]) * sample_count
    worst = ""

    # Samples where the pdf says none can be: fail outright (as Mitsuba does).
    impossible = (exp == 0) & (obs > 0)
    if np.any(impossible):
        statistic, dof, p_value, pooled = np.inf, 1, 0.0, 0
        worst = f"{int(obs[impossible].sum())} samples in cells of zero expected count"
    else:
        order = np.argsort(exp)
        exp, obs = exp[order], obs[order]
        low = exp < MIN_EXPECTED
        pooled = int(np.count_nonzero(low))
        pool_exp, pool_obs = exp[low].sum(), obs[low].sum()
        exp, obs = exp[~low], obs[~low]
        if pooled:
            if pool_exp < MIN_EXPECTED and len(exp):      # too small alone: merge into the smallest cell
                exp[0] += pool_exp
                obs[0] += pool_obs
            else:
                exp = np.append(exp, pool_exp)
                obs = np.append(obs, pool_obs)
        terms = (obs - exp) ** 2 / exp
        statistic = float(terms.sum())
        dof = max(len(exp) - 1, 1)
        p_value = float(stats.chi2.sf(statistic, dof))
        top = np.argsort(terms)[::-1][:3]
        worst = ", ".join(f"observed {obs[i]:.0f} expected {exp[i]:.1f}" for i in top)
    return statistic, dof, p_value, pooled, worst


def chi2_test(technique: str, config: LightConfig, dtype: str = "float32", sample_count: int = 500_000,
              resolution: int = 24, seed: int = 1, significance: float = 1e-3, test_count: int = 1,
              tolerance: float = 1e-4, against: Optional[str] = None,
              pdf_factor: Optional[Callable] = None, sample_fn: Optional[Callable] = None,
              pdf_fn: Optional[Callable] = None) -> Chi2Result:
    """Samples of `technique` against the pdf of `against` (default: its own), times
    `pdf_factor(points)` when given (another technique's pdf, or a factor, is how the tests check
    that this test can fail).  A sampler outside sphrect.techniques passes `sample_fn(uv) -> (points, pdf)` and
    `pdf_fn(points) -> pdf` instead (`technique` then only names it)."""
    s_edges = grid_edges(config, resolution, 0)
    t_edges = grid_edges(config, resolution, 1)
    probability = cell_probabilities(against or technique, config, s_edges, t_edges, dtype,
                                     pdf_factor=pdf_factor, pdf_fn=pdf_fn)

    uv = sphrect.pattern("independent", sample_count, seed=seed)
    if sample_fn is not None:
        points, pdf = sample_fn(uv)
    else:
        points, pdf = sphrect.sample(technique, config.origin, config.corner, config.edge_x, config.edge_y, uv,
                                     normal=config.normal, dtype=dtype, two_sided=config.two_sided)
    valid = pdf > 0
    s, t = light_coordinates(points[valid], config)
    off = (s < -tolerance) | (s > 1 + tolerance) | (t < -tolerance) | (t > 1 + tolerance) | \
        ~np.isfinite(s) | ~np.isfinite(t)
    s, t = np.clip(s[~off], 0.0, 1.0), np.clip(t[~off], 0.0, 1.0)
    observed, _, _ = np.histogram2d(s, t, bins=[s_edges, t_edges])

    statistic, dof, p_value, pooled, worst = pearson(observed, probability, int(np.count_nonzero(~valid)),
                                                     sample_count)
    return Chi2Result(technique, config.name, dtype, statistic, dof, p_value, sidak_alpha(significance, test_count),
                      int(probability.size), pooled, int(np.count_nonzero(~valid)), int(np.count_nonzero(off)),
                      float(probability.sum()), worst)


# ---------------------------------------------------------------------------------------------
# Ellipse (disk) lights: the same test through sphrect.sample_ellipse / ellipse_pdf.  The light's
# coordinates are (s, t) = (polar angle / 2 pi, squared radius) in the unit disk of the semi-axes,
# P(s, t) = center + sqrt(t) (cos 2 pi s axis_u + sin 2 pi s axis_v), for which dA = pi a b ds dt.

@dataclasses.dataclass
class EllipseConfig:
    """A shading point and an elliptical light, as sphrect's ellipse functions take them."""
    name: str
    origin: Sequence[float]
    center: Sequence[float]
    axis_u: Sequence[float]
    axis_v: Sequence[float]
    normal: Optional[Sequence[float]] = None
    two_sided: bool = True

    def light_args(self):
        return (np.asarray(self.origin, float), np.asarray(self.center, float), np.asarray(self.axis_u, float),
                np.asarray(self.axis_v, float))

    def point(self, s, t):
        _, c, au, av = self.light_args()
        r, phi = np.sqrt(t), 2 * np.pi * s
        return c + (r * np.cos(phi))[:, None] * au + (r * np.sin(phi))[:, None] * av

    def coordinates(self, points):
        """(s, t) of points on the light."""
        _, c, au, av = self.light_args()
        rel = np.asarray(points, np.float64) - c
        p, q = rel @ au / au.dot(au), rel @ av / av.dot(av)
        return np.mod(np.arctan2(q, p) / (2 * np.pi), 1.0), p * p + q * q

    def __str__(self):
        return self.name


def ellipse_chi2_test(technique: str, config: EllipseConfig, dtype: str = "float32", sample_count: int = 500_000,
                      resolution: int = 24, seed: int = 1, significance: float = 1e-3, test_count: int = 1,
                      tolerance: float = 1e-4, against: Optional[str] = None,
                      pdf_factor: Optional[Callable] = None) -> Chi2Result:
    """chi2_test for an ellipse.  The grid lines are half uniform, half at quantiles of an independent
    set of the technique's own samples (another seed), so that cells stay small where it concentrates
    them; the expected counts integrate the pdf of `against` (default: the technique's own)."""
    origin, c, au, av = config.light_args()
    n = np.cross(au, av)
    ab = np.linalg.norm(n)
    h = abs(np.dot(n / ab, origin - c))

    def sample(uv_seed):
        uv = sphrect.pattern("independent", sample_count, seed=uv_seed)
        return sphrect.sample_ellipse(technique, config.origin, config.center, config.axis_u, config.axis_v, uv,
                                      normal=config.normal, dtype=dtype, two_sided=config.two_sided)

    grid_points, grid_pdf = sample(seed + 7919)
    gs, gt = config.coordinates(grid_points[grid_pdf > 0])
    half = resolution // 2
    edges = []
    for q in (gs, gt):
        uniform = np.linspace(0.0, 1.0, resolution - half + 1)
        lines = np.quantile(q, np.linspace(0, 1, half + 1)[1:-1]) if len(q) else np.zeros(0)
        lines = [x for x in lines if np.min(np.abs(uniform - x)) > 0.05 / resolution]   # no sliver cells
        e = np.unique(np.concatenate([uniform, lines]))
        e = e[np.concatenate([[True], np.diff(e) > 1e-9])]
        e[0], e[-1] = 0.0, 1.0
        edges.append(e)

    def integrand(s, t):
        P = config.point(s, t)
        d = np.linalg.norm(P - origin, axis=1)
        pdf = sphrect.ellipse_pdf(against or technique, config.origin, config.center, config.axis_u, config.axis_v,
                                  P, normal=config.normal, dtype=dtype, two_sided=config.two_sided).astype(np.float64)
        if pdf_factor is not None:
            pdf = pdf * pdf_factor(P)
        return pdf * h * np.pi * ab / d ** 3

    probability = adaptive_cell_integrals(integrand, edges[0], edges[1])
    points, pdf = sample(seed)
    valid = pdf > 0
    s, t = config.coordinates(points[valid])
    off = (t > 1 + tolerance) | ~np.isfinite(s) | ~np.isfinite(t)
    s, t = np.clip(s[~off], 0.0, 1.0), np.clip(t[~off], 0.0, 1.0)
    observed, _, _ = np.histogram2d(s, t, bins=edges)
    statistic, dof, p_value, pooled, worst = pearson(observed, probability, int(np.count_nonzero(~valid)),
                                                     sample_count)
    return Chi2Result(technique, config.name, dtype, statistic, dof, p_value, sidak_alpha(significance, test_count),
                      int(probability.size), pooled, int(np.count_nonzero(~valid)), int(np.count_nonzero(off)),
                      float(probability.sum()), worst)


# ---------------------------------------------------------------------------------------------
# Image worlds (render/environment_light.h): the same test through sphrect.EnvironmentSampler.  A direction is
# histogrammed at its equirectangular coordinates (u, v) in the image's own frame (to_world^T w, Cycles'
# direction_to_equirectangular), over which d omega = 2 pi^2 sin(theta) du dv, theta = pi (1 - v).

def equirectangular_direction(u, v):
    """Unit directions of the image's frame at (u, v) (arrays), and sin(theta)."""
    theta, phi = np.pi * (1 - v), np.pi * (1 - 2 * u)
    s = np.sin(theta)
    return np.stack([s * np.cos(phi), s * np.sin(phi), np.cos(theta)], axis=-1), s


def equirectangular_coordinates(d):
    """(u, v) of directions d [N, 3] of the image's frame."""
    theta = np.arctan2(np.hypot(d[:, 0], d[:, 1]), d[:, 2])
    return np.mod((np.pi - np.arctan2(d[:, 1], d[:, 0])) / (2 * np.pi), 1.0), 1 - theta / np.pi


def environment_chi2_test(sampler, name: str, to_world=None, sample_count: int = 500_000,
                          resolution=(25, 13), seed: int = 1, significance: float = 1e-3, test_count: int = 1,
                          pdf_factor: Optional[Callable] = None) -> Chi2Result:
    """SampleEnvironment against EnvironmentPDF (times `pdf_factor(world directions)` when given) for the
    sampler (an EnvironmentSampler built with `to_world`), on a uniform grid of `resolution` (u, v) cells (by
    default not a divisor of the tests' image sizes: a sample rounded onto a pixel's edge then never lands in a
    cell of zero expected count)."""
    R = np.eye(3) if to_world is None else np.asarray(to_world, np.float64)
    u_edges = np.linspace(0.0, 1.0, resolution[0] + 1)
    v_edges = np.linspace(0.0, 1.0, resolution[1] + 1)

    def integrand(u, v):
        d, sin_theta = equirectangular_direction(u, v)
        w = d @ R.T
        pdf = sampler.pdf(w)[:, 0]
        if pdf_factor is not None:
            pdf = pdf * pdf_factor(w)
        return pdf * 2 * np.pi ** 2 * sin_theta

    probability = adaptive_cell_integrals(integrand, u_edges, v_edges)
    uv = sphrect.pattern("independent", sample_count, seed=seed)
    dirs, pdf = sampler.sample(uv)
    valid = pdf > 0
    u, v = equirectangular_coordinates(dirs[valid] @ R)
    norms = np.linalg.norm(dirs[valid], axis=1)
    off = ~np.isfinite(u) | ~np.isfinite(v) | (np.abs(norms - 1) > 1e-4)
    observed, _, _ = np.histogram2d(np.clip(u[~off], 0, 1), np.clip(v[~off], 0, 1), bins=[u_edges, v_edges])
    statistic, dof, p_value, pooled, worst = pearson(observed, probability, int(np.count_nonzero(~valid)),
                                                     sample_count)
    return Chi2Result("environment", name, "float32", statistic, dof, p_value, sidak_alpha(significance, test_count),
                      int(probability.size), pooled, int(np.count_nonzero(~valid)), int(np.count_nonzero(off)),
                      float(probability.sum()), worst)
