"""The study's report: runs.csv / runs.json, plots, tables and findings in report.md and report.html.

Everything stated in the findings is computed here from the measured records; a finding that does not
reproduce is reported as such.
"""
from __future__ import annotations

import csv
import html
import json
import math
import os
from collections import defaultdict
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import metrics
from .jobs import CYCLES, CYCLES_CURVE, EQUAL_TIME, LADDER, SPHRECT, StudyConfig, curve_label
from .reference import load_reference_info
from .store import ResultStore, atomic_write_bytes, atomic_write_json

PAPER_ORDER = ("rectangle", "triangles", "area")  # the paper: RMSE rectangle < triangles < area
TECHNIQUE_COLOURS = {"area": "tab:red", "triangles": "tab:orange", "rectangle": "tab:blue",
                     "rectangle_cosine": "tab:green", "cycles": "black"}
SLOPE_MIN_POINTS = 3
SLOPE_DIFFERENCE = 0.03  # smallest slope difference reported as a difference
# Above this share of Cycles' top MSE being a systematic difference from our reference, an equal-error time
# ratio measures that difference, not sampling, and is not reported as one.
SYSTEMATIC_SHARE_LIMIT = 0.5


# ------------------------------------------------------------------------------------------------
# Loading

def load_study(out_dir: str) -> Dict:
    with open(os.path.join(out_dir, "config.json")) as f:
        config = json.load(f)
    with open(os.path.join(out_dir, "state.json")) as f:
        state = json.load(f)
    store = ResultStore(out_dir)
    records = list(store.runs(state["run_fingerprint"]))
    study = StudyConfig.from_dict(config["study"])
    from .study import time_of
    for r in records:  # the time each run is judged by (CPU time for single-thread runs; see time_of)
        r["time"] = time_of(r, study.threads)
    return {"config": config, "state": state, "store": store, "reference": load_reference_info(store),
            "study": study,
            "ladder": [r for r in records if r["job"]["kind"] == LADDER],
            "equal_time": [r for r in records if r["job"]["kind"] == EQUAL_TIME],
            "failures": list(store.failures())}


def curves(records: List[Dict]) -> Dict[Tuple[str, str, str], List[Dict]]:
    """(technique, mis, pattern) -> records sorted by samples (Cycles: CYCLES_CURVE)."""
    out = defaultdict(list)
    for r in records:
        j = r["job"]
        out[(j["technique"], j["mis"], j["pattern"])].append(r)
    for k in out:
        out[k].sort(key=lambda r: r["job"]["samples"])
    return dict(out)


def curve_name(key: Tuple[str, str, str]) -> str:
    return curve_label(*key)


def fitted_slope(curve: List[Dict], x: str, reference_rmse: float) -> float:
    return fitted_slope_with_error(curve, x, reference_rmse)[0]


def fitted_slope_with_error(curve: List[Dict], x: str, reference_rmse: float) -> Tuple[float, float]:
    """Log-log slope of RMSE against `x` ("samples" or "time"), fitted on the points whose error is more than
    3x the reference's own RMSE (below that, the reference's noise flattens the curve) and, when enough
    remain, without the first (pre-asymptotic) point."""
    pts = [(_x(r, x), r["rmse"]) for r in curve if r.get("rmse") and r["rmse"] > 3 * reference_rmse]
    pts = [(a, b) for a, b in pts if a and a > 0]
    if len(pts) > SLOPE_MIN_POINTS:
        pts = pts[1:]
    if len(pts) < 2:
        return float("nan"), float("nan")
    return metrics.fit_slope_with_error([a for a, _ in pts], [b for _, b in pts])


def _x(record: Dict, x: str) -> Optional[float]:
    return record["job"]["samples"] if x == "samples" else record.get("time")


def time_label(study: Dict) -> str:
    return ("CPU time of the render [s] (1 thread)" if study["study"].threads == 1
            else f"render wall time [s] ({study['study'].threads or 'all'} threads)")


# ------------------------------------------------------------------------------------------------
# Tables (as lists of rows; rendered to Markdown and HTML)

