"""Measures of one curve (a configuration's runs over the sample ladder, sorted by samples): its convergence
slope, its cost per sample, the time it takes to reach an error, and how much of its error is systematic."""
from __future__ import annotations

from typing import Dict, List, NamedTuple, Optional, Tuple

from .. import metrics

SLOPE_MIN_POINTS = 3
# Points within this factor of the reference's own RMSE are bent by the reference's noise, not the run's.
REFERENCE_NOISE_FACTOR = 3
# Extrapolating a curve further than this factor beyond its longest run is refused.
EXTRAPOLATION_LIMIT = 100


def curve_x(record: Dict, x: str) -> Optional[float]:
    """A run's position along `x`: "samples" (per pixel) or "time" (the time it is judged by)."""
    return record["job"]["samples"] if x == "samples" else record.get("time")


def fitted_slope_with_error(curve: List[Dict], x: str, reference_rmse: float) -> Tuple[float, float]:
    """Log-log slope of RMSE against `x` ("samples" or "time"), and its standard error, fitted on the points whose
    error is more than REFERENCE_NOISE_FACTOR x the reference's own RMSE and, when enough remain, without the
    first (pre-asymptotic) point."""
    pts = [(curve_x(r, x), r["rmse"]) for r in curve
           if r.get("rmse") and r["rmse"] > REFERENCE_NOISE_FACTOR * reference_rmse]
    pts = [(a, b) for a, b in pts if a and a > 0]
    if len(pts) > SLOPE_MIN_POINTS:
        pts = pts[1:]
    if len(pts) < 2:
        return float("nan"), float("nan")
    return metrics.fit_slope_with_error([a for a, _ in pts], [b for _, b in pts])


def fitted_slope(curve: List[Dict], x: str, reference_rmse: float) -> float:
    return fitted_slope_with_error(curve, x, reference_rmse)[0]


def curve_cost(curve: List[Dict]) -> Tuple[float, float]:
    """metrics.cost_per_sample of a ladder curve: (seconds per sample, its relative standard error)."""
    return metrics.cost_per_sample([r.get("time") for r in curve], [r["job"]["samples"] for r in curve])


class Reach(NamedTuple):
    """When a curve reaches an error: seconds, how it was found (metrics.cost_to_reach's "measured", "below",
    "extrapolated", "unreachable", or a refusal below), samples per pixel; `longest` is the longest run's time
    when the extrapolation was refused as beyond EXTRAPOLATION_LIMIT x of it."""
    time: float
    how: str
    samples: float
    longest: Optional[float] = None


BELOW_REFERENCE = "below reference accuracy"
BEYOND_LONGEST = "beyond the longest run"
BELOW_FEWEST = "below"  # metrics.cost_to_reach's word: the curve's cheapest run is already below the target


def time_to_target(curve: List[Dict], target: float, reference_rmse: float = 0.0) -> Reach:
    """Reach of RMSE `target`: the samples per pixel it takes (metrics.cost_to_reach on the samples) times the
    curve's cost per sample (curve_cost: averaged over its largest runs, so that one run's time does not decide
    a comparison).  Extrapolation uses only the points above REFERENCE_NOISE_FACTOR x the reference's own error
    (below, the reference's noise bends the curve), and is refused for targets under that level.  A target that
    the curve's fewest samples already beat is reached, at most, in their time (BELOW_FEWEST): a render takes
    whole samples, so extrapolating below them would promise a time no render can take."""
    cost, _ = curve_cost(curve)

    def reach(points):
        n, how = metrics.cost_to_reach([r["job"]["samples"] for r in points], [r["rmse"] for r in points], target)
        return Reach(n * cost, how, n)
    measured = reach(curve)
    if measured.how != "extrapolated":
        return measured
    fewest = min(curve, key=lambda r: r["job"]["samples"])
    if fewest["rmse"] <= target:
        return Reach(fewest["job"]["samples"] * cost, BELOW_FEWEST, fewest["job"]["samples"])
    noise_floor = REFERENCE_NOISE_FACTOR * reference_rmse
    if target < noise_floor:
        return Reach(float("nan"), BELOW_REFERENCE, float("nan"))
    extrapolated = reach([r for r in curve if r["rmse"] > noise_floor])
    longest = max((r["time"] for r in curve if r.get("time")), default=0.0)
    if extrapolated.how == "extrapolated" and extrapolated.time > EXTRAPOLATION_LIMIT * longest:
        return Reach(float("nan"), BEYOND_LONGEST, float("nan"), longest)
    return extrapolated


def systematic_share(curve: List[Dict]) -> float:
    """Share of the top rung's MSE that does not fall with the sample count: from the top two rungs and
    MSE(n) = b^2 + s / n (Monte Carlo variance s / n plus a systematic difference b^2 from the reference, e.g.
    another renderer's different material model).  0 when the MSE falls as 1 / n or faster."""
    points = sorted((r["job"]["samples"], r["rmse"] ** 2) for r in curve)
    if len(points) < 2:
        return 0.0
    (n1, m1), (n2, m2) = points[-2:]
    if not (n2 > n1 and m2 > 0):
        return 0.0
    s = (m1 - m2) / (1 / n1 - 1 / n2)
    return min(1.0, max(0.0, (m2 - s / n2) / m2))
