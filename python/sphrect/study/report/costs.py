"""The cost model in the report, as numbers (wording.py words them, plots.py draws them): every configuration's time per
camera sample term by term (cost_model.CostTerms, the mean of its curve's largest runs) with each run's check against
its measured CPU time, and, for pairs of configurations -- every two techniques at the same other settings, every two
MIS modes and every two light selections of a technique -- the time each takes to the same error as a function of
what a ray and what shading a hit costs: the break-even costs and the relative efficiency over RAY_COSTS and
SHADING_COSTS."""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Dict, List, NamedTuple, Optional

from ..cost_model import (RAY_AXIS, SHADING_AXIS, BreakEven, CostTerms, break_even, cost_terms, log_grid, mean_terms,
                          relative_efficiency, upper_median)
from ..jobs import CYCLES_CURVE, CurveKey, StudyConfig
from .curves import time_to_target
from .equal_error import curves_along
from .results import Curves

# The check's tolerance: the terms' sum within this share of the CPU time measured around the render call (the terms
# leave out the call's own setup -- cutting tiles, starting threads -- and the timers' cost; a loaded machine stretches
# the timers' wall clocks but not the CPU time), on runs of at least CHECK_MIN_TIME seconds, where that setup (the
# intercept of CPU time against samples, reported) is a few percent.
CHECK_TOLERANCE = 0.10
CHECK_MIN_TIME = 0.02
# The ray costs and shading costs per hit the efficiency is drawn over: from this renderer's rays to a production
# scene's, and from a Lambert lobe to a production shader network.
RAY_COSTS = log_grid(10e-9, 100e-6, 41)
# Two configurations whose samples to the same error differ by less than this share are as accurate as each other
# within the noise of the RMSEs they are read from (one image's RMSE and the reference's own): their break-even cost
# is then the ratio of near-equal numbers, and the report calls them a tie in accuracy instead.
ACCURACY_TIE = 0.05
# The technique the others' efficiency is drawn against, when the study has it: the paper's map.
BASELINE = "rectangle"
SHADING_COSTS = log_grid(10e-9, 100e-6, 41)


@dataclass(frozen=True)
class ConfigurationCost:
    key: CurveKey
    terms: CostTerms     # the mean of the curve's largest runs
    checks: List[float]  # the check of every run of at least CHECK_MIN_TIME
    setup: float         # the intercept of the runs' CPU time against samples: the render call's own setup [s]


@dataclass(frozen=True)
class PairCost:
    """A (fewer samples to the error, or the first) against A, at the larger of their top-rung RMSEs."""
    a: CurveKey
    b: CurveKey
    target: float
    n_a: float          # samples per pixel to the target
    n_b: float
    terms_a: CostTerms
    terms_b: CostTerms
    ray: BreakEven      # along the ray cost, no shading cost added
    shading: BreakEven  # along the shading cost per hit, each at its own ray cost

    @property
    def accuracy_tie(self) -> bool:
        """Whether A and B need the same samples within ACCURACY_TIE (then only their costs per sample differ)."""
        return self.n_a <= self.n_b * (1 + ACCURACY_TIE)

    def efficiency(self, ray_cost: Optional[float] = None, shading_cost: float = 0.0) -> float:
        """B's efficiency over A's at equal error (> 1: B reaches the error sooner)."""
        return relative_efficiency(self.n_a, self.terms_a, self.n_b, self.terms_b, ray_cost, shading_cost)


def configuration_costs(all_curves: Curves) -> Dict[CurveKey, ConfigurationCost]:
    """Every curve of ours whose runs carry the model's measurements."""
    out = {}
    for key, curve in all_curves.items():
        if key == CYCLES_CURVE:
            continue
        measured = [(r, t) for r, t in ((r, cost_terms(r)) for r in curve) if t is not None]
        mean = mean_terms([t for _, t in measured])
        if mean is None:
            continue
        checks = [t.check for r, t in measured if (r.get("cpu_time") or 0) >= CHECK_MIN_TIME]
        out[key] = ConfigurationCost(key, mean, checks, setup_time([r for r, _ in measured]))
    return out


