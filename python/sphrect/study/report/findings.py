"""The paper's findings, measured: computed from the curves as numbers (small dataclasses); wording.py turns
them into sentences and table rows, once, at the end.  equal_error.py has the comparisons at equal error.

The techniques named here are the ones the paper's claims are about; a study without them skips the finding.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

from ..jobs import CYCLES_CURVE, CurveKey, StudyConfig
from .curves import curve_cost, fitted_slope, fitted_slope_with_error
from .results import Curves

PAPER_ORDER = ("rectangle", "triangles", "area")  # the paper: RMSE rectangle < triangles < area
RECTANGLE, TRIANGLES, AREA = PAPER_ORDER
COSINE = "rectangle_cosine"
PROJECTED = "rectangle_projected"
LTC = "rectangle_ltc"
UNSTRATIFIED = "independent"  # the pattern without stratification
LIGHT_TREE, POWER_SELECTION = "tree", "power"  # the light selections equal_error.selection_comparisons compares
# The ellipse techniques equal_error.ellipse_comparisons compares: the solid-angle map against area sampling.
ELLIPSE_MAP, ELLIPSE_AREA = "spherical_ellipse", "area"
SLOPE_DIFFERENCE = 0.03  # smallest slope difference reported as a difference


def headline_pattern(cfg: StudyConfig) -> str:
    """The pattern of the report's headline figures: the equal-time grid's if studied, else the first stratifying
    one."""
    if cfg.grid_pattern in cfg.patterns:
        return cfg.grid_pattern
    return next((p for p in cfg.patterns if p != UNSTRATIFIED), cfg.patterns[0])


def ratio_of(a: float, b: float) -> float:
    """a / b, NaN when b is 0 (a run can be infinitely wrong; a ratio is then no number)."""
    return a / b if b else float("nan")


def noise_verdict(ratio: float, noise: float, above: str, below: str) -> str:
    """`above` or `below` as a ratio of two configurations' figures is above or below 1 by more than `noise` (a
    relative margin); a tie ("within the timing noise") inside it, "not measured" without numbers."""
    if not (math.isfinite(ratio) and ratio > 0 and math.isfinite(noise)):
        return "not measured"
    if abs(math.log(ratio)) <= noise:
        return "within the timing noise"
    return above if ratio > 1 else below


def finite_span(values: Sequence[float]) -> Tuple[float, float]:
    """(min, max) of the finite values, (NaN, NaN) without one."""
    finite = [v for v in values if math.isfinite(v)]
    return (min(finite), max(finite)) if finite else (float("nan"), float("nan"))


@dataclass(frozen=True)
class OrderingRow:
    """The paper's ordering at equal samples, for one (MIS, pattern, light selection, ellipse technique), over the
    sample counts all three have."""
    mis: str
    pattern: str
    light_selection: str
    ellipse_technique: str
    points: int
    order_holds: int            # counts where RMSE rectangle < triangles < area
    rectangle_wins: int         # counts where RMSE rectangle < triangles
    triangles_ratio: float      # RMSE triangles / rectangle at the top count
    area_ratio: float           # RMSE area / rectangle at the top count

    @property
    def area_worst(self) -> bool:
        return self.area_ratio > max(1.0, self.triangles_ratio)


@dataclass(frozen=True)
class TrianglesComparison:
    """rectangle against triangles over the (MIS, light selection, ellipse technique) rows of one pattern."""
    pattern: str
    wins: int
    points: int
    low: float                  # the span of RMSE triangles / rectangle at the top
    high: float

    @property
    def verdict(self) -> str:
        if self.wins >= 0.8 * self.points and self.low > 1:
            return "reproduces"
        if self.wins <= 0.5 * self.points or self.high < 1:
            return "does NOT reproduce"
        return "partly reproduces"


def settings(cfg: StudyConfig) -> List[Tuple[str, str, str, str]]:
    """Every (MIS, pattern, light selection, ellipse technique) of the study: what a comparison of techniques holds
    fixed."""
    return [(m, p, s, e) for m in cfg.mis for p in cfg.patterns for s in cfg.light_selections
            for e in cfg.ellipse_techniques]


def ordering(cfg: StudyConfig, all_curves: Curves) -> Optional[List[OrderingRow]]:
    """None when the study lacks one of the paper's three techniques."""
    if not all(t in cfg.techniques for t in PAPER_ORDER):
        return None
    rows, medium = [], cfg.findings_medium_sampling
    for mis, pattern, selection, ellipse in settings(cfg):
        by_n = {t: {r["job"]["samples"]: r["rmse"]
                    for r in all_curves.get(CurveKey(t, mis, pattern, selection, ellipse, medium), [])}
                for t in PAPER_ORDER}
        ns = sorted(set.intersection(*(set(d) for d in by_n.values())))
        if not ns:
            continue
        rect, tri, area = (by_n[t] for t in PAPER_ORDER)
        top = ns[-1]
        rows.append(OrderingRow(mis, pattern, selection, ellipse, len(ns), sum(rect[n] < tri[n] < area[n] for n in ns),
                                sum(rect[n] < tri[n] for n in ns), ratio_of(tri[top], rect[top]),
                                ratio_of(area[top], rect[top])))
    return rows


