"""Comparisons at equal error, as numbers (wording.py words them): the time every configuration takes to reach one
target RMSE, the time our fastest configuration takes to reach each of Cycles' errors, the light tree's time
against power selection's for the same error, and the ellipse techniques side by side (disk and ellipse lights)."""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

from ..jobs import CYCLES_CURVE, DEFAULT_ELLIPSE_TECHNIQUE, CurveKey, StudyConfig
from .curves import Reach, curve_cost, fitted_slope, systematic_share, time_to_target
from .findings import (ELLIPSE_AREA, ELLIPSE_MAP, LIGHT_TREE, POWER_SELECTION, RECTANGLE, noise_verdict,
                       ratio_of)
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
    else rectangle's (last MIS mode, pattern, light selection and ellipse technique) in the middle of its ladder."""
    key, samples = None, None
    if given is not None:
        target, source = given, "given"
    elif all_curves.get(CYCLES_CURVE):
        cycles = all_curves[CYCLES_CURVE]
        target, source, key, samples = cycles[-1]["rmse"], "cycles", CYCLES_CURVE, cycles[-1]["job"]["samples"]
    else:
        key, source = CurveKey(RECTANGLE, cfg.mis[-1], cfg.patterns[-1], cfg.light_selections[-1],
                               cfg.ellipse_techniques[-1], cfg.findings_medium_sampling), "middle"
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
    ellipse_technique: str = DEFAULT_ELLIPSE_TECHNIQUE

    @property
    def ratio(self) -> float:
        """The tree's time / power's."""
        return ratio_of(self.tree.time, self.power.time)

    @property
    def verdict(self) -> str:
        return noise_verdict(self.ratio, self.noise, "slower", "faster")


def selection_comparisons(cfg: StudyConfig, all_curves: Curves, reference_rmse: float
                          ) -> Optional[List[SelectionComparison]]:
    """tree against power for every (technique, MIS, pattern, ellipse technique) both were measured with; None when
    the study does not have both light selections."""
    if not {LIGHT_TREE, POWER_SELECTION} <= set(cfg.light_selections):
        return None
    out = []
    for mis in cfg.mis:
        for pattern in cfg.patterns:
            for ellipse in cfg.ellipse_techniques:
                for technique in cfg.techniques:
                    power, tree = (all_curves.get(CurveKey(technique, mis, pattern, s, ellipse,
                                                           cfg.findings_medium_sampling), [])
                                   for s in (POWER_SELECTION, LIGHT_TREE))
                    tops = [c[-1]["rmse"] for c in (power, tree) if c and math.isfinite(c[-1]["rmse"])]
                    if not (power and tree and tops):
                        continue
                    target = max(tops)
                    (_, se_power), (_, se_tree) = curve_cost(power), curve_cost(tree)
                    out.append(SelectionComparison(technique, mis, pattern, target,
                                                   time_to_target(power, target, reference_rmse),
                                                   time_to_target(tree, target, reference_rmse),
                                                   2 * math.hypot(se_power, se_tree), ellipse))
    return out


def top_common_samples(runs) -> Optional[int]:
    """The largest sample count every curve of `runs` (name -> curve) measured: where the comparisons of a study axis
    (ellipse techniques, medium samplings) compare them; None where a curve is missing or they share none."""
    if not all(runs.values()):
        return None
    common = set.intersection(*({r["job"]["samples"] for r in c} for c in runs.values()))
    return max(common) if common else None


def rmse_at(curve, samples: int) -> float:
    return next(r["rmse"] for r in curve if r["job"]["samples"] == samples)


@dataclass(frozen=True)
class EllipseCurve:
    """One ellipse technique's curve, as the disk finding measures it."""
    rmse: float             # at the comparison's sample count
    slope: float            # RMSE vs samples (curves.fitted_slope)
    cost: float             # seconds per sample (curve_cost)
    cost_error: float       # its relative standard error
    cycles: Optional[Reach]  # reaching Cycles' RMSE at the top of its ladder; None without Cycles


@dataclass(frozen=True)
class EllipseComparison:
    """The ellipse techniques (how disk and ellipse lights are sampled) for one (technique, MIS, pattern, light
    selection): each one's RMSE at the top sample count all measured, slope, cost per sample and time to reach
    Cycles' error; the solid-angle map against area sampling in the ratios."""
    technique: str
    mis: str
    pattern: str
    light_selection: str
    samples: int
    curves: Dict[str, EllipseCurve]     # ellipse technique -> its measures
    cycles_time: Optional[float]        # Cycles' time for its top RMSE (its samples x its cost per sample)

    def _pair(self) -> Tuple[EllipseCurve, EllipseCurve]:
        return self.curves[ELLIPSE_MAP], self.curves[ELLIPSE_AREA]

    @property
    def rmse_ratio(self) -> float:
        """RMSE spherical_ellipse / area at equal samples."""
        ours, area = self._pair()
        return ratio_of(ours.rmse, area.rmse)

    @property
    def cost_ratio(self) -> float:
        ours, area = self._pair()
        return ratio_of(ours.cost, area.cost)

    @property
    def efficiency(self) -> float:
        """(1 / (MSE x cost per sample)) of spherical_ellipse / area's: above 1, the map reaches an error sooner."""
        ours, area = self._pair()
        return ratio_of(area.rmse ** 2 * area.cost, ours.rmse ** 2 * ours.cost)

    @property
    def noise(self) -> float:
        """Two standard errors of the two costs per sample, relative."""
        ours, area = self._pair()
        return 2 * math.hypot(ours.cost_error, area.cost_error)

    @property
    def verdict(self) -> str:
        return noise_verdict(self.efficiency, self.noise, "better than area", "worse than area")


