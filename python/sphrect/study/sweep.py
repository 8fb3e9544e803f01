"""The cost model's validation: a finished study's scene made costlier, level by level, and each pair's verdict at
equal error measured against the model's prediction.

    PYTHONPATH=build/python /usr/bin/python3 -m sphrect.study.sweep STUDY_DIR [--levels 0,2,4,6]
        [--ray-costs 0,1e-7,3e-7,1e-6,3e-6,1e-5] [--shading-costs ...] [--repeats 3] [--report-only]

Three axes.  Geometry: the scene's non-emissive meshes split `level` times (complexity.subdivide_scene: the same
image, a deeper BVH), so that a ray costs more -- really, but only over what one scene's BVH can span (here tens of
ns).  A cost added per ray traced and one added per surface hit shaded (Renderer's added_ray_cost and
added_shading_cost: busy waits): a production scene's rays and shaders, over microseconds.  None changes the image, so
the samples each configuration needs for an error are the study's (its ladder, level 0); at every level each
configuration at the study's headline pattern (its techniques under each of its MIS modes: headline_keys) is rendered
again for its cost per camera sample (the least CPU time of --repeats renders).  Per pair -- every two techniques
under one MIS mode, every two MIS modes of a technique (report/costs.py: B needs fewer samples than A for the larger
of their top-rung RMSEs):

- predicted: A's time to the error over B's at that level, from the study's own terms (cost_model.CostTerms) with the
  level's ray cost (the median t_ray measured there) or its added shading cost, and the break-even cost;
- measured: the same ratio from the costs per camera sample measured at that level, and where it crosses 1.

Writes STUDY_DIR/sweep/sweep.md, sweep.json and sweep.png (--report-only: sweep.md and sweep.png again from sweep.json).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import asdict, dataclass
from typing import Dict, List, Optional, Sequence

from . import complexity
from .cost_model import RAY_AXIS, SHADING_AXIS, break_even, cost_terms, upper_median
from .jobs import CurveKey, Job
from .store import atomic_write_bytes, atomic_write_json

# Each render of the sweep lasts about this long (its samples per pixel chosen from the study's cost per sample), so
# that the timers' resolution and the call's own setup stay small against it.
RENDER_SECONDS = 0.3
MAX_SWEEP_SAMPLES = 64
# The sweep's axes: the geometry subdivided, a cost added per ray traced, a cost added per surface hit shaded; the
# model's axis each moves along (the first two: the ray cost, measured at each level), and their titles.
GEOMETRY, ADDED_RAY, ADDED_SHADING = "geometry", "added ray cost", "added shading cost"
MODEL_AXIS = {GEOMETRY: RAY_AXIS, ADDED_RAY: RAY_AXIS, ADDED_SHADING: SHADING_AXIS}
AXIS_TITLES = {GEOMETRY: "geometry (subdivision levels)", ADDED_RAY: "a cost added per ray traced",
               ADDED_SHADING: "a cost added per surface hit shaded"}
# A measured time ratio within this of 1 is a tie: the least of three renders' CPU times scatters by ~1-3% between
# levels on the shared machine (the paper scene's MIS pairs, whose images are the same, measured 0.975-1.01).
TIMING_NOISE = 0.03


@dataclass(frozen=True)
class Level:
    axis: str            # GEOMETRY, ADDED_RAY or ADDED_SHADING
    value: float         # subdivision levels, or the cost added per ray or per hit [s]
    triangles: int
    ray_cost: float      # the median t_ray measured at this level [s]
    costs: Dict[str, float]   # configuration (label) -> measured CPU time per camera sample [s]
    terms: Dict[str, Dict]    # configuration -> its measured CostTerms (as a dict)


@dataclass(frozen=True)
class PairVerdict:
    a: str
    b: str
    n_a: float
    n_b: float
    break_even: float        # predicted break-even along the axis [s] (NaN: none)
    side: str                # BreakEven.side
    predicted: List[float]   # per level: A's time to the error over B's, from the study's terms
    measured: List[float]    # per level: the same from the measured costs
    measured_crossing: Optional[float]  # where the measured ratio crosses 1 along the axis (interpolated), or None
    accuracy_tie: bool = False          # report/costs.PairCost.accuracy_tie: the break-even means nothing


def headline_keys(settings, all_curves) -> List[CurveKey]:
    """The study's techniques under each of its MIS modes at its headline pattern and first light selection (ellipse
    technique, medium sampling): the configurations the sweep renders again."""
    from .report.findings import headline_pattern
    keys = [CurveKey(t, m, headline_pattern(settings), *settings.variants[0]) for m in settings.mis
            for t in settings.techniques]
    return [k for k in keys if all_curves.get(k)]


def label(key: CurveKey) -> str:
    """A configuration's name in the sweep: its technique and MIS mode (the rest is the headline's)."""
    return f"{key.technique} / mis={key.mis}"


def measure_level(scene, keys: Sequence[CurveKey], samples: Dict[str, int], repeats: int, axis: str, value: float,
                  run_options: Dict[str, Dict[str, int]]) -> Level:
    """Every configuration rendered `repeats` times at this level, the repeats interleaved (a round over all of them,
    then the next), so that a stretch of other load on the machine slows one round, not every repeat of one
    configuration; each keeps its least CPU time per camera sample."""
    import sphrect
    shading = value if axis == ADDED_SHADING else 0.0
    ray = value if axis == ADDED_RAY else 0.0
    best: Dict[str, object] = {}
    for r in range(repeats):
        for key in keys:
            renderer = sphrect.Renderer(scene, techniques=[key.technique], mis=key.mis, pattern=key.pattern,
                                        light_selection=key.light_selection, ellipse_technique=key.ellipse_technique,
                                        medium_sampling=key.medium_sampling, **run_options[label(key)], threads=1,
                                        seed=7 + r, added_shading_cost=shading, added_ray_cost=ray)
            c0 = time.process_time()
            renderer.render(samples[label(key)])
            cpu = time.process_time() - c0
            t = cost_terms({**renderer.stats(), "cpu_time": cpu})
            if label(key) not in best or t.measured < best[label(key)].measured:
                best[label(key)] = t
    costs = {name: t.measured for name, t in best.items()}
    terms = {name: asdict(t) for name, t in best.items()}
    return Level(axis, value, complexity.triangle_count(scene), upper_median([t["t_ray"] for t in terms.values()]),
                 costs, terms)


def crossing(xs: Sequence[float], ratios: Sequence[float], noise: float = 0.0) -> Optional[float]:
    """Where the ratio goes from one side of 1 to the other, each by more than `noise` (relative: a ratio within it of
    1 is a tie, not a side) -- between the last point on the first side and the next point on the other, in
    log-linear interpolation (x = 0 kept linear); the first such place; None where it does not."""
    sides = [0 if abs(r - 1) <= noise else (1 if r > 1 else -1) for r in ratios]
    last = None
    for i, side in enumerate(sides):
        if side == 0:
            continue
        if last is not None and sides[last] != side:
            x0, r0, x1, r1 = xs[last], ratios[last], xs[i], ratios[i]
            f = (1 - r0) / (r1 - r0)
            if x0 > 0 and x1 > 0:
                return math.exp(math.log(x0) + f * (math.log(x1) - math.log(x0)))
            return x0 + f * (x1 - x0)
        last = i
    return None


def axis_positions(levels: List[Level], axis: str) -> List[float]:
    """Where the levels of a sweep axis lie on the model's axis: the ray cost measured there, or the shading cost."""
    return [lv.ray_cost if MODEL_AXIS[axis] == RAY_AXIS else lv.value for lv in levels]