def triangles_comparisons(cfg: StudyConfig, rows: List[OrderingRow]) -> List[TrianglesComparison]:
    """rectangle and triangles have the same pdf (uniform in solid angle): with independent samples their
    estimators have the same variance, so rectangle < triangles can only come from stratification. Judged per
    pattern, the unstratified one first."""
    out = []
    for pattern in [UNSTRATIFIED] + [p for p in cfg.patterns if p != UNSTRATIFIED]:
        selected = [r for r in rows if r.pattern == pattern]
        if selected:
            out.append(TrianglesComparison(pattern, sum(r.rectangle_wins for r in selected),
                                           sum(r.points for r in selected),
                                           *finite_span([r.triangles_ratio for r in selected])))
    return out


@dataclass(frozen=True)
class SlopeComparison:
    """Convergence slopes (RMSE vs samples) of the paper's techniques for one stratifying pattern, MIS mode, light
    selection and ellipse technique."""
    pattern: str
    mis: str
    light_selection: str
    ellipse_technique: str
    slopes: Dict[str, float]        # technique -> slope
    unstratified_rectangle: float   # rectangle's slope with independent samples
    difference: float               # slope triangles - slope rectangle
    threshold: float

    @property
    def verdict(self) -> str:
        """"faster", "slower" or "same": how the area-preserving map converges against the two-triangle map."""
        return ("faster" if self.difference > self.threshold else
                "slower" if self.difference < -self.threshold else "same")


@dataclass(frozen=True)
class Slopes:
    table: Dict[CurveKey, float]     # every curve of ours in the study -> fitted slope
    cycles: Optional[float]          # Cycles' slope, None without Cycles
    comparisons: List[SlopeComparison]


def slopes(cfg: StudyConfig, all_curves: Curves, reference_rmse: float) -> Slopes:
    table = {CurveKey(t, m, p, s, e, v): fitted_slope(all_curves.get(CurveKey(t, m, p, s, e, v), []), "samples",
                                                      reference_rmse)
             for m, p, s, e in settings(cfg) for v in cfg.medium_samplings for t in cfg.techniques}
    cycles = all_curves.get(CYCLES_CURVE)
    comparisons, medium = [], cfg.findings_medium_sampling
    for pattern in [p for p in cfg.patterns if p != UNSTRATIFIED]:
        for mis in cfg.mis:
            for selection in cfg.light_selections:
                for ellipse in cfg.ellipse_techniques:
                    fits = {t: fitted_slope_with_error(all_curves.get(CurveKey(t, mis, pattern, selection, ellipse,
                                                                               medium), []),
                                                       "samples", reference_rmse)
                            for t in PAPER_ORDER}
                    s = {t: f[0] for t, f in fits.items()}
                    if any(not math.isfinite(v) for v in s.values()):
                        continue
                    # A difference counts when it exceeds SLOPE_DIFFERENCE and twice the combined standard error.
                    se = math.hypot(fits[RECTANGLE][1], fits[TRIANGLES][1])
                    threshold = max(SLOPE_DIFFERENCE, 2 * se if math.isfinite(se) else 0.0)
                    independent = fitted_slope(all_curves.get(CurveKey(RECTANGLE, mis, UNSTRATIFIED, selection,
                                                                       ellipse, medium), []), "samples",
                                               reference_rmse)
                    comparisons.append(SlopeComparison(pattern, mis, selection, ellipse, s, independent,
                                                       s[TRIANGLES] - s[RECTANGLE], threshold))
    return Slopes(table, fitted_slope(cycles, "samples", reference_rmse) if cycles else None, comparisons)


