"""The findings in words: every number of the report is formatted here (fmt), once, from the dataclasses of
findings.py and equal_error.py.  A number that is not finite prints as PLACEHOLDER.  A configuration names its
light selection only in a study of more than one (`show_selection`, StudyConfig.shows_selection), its ellipse
technique likewise (`show_ellipse`, StudyConfig.shows_ellipse), its medium sampling likewise (`show_medium`,
StudyConfig.shows_medium)."""
from __future__ import annotations

import math
from typing import List, Optional

import numpy as np

from .. import metrics
from ..jobs import CYCLES, CYCLES_CURVE, CurveKey, curve_label, ellipse_part, medium_part, selection_part
from .curves import BELOW_FEWEST, BEYOND_LONGEST, EXTRAPOLATION_LIMIT, Reach
from .equal_error import CyclesComparison, EllipseComparison, MediumComparison, SelectionComparison, TargetTimes
from .findings import (AREA, COSINE, ELLIPSE_AREA, ELLIPSE_MAP, LIGHT_TREE, POWER_SELECTION, RECTANGLE, TRIANGLES,
                       UNSTRATIFIED, CosineComparison, OrderingRow, SlopeComparison, Slopes, TrianglesComparison,
                       finite_span)
from .results import EqualTimeGrid

PLACEHOLDER = "–"
CYCLES_NAME = curve_label(CYCLES_CURVE)
COST_NOTE = (f"Times are samples per pixel x the configuration's cost per sample, the mean of time / samples over "
             f"its {metrics.COST_RUNS} largest runs: single runs' times scatter by 10-20% on a shared machine.")