def verdicts(pairs, levels: List[Level], axis: str) -> List[PairVerdict]:
    """Every pair along the sweep axis `axis` (GEOMETRY, ADDED_RAY, ADDED_SHADING)."""
    xs = axis_positions(levels, axis)
    model_axis = MODEL_AXIS[axis]
    out = []
    for p in pairs:
        a, b = label(p.a), label(p.b)
        predicted = [p.efficiency(x) if model_axis == RAY_AXIS else p.efficiency(None, x) for x in xs]
        measured = [(p.n_a * lv.costs[a]) / (p.n_b * lv.costs[b]) for lv in levels]
        be = break_even(p.n_a, p.terms_a, p.n_b, p.terms_b, model_axis)
        out.append(PairVerdict(a, b, p.n_a, p.n_b, be.threshold, be.side, predicted, measured,
                               crossing(xs, measured, TIMING_NOISE), p.accuracy_tie))
    return out


def ns(seconds: Optional[float]) -> str:
    if seconds is None or not math.isfinite(seconds):
        return "–"
    return f"{seconds * 1e9:.3g} ns" if seconds < 1e-6 else f"{seconds * 1e6:.3g} µs"


def predicted_side(v: PairVerdict) -> str:
    if v.accuracy_tie:
        return "tie in accuracy"
    if v.side in ("always", "never"):
        return "B faster at every cost" if v.side == "always" else "A faster at every cost"
    return f"B faster {v.side} {ns(v.break_even)}"