def setup_time(runs: List[Dict]) -> float:
    """The intercept of the runs' CPU time against their samples per pixel (least squares; NaN for fewer than two
    sample counts): what a render call costs besides its samples."""
    points = [(r["job"]["samples"], r["cpu_time"]) for r in runs if r.get("cpu_time")]
    if len({n for n, _ in points}) < 2:
        return float("nan")
    n_mean = sum(n for n, _ in points) / len(points)
    t_mean = sum(t for _, t in points) / len(points)
    slope = (sum((n - n_mean) * (t - t_mean) for n, t in points) / sum((n - n_mean) ** 2 for n, _ in points))
    return t_mean - slope * n_mean


class CheckSummary(NamedTuple):
    within: int  # runs whose check is within CHECK_TOLERANCE
    checked: int  # runs checked (at least CHECK_MIN_TIME)
    largest: float  # the largest |check|
    median: float  # the median check (signed: > 0 where the terms add up to more than the CPU time)
    setup: float  # the median setup time of a render call


def checks_within(costs: Dict[CurveKey, ConfigurationCost]) -> CheckSummary:
    checks = [c for cost in costs.values() for c in cost.checks if not math.isnan(c)]
    return CheckSummary(sum(abs(c) <= CHECK_TOLERANCE for c in checks), len(checks),
                        max((abs(c) for c in checks), default=float("nan")), upper_median(checks),
                        upper_median([c.setup for c in costs.values() if not math.isnan(c.setup)]))


def pair_cost(a: CurveKey, b: CurveKey, all_curves: Curves, costs: Dict[CurveKey, ConfigurationCost],
              reference_rmse: float, ordered: bool = True) -> Optional[PairCost]:
    """The pair at the larger of their top-rung RMSEs (both reach it), `ordered` so that B needs no more samples
    than A (else as given); None where either lacks the model's terms or a measured or extrapolated sample count."""
    if a not in costs or b not in costs or not all_curves.get(a) or not all_curves.get(b):
        return None
    target = max(all_curves[a][-1]["rmse"], all_curves[b][-1]["rmse"])
    n_a = time_to_target(all_curves[a], target, reference_rmse).samples
    n_b = time_to_target(all_curves[b], target, reference_rmse).samples
    if not (n_a > 0 and n_b > 0):
        return None
    if ordered and n_b > n_a:
        a, b, n_a, n_b = b, a, n_b, n_a
    ta, tb = costs[a].terms, costs[b].terms
    return PairCost(a, b, target, n_a, n_b, ta, tb, break_even(n_a, ta, n_b, tb, RAY_AXIS),
                    break_even(n_a, ta, n_b, tb, SHADING_AXIS))


def pair_costs(cfg: StudyConfig, all_curves: Curves, costs: Dict[CurveKey, ConfigurationCost],
               reference_rmse: float) -> List[PairCost]:
    """Every two techniques at each combination of the other settings, then every two MIS modes, then every two light
    selections of each technique."""
    out = []
    for axis in ("technique", "mis", "light_selection"):
        for key, along in curves_along(cfg, all_curves, axis):
            measured = [key._replace(**{axis: value}) for value, curve in along.items() if curve]
            for a, b in itertools.combinations(measured, 2):
                pair = pair_cost(a, b, all_curves, costs, reference_rmse)
                if pair:
                    out.append(pair)
    return out


def ray_cost_here(costs: Dict[CurveKey, ConfigurationCost]) -> float:
    """This renderer's ray cost on the scene: the median of the configurations' t_ray."""
    return upper_median([c.terms.t_ray for c in costs.values() if c.terms.t_ray > 0])


@dataclass(frozen=True)
class CyclesCost:
    """Cycles' time per camera sample (its CPU time over samples x pixels at its top rung) and ours at the same rung
    of the configuration with the least time per camera sample; Cycles counts no rays."""
    cycles: float
    ours: float
    ours_key: CurveKey


def cycles_cost(all_curves: Curves, costs: Dict[CurveKey, ConfigurationCost], pixels: int) -> Optional[CyclesCost]:
    curve = all_curves.get(CYCLES_CURVE)
    if not curve or not costs or not pixels:
        return None
    top = curve[-1]
    time = top.get("cpu_time") or top.get("time")
    if not time:
        return None
    best = min(costs.values(), key=lambda c: c.terms.measured if c.terms.measured > 0 else math.inf)
    return CyclesCost(time / (top["job"]["samples"] * pixels), best.terms.measured, best.key)