@dataclass(frozen=True)
class TechniqueComparison:
    """One technique against another for one (MIS, pattern, light selection, ellipse technique) at the top
    sample count both measured."""
    mis: str
    pattern: str
    light_selection: str
    ellipse_technique: str
    samples: int
    rmse_ratio: float
    cost_ratio: float       # per sample (curve_cost)
    efficiency: float       # (1 / (MSE x cost)) ratio
    noise: float            # two standard errors of the costs, relative
    technique: str = COSINE
    against: str = RECTANGLE

    @property
    def equal_time_rmse_ratio(self) -> float:
        """RMSE ratio at equal time (from the costs per sample: MSE ~ 1 / samples)."""
        return self.rmse_ratio * math.sqrt(self.cost_ratio)

    @property
    def verdict(self) -> str:
        return noise_verdict(self.efficiency, self.noise, f"better than {self.against}", f"worse than {self.against}")


CosineComparison = TechniqueComparison  # rectangle_cosine against rectangle


def technique_comparisons(cfg: StudyConfig, all_curves: Curves, technique: str,
                          against: str) -> Optional[List[TechniqueComparison]]:
    """`technique` against `against` per (MIS, pattern, light selection, ellipse technique): RMSE at the top of
    the ladder, cost per sample (curve_cost) and efficiency 1 / (MSE x cost).  An efficiency ratio within two
    standard errors of the cost ratio of 1 is a tie: single runs' times move by more than that between studies.
    (The top run's MSE has its own noise, which this margin does not count.)  None when the study lacks one of the
    two."""
    if technique not in cfg.techniques or against not in cfg.techniques:
        return None
    out, medium = [], cfg.findings_medium_sampling
    for mis, pattern, selection, ellipse in settings(cfg):
        curve_a = all_curves.get(CurveKey(technique, mis, pattern, selection, ellipse, medium), [])
        curve_b = all_curves.get(CurveKey(against, mis, pattern, selection, ellipse, medium), [])
        a = {r["job"]["samples"]: r["rmse"] for r in curve_a}
        b = {r["job"]["samples"]: r["rmse"] for r in curve_b}
        ns = sorted(set(a) & set(b))
        if not ns:
            continue
        n = ns[-1]
        (cost_a, se_a), (cost_b, se_b) = curve_cost(curve_a), curve_cost(curve_b)
        out.append(TechniqueComparison(mis, pattern, selection, ellipse, n, ratio_of(a[n], b[n]), cost_a / cost_b,
                                       ratio_of(b[n] ** 2 * cost_b, a[n] ** 2 * cost_a), 2 * math.hypot(se_a, se_b),
                                       technique, against))
    return out


def cosine_comparisons(cfg: StudyConfig, all_curves: Curves) -> Optional[List[TechniqueComparison]]:
    """rectangle_cosine against rectangle (technique_comparisons)."""
    return technique_comparisons(cfg, all_curves, COSINE, RECTANGLE)


# The costlier maps and what each is set against: rectangle_projected against rectangle and rectangle_cosine,
# rectangle_ltc (which follows glossy lobes) against rectangle and rectangle_projected.
COSTLIER_MAPS = ((PROJECTED, (RECTANGLE, COSINE)), (LTC, (RECTANGLE, PROJECTED)))


def costlier_map_comparisons(cfg: StudyConfig, all_curves: Curves) -> Optional[List[TechniqueComparison]]:
    """Each of COSTLIER_MAPS the study has against the techniques it is set against (technique_comparisons; the
    pairs the study has); None if the study has none of them."""
    out = [c for technique, against_list in COSTLIER_MAPS if technique in cfg.techniques
           for against in against_list for c in technique_comparisons(cfg, all_curves, technique, against) or []]
    return out if any(technique in cfg.techniques for technique, _ in COSTLIER_MAPS) else None