def cycles_top(all_curves: Curves) -> Tuple[Optional[float], Optional[int], Optional[float]]:
    """Cycles' RMSE at the top of its ladder, its sample count there and its time for it (its samples x its cost per
    sample); all None without Cycles (or with a non-finite top RMSE)."""
    cycles = all_curves.get(CYCLES_CURVE)
    if not cycles or not math.isfinite(cycles[-1]["rmse"]):
        return None, None, None
    samples = cycles[-1]["job"]["samples"]
    return cycles[-1]["rmse"], samples, samples * curve_cost(cycles)[0]


def curves_along(cfg: StudyConfig, all_curves: Curves, axis: str, **fixed: str):
    """For every combination of the study's other settings (MIS, pattern, light selection, ellipse technique, medium
    sampling, technique, in that order of nesting; those in `fixed` held at the value given), the CurveKey of the
    first value of `axis` (a CurveKey field) and {value of `axis`: its curve} over the study's values of it."""
    values = {"mis": cfg.mis, "pattern": cfg.patterns, "light_selection": cfg.light_selections,
              "ellipse_technique": cfg.ellipse_techniques, "medium_sampling": cfg.medium_samplings,
              "technique": cfg.techniques}
    along = values.pop(axis)
    for field, value in fixed.items():
        values[field] = (value,)
    for combination in itertools.product(*values.values()):
        key = CurveKey(**dict(zip(values, combination)), **{axis: along[0]})
        yield key, {v: all_curves.get(key._replace(**{axis: v}), []) for v in along}


def ellipse_comparisons(cfg: StudyConfig, all_curves: Curves, reference_rmse: float
                        ) -> Optional[List[EllipseComparison]]:
    """The ellipse techniques side by side for every (technique, MIS, pattern, light selection) all were measured
    with; None when the study does not have both spherical_ellipse and area."""
    if not {ELLIPSE_MAP, ELLIPSE_AREA} <= set(cfg.ellipse_techniques):
        return None
    target, _, cycles_time = cycles_top(all_curves)
    out = []
    for key, runs in curves_along(cfg, all_curves, "ellipse_technique", medium_sampling=cfg.findings_medium_sampling):
        n = top_common_samples(runs)
        if n is None:
            continue
        measures = {}
        for e, curve in runs.items():
            cost, cost_error = curve_cost(curve)
            measures[e] = EllipseCurve(
                rmse_at(curve, n), fitted_slope(curve, "samples", reference_rmse), cost, cost_error,
                time_to_target(curve, target, reference_rmse) if target is not None else None)
        out.append(EllipseComparison(key.technique, key.mis, key.pattern, key.light_selection, n, measures,
                                     cycles_time))
    return out


@dataclass(frozen=True)
class MediumCurve:
    """One medium sampling's curve, as the medium comparison measures it."""
    rmse: float             # at the comparison's sample count
    cost: float             # seconds per sample (curve_cost)
    cost_error: float       # its relative standard error
    cycles: Optional[Reach]  # reaching Cycles' RMSE at the top of its ladder; None without Cycles


@dataclass(frozen=True)
class MediumComparison:
    """The medium samplings (how camera rays through a volume choose their scattering point) for one (technique,
    MIS, pattern, light selection, ellipse technique): each one's RMSE at the top sample count all measured, cost
    per sample, and time to reach Cycles' RMSE at the top of its ladder as a share of Cycles' time."""
    technique: str
    mis: str
    pattern: str
    light_selection: str
    ellipse_technique: str
    samples: int
    curves: Dict[str, MediumCurve]      # medium sampling -> its measures, in the study's order
    cycles_samples: Optional[int]       # Cycles' top sample count; None without Cycles
    cycles_time: Optional[float]        # Cycles' time for its top RMSE (its samples x its cost per sample)

    def cycles_ratio(self, medium: str) -> float:
        """Our time to Cycles' top RMSE / Cycles' time with `medium` (NaN without Cycles)."""
        reach = self.curves[medium].cycles
        return ratio_of(reach.time, self.cycles_time) if reach and self.cycles_time else float("nan")

    def rmse_ratio(self, medium: str, against: str) -> float:
        """RMSE `medium` / `against` at equal samples."""
        return ratio_of(self.curves[medium].rmse, self.curves[against].rmse)

    def efficiency(self, medium: str, against: str) -> float:
        """(1 / (MSE x cost per sample)) of `medium` / `against`'s: above 1, `medium` reaches an error sooner."""
        a, b = self.curves[medium], self.curves[against]
        return ratio_of(b.rmse ** 2 * b.cost, a.rmse ** 2 * a.cost)


def medium_comparisons(cfg: StudyConfig, all_curves: Curves, reference_rmse: float
                       ) -> Optional[List[MediumComparison]]:
    """The medium samplings side by side for every (technique, MIS, pattern, light selection, ellipse technique)
    all were measured with; None when the study has only one."""
    if len(cfg.medium_samplings) < 2:
        return None
    target, cycles_samples, cycles_time = cycles_top(all_curves)
    out = []
    for key, runs in curves_along(cfg, all_curves, "medium_sampling"):
        n = top_common_samples(runs)
        if n is None:
            continue
        measures = {}
        for v, curve in runs.items():
            cost, cost_error = curve_cost(curve)
            measures[v] = MediumCurve(rmse_at(curve, n), cost, cost_error,
                                      time_to_target(curve, target, reference_rmse) if target is not None else None)
        out.append(MediumComparison(key.technique, key.mis, key.pattern, key.light_selection, key.ellipse_technique,
                                    n, measures, cycles_samples, cycles_time))
    return out