def fmt(x, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return PLACEHOLDER
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return f"{x:.{digits}g}"


def reach_how(reach: Reach) -> str:
    if reach.how == BEYOND_LONGEST:
        return f"beyond {EXTRAPOLATION_LIMIT}x the longest run ({fmt(reach.longest)} s)"
    if reach.how == BELOW_FEWEST:
        return f"at most: already below at {fmt(reach.samples)} spp"
    return reach.how


# ------------------------------------------------------------------------------------------------
# The paper's findings

def setting_names(show_selection: bool = False, show_ellipse: bool = False, first: str = "MIS, pattern") -> str:
    """What a comparison holds fixed, in words: `first`, then the light selection and the ellipse technique when
    the study has several."""
    return first + (", light selection" if show_selection else "") + (", ellipse technique" if show_ellipse else "")


def ordering_lines(rows: Optional[List[OrderingRow]], comparisons: List[TrianglesComparison],
                   show_selection: bool = False, show_ellipse: bool = False) -> List[str]:
    if rows is None:
        return [f"The paper's ordering needs the {AREA}, {TRIANGLES} and {RECTANGLE} techniques."]
    setting = setting_names(show_selection, show_ellipse)
    lines = []
    total = sum(r.points for r in rows)
    if total:
        lines.append(f"At equal samples, RMSE({RECTANGLE}) < RMSE({TRIANGLES}) < RMSE({AREA}) holds at "
                     f"{sum(r.order_holds for r in rows)} of {total} ({setting}, sample count) points.")
    worst = sum(r.area_worst for r in rows)
    lines.append(f"- area is the worst of the three at the top of the ladder in {worst} of {len(rows)} "
                 f"({setting}) cases: "
                 + ("**reproduces** the paper." if worst == len(rows) else "**does NOT fully reproduce**."))
    for c in comparisons:
        start = (f"- rectangle vs triangles with {c.pattern} samples: rectangle is lower at {c.wins} of {c.points} "
                 f"points, RMSE ratio triangles/rectangle at the top {fmt(c.low)} ... {fmt(c.high)}")
        if c.pattern == UNSTRATIFIED:
            lines.append(start + ". Both sample uniformly in solid angle (the same pdf), so with independent samples "
                         "they are expected to tie; the paper's advantage is about stratification.")
        else:
            lines.append(start + f": the paper's finding **{c.verdict}** here.")
    return lines


def ordering_rows(rows: Optional[List[OrderingRow]], show_selection: bool = False,
                  show_ellipse: bool = False) -> List[List[str]]:
    return [[r.mis, r.pattern] + ([r.light_selection] if show_selection else [])
            + ([r.ellipse_technique] if show_ellipse else [])
            + [f"{r.order_holds}/{r.points}", f"{r.rectangle_wins}/{r.points}", fmt(r.triangles_ratio),
               fmt(r.area_ratio)] for r in rows or []]


def slope_rows(slopes: Slopes, cfg) -> List[List[str]]:
    """A row per (MIS, light selection, ellipse technique, medium sampling, technique) of the study's StudyConfig
    `cfg`, a column per pattern (after a light selection, an ellipse technique and a medium sampling column in a
    study of several); Cycles' last."""
    show, show_ellipse, show_medium = cfg.shows_selection, cfg.shows_ellipse, cfg.shows_medium
    rows = [[t, m] + ([s] if show else []) + ([e] if show_ellipse else []) + ([v] if show_medium else [])
            + [fmt(slopes.table[CurveKey(t, m, p, s, e, v)], 3) for p in cfg.patterns]
            for m in cfg.mis for s, e, v in cfg.variants for t in cfg.techniques]
    if slopes.cycles is not None:
        rows.append([CYCLES_NAME, CYCLES_CURVE.mis] + ([""] if show else []) + ([""] if show_ellipse else [])
                    + ([""] if show_medium else [])
                    + [fmt(slopes.cycles, 3) if i == 0 else "" for i in range(len(cfg.patterns))])
    return rows


SLOPE_VERDICTS = {
    "faster": "converges faster than the two-triangle map (reproduces the paper)",
    "slower": "converges SLOWER than the two-triangle map (does NOT reproduce the paper)",
}


def slope_line(c: SlopeComparison, show_selection: bool = False, show_ellipse: bool = False) -> str:
    verdict = SLOPE_VERDICTS.get(c.verdict) or (
        "converges at the same rate as the two-triangle map within the fits' precision "
        f"(difference {fmt(c.difference, 2)}, threshold {fmt(c.threshold, 2)}): the paper's "
        "stratification advantage is NOT visible in the slope")
    return (f"- {c.pattern}, MIS {c.mis}{selection_part(c.light_selection, show_selection, ', ')}"
            f"{ellipse_part(c.ellipse_technique, show_ellipse, ', ')}: slope rectangle "
            f"{fmt(c.slopes[RECTANGLE], 3)}, triangles "
            f"{fmt(c.slopes[TRIANGLES], 3)}, area {fmt(c.slopes[AREA], 3)}; independent-pattern slope of "
            f"rectangle {fmt(c.unstratified_rectangle, 3)} -> the area-preserving map {verdict}.")


def cosine_line(c: CosineComparison, show_selection: bool = False, show_ellipse: bool = False) -> str:
    """One technique comparison (rectangle_cosine against rectangle, or a costlier map against those of
    findings.COSTLIER_MAPS)."""
    equal_time = (f", RMSE ratio at equal time {fmt(c.equal_time_rmse_ratio)}" if c.technique != COSINE else "")
    return (f"- MIS {c.mis}, {c.pattern}{selection_part(c.light_selection, show_selection, ', ')}"
            f"{ellipse_part(c.ellipse_technique, show_ellipse, ', ')}, {c.samples} spp: "
            f"RMSE({c.technique})/RMSE({c.against}) = {fmt(c.rmse_ratio)}, "
            f"cost ratio {fmt(c.cost_ratio)} (per sample, top {metrics.COST_RUNS} runs){equal_time}, efficiency "
            f"(1/(MSE x time)) ratio {fmt(c.efficiency)}, timing noise +-{fmt(100 * c.noise, 2)}% ({c.verdict}).")


def costlier_map_summary_lines(comparisons: Optional[List[CosineComparison]], selection_case: str = "") -> List[str]:
    """Summary: in how many cases each costlier map (rectangle_projected, rectangle_ltc) is more efficient than each
    technique it is compared with."""
    lines = []
    for technique, against in dict.fromkeys((c.technique, c.against) for c in comparisons or []):
        verdicts = [c.verdict for c in comparisons if (c.technique, c.against) == (technique, against)]
        lines.append(f"- {technique} is more efficient (1 / (MSE x time)) than {against} in "
                     f"{verdicts.count('better than ' + against)} of {len(verdicts)} (MIS, pattern{selection_case}) "
                     f"cases at the top of the ladder, less in {verdicts.count('worse than ' + against)}, "
                     f"indistinguishable within the timing noise in the rest.")
    return lines


# ------------------------------------------------------------------------------------------------
# Equal error

def cycles_lines(c: Optional[CyclesComparison]) -> List[str]:
    if c is None:
        return ["Cycles was not part of this study (no Blender, no .blend, or --no-cycles)."]
    reached = c.reached
    if not c.measurable:
        return [f"Cycles 3.4 comparison not measurable here: its error has stopped falling with samples. About "
                f"{c.systematic_share:.0%} of its MSE at {c.top_samples} spp is a systematic difference from our "
                f"reference (for example Cycles' multiscatter GGX against our single-scatter GGX on glossy "
                f"materials), so the time our renderer needs to reach Cycles' error measures that difference, not "
                f"light sampling (the table shows the ratios anyway: {fmt(reached[-1].ratio)}x at the top)."]
    if reached:
        low, high = (f([p.ratio for p in reached]) for f in (min, max))
        goal = "meets" if c.meets_goal else "does NOT meet"
        bound = "at most " if reached[-1].reach.how == BELOW_FEWEST else ""
        return [f"To reach the RMSE Cycles 3.4 reaches with {reached[-1].samples} spp, our best configuration needs "
                f"{bound}**{fmt(c.top_ratio)}x** Cycles' time (goal: at most 1/3 -> this {goal} the goal). Over the "
                f"whole ladder the ratio ranges {fmt(low)} ... {fmt(high)}."]
    return ["No configuration of ours reached Cycles' errors within the measured ladder."]


def cycles_rows(c: Optional[CyclesComparison], show_selection: bool = False,
                show_ellipse: bool = False, show_medium: bool = False) -> List[List[str]]:
    rows = []
    for p in c.points if c else []:
        start = [fmt(p.samples), fmt(p.rmse), fmt(p.time)]
        if p.reach is None:
            rows.append(start + [PLACEHOLDER] * 3)
        else:
            how = "" if p.reach.how == "measured" else f" ({reach_how(p.reach)})"
            rows.append(start + [curve_label(p.best, show_selection, show_ellipse, show_medium),
                                 fmt(p.reach.time) + how,
                                 fmt(p.ratio)])
    return rows


def target_line(t: TargetTimes, show_selection: bool = False, show_ellipse: bool = False,
                show_medium: bool = False) -> str:
    why = {"given": "given on the command line",
           "cycles": f"the RMSE of {CYCLES_NAME} at {t.samples} spp",
           "middle": f"the RMSE of {curve_label(t.key, show_selection, show_ellipse, show_medium)} in the middle "
                     f"of the ladder"
                     if t.key else ""
           }[t.source]
    return (f"Target RMSE {fmt(t.rmse)} ({why}). 'measured' = interpolated between measured points "
            f"(log-log); 'extrapolated' = along the power law fitted to the curve's upper half. {COST_NOTE}")


def target_rows(t: TargetTimes, show_selection: bool = False, show_ellipse: bool = False,
                show_medium: bool = False) -> List[List[str]]:
    return [[curve_label(key, show_selection, show_ellipse, show_medium), fmt(r.time), reach_how(r), fmt(r.samples)]
            for key, r in t.reached]


def equal_time_rows(grid: EqualTimeGrid, show_selection: bool = False, show_ellipse: bool = False,
                    show_medium: bool = False) -> List[List[str]]:
    """configuration, samples per pixel, time, RMSE, relMSE of every render the grid shows (Cycles once)."""
    rows = []
    for row_index, row in enumerate(grid.rows):
        for name in grid.columns:
            r = grid.cells.get((row, name))  # none for the reference's column
            if r is None or (name == CYCLES and row_index):
                continue
            label = CYCLES_NAME if name == CYCLES else \
                f"{name} / mis={row.mis}" + selection_part(row.light_selection, show_selection, " / ") \
                + ellipse_part(row.ellipse_technique, show_ellipse, " / ") \
                + medium_part(row.medium_sampling, show_medium, " / ")
            rows.append([label, fmt(r.get("samples_done")), fmt(r.get("time")), fmt(r["rmse"]), fmt(r["relmse"])])
    return rows


def selection_lines(comparisons: Optional[List[SelectionComparison]]) -> List[str]:
    """The light tree against power selection at equal error: the sentence of the findings and of the summary."""
    if comparisons is None:
        return [f"The study has not both the {POWER_SELECTION} and the {LIGHT_TREE} light selection "
                f"(--light-selections {POWER_SELECTION},{LIGHT_TREE} compares them)."]
    ratios = [c.ratio for c in comparisons if math.isfinite(c.ratio)]
    if not ratios:
        return [f"- Light selection: no (technique, MIS, pattern) configuration reached a common error with both "
                f"{LIGHT_TREE} and {POWER_SELECTION}."]
    verdicts = [c.verdict for c in comparisons]
    low, high = finite_span(ratios)
    return [f"- Light selection: to reach the same RMSE, {LIGHT_TREE} takes **{fmt(float(np.median(ratios)))}x** the "
            f"time of {POWER_SELECTION} (median over {len(comparisons)} (technique, MIS, pattern) configurations, "
            f"range {fmt(low)} ... {fmt(high)}): faster in {verdicts.count('faster')}, "
            f"slower in {verdicts.count('slower')}, "
            f"indistinguishable within the timing noise in the rest."]


def selection_rows(comparisons: Optional[List[SelectionComparison]], show_ellipse: bool = False
                   ) -> List[List[str]]:
    return [[c.technique, c.mis, c.pattern] + ([c.ellipse_technique] if show_ellipse else [])
            + [fmt(c.rmse), fmt(c.power.time), fmt(c.tree.time), fmt(c.ratio),
               f"{c.verdict} (+-{fmt(100 * c.noise, 2)}%)"] for c in comparisons or []]


def ellipse_lines(comparisons: Optional[List[EllipseComparison]], show_selection: bool = False) -> List[str]:
    """The ellipse techniques side by side: the sentence of the findings and of the summary."""
    if comparisons is None:
        return [f"The study has not both the {ELLIPSE_AREA} and the {ELLIPSE_MAP} ellipse technique "
                f"(--ellipse-techniques {ELLIPSE_AREA},{ELLIPSE_MAP} compares them)."]
    if not comparisons:
        return [f"- Disk and ellipse lights: no configuration was measured with both {ELLIPSE_AREA} and "
                f"{ELLIPSE_MAP}."]
    configurations = f"{len(comparisons)} ({setting_names(show_selection, first='technique, MIS, pattern')})"
    rmse_low, rmse_high = finite_span([c.rmse_ratio for c in comparisons])
    rmse = [c.rmse_ratio for c in comparisons if math.isfinite(c.rmse_ratio)]
    cost = [c.cost_ratio for c in comparisons if math.isfinite(c.cost_ratio)]
    verdicts = [c.verdict for c in comparisons]
    return [f"- Disk and ellipse lights: at equal samples RMSE({ELLIPSE_MAP}) / RMSE({ELLIPSE_AREA}) = "
            f"**{fmt(float(np.median(rmse)) if rmse else math.nan)}** (median over {configurations} "
            f"configurations, range {fmt(rmse_low)} ... {fmt(rmse_high)}) at "
            f"{fmt(float(np.median(cost)) if cost else math.nan)}x the cost per sample; efficiency "
            f"(1 / (MSE x time)): {ELLIPSE_MAP} better in {verdicts.count('better than area')}, worse in "
            f"{verdicts.count('worse than area')}, indistinguishable within the timing noise in the rest."]


def ellipse_columns(show_selection: bool = False) -> List[str]:
    """The header of ellipse_rows: a column per ellipse technique for each measure."""
    both = (ELLIPSE_AREA, ELLIPSE_MAP)
    return (["technique", "MIS", "pattern"] + (["light selection"] if show_selection else []) + ["spp"]
            + [f"RMSE {e}" for e in both] + [f"RMSE ratio {ELLIPSE_MAP}/{ELLIPSE_AREA}"]
            + [f"slope {e}" for e in both] + [f"cost per sample [ms per spp] {e}" for e in both]
            + [f"time to Cycles' RMSE [s] {e}" for e in both] + ["Cycles' time [s]", "efficiency verdict"])


def ellipse_rows(comparisons: Optional[List[EllipseComparison]], show_selection: bool = False) -> List[List[str]]:
    rows = []
    for c in comparisons or []:
        both = [c.curves[e] for e in (ELLIPSE_AREA, ELLIPSE_MAP)]
        reach = [fmt(m.cycles.time) + ("" if m.cycles.how == "measured" else f" ({reach_how(m.cycles)})")
                 if m.cycles else PLACEHOLDER for m in both]
        rows.append([c.technique, c.mis, c.pattern] + ([c.light_selection] if show_selection else [])
                    + [fmt(c.samples)] + [fmt(m.rmse) for m in both] + [fmt(c.rmse_ratio)]
                    + [fmt(m.slope, 3) for m in both] + [fmt(1e3 * m.cost) for m in both] + reach
                    + [fmt(c.cycles_time), f"{c.verdict} (ratio {fmt(c.efficiency)}, +-{fmt(100 * c.noise, 2)}%)"])
    return rows


def medium_lines(comparisons: Optional[List[MediumComparison]]) -> List[str]:
    """The medium samplings side by side: the sentences of the findings and of the summary (the time each needs
    for Cycles' RMSE, as a share of Cycles' time, per technique)."""
    if comparisons is None:
        return ["The study has only one medium sampling (--medium-samplings mis,distance,equiangular compares "
                "them)."]
    if not comparisons:
        return ["- Medium sampling: no configuration was measured with every medium sampling."]
    lines = []
    for c in comparisons:
        setting = f"{c.technique}, MIS {c.mis}, {c.pattern}"
        if c.cycles_time:
            times = ", ".join(f"{v} {fmt(c.cycles_ratio(v))}x" + _bound(c.curves[v].cycles) for v in c.curves)
            lines.append(f"- Medium sampling ({setting}): to reach Cycles' RMSE at {c.cycles_samples} spp: {times} "
                         f"Cycles' time.")
        else:
            rmse = ", ".join(f"{v} {fmt(c.curves[v].rmse)}" for v in c.curves)
            lines.append(f"- Medium sampling ({setting}): RMSE at {c.samples} spp: {rmse}.")
    return lines


def _bound(reach) -> str:
    """How a time to Cycles' RMSE was found, when not between measured points."""
    return "" if reach is None or reach.how == "measured" else f" ({reach_how(reach)})"


def medium_columns(comparisons: List[MediumComparison], show_selection: bool = False,
                   show_ellipse: bool = False) -> List[str]:
    """The header of medium_rows: a column per medium sampling for each measure."""
    names = list(comparisons[0].curves) if comparisons else []
    return (["technique", "MIS", "pattern"] + (["light selection"] if show_selection else [])
            + (["ellipse technique"] if show_ellipse else []) + ["spp"] + [f"RMSE {v}" for v in names]
            + [f"cost per sample [ms per spp] {v}" for v in names]
            + [f"time to Cycles' RMSE [s] {v}" for v in names] + ["Cycles' time [s]"]
            + [f"x Cycles' time {v}" for v in names])


def medium_rows(comparisons: Optional[List[MediumComparison]], show_selection: bool = False,
                show_ellipse: bool = False) -> List[List[str]]:
    rows = []
    for c in comparisons or []:
        measures = list(c.curves.values())
        reach = [fmt(m.cycles.time) + _bound(m.cycles) if m.cycles else PLACEHOLDER for m in measures]
        rows.append([c.technique, c.mis, c.pattern] + ([c.light_selection] if show_selection else [])
                    + ([c.ellipse_technique] if show_ellipse else []) + [fmt(c.samples)]
                    + [fmt(m.rmse) for m in measures] + [fmt(1e3 * m.cost) for m in measures] + reach
                    + [fmt(c.cycles_time)] + [fmt(c.cycles_ratio(v)) for v in c.curves])
    return rows


# ------------------------------------------------------------------------------------------------
# Summary

def summary_lines(ordering: List[str], slopes: Slopes, cosine: Optional[List[CosineComparison]],
                  cycles: Optional[CyclesComparison], reference_rmse: float, smallest: float,
                  selection: Optional[List[SelectionComparison]] = None, show_selection: bool = False,
                  ellipse: Optional[List[EllipseComparison]] = None, show_ellipse: bool = False,
                  costlier_maps: Optional[List[CosineComparison]] = None,
                  medium: Optional[List[MediumComparison]] = None) -> List[str]:
    """The headline numbers, from the findings the report shows below the summary (`ordering`: its lines)."""
    selection_case = setting_names(show_selection, show_ellipse, first="")
    lines = []
    ratio = cycles.top_ratio if cycles else None
    if ratio is not None:
        lines.append("- Goal (our best configuration needs at most 1/3 of Cycles 3.4's time for Cycles' RMSE at the "
                     "top of the ladder, or the highest count whose error our runs reach): measured ratio "
                     + ("at most " if cycles.reached[-1].reach.how == BELOW_FEWEST else "")
                     + f"**{fmt(ratio)}** -> " + ("**met**." if cycles.meets_goal else "**not met**."))
    else:
        lines.append("- " + cycles_lines(cycles)[0])
    lines += [l for l in ordering if l.startswith("- ")]
    verdicts = [c.verdict for c in slopes.comparisons]
    if verdicts:
        lines.append(f"- Stratification (convergence slopes, stratified/low-discrepancy patterns): the area-preserving "
                     f"map converges faster than the two-triangle map in {verdicts.count('faster')} of "
                     f"{len(verdicts)} (pattern, MIS{selection_case}) cases, slower in {verdicts.count('slower')}, "
                     f"indistinguishable in the rest.")
    if cosine:
        verdicts = [c.verdict for c in cosine]
        lines.append(f"- rectangle_cosine is more efficient (1 / (MSE x time)) than rectangle in "
                     f"{verdicts.count('better than rectangle')} of {len(cosine)} (MIS, pattern{selection_case}) cases "
                     f"at the top of the ladder, less in {verdicts.count('worse than rectangle')}, indistinguishable "
                     f"within the timing noise in the rest.")
    lines += costlier_map_summary_lines(costlier_maps, selection_case)
    if selection is not None:
        lines += selection_lines(selection)
    if ellipse is not None:
        lines += ellipse_lines(ellipse, show_selection)
    if medium is not None:
        lines += medium_lines(medium)
    if math.isfinite(smallest):
        lines.append(f"- The reference's own RMSE is {fmt(100 * reference_rmse / smallest, 2)}% of the "
                     f"smallest error measured.")
    return lines