def fmt(x, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return f"{x:.{digits}g}"


def write_csv(path: str, records: List[Dict]) -> None:
    columns = ["key", "kind", "engine", "technique", "mis", "pattern", "samples", "light_samples", "seed", "threads",
               "time_budget", "samples_done", "time", "cpu_time", "wall_time", "call_time", "build_time", "light_time",
               "shading_time", "camera_time", "rays", "camera_rays", "rmse", "relmse", "finite"]
    import io
    buffer = io.StringIO()
    writer = csv.writer(buffer)
    writer.writerow(columns)
    for r in sorted(records, key=lambda r: r["key"]):
        row = {**r["job"], **{k: v for k, v in r.items() if k != "job"}}
        writer.writerow(["" if row.get(c) is None else row.get(c) for c in columns])
    atomic_write_bytes(path, buffer.getvalue().encode("utf-8"))


COST_NOTE = (f"Times are samples per pixel x the configuration's cost per sample, the mean of time / samples over "
             f"its {metrics.COST_RUNS} largest runs: single runs' times scatter by 10-20% on a shared machine.")


def curve_cost(curve: List[Dict]) -> Tuple[float, float]:
    """metrics.cost_per_sample of a ladder curve: (seconds per sample, its relative standard error)."""
    return metrics.cost_per_sample([r.get("time") for r in curve], [r["job"]["samples"] for r in curve])


def time_to_target(curve: List[Dict], target: float, reference_rmse: float = 0.0) -> Tuple[float, str, float]:
    """(seconds, how, samples) to reach RMSE `target`: the samples per pixel it takes (metrics.cost_to_reach on
    the samples) times the curve's cost per sample (curve_cost: averaged over its largest runs, so that one
    run's time does not decide a comparison).  Extrapolation uses only the points whose error is above 3x the
    reference's own (below, the reference's noise bends the curve), and is refused ("below reference accuracy")
    for targets under that level."""
    cost, _ = curve_cost(curve)

    def reach(points):
        n, how = metrics.cost_to_reach([r["job"]["samples"] for r in points], [r["rmse"] for r in points], target)
        return n * cost, how, n
    t, how, n = reach(curve)
    if how != "extrapolated":
        return t, how, n
    if target < 3 * reference_rmse:
        return float("nan"), "below reference accuracy", float("nan")
    t, how, n = reach([r for r in curve if r["rmse"] > 3 * reference_rmse])
    longest = max((r["time"] for r in curve if r.get("time")), default=0.0)
    if how == "extrapolated" and t > 100 * longest:
        return float("nan"), f"beyond 100x the longest run ({fmt(longest)} s)", float("nan")
    return t, how, n


# ------------------------------------------------------------------------------------------------
# Plots

def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_convergence(study: Dict, all_curves: Dict, pattern: str, x: str, path: str) -> None:
    plt = _plt()
    mis_modes = list(study["study"].mis)
    ref_rmse = study["reference"]["estimated_rmse"]
    fig, axes = plt.subplots(1, len(mis_modes), figsize=(5.2 * len(mis_modes), 4.4), squeeze=False,
                             sharey=True)
    cycles = all_curves.get(CYCLES_CURVE)
    for ax, mis in zip(axes[0], mis_modes):
        for technique in study["study"].techniques:
            curve = all_curves.get((technique, mis, pattern))
            if not curve:
                continue
            xs = [_x(r, x) for r in curve]
            ys = [r["rmse"] for r in curve]
            slope = fitted_slope(curve, x, ref_rmse)
            ax.loglog(xs, ys, "o-", color=TECHNIQUE_COLOURS.get(technique), ms=3,
                      label=f"{technique} (slope {fmt(slope, 2)})")
        if cycles:
            xs = [_x(r, x) for r in cycles]
            ax.loglog(xs, [r["rmse"] for r in cycles], "s--", color="black", ms=3,
                      label=f"Cycles 3.4 (slope {fmt(fitted_slope(cycles, x, ref_rmse), 2)})")
        ax.axhline(ref_rmse, color="grey", ls=":", lw=1, label="reference's own RMSE")
        ax.set_title(f"MIS: {mis}, pattern: {pattern}")
        ax.set_xlabel("samples per pixel" if x == "samples" else time_label(study))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("RMSE")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_slopes(study: Dict, all_curves: Dict, path: str) -> None:
    """Bar chart: fitted RMSE-vs-samples slope for every technique, per pattern (one panel per MIS mode)."""
    plt = _plt()
    cfg = study["study"]
    ref_rmse = study["reference"]["estimated_rmse"]
    fig, axes = plt.subplots(1, len(cfg.mis), figsize=(4.8 * len(cfg.mis), 3.6), squeeze=False, sharey=True)
    width = 0.8 / len(cfg.techniques)
    for ax, mis in zip(axes[0], cfg.mis):
        for i, technique in enumerate(cfg.techniques):
            slopes = [fitted_slope(all_curves.get((technique, mis, p), []), "samples", ref_rmse) for p in cfg.patterns]
            ax.bar(np.arange(len(cfg.patterns)) + (i - (len(cfg.techniques) - 1) / 2) * width, slopes, width,
                   color=TECHNIQUE_COLOURS.get(technique), label=technique)
        ax.axhline(-0.5, color="grey", ls=":", lw=1)
        ax.set_xticks(np.arange(len(cfg.patterns)))
        ax.set_xticklabels(cfg.patterns)
        ax.set_title(f"RMSE ~ N^slope, MIS: {mis}")
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("fitted slope (-0.5 = plain Monte Carlo)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_equal_time_grid(study: Dict, path: str) -> List[List[str]]:
    """Images and error heat maps of the equal-time renders; returns the table rows (name, samples, RMSE)."""
    plt = _plt()
    store = study["store"]
    reference = store.load_image(study["reference"]["image"])
    records = study["equal_time"]
    mis_rows = [m for m in study["study"].grid_mis if any(r["job"]["mis"] == m and r["job"]["engine"] == SPHRECT
                                                          for r in records)]
    cycles = [r for r in records if r["job"]["engine"] == CYCLES]
    columns = list(study["study"].techniques) + (["cycles"] if cycles else []) + ["reference"]
    white = metrics.white_point(reference)
    maps = {}
    for r in records:
        img = store.load_image(r["image"])
        if img is not None:
            maps[r["key"]] = (img, metrics.error_map(img, reference))
    vmax = max([float(np.percentile(m, 99)) for _, m in maps.values()] + [1e-12])
    rows = max(1, len(mis_rows)) * 2
    h, w = reference.shape[:2]
    fig, axes = plt.subplots(rows, len(columns), figsize=(2.6 * len(columns), 2.6 * rows * h / w + 0.6),
                             squeeze=False)
    table = []
    for row_index, mis in enumerate(mis_rows or [None]):
        for col, name in enumerate(columns):
            ax_img, ax_err = axes[2 * row_index][col], axes[2 * row_index + 1][col]
            for ax in (ax_img, ax_err):
                ax.set_xticks([])
                ax.set_yticks([])
            if name == "reference":
                ax_img.imshow(metrics.tonemap(reference, white))
                ax_img.set_title(f"reference\n{study['reference']['settings']['samples']} spp", fontsize=8)
                ax_err.axis("off")
                continue
            match = [r for r in (cycles if name == "cycles" else records)
                     if r["job"]["technique"] == name and (name == "cycles" or r["job"]["mis"] == mis)]
            if not match or match[0]["key"] not in maps:
                ax_img.axis("off")
                ax_err.axis("off")
                continue
            r = match[0]
            img, err = maps[r["key"]]
            ax_img.imshow(metrics.tonemap(img, white))
            spp = r.get("samples_done")
            title = ("Cycles 3.4" if name == "cycles" else f"{name}\nmis={mis}") + \
                f"\n{fmt(spp) if spp else '?'} spp, RMSE {fmt(r['rmse'])}"
            ax_img.set_title(title, fontsize=8)
            ax_err.imshow(err, cmap="inferno", vmin=0, vmax=vmax)
            ax_err.set_title("|error| (RMS over RGB)", fontsize=7)
            if name != "cycles" or row_index == 0:
                table.append(["Cycles 3.4" if name == "cycles" else f"{name} / mis={mis}", fmt(spp),
                              fmt(r.get("time")), fmt(r["rmse"]), fmt(r["relmse"])])
    fig.suptitle(f"Equal time: {fmt(study['state'].get('equal_time_budget'))} s per image (sample counts "
                 f"predicted from the ladder's time per sample) "
                 f"(pattern {study['study'].grid_pattern}); heat maps share one colour scale", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return table


# ------------------------------------------------------------------------------------------------
# Findings

def ordering_finding(study: Dict, all_curves: Dict) -> Tuple[List[str], List[List[str]]]:
    """The paper's ordering at equal samples: RMSE rectangle < triangles < area, for each MIS mode/pattern."""
    cfg = study["study"]
    if not all(t in cfg.techniques for t in PAPER_ORDER):
        return ["The paper's ordering needs the area, triangles and rectangle techniques."], []
    rows, lines, all_hold, total = [], [], 0, 0
    for mis in cfg.mis:
        for pattern in cfg.patterns:
            by_n = {t: {r["job"]["samples"]: r["rmse"] for r in all_curves.get((t, mis, pattern), [])}
                    for t in PAPER_ORDER}
            ns = sorted(set.intersection(*(set(d) for d in by_n.values())))
            if not ns:
                continue
            holds = [n for n in ns if by_n["rectangle"][n] < by_n["triangles"][n] < by_n["area"][n]]
            rect_vs_tri = [n for n in ns if by_n["rectangle"][n] < by_n["triangles"][n]]
            top = ns[-1]
            rows.append([mis, pattern, f"{len(holds)}/{len(ns)}", f"{len(rect_vs_tri)}/{len(ns)}",
                         fmt(by_n["triangles"][top] / by_n["rectangle"][top]),
                         fmt(by_n["area"][top] / by_n["rectangle"][top])])
            all_hold += len(holds)
            total += len(ns)
    if total:
        lines.append(f"At equal samples, RMSE(rectangle) < RMSE(triangles) < RMSE(area) holds at {all_hold} of {total} "
                     "(MIS, pattern, sample count) points.")
    # rectangle and triangles have the same pdf (uniform in solid angle): with independent samples their
    # estimators have the same variance, so rectangle < triangles can only come from stratification. Judge the
    # two comparisons separately, and the stratification effect only on the stratified/low-discrepancy patterns.
    area_worst = [r for r in rows if float(r[5]) > max(1.0, float(r[4]))]
    lines.append(f"- area is the worst of the three at the top of the ladder in {len(area_worst)} of {len(rows)} "
                 f"(MIS, pattern) cases: "
                 + ("**reproduces** the paper." if len(area_worst) == len(rows) else "**does NOT fully reproduce**."))
    groups = [("independent samples", ["independent"])] + [(f"{p} samples", [p]) for p in cfg.patterns
                                                             if p != "independent"]
    for group, patterns in groups:
        selected = [r for r in rows if r[1] in patterns]
        if not selected:
            continue
        wins = sum(int(r[3].split("/")[0]) for r in selected)
        count = sum(int(r[3].split("/")[1]) for r in selected)
        ratios = [float(r[4]) for r in selected]
        if group == "independent samples":
            lines.append(f"- rectangle vs triangles with {group}: rectangle is lower at {wins} of {count} points, "
                         f"RMSE ratio triangles/rectangle at the top {fmt(min(ratios))} ... {fmt(max(ratios))}. Both "
                         "sample uniformly in solid angle (the same pdf), so with independent samples they are "
                         "expected to tie; the paper's advantage is about stratification.")
        else:
            verdict = ("**reproduces**" if wins >= 0.8 * count and min(ratios) > 1 else
                       "**does NOT reproduce**" if wins <= 0.5 * count or max(ratios) < 1 else
                       "**partly reproduces**")
            lines.append(f"- rectangle vs triangles with {group}: rectangle is lower at {wins} "
                         f"of {count} points, RMSE ratio triangles/rectangle at the top {fmt(min(ratios))} ... "
                         f"{fmt(max(ratios))}: the paper's finding {verdict} here.")
    return lines, rows


def slope_finding(study: Dict, all_curves: Dict) -> Tuple[List[str], List[List[str]]]:
    cfg = study["study"]
    ref_rmse = study["reference"]["estimated_rmse"]
    rows, lines = [], []
    for mis in cfg.mis:
        for technique in cfg.techniques:
            rows.append([technique, mis] + [fmt(fitted_slope(all_curves.get((technique, mis, p), []), "samples",
                                                              ref_rmse), 3) for p in cfg.patterns])
    cycles = all_curves.get(CYCLES_CURVE)
    if cycles:
        rows.append(["Cycles 3.4", "power"] + [fmt(fitted_slope(cycles, "samples", ref_rmse), 3)
                                                if i == 0 else "" for i in range(len(cfg.patterns))])
    for pattern in [p for p in cfg.patterns if p != "independent"]:
        for mis in cfg.mis:
            fits = {t: fitted_slope_with_error(all_curves.get((t, mis, pattern), []), "samples", ref_rmse)
                    for t in ("rectangle", "triangles", "area")}
            s = {t: f[0] for t, f in fits.items()}
            if any(not math.isfinite(v) for v in s.values()):
                continue
            # A difference counts when it exceeds 0.03 and twice the combined standard error of the two fits.
            se = math.hypot(fits["rectangle"][1], fits["triangles"][1])
            threshold = max(SLOPE_DIFFERENCE, 2 * se if math.isfinite(se) else 0.0)
            difference = s["triangles"] - s["rectangle"]
            if difference > threshold:
                verdict = "converges faster than the two-triangle map (reproduces the paper)"
            elif difference < -threshold:
                verdict = "converges SLOWER than the two-triangle map (does NOT reproduce the paper)"
            else:
                verdict = ("converges at the same rate as the two-triangle map within the fits' precision "
                           f"(difference {fmt(difference, 2)}, threshold {fmt(threshold, 2)}): the paper's "
                           "stratification advantage is NOT visible in the slope")
            lines.append(f"- {pattern}, MIS {mis}: slope rectangle {fmt(s['rectangle'], 3)}, triangles "
                         f"{fmt(s['triangles'], 3)}, area {fmt(s['area'], 3)}; independent-pattern slope of "
                         f"rectangle {fmt(fitted_slope(all_curves.get(('rectangle', mis, 'independent'), []), 'samples', ref_rmse), 3)}"
                         f" -> the area-preserving map {verdict}.")
    return lines, rows


def cosine_finding(study: Dict, all_curves: Dict) -> List[str]:
    """rectangle_cosine against rectangle per (MIS, pattern): RMSE at the top of the ladder, cost per sample
    (curve_cost) and efficiency 1 / (MSE x cost).  An efficiency ratio within two standard errors of the
    cost ratio of 1 is reported as a tie: single runs' times move by more than that between studies.  (The
    top run's MSE has its own noise, which this margin does not count.)"""
    cfg = study["study"]
    if "rectangle_cosine" not in cfg.techniques or "rectangle" not in cfg.techniques:
        return []
    lines = []
    for mis in cfg.mis:
        for pattern in cfg.patterns:
            curve_a = all_curves.get(("rectangle_cosine", mis, pattern), [])
            curve_b = all_curves.get(("rectangle", mis, pattern), [])
            a = {r["job"]["samples"]: r for r in curve_a}
            b = {r["job"]["samples"]: r for r in curve_b}
            ns = sorted(set(a) & set(b))
            if not ns:
                continue
            n = ns[-1]
            (cost_a, se_a), (cost_b, se_b) = curve_cost(curve_a), curve_cost(curve_b)
            ratio = a[n]["rmse"] / b[n]["rmse"]
            eff = (b[n]["rmse"] ** 2 * cost_b) / (a[n]["rmse"] ** 2 * cost_a) if a[n]["rmse"] else float("nan")
            noise = 2 * math.hypot(se_a, se_b)
            verdict = ("within the timing noise" if abs(math.log(eff)) <= noise
                       else "better than rectangle" if eff > 1 else "worse than rectangle") \
                if math.isfinite(eff) and eff > 0 and math.isfinite(noise) else "not measured"
            lines.append(f"- MIS {mis}, {pattern}, {n} spp: RMSE(rectangle_cosine)/RMSE(rectangle) = {fmt(ratio)}, "
                         f"cost ratio {fmt(cost_a / cost_b)} (per sample, top {metrics.COST_RUNS} runs), efficiency "
                         f"(1/(MSE x time)) ratio {fmt(eff)}, timing noise +-{fmt(100 * noise, 2)}% ({verdict}).")
    return lines


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


def cycles_comparison(study: Dict, all_curves: Dict) -> Tuple[List[str], List[List[str]], Optional[float]]:
    """For each Cycles ladder point (N, RMSE e, time t): the time our best configuration needs to reach e.
    The ratio at the top is None when Cycles' error there is mostly a systematic difference."""
    cycles = all_curves.get(CYCLES_CURVE)
    if not cycles:
        return ["Cycles was not part of this study (no Blender, no .blend, or --no-cycles)."], [], None
    ours = {k: c for k, c in all_curves.items() if k != CYCLES_CURVE}
    cycles_cost, _ = curve_cost(cycles)
    rows, ratios = [], []
    for r in cycles:
        cycles_time = r["job"]["samples"] * cycles_cost
        best = None
        for key, curve in ours.items():
            t, how, n = time_to_target(curve, r["rmse"], study["reference"]["estimated_rmse"])
            if math.isfinite(t) and how in ("measured", "below") and (best is None or t < best[0]):
                best = (t, key, how, n)
        if best is None:
            rows.append([fmt(r["job"]["samples"]), fmt(r["rmse"]), fmt(cycles_time), "–", "–", "–"])
            continue
        ratio = best[0] / cycles_time
        ratios.append((r["job"]["samples"], ratio))
        rows.append([fmt(r["job"]["samples"]), fmt(r["rmse"]), fmt(cycles_time), curve_name(best[1]),
                     fmt(best[0]) + ("" if best[2] == "measured" else f" ({best[2]})"), fmt(ratio)])
    lines = []
    share = systematic_share(cycles)
    if ratios and share > SYSTEMATIC_SHARE_LIMIT:
        n_top = cycles[-1]["job"]["samples"]
        lines.append(f"Cycles 3.4 comparison not measurable here: its error has stopped falling with samples. About "
                     f"{share:.0%} of its MSE at {n_top} spp is a systematic difference from our reference (for "
                     f"example Cycles' multiscatter GGX against our single-scatter GGX on glossy materials), so "
                     f"the time our renderer needs to reach Cycles' error measures that difference, not light "
                     f"sampling (the table shows the ratios anyway: {fmt(ratios[-1][1])}x at the top).")
        return lines, rows, None
    if ratios:
        n_top, top_ratio = ratios[-1]
        goal = "meets" if top_ratio <= 1 / 3 else "does NOT meet"
        lines.append(f"To reach the RMSE Cycles 3.4 reaches with {n_top} spp, our best configuration needs "
                     f"**{fmt(top_ratio)}x** Cycles' time (goal: at most 1/3 -> this {goal} the goal). Over the "
                     f"whole ladder the ratio ranges {fmt(min(r for _, r in ratios))} ... "
                     f"{fmt(max(r for _, r in ratios))}.")
        return lines, rows, top_ratio
    lines.append("No configuration of ours reached Cycles' errors within the measured ladder.")
    return lines, rows, None


def summary_lines(study: Dict, ordering: List[str], slopes: List[str], cosine: List[str], cycles_lines: List[str],
                  ratio: Optional[float]) -> List[str]:
    """The headline numbers, from the lines of the findings (ordering_finding, slope_finding, cosine_finding,
    cycles_comparison with its ratio) that the report shows below the summary."""
    lines = []
    if ratio is not None:
        lines.append(f"- Goal (our best configuration needs at most 1/3 of Cycles 3.4's time for Cycles' RMSE at the "
                     f"top of the ladder, or the highest count whose error our runs reach): measured ratio "
                     f"**{fmt(ratio)}** -> "
                     + ("**met**." if ratio <= 1 / 3 else "**not met**."))
    else:
        lines.append("- " + cycles_lines[0])
    lines += [l for l in ordering if l.startswith("- ")]
    faster = [l for l in slopes if "converges faster" in l]
    slower = [l for l in slopes if "SLOWER" in l]
    if slopes:
        lines.append(f"- Stratification (convergence slopes, stratified/low-discrepancy patterns): the area-preserving "
                     f"map converges faster than the two-triangle map in {len(faster)} of {len(slopes)} "
                     f"(pattern, MIS) cases, slower in {len(slower)}, indistinguishable in the rest.")
    better = [l for l in cosine if "(better than rectangle)" in l]
    worse = [l for l in cosine if "(worse than rectangle)" in l]
    if cosine:
        lines.append(f"- rectangle_cosine is more efficient (1 / (MSE x time)) than rectangle in {len(better)} of "
                     f"{len(cosine)} (MIS, pattern) cases at the top of the ladder, less in {len(worse)}, "
                     f"indistinguishable within the timing noise in the rest.")
    ref = study["reference"]
    rmse = [r["rmse"] for r in study["ladder"] if r.get("rmse") and math.isfinite(r["rmse"])]
    if rmse:
        lines.append(f"- The reference's own RMSE is {fmt(100 * ref['estimated_rmse'] / min(rmse), 2)}% of the "
                     f"smallest error measured.")
    return lines


# ------------------------------------------------------------------------------------------------
# Report documents

class Document:
    """Builds the same content as Markdown and as HTML."""

    def __init__(self):
        self.md, self.html = [], []

    def heading(self, text: str, level: int = 2):
        self.md.append("#" * level + " " + text + "\n")
        self.html.append(f"<h{level}>{html.escape(text)}</h{level}>")

    def para(self, text: str):
        self.md.append(text + "\n")
        body = html.escape(text)
        while "**" in body:  # the only Markdown emphasis we use
            body = body.replace("**", "<b>", 1).replace("**", "</b>", 1)
        if body.startswith("- "):
            body = "&bull; " + body[2:]
        self.html.append(f"<p>{body}</p>")

    def table(self, header: Sequence[str], rows: Sequence[Sequence[str]]):
        if not rows:
            return
        self.md.append("| " + " | ".join(header) + " |")
        self.md.append("|" + "|".join("---" for _ in header) + "|")
        for r in rows:
            self.md.append("| " + " | ".join(str(c) for c in r) + " |")
        self.md.append("")
        head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>" for r in rows)
        self.html.append(f"<table><tr>{head}</tr>{body}</table>")

    def image(self, path: str, caption: str):
        self.md.append(f"![{caption}]({path})\n")
        self.html.append(f'<figure><img src="{html.escape(path)}" alt="{html.escape(caption)}">'
                         f"<figcaption>{html.escape(caption)}</figcaption></figure>")

    def markdown(self) -> str:
        return "\n".join(self.md) + "\n"

    def to_html(self, title: str) -> str:
        style = ("body{font-family:sans-serif;max-width:1300px;margin:2em auto;padding:0 1em}"
                 "table{border-collapse:collapse;margin:1em 0;font-size:90%}td,th{border:1px solid #ccc;"
                 "padding:3px 8px;text-align:right}img{max-width:100%}figcaption{color:#555;font-size:90%}")
        return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
                f"<style>{style}</style></head><body>" + "\n".join(self.html) + "</body></html>\n")


def write_report(out_dir: str, sampler_table: bool = True, target_rmse: Optional[float] = None) -> str:
    """Write runs.csv, runs.json, the plots and report.md / report.html into out_dir; returns report.md's path."""
    study = load_study(out_dir)
    cfg, ref = study["study"], study["reference"]
    plots = os.path.join(out_dir, "plots")
    os.makedirs(plots, exist_ok=True)
    records = study["ladder"] + study["equal_time"]
    write_csv(os.path.join(out_dir, "runs.csv"), records)
    atomic_write_json(os.path.join(out_dir, "runs.json"), {"reference": ref, "runs": records})
    all_curves = curves(study["ladder"])

    doc = Document()
    doc.heading("What accuracy costs in time: light-sampling study", 1)
    c = study["config"]
    doc.para(f"Scene: `{c['input']}`, {c['width']}x{c['height']} pixels. Techniques {', '.join(cfg.techniques)}; "
             f"MIS {', '.join(cfg.mis)}; patterns {', '.join(cfg.patterns)}; sample ladder "
             f"{', '.join(map(str, cfg.ladder))} camera samples per pixel, {cfg.light_samples} light sample(s) each. "
             f"{len(study['ladder'])} ladder runs and {len(study['equal_time'])} equal-time runs measured. "
             f"Every run renders with {cfg.threads or 'all'} thread(s), {c.get('workers') or 1} run(s) at a time "
             f"({c.get('executor')}). "
             + ("Times are the CPU time of each single-threaded render (excluding the scene/BVH build): unlike "
                "wall time they do not grow when other processes compete for the cores. "
                if cfg.threads == 1 else "Times are render wall times (excluding the scene/BVH build). ")
             + "runs.csv also has wall_time, build_time, light_time and rays of every run.")
    if study["failures"]:
        doc.para(f"**{len(study['failures'])} runs failed** and are missing from the plots: " +
                 "; ".join(f"{f['key']}: {f['error'].splitlines()[0] if f['error'] else ''}"
                           for f in study["failures"][:5]))
    non_finite = [r["key"] for r in records if not r.get("finite", True)]
    if non_finite:
        doc.para(f"**{len(non_finite)} runs produced NaN/Inf pixels** (their RMSE is infinite): "
                 + ", ".join(non_finite[:8]))

    ordering_lines, ordering_rows = ordering_finding(study, all_curves)
    slope_lines, slope_rows = slope_finding(study, all_curves)
    cosine_lines = cosine_finding(study, all_curves)
    cycles_lines, cycles_rows, cycles_ratio = cycles_comparison(study, all_curves)

    doc.heading("Summary")
    for line in summary_lines(study, ordering_lines, slope_lines, cosine_lines, cycles_lines, cycles_ratio):
        doc.para(line)
    for pattern in [p for p in ("stratified", "sobol", "independent") if p in cfg.patterns][:1]:
        doc.image(f"plots/rmse_vs_time_{pattern}.png", f"RMSE vs time, pattern {pattern} (more below)")

    doc.heading("Reference")
    s = ref["settings"]
    all_rmse = [r["rmse"] for r in study["ladder"] if r.get("rmse") and math.isfinite(r["rmse"])]
    smallest = min(all_rmse) if all_rmse else float("nan")
    ratio = ref["estimated_rmse"] / smallest if all_rmse else float("nan")
    doc.para(f"Mean of {s['chunks']} independent renders ({s['technique']}, MIS {s['mis']}, {s['pattern']}, "
             f"{s['samples']} samples per pixel in total, {fmt(ref['render_time_total'])} s of rendering). Its own "
             f"RMSE, estimated from the spread of the independent chunks (variance across chunks / their number), "
             f"is **{fmt(ref['estimated_rmse'])}** (relMSE {fmt(ref['estimated_relmse'])}). The smallest RMSE the "
             f"study reports is {fmt(smallest)}: the reference's error is {fmt(100 * ratio, 2)}% of it "
             + ("(well under it: the measured errors are the runs' own)." if ratio < 0.3 else
                "(**not** well under it: the smallest errors are inflated by the reference's noise; rerun with "
                "more --reference-samples). Slopes are fitted only on points above 3x the reference's error."))

    doc.heading("Convergence")
    doc.para("RMSE against the reference (log-log), one line per technique; the legend gives the fitted slope "
             "(RMSE ~ N^slope; -0.5 is plain Monte Carlo, steeper is better). Cycles 3.4 (MIS with its own "
             "pattern) is drawn in every panel for comparison.")
    for pattern in cfg.patterns:
        for x in ("samples", "time"):
            name = f"rmse_vs_{x}_{pattern}.png"
            plot_convergence(study, all_curves, pattern, x, os.path.join(plots, name))
            doc.image(f"plots/{name}", f"RMSE vs {'samples per pixel' if x == 'samples' else 'wall time'}, "
                                       f"pattern {pattern}")

    doc.heading("The paper's findings, measured")
    doc.para("**1. Equal samples: rectangle < triangles < area.**")
    for line in ordering_lines:
        doc.para(line)
    doc.table(["MIS", "pattern", "order holds at", "rectangle < triangles at", "RMSE triangles/rectangle (top N)",
               "RMSE area/rectangle (top N)"], ordering_rows)
    doc.para("**2. Stratification: fitted convergence slopes (RMSE vs samples).**")
    name = "slopes.png"
    plot_slopes(study, all_curves, os.path.join(plots, name))
    doc.image(f"plots/{name}", "fitted slopes per technique and pattern")
    doc.table(["technique", "MIS"] + list(cfg.patterns), slope_rows)
    for line in slope_lines:
        doc.para(line)
    doc.para("**3. Where rectangle_cosine stands** (against rectangle, same MIS and pattern, top of the ladder).")
    for line in cosine_lines or ["rectangle_cosine or rectangle was not part of the study."]:
        doc.para(line)
    doc.para("**4. Cycles 3.4 at equal error: time our best configuration needs to reach Cycles' RMSE.**")
    for line in cycles_lines:
        doc.para(line)
    doc.para(COST_NOTE)
    doc.table(["Cycles spp", "Cycles RMSE", "Cycles time [s]", "our best configuration", "its time [s]",
               "time ratio (ours/Cycles)"], cycles_rows)

    doc.heading("Time to reach a target error")
    cycles_curve = all_curves.get(CYCLES_CURVE)
    if target_rmse is None:
        if cycles_curve:
            target_rmse = cycles_curve[-1]["rmse"]
            why = f"the RMSE of Cycles 3.4 at {cycles_curve[-1]['job']['samples']} spp"
        else:
            key = ("rectangle", cfg.mis[-1], cfg.patterns[-1])
            mid = all_curves.get(key, [])
            target_rmse = mid[len(mid) // 2]["rmse"] if mid else smallest
            why = f"the RMSE of {curve_name(key)} in the middle of the ladder"
    else:
        why = "given on the command line"
    doc.para(f"Target RMSE {fmt(target_rmse)} ({why}). 'measured' = interpolated between measured points "
             f"(log-log); 'extrapolated' = along the power law fitted to the curve's upper half. {COST_NOTE}")
    rows = []
    ref_rmse = ref["estimated_rmse"]
    reached = {key: time_to_target(curve, target_rmse, ref_rmse) for key, curve in all_curves.items()}
    for key in sorted(reached, key=lambda k: reached[k][0] if math.isfinite(reached[k][0]) else math.inf):
        t, how, n = reached[key]
        rows.append([curve_name(key), fmt(t), how, fmt(n)])
    doc.table(["configuration", "time [s]", "how", "samples per pixel"], rows)

    doc.heading("Equal time")
    if study["equal_time"]:
        name = "equal_time_grid.png"
        rows = plot_equal_time_grid(study, os.path.join(plots, name))
        doc.image(f"plots/{name}", "equal-time renders and their error heat maps")
        doc.table(["configuration", "samples per pixel", "time [s]", "RMSE", "relMSE"], rows)
    else:
        doc.para("No equal-time runs were measured.")

    doc.heading("The sampler itself: accuracy and cost")
    if sampler_table:
        try:
            from .sampler_table import sampler_tables
            tables, notes = sampler_tables()
            for title, header, rows in tables:
                doc.para(f"**{title}**")
                doc.table(header, rows)
            for note in notes:
                doc.para(note)
        except Exception as e:  # the table is optional; say why it is missing
            doc.para(f"(sampler table unavailable: {type(e).__name__}: {e})")
    else:
        doc.para("(skipped: --no-sampler-table)")

    doc.heading("Files")
    doc.para("runs.csv and runs.json: every run (job, times, rays, RMSE, relMSE); reference.json: the reference "
             "and its error estimate; images/: the reference, its chunks and the equal-time renders (.npy, linear "
             "radiance, row 0 at the top); plots/: the figures above.")
    atomic_write_bytes(os.path.join(out_dir, "report.md"), doc.markdown().encode("utf-8"))
    atomic_write_bytes(os.path.join(out_dir, "report.html"), doc.to_html("sphrect study").encode("utf-8"))
    return os.path.join(out_dir, "report.md")