def summary(pair_verdicts: List[PairVerdict], levels: List[Level], axis: str) -> str:
    """The agreement in words: the predicted ratios against the measured, the verdicts beyond the timing noise, the
    flips predicted within the levels' range and those measured."""
    differences = sorted(abs(p / m - 1) for v in pair_verdicts for p, m in zip(v.predicted, v.measured))
    side = [(0 if abs(r - 1) <= TIMING_NOISE else (1 if r > 1 else -1)) for v in pair_verdicts for r in v.measured]
    predicted_sides = [(1 if r > 1 else -1) for v in pair_verdicts for r in v.predicted]
    decided = [(s, p) for s, p in zip(side, predicted_sides) if s != 0]
    xs = axis_positions(levels, axis)
    inside = [v for v in pair_verdicts if v.side in ("above", "below") and min(xs) <= v.break_even <= max(xs)
              and not v.accuracy_tie]
    measured = [v for v in pair_verdicts if v.measured_crossing is not None and not v.accuracy_tie]
    ties = [v for v in pair_verdicts if v.measured_crossing is not None and v.accuracy_tie]
    if not differences:
        return "No pair to compare."
    return (f"Over {len(pair_verdicts)} pairs x {len(levels)} levels ({ns(min(xs))} to {ns(max(xs))}): the predicted "
            f"ratio is within {100 * upper_median(differences):.2g}% of the measured one at the median, "
            f"{100 * differences[-1]:.2g}% at worst; where the measured ratio is beyond the ±{100 * TIMING_NOISE:.0f}% "
            f"timing noise, the predicted verdict (which of the two is faster) agrees in "
            f"**{sum(s == p for s, p in decided)} of {len(decided)}** cases. Break-even costs the model puts within "
            f"the levels' range: {len(inside)}; crossings measured: {len(measured)}"
            + (" -- " + "; ".join(f"{v.b} / {v.a}: predicted {predicted_side(v)}, measured "
                                  f"{ns(v.measured_crossing) if v.measured_crossing is not None else 'none'}"
                                  for v in {id(v): v for v in inside + measured}.values()) if inside or measured
               else "")
            + (f"; pairs tied in accuracy whose measured ratio strays across 1 by more than the noise: {len(ties)}"
               if ties else "") + ". A measured crossing lies between the last level on one side of 1 and the "
            "next beyond the noise on the other: it is located to within the levels' spacing.")


