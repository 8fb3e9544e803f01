"""Error metrics against a reference image, convergence-slope fits and time-to-error interpolation.

Images are [H, W, C] arrays; only the colour channels (the first three) are compared.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence, Tuple

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


def _check_shapes(image: np.ndarray, reference: np.ndarray) -> None:
    if image.shape[:2] != reference.shape[:2]:
        raise ValueError(f"image {image.shape[:2]} and reference {reference.shape[:2]} differ in size")


def mse(image: np.ndarray, reference: np.ndarray) -> float:
    _check_shapes(image, reference)
    return float(np.mean((colour(image) - colour(reference)) ** 2))


def rmse(image: np.ndarray, reference: np.ndarray) -> float:
    return math.sqrt(mse(image, reference))


def relmse(image: np.ndarray, reference: np.ndarray, epsilon: float = RELMSE_EPSILON) -> float:
    _check_shapes(image, reference)
    r = colour(reference)
    return float(np.mean((colour(image) - r) ** 2 / (r * r + epsilon)))


def error_map(image: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Per-pixel RMS error over the colour channels, [H, W]."""
    _check_shapes(image, reference)
    return np.sqrt(np.mean((colour(image) - colour(reference)) ** 2, axis=2))


def fit_slope(x: Sequence[float], y: Sequence[float]) -> Tuple[float, float]:
    """Least-squares line through (log x, log y): returns (slope, intercept), so y ~ exp(intercept) * x**slope.
    NaN when fewer than two usable points."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    keep = (x > 0) & (y > 0) & np.isfinite(x) & np.isfinite(y)
    if np.count_nonzero(keep) < 2 or np.ptp(np.log(x[keep])) == 0:
        return float("nan"), float("nan")
    slope, intercept = np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)
    return float(slope), float(intercept)


def fit_slope_with_error(x: Sequence[float], y: Sequence[float]) -> Tuple[float, float]:
    """(slope, its standard error) of the log-log least-squares line; the error is NaN with < 3 points."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    keep = (x > 0) & (y > 0) & np.isfinite(x) & np.isfinite(y)
    lx, ly = np.log(x[keep]), np.log(y[keep])
    slope, intercept = fit_slope(x, y)
    if len(lx) < 3 or not math.isfinite(slope):
        return slope, float("nan")
    residuals = ly - (slope * lx + intercept)
    variance = float(np.sum(residuals ** 2)) / (len(lx) - 2)
    return slope, math.sqrt(variance / float(np.sum((lx - lx.mean()) ** 2)))


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
    c = np.asarray(costs, dtype=np.float64)
    e = np.asarray(errors, dtype=np.float64)
    keep = (c > 0) & (e > 0) & np.isfinite(c) & np.isfinite(e)
    c, e = c[keep], e[keep]
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
    """Linear radiance -> 8-bit-ready sRGB in [0, 1] for display: scale so that `white` maps to 1, clamp,
    apply the sRGB transfer curve. `white` defaults to white_point(image)."""
    rgb = colour(image)
    if white is None:
        white = white_point(image)
    x = np.clip(rgb / max(white, 1e-30), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
