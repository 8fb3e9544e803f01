"""Comparisons at equal error, as numbers (wording.py words them): the time every configuration takes to reach one
target RMSE, the time our fastest configuration takes to reach each of Cycles' errors, and the light tree's time
against power selection's for the same error."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List, Optional, Tuple

from ..jobs import CYCLES_CURVE, CurveKey, StudyConfig
from .curves import Reach, curve_cost, systematic_share, time_to_target
from .findings import LIGHT_TREE, POWER_SELECTION, RECTANGLE, noise_verdict, ratio_of
from .results import Curves

# Above this share of Cycles' top MSE being a systematic difference from our reference, an equal-error time
# ratio measures that difference, not sampling, and is not reported as one.
SYSTEMATIC_SHARE_LIMIT = 0.5
GOAL_RATIO = 1 / 3  # the goal: at most 1/3 of Cycles' time for Cycles' error


@dataclass(frozen=True)
class CyclesPoint:
    """One Cycles ladder run and the fastest configuration of ours that reaches its RMSE."""
    samples: int
    rmse: float
    time: float                       # Cycles' samples x its cost per sample
    best: Optional[CurveKey]          # None when none of ours reaches the error within the ladder
    reach: Optional[Reach]

    @property
    def ratio(self) -> float:
        return ratio_of(self.reach.time, self.time) if self.reach else float("nan")


@dataclass(frozen=True)
class CyclesComparison:
    points: List[CyclesPoint]
    top_samples: int                  # Cycles' top sample count
    systematic_share: float

    @property
    def reached(self) -> List[CyclesPoint]:
        return [p for p in self.points if p.reach]

    @property
    def measurable(self) -> bool:
        """False when Cycles' error has stopped falling: a time ratio would measure a systematic difference."""
        return not (self.reached and self.systematic_share > SYSTEMATIC_SHARE_LIMIT)

    @property
    def top_ratio(self) -> Optional[float]:
        """Our time / Cycles' at the highest Cycles count our runs reach; None when not measurable or reached."""
        return self.reached[-1].ratio if self.measurable and self.reached else None

    @property
    def meets_goal(self) -> bool:
        return self.top_ratio is not None and self.top_ratio <= GOAL_RATIO


def cycles_comparison(all_curves: Curves, reference_rmse: float) -> Optional[CyclesComparison]:
    """For each Cycles ladder point (N, RMSE e, time t): the time our best configuration needs to reach e.
    None without Cycles."""
    cycles = all_curves.get(CYCLES_CURVE)
    if not cycles:
        return None
    ours = {k: c for k, c in all_curves.items() if k != CYCLES_CURVE}
    cycles_cost, _ = curve_cost(cycles)
    points = []
    for r in cycles:
        best, best_reach = None, None
        for key, curve in ours.items():
            reach = time_to_target(curve, r["rmse"], reference_rmse)
            if math.isfinite(reach.time) and reach.how in ("measured", "below") and \
                    (best_reach is None or reach.time < best_reach.time):
                best, best_reach = key, reach
        points.append(CyclesPoint(r["job"]["samples"], r["rmse"], r["job"]["samples"] * cycles_cost, best, best_reach))
    return CyclesComparison(points, cycles[-1]["job"]["samples"], systematic_share(cycles))


@dataclass(frozen=True)
class TargetTimes:
    rmse: float
    source: str                       # "given", "cycles" (its top run's RMSE) or "middle" (of `key`'s ladder)
    key: Optional[CurveKey]           # the curve the target comes from
    samples: Optional[int]            # Cycles' top count, for source "cycles"
    reached: List[Tuple[CurveKey, Reach]]  # fastest first, unreachable last


def target_times(cfg: StudyConfig, all_curves: Curves, reference_rmse: float, smallest: float,
                 given: Optional[float] = None) -> TargetTimes:
    """The time every configuration takes to reach one RMSE: `given`, else Cycles' at the top of its ladder,
    else rectangle's (last MIS mode, pattern and light selection) in the middle of its ladder."""
    key, samples = None, None
    if given is not None:
        target, source = given, "given"
    elif all_curves.get(CYCLES_CURVE):
        cycles = all_curves[CYCLES_CURVE]
        target, source, key, samples = cycles[-1]["rmse"], "cycles", CYCLES_CURVE, cycles[-1]["job"]["samples"]
    else:
        key, source = CurveKey(RECTANGLE, cfg.mis[-1], cfg.patterns[-1], cfg.light_selections[-1]), "middle"
        mid = all_curves.get(key, [])
        target = mid[len(mid) // 2]["rmse"] if mid else smallest
    reached = {k: time_to_target(curve, target, reference_rmse) for k, curve in all_curves.items()}
    order = sorted(reached, key=lambda k: reached[k].time if math.isfinite(reached[k].time) else math.inf)
    return TargetTimes(target, source, key, samples, [(k, reached[k]) for k in order])


@dataclass(frozen=True)
class SelectionComparison:
    """The light tree against power selection for one (technique, MIS, pattern): the time each takes to reach
    the same RMSE, the larger of the two curves' errors at the top of the ladder (so both reach it within their
    measured runs)."""
    technique: str
    mis: str
    pattern: str
    rmse: float
    power: Reach
    tree: Reach
    noise: float            # two standard errors of the two costs per sample, relative

    @property
    def ratio(self) -> float:
        """The tree's time / power's."""
        return ratio_of(self.tree.time, self.power.time)

    @property
    def verdict(self) -> str:
        return noise_verdict(self.ratio, self.noise, "slower", "faster")


def selection_comparisons(cfg: StudyConfig, all_curves: Curves, reference_rmse: float
                          ) -> Optional[List[SelectionComparison]]:
    """tree against power for every (technique, MIS, pattern) both were measured with; None when the study
    does not have both light selections."""
    if not {LIGHT_TREE, POWER_SELECTION} <= set(cfg.light_selections):
        return None
    out = []
    for mis in cfg.mis:
        for pattern in cfg.patterns:
            for technique in cfg.techniques:
                power, tree = (all_curves.get(CurveKey(technique, mis, pattern, s), [])
                               for s in (POWER_SELECTION, LIGHT_TREE))
                tops = [c[-1]["rmse"] for c in (power, tree) if c and math.isfinite(c[-1]["rmse"])]
                if not (power and tree and tops):
                    continue
                target = max(tops)
                (_, se_power), (_, se_tree) = curve_cost(power), curve_cost(tree)
                out.append(SelectionComparison(technique, mis, pattern, target,
                                               time_to_target(power, target, reference_rmse),
                                               time_to_target(tree, target, reference_rmse),
                                               2 * math.hypot(se_power, se_tree)))
    return out