def write_outputs(out_dir: str, levels: Dict[str, List[Level]], pair_verdicts: Dict[str, List[PairVerdict]]) -> str:
    os.makedirs(out_dir, exist_ok=True)
    atomic_write_json(os.path.join(out_dir, "sweep.json"),
                      {axis: {"levels": [asdict(lv) for lv in levels[axis]],
                              "pairs": [asdict(v) for v in pair_verdicts[axis]]} for axis in levels})
    lines = ["# The cost model against a sweep of the scene's cost\n",
             "A's time to the same error over B's (> 1: B reaches it sooner), predicted from the study's own terms "
             "and measured at each level; the break-even cost predicted from the study's terms, and where the "
             "measured ratio crosses 1.\n"]
    for axis, axis_levels in levels.items():
        lines.append(f"## {AXIS_TITLES[axis]}\n")
        lines.append(summary(pair_verdicts[axis], axis_levels, axis) + "\n")
        lines.append("| level | triangles | ray cost | " + " | ".join(
            f"{t} [ns per camera sample]" for t in axis_levels[0].costs) + " |")
        lines.append("|" + "---|" * (3 + len(axis_levels[0].costs)))
        for lv in axis_levels:
            label = f"{lv.value:g}" if axis == GEOMETRY else ns(lv.value)
            lines.append(f"| {label} | {lv.triangles} | {ns(lv.ray_cost)} | " + " | ".join(
                f"{c * 1e9:.0f}" for c in lv.costs.values()) + " |")
        lines.append("")
        lines.append("| B | against A | spp B / A | predicted | measured crossing | " + " | ".join(
            f"level {lv.value:g}" if axis == GEOMETRY else ns(lv.value) for lv in axis_levels)
            + " (measured / predicted) |")
        lines.append("|" + "---|" * (5 + len(axis_levels)))
        for v in pair_verdicts[axis]:
            cells = " | ".join(f"{m:.3g} / {p:.3g}" for m, p in zip(v.measured, v.predicted))
            lines.append(f"| {v.b} | {v.a} | {v.n_b:.3g} / {v.n_a:.3g} | {predicted_side(v)} | "
                         f"{ns(v.measured_crossing) if v.measured_crossing is not None else 'none'} | {cells} |")
        lines.append("")
    path = os.path.join(out_dir, "sweep.md")
    atomic_write_bytes(path, "\n".join(lines).encode("utf-8"))
    plot(out_dir, levels, pair_verdicts)
    return path


def plot(out_dir: str, levels: Dict[str, List[Level]], pair_verdicts: Dict[str, List[PairVerdict]]) -> None:
    from .report.plots import plot_sweep
    panels = [(AXIS_TITLES[axis], "cost of a ray [ns]" if MODEL_AXIS[axis] == RAY_AXIS else
               "shading cost added per hit [ns]", axis_positions(axis_levels, axis), pair_verdicts[axis])
              for axis, axis_levels in levels.items()]
    plot_sweep(panels, os.path.join(out_dir, "sweep.png"))


