"""Error metrics against a reference image, convergence-slope fits, the time a run is judged by, its cost per
sample and time-to-error interpolation.

Images are [H, W, C] arrays; only the colour channels (the first three) are compared.
"""
from __future__ import annotations

import math
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

# Relative MSE: per pixel and channel (x - r)^2 / (r^2 + eps), averaged. eps keeps black pixels from
# dominating; 0.01 is the usual choice (Rousselle et al. 2011 and later denoising papers).
RELMSE_EPSILON = 1e-2


def colour(image: np.ndarray) -> np.ndarray:
    """The RGB part of an [H, W, 3|4] image, as float64."""
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] < 3:
        raise ValueError(f"expected an [H, W, 3 or 4] image, got shape {image.shape}")
    return image[..., :3].astype(np.float64)


def squared_error(image: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """(x - r)^2 per pixel and colour channel, [H, W, 3]: what every error metric here averages."""
    if image.shape[:2] != reference.shape[:2]:
        raise ValueError(f"image {image.shape[:2]} and reference {reference.shape[:2]} differ in size")
    return (colour(image) - colour(reference)) ** 2


def mse(image: np.ndarray, reference: np.ndarray) -> float:
    return float(np.mean(squared_error(image, reference)))


def rmse(image: np.ndarray, reference: np.ndarray) -> float:
    """The study's one RMSE: over all pixels and colour channels."""
    return math.sqrt(mse(image, reference))


def relmse(image: np.ndarray, reference: np.ndarray, epsilon: float = RELMSE_EPSILON) -> float:
    r = colour(reference)
    return float(np.mean(squared_error(image, reference) / (r * r + epsilon)))


def error_map(image: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Per-pixel RMS error over the colour channels, [H, W]."""
    return np.sqrt(np.mean(squared_error(image, reference), axis=2))


def _usable(x: Sequence[float], y: Sequence[float]) -> Tuple[np.ndarray, np.ndarray]:
    """The points (x, y) a log-log fit can use: both positive and finite, as float64 arrays."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    keep = (x > 0) & (y > 0) & np.isfinite(x) & np.isfinite(y)
    return x[keep], y[keep]


def fit_slope(x: Sequence[float], y: Sequence[float]) -> Tuple[float, float]:
    """Least-squares line through (log x, log y): returns (slope, intercept), so y ~ exp(intercept) * x**slope.
    NaN when fewer than two usable points."""
    x, y = _usable(x, y)
    if len(x) < 2 or np.ptp(np.log(x)) == 0:
        return float("nan"), float("nan")
    slope, intercept = np.polyfit(np.log(x), np.log(y), 1)
    return float(slope), float(intercept)


def fit_slope_with_error(x: Sequence[float], y: Sequence[float]) -> Tuple[float, float]:
    """(slope, its standard error) of the log-log least-squares line; the error is NaN with < 3 points."""
    slope, intercept = fit_slope(x, y)
    x, y = _usable(x, y)
    lx, ly = np.log(x), np.log(y)
    if len(lx) < 3 or not math.isfinite(slope):
        return slope, float("nan")
    residuals = ly - (slope * lx + intercept)
    variance = float(np.sum(residuals ** 2)) / (len(lx) - 2)
    return slope, math.sqrt(variance / float(np.sum((lx - lx.mean()) ** 2)))


def time_of(record: Dict, threads: int) -> float:
    """The time a run is judged by: its CPU time when it rendered with one thread (robust to other load on the
    machine), else its wall time (see executors.py)."""
    if threads == 1 and record.get("cpu_time"):
        return float(record["cpu_time"])
    return float(record["wall_time"])


# How many of a sample ladder's largest runs pool their times into its cost per sample.
COST_RUNS = 3


def cost_per_sample(times: Sequence[float], samples: Sequence[int], top: int = COST_RUNS) -> Tuple[float, float]:
    """Seconds per sample from the runs of a sample ladder (ascending samples): the mean of time / samples over
    its `top` largest runs -- one run's time is noisy on a shared machine -- and the relative standard error of
    that mean from their scatter (0 from one run; NaN without runs)."""
    per_sample = np.array([t / n for t, n in zip(times, samples) if t and t > 0 and n > 0][-top:], dtype=np.float64)
    if len(per_sample) == 0:
        return float("nan"), float("nan")
    cost = float(per_sample.mean())
    rel_se = float(per_sample.std(ddof=1) / cost / math.sqrt(len(per_sample))) if len(per_sample) > 1 else 0.0
    return cost, rel_se


def cost_to_reach(costs: Sequence[float], errors: Sequence[float], target: float) -> Tuple[float, str]:
    """Cost (time or samples) at which the error first falls to `target`.

    Piecewise log-log interpolation between the measured points when the target lies inside the measured
    range ("measured"); otherwise extrapolation along a power law fitted to the points ("extrapolated"),
    or NaN when no fit is possible ("unreachable")."""
    c, e = _usable(costs, errors)
    if len(c) == 0 or not target > 0:
        return float("nan"), "unreachable"
    order = np.argsort(c)
    c, e = c[order], e[order]
    if e[0] <= target:
        if len(c) == 1 or e[0] == target:
            return float(c[0]), "measured" if e[0] == target else "below"
        # Already below target at the cheapest point: extrapolate backwards along the fit.
        slope, intercept = fit_slope(c, e)
        if slope < 0:
            return float(math.exp((math.log(target) - intercept) / slope)), "extrapolated"
        return float(c[0]), "below"
    for i in range(1, len(c)):
        if e[i] <= target:
            # Interpolate in log-log between points i-1 and i.
            t = (math.log(target) - math.log(e[i - 1])) / (math.log(e[i]) - math.log(e[i - 1]))
            return float(math.exp(math.log(c[i - 1]) + t * (math.log(c[i]) - math.log(c[i - 1])))), "measured"
    slope, intercept = fit_slope(c[len(c) // 2:] if len(c) >= 4 else c, e[len(c) // 2:] if len(c) >= 4 else e)
    if not slope < 0:
        return float("nan"), "unreachable"
    return float(math.exp((math.log(target) - intercept) / slope)), "extrapolated"


def white_point(image: np.ndarray) -> float:
    """The 99.5th percentile of the image's positive RGB values (1 for a black image): what maps to white."""
    rgb = colour(image)
    positive = rgb[rgb > 0]
    return float(np.percentile(positive, 99.5)) if positive.size else 1.0


def tonemap(image: np.ndarray, white: Optional[float] = None) -> np.ndarray:
    """Linear radiance -> 8-bit-ready sRGB in [0, 1] for display: scale so that `white` maps to 1, clamp (NaN
    to black), apply the sRGB transfer curve. `white` defaults to white_point(image)."""
    rgb = colour(image)
    if white is None:
        white = white_point(image)
    x = np.clip(np.nan_to_num(rgb / max(white, 1e-30), nan=0.0), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
