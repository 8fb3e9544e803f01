"""The cost model's section in words (costs.py has its numbers): the check of the terms against the measured time,
every configuration's terms, the break-even ray and shading costs of each pair, and Cycles' cost per camera sample."""
from __future__ import annotations

import math
from typing import Dict, List, Optional, Tuple

from ..cost_model import BreakEven
from ..jobs import CurveKey, curve_label
from .costs import (ACCURACY_TIE, CHECK_MIN_TIME, CHECK_TOLERANCE, CheckSummary, ConfigurationCost, CyclesCost,
                    PairCost)
from .wording import PLACEHOLDER, fmt


def duration(seconds: float) -> str:
    """A time per sample or per ray: in ns below a microsecond, µs below a millisecond, else ms."""
    if seconds is None or not math.isfinite(seconds):
        return PLACEHOLDER
    if abs(seconds) < 1e-6:
        return f"{fmt(seconds * 1e9)} ns"
    return f"{fmt(seconds * 1e6)} µs" if abs(seconds) < 1e-3 else f"{fmt(seconds * 1e3)} ms"


def model_lines(check: CheckSummary, ray_cost: float) -> List[str]:
    lines = ["Time per camera sample = fixed work + light sampling + rays × the cost of a ray, each term from the "
             "renderer's own stage timers and counters in the run (the fixed work: pattern, camera rays, hits, BSDFs, "
             "MIS, the shadow queue; light sampling: the choice, the technique's setup, map and pdfs; a ray: the "
             "Embree streams' time over the camera and occlusion rays). Another renderer differs chiefly in what a "
             "ray and what shading a hit cost: below, each pair's time to the same error as those two change."]
    if check.checked:
        lines.append(f"- Check: the terms add up to within {fmt(100 * CHECK_TOLERANCE)}% of the CPU time measured "
                     f"around the render call in **{check.within} of {check.checked}** runs of at least "
                     f"{fmt(1000 * CHECK_MIN_TIME)} ms (largest difference {fmt(100 * check.largest)}%). A render call "
                     f"also costs {duration(check.setup)} besides its samples (cutting tiles, starting threads: the "
                     f"intercept of CPU time against samples, median over the configurations), which shorter runs "
                     f"are not checked against.")
        if check.median > CHECK_TOLERANCE:
            lines.append(f"- **The terms run ahead of the CPU time** (by {fmt(100 * check.median)}% at the median): "
                         "the stage timers count elapsed time, which includes the time the render's threads waited "
                         "for a core while other work ran on the machine. The figures below are inflated by that "
                         "wait: run the study alone for a model to trust.")
    else:
        lines.append("- No run of at least the checked length carries the renderer's stage timers (or the runs were "
                     "measured before they existed: run the study again).")
    lines.append(f"- A ray costs **{duration(ray_cost)}** here (the median over the configurations).")
    return lines


def term_rows(costs: Dict[CurveKey, ConfigurationCost], show_selection: bool, show_ellipse: bool,
              show_medium: bool) -> List[List[str]]:
    rows = []
    for key, c in sorted(costs.items()):
        t = c.terms
        rows.append([curve_label(key, show_selection, show_ellipse, show_medium), duration(t.fixed),
                     duration(t.sampler), fmt(t.rays), duration(t.t_ray), fmt(t.hits), duration(t.modelled),
                     duration(t.measured), f"{fmt(100 * t.check, 2)}%"])
    return rows


TERM_HEADER = ["configuration", "fixed", "light sampling", "rays", "per ray", "hits", "modelled", "measured",
               "check"]


def crossing(be: BreakEven, accuracy_tie: bool = False) -> str:
    if accuracy_tie:
        return "tie in accuracy"
    if be.side == "always":
        return "at every cost"
    if be.side == "never":
        return "at no cost"
    return f"{'above' if be.side == 'above' else 'below'} {duration(be.threshold)}"


def pair_rows(pairs: List[PairCost], show_selection: bool, show_ellipse: bool, show_medium: bool) -> List[List[str]]:
    rows = []
    for p in pairs:
        rows.append([curve_label(p.b, show_selection, show_ellipse, show_medium),
                     curve_label(p.a, show_selection, show_ellipse, show_medium), fmt(p.target),
                     f"{fmt(p.n_b)} / {fmt(p.n_a)}", crossing(p.ray, p.accuracy_tie), fmt(p.efficiency()),
                     fmt(p.efficiency(1e-6)), fmt(p.efficiency(100e-6)), crossing(p.shading, p.accuracy_tie)])
    return rows


PAIR_HEADER = ["B", "against A", "RMSE", "spp B / A", "B faster at a ray cost", "efficiency B/A here", "at 1 µs",
               "at 100 µs", "B faster at a shading cost per hit"]
# ("tie in accuracy": samples within costs.ACCURACY_TIE of each other.)


def pair_names(p: PairCost) -> Tuple[str, str]:
    """B's and A's names by the setting they differ in (pair_costs: technique, MIS mode or light selection)."""
    if p.a.technique != p.b.technique:
        return p.b.technique, p.a.technique
    if p.a.mis != p.b.mis:
        return f"MIS {p.b.mis}", f"MIS {p.a.mis}"
    return (f"{p.b.technique} with light selection {p.b.light_selection}",
            f"{p.a.technique} with {p.a.light_selection}")


def pair_finding(p: PairCost, ray_cost: float) -> str:
    """One pair's verdict in a sentence."""
    b, a = pair_names(p)
    here = p.efficiency()
    if p.accuracy_tie:
        return (f"- {b} and {a} are as accurate as each other here (samples to the same error within "
                f"{fmt(100 * ACCURACY_TIE)}%): the one that costs less per sample wins, by {fmt(max(here, 1 / here))}× "
                f"at this renderer's ray cost, and neither by much where rays or shading dominate.")
    if p.ray.side == "above":
        return (f"- {b} pays off against {a} above a ray cost of **{duration(p.ray.threshold)}** (here a ray costs "
                f"{duration(ray_cost)}: efficiency {fmt(here)}×; at 100 µs per ray {fmt(p.efficiency(100e-6))}×).")
    if p.ray.side == "below":
        return (f"- {b} reaches the error sooner than {a} only below a ray cost of **{duration(p.ray.threshold)}** "
                f"(here {fmt(here)}×).")
    verdict = "sooner" if p.ray.side == "always" else "later"
    return (f"- {b} reaches the error {verdict} than {a} at every ray cost (here {fmt(here)}×, at 100 µs per ray "
            f"{fmt(p.efficiency(100e-6))}×).")


def cycles_line(c: Optional[CyclesCost], show_selection: bool, show_ellipse: bool, show_medium: bool) -> str:
    if c is None:
        return "Cycles 3.4 was not measured (or without its CPU time)."
    return (f"Cycles 3.4 takes {duration(c.cycles)} of CPU time per camera sample at its top rung (it reports no "
            f"count of rays); our cheapest configuration per camera sample, "
            f"{curve_label(c.ours_key, show_selection, show_ellipse, show_medium)}, {duration(c.ours)} "
            f"({fmt(c.ours / c.cycles)}× Cycles').")