def stored_levels(study_dir: str) -> Optional[Dict[str, List[Level]]]:
    """The levels the last sweep of the study measured (its sweep.json), or None."""
    path = os.path.join(study_dir, "sweep", "sweep.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        stored = json.load(f)
    return {axis: [Level(**lv) for lv in stored[axis]["levels"]] for axis in MODEL_AXIS if axis in stored}


def summaries(study_dir: str, pairs) -> List[str]:
    """The last sweep's agreement in words per axis (summary), for the study's report; [] without a sweep."""
    levels = stored_levels(study_dir)
    if not levels:
        return []
    return [f"- {AXIS_TITLES[axis]}: " + summary(verdicts(pairs, axis_levels, axis), axis_levels, axis)
            for axis, axis_levels in levels.items()]


ADDED_COSTS = (0.0, 1e-7, 3e-7, 1e-6, 3e-6, 1e-5)  # the added costs' default levels [s]
# The most triangles a geometry level may have: beyond it the level is skipped (the subdivided arrays and Embree's BVH
# take some 250 bytes per triangle at their peak: 24 GB ran out at 99 M).
MAX_SWEEP_TRIANGLES = 30_000_000


def run_sweep(study_dir: str, geometry_levels: Sequence[int] = (0, 2, 4, 6),
              shading_costs: Sequence[float] = ADDED_COSTS, repeats: int = 3,
              report_only: bool = False, ray_costs: Sequence[float] = ADDED_COSTS) -> str:
    """Measure the levels (or, report_only, read them from the last sweep's sweep.json) and write the outputs."""
    from .report import costs as report_costs
    from .report.results import curves, load_study
    from .runner import load_study_scene
    results = load_study(study_dir)
    cfg, all_curves = results.settings, curves(results.ladder)
    model = report_costs.configuration_costs(all_curves)
    keys = [k for k in headline_keys(cfg, all_curves) if k in model]
    if len(keys) < 2:
        raise ValueError("the study has fewer than two configurations with the cost model's measurements at its "
                         "headline setting: run it again with this build")
    pairs = [p for p in report_costs.pair_costs(cfg, all_curves, model, results.reference_rmse)
             if p.a in keys and p.b in keys]
    out_dir = os.path.join(study_dir, "sweep")
    if report_only:
        levels = stored_levels(study_dir)
        if not levels:
            raise ValueError(f"{out_dir} has no sweep.json to report: run the sweep first")
        return write_outputs(out_dir, levels, {axis: verdicts(pairs, levels[axis], axis) for axis in levels})
    width, height = results.config["width"], results.config["height"]
    base = load_study_scene(results.config["scene_file"], width, height)
    base_terms = {label(k): model[k].terms for k in keys}  # (the study's: the sweep's first estimate of a cost)
    # The study's per-run settings that are not part of a curve's key.
    jobs = {label(k): Job.from_dict(all_curves[k][0]["job"]) for k in keys}
    run_options = {name: {"light_samples": j.light_samples, "ris_candidates": j.ris_candidates}
                   for name, j in jobs.items()}
    axes = ((GEOMETRY, geometry_levels), (ADDED_RAY, ray_costs), (ADDED_SHADING, shading_costs))
    levels: Dict[str, List[Level]] = {axis: [] for axis, values in axes if values}
    for axis, values in axes:
        for value in values:
            triangles = complexity.subdivided_triangle_count(base, int(value)) if axis == GEOMETRY else 0
            if triangles > MAX_SWEEP_TRIANGLES:
                print(f"{axis} {value:g}: skipped, {triangles:,} triangles would exceed the sweep's "
                      f"{MAX_SWEEP_TRIANGLES:,} (memory)", file=sys.stderr, flush=True)
                continue
            scene = complexity.subdivide_scene(base, int(value)) if axis == GEOMETRY else base
            estimate = {t: terms.at(terms.t_ray + (value if axis == ADDED_RAY else 0.0),
                                    value if axis == ADDED_SHADING else 0.0) for t, terms in base_terms.items()}
            samples = {t: max(1, min(MAX_SWEEP_SAMPLES, round(RENDER_SECONDS / (c * width * height))))
                       for t, c in estimate.items()}
            levels[axis].append(measure_level(scene, keys, samples, repeats, axis, value, run_options))
            print(f"{axis} {value:g}: ray {ns(levels[axis][-1].ray_cost)}", file=sys.stderr, flush=True)
    return write_outputs(out_dir, levels, {axis: verdicts(pairs, levels[axis], axis) for axis in levels})


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("study_dir")
    ap.add_argument("--levels", default="0,2,4,6", help="subdivision levels (comma list)")
    costs = ",".join(f"{c:g}" for c in ADDED_COSTS)
    ap.add_argument("--ray-costs", default=costs, help="seconds added per ray (comma list)")
    ap.add_argument("--shading-costs", default=costs, help="seconds added per hit (comma list)")
    ap.add_argument("--repeats", type=int, default=3, help="renders per configuration and level (the least time)")
    ap.add_argument("--report-only", action="store_true", help="rewrite sweep.md from the last sweep's sweep.json")
    a = ap.parse_args(argv)
    path = run_sweep(a.study_dir, [int(x) for x in a.levels.split(",")],
                     [float(x) for x in a.shading_costs.split(",")], a.repeats, a.report_only,
                     [float(x) for x in a.ray_costs.split(",")])
    print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
