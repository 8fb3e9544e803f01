"""write_report: the study's report as a row of sections into one Document.  The findings are computed first,
once (measure: findings.py, equal_error.py); each section then draws its figure (plots.py) and words its
numbers (wording.py)."""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import List, Optional

from ..jobs import DEFAULT_ELLIPSE_TECHNIQUE, DEFAULT_LIGHT_SELECTION, DEFAULT_MEDIUM_SAMPLING, RIS, CurveKey
from ..store import atomic_write_bytes
from . import cost_wording, costs, equal_error, findings, plots, wording
from .curves import REFERENCE_NOISE_FACTOR
from .document import Document
from .results import (Curves, StudyResults, curves, equal_time_grid, load_study, smallest_rmse, study_warnings,
                      write_runs)
from .wording import COST_NOTE, fmt

PLOTS = "plots"
# The reference's error is "well under" the smallest error reported below this share of it.
REFERENCE_SHARE_OK = 0.3
# Distinct warnings the report lists (the runs' records have them all).
MAX_WARNINGS_SHOWN = 12


@dataclass
class Report:
    """What the sections share: the results, their curves and the findings (computed once, in measure)."""
    out_dir: str
    results: StudyResults
    curves: Curves
    smallest: float                                     # the smallest finite RMSE of the ladder
    ordering: Optional[List[findings.OrderingRow]]
    ordering_lines: List[str]                           # shown in the summary and in finding 1
    slopes: findings.Slopes
    cosine: Optional[List[findings.CosineComparison]]
    costlier_maps: Optional[List[findings.TechniqueComparison]]  # findings.COSTLIER_MAPS' comparisons
    cycles: Optional[equal_error.CyclesComparison]
    selection: Optional[List[equal_error.SelectionComparison]]  # None unless the study has tree and power
    ellipse: Optional[List[equal_error.EllipseComparison]]  # None unless it has spherical_ellipse and area
    medium: Optional[List[equal_error.MediumComparison]]  # None unless it has several medium samplings
    doc: Document

    @property
    def show_selection(self) -> bool:
        return self.results.settings.shows_selection

    @property
    def show_ellipse(self) -> bool:
        return self.results.settings.shows_ellipse

    @property
    def show_medium(self) -> bool:
        return self.results.settings.shows_medium

    def plot(self, name: str) -> str:
        return os.path.join(self.out_dir, PLOTS, name)


def measure(out_dir: str, results: StudyResults) -> Report:
    cfg, ref_rmse, all_curves = results.settings, results.reference_rmse, curves(results.ladder)
    ordering = findings.ordering(cfg, all_curves)
    return Report(out_dir, results, all_curves, smallest_rmse(results.ladder), ordering,
                  wording.ordering_lines(ordering, findings.triangles_comparisons(cfg, ordering or []),
                                         cfg.shows_selection, cfg.shows_ellipse),
                  findings.slopes(cfg, all_curves, ref_rmse), findings.cosine_comparisons(cfg, all_curves),
                  findings.costlier_map_comparisons(cfg, all_curves),
                  equal_error.cycles_comparison(all_curves, ref_rmse),
                  equal_error.selection_comparisons(cfg, all_curves, ref_rmse),
                  equal_error.ellipse_comparisons(cfg, all_curves, ref_rmse),
                  equal_error.medium_comparisons(cfg, all_curves, ref_rmse), Document())


def shown_path(path: str) -> str:
    """A path as the report shows it: relative, never the machine's absolute path. The study records its input
    relative to the directory it ran from; a study recorded before that shows it relative to the current one."""
    return os.path.relpath(path) if os.path.isabs(path) else path


def scene_section(report: Report) -> None:
    doc, results, cfg, c = report.doc, report.results, report.results.settings, report.results.config
    doc.heading("What accuracy costs in time: light-sampling study", 1)
    # The light selection is named unless the study has only the renderer's default (as before it was an axis).
    selections = "" if cfg.light_selections == (DEFAULT_LIGHT_SELECTION,) else \
        f"light selection {', '.join(cfg.light_selections)}; "
    selections += f"ris with {cfg.ris_candidates} candidates per light sample; " if RIS in cfg.light_selections else ""
    # Likewise the ellipse technique (disk and ellipse lights).
    selections += "" if cfg.ellipse_techniques == (DEFAULT_ELLIPSE_TECHNIQUE,) else \
        f"disk and ellipse lights sampled by {', '.join(cfg.ellipse_techniques)}; "
    # Likewise the medium sampling (camera rays through volumes).
    selections += "" if cfg.medium_samplings == (DEFAULT_MEDIUM_SAMPLING,) else \
        f"medium sampling {', '.join(cfg.medium_samplings)}; "
    doc.para(f"Scene: `{shown_path(c['input'])}`, {c['width']}x{c['height']} pixels. "
             f"Techniques {', '.join(cfg.techniques)}; "
             f"MIS {', '.join(cfg.mis)}; patterns {', '.join(cfg.patterns)}; {selections}sample ladder "
             f"{', '.join(map(str, cfg.ladder))} camera samples per pixel, {cfg.light_samples} light sample(s) each. "
             f"{len(results.ladder)} ladder runs and {len(results.equal_time)} equal-time runs measured. "
             f"Every run renders with {cfg.threads or 'all'} thread(s), {c.get('workers') or 1} run(s) at a time "
             f"({c.get('executor')}). "
             + ("Times are the CPU time of each single-threaded render (excluding the scene/BVH build): unlike "
                "wall time they do not grow when other processes compete for the cores. "
                if cfg.threads == 1 else "Times are render wall times (excluding the scene/BVH build). ")
             + f"Time basis: {results.time_basis}. "
             + "runs.csv also has wall_time, build_time, light_time and rays of every run.")
    if results.failures:
        doc.para(f"**{len(results.failures)} runs failed** and are missing from the plots: " +
                 "; ".join(f"{f['key']}: {f['error'].splitlines()[0] if f['error'] else ''}"
                           for f in results.failures[:5]))
    non_finite = [r["key"] for r in results.ladder + results.equal_time if not r.get("finite", True)]
    if non_finite:
        doc.para(f"**{len(non_finite)} runs produced NaN/Inf pixels** (their RMSE is infinite): "
                 + ", ".join(non_finite[:8]))
    warnings_paragraphs(report)


def warnings_paragraphs(report: Report) -> None:
    """Every warning the study gave (study_warnings), at most MAX_WARNINGS_SHOWN, so that what renders otherwise than
    intended (a missing image, samples left out) is in the report and not only in a terminal."""
    warned = study_warnings(report.results)
    if not warned:
        return
    report.doc.para(f"**{len(warned)} warning{'s' if len(warned) > 1 else ''}**: the images may not be what the "
                    f"scene means (each run's record in runs/ has its own):")
    for message, where in warned[:MAX_WARNINGS_SHOWN]:
        report.doc.para(f"- {message} ({where})")
    if len(warned) > MAX_WARNINGS_SHOWN:
        report.doc.para(f"- and {len(warned) - MAX_WARNINGS_SHOWN} more")


def reference_section(report: Report) -> None:
    ref, doc = report.results.reference, report.doc
    s = ref["settings"]
    share = findings.ratio_of(ref["estimated_rmse"], report.smallest)
    doc.heading("Reference")
    doc.para(f"Mean of {s['chunks']} independent renders ({s['technique']}, MIS {s['mis']}, {s['pattern']}, "
             f"{s['samples']} samples per pixel in total, {fmt(ref['render_time_total'])} s of rendering). Its own "
             f"RMSE, estimated from the spread of the independent chunks (variance across chunks / their number), "
             f"is **{fmt(ref['estimated_rmse'])}** (relMSE {fmt(ref['estimated_relmse'])}). The smallest RMSE the "
             f"study reports is {fmt(report.smallest)}: the reference's error is {fmt(100 * share, 2)}% of it "
             + ("(well under it: the measured errors are the runs' own)." if share < REFERENCE_SHARE_OK else
                "(**not** well under it: the smallest errors are inflated by the reference's noise; rerun with "
                f"more --reference-samples). Slopes are fitted only on points above {REFERENCE_NOISE_FACTOR}x the "
                "reference's error."))


def convergence_section(report: Report) -> None:
    doc = report.doc
    doc.heading("Convergence")
    doc.para("RMSE against the reference (log-log), one line per technique; the legend gives the fitted slope "
             "(RMSE ~ N^slope; -0.5 is plain Monte Carlo, steeper is better). Cycles 3.4 (MIS with its own "
             "pattern) is drawn in every panel for comparison.")
    for pattern in report.results.settings.patterns:
        for x in ("samples", "time"):
            name = f"rmse_vs_{x}_{pattern}.png"
            plots.plot_convergence(report.results, report.curves, pattern, x, report.plot(name))
            doc.image(f"{PLOTS}/{name}", f"RMSE vs {'samples per pixel' if x == 'samples' else 'wall time'}, "
                                         f"pattern {pattern}")


def summary_section(report: Report) -> None:
    report.doc.heading("Summary")
    for line in wording.summary_lines(report.ordering_lines, report.slopes, report.cosine, report.cycles,
                                      report.results.reference_rmse, report.smallest, report.selection,
                                      report.show_selection, report.ellipse, report.show_ellipse,
                                      report.costlier_maps, report.medium):
        report.doc.para(line)
    pattern = findings.headline_pattern(report.results.settings)
    report.doc.image(f"{PLOTS}/rmse_vs_time_{pattern}.png", f"RMSE vs time, pattern {pattern} (more below)")


def findings_section(report: Report) -> None:
    doc, cfg, show, show_ellipse = report.doc, report.results.settings, report.show_selection, report.show_ellipse
    selection_column = (["light selection"] if show else []) + (["ellipse technique"] if show_ellipse else [])
    slope_column = selection_column + (["medium sampling"] if report.show_medium else [])
    doc.heading("The paper's findings, measured")
    if report.show_medium:
        doc.para(f"Findings 1-3, 5 and 6 compare light sampling at medium sampling {cfg.findings_medium_sampling}; "
                 f"finding 7 compares the medium samplings.")
    doc.para("**1. Equal samples: rectangle < triangles < area.**")
    for line in report.ordering_lines:
        doc.para(line)
    doc.table(["MIS", "pattern"] + selection_column
              + ["order holds at", "rectangle < triangles at", "RMSE triangles/rectangle (top N)",
                 "RMSE area/rectangle (top N)"], wording.ordering_rows(report.ordering, show, show_ellipse))
    doc.para("**2. Stratification: fitted convergence slopes (RMSE vs samples).**")
    plots.plot_slopes(report.results, report.slopes, report.plot("slopes.png"))
    doc.image(f"{PLOTS}/slopes.png", "fitted slopes per technique and pattern")
    doc.table(["technique", "MIS"] + slope_column + list(cfg.patterns), wording.slope_rows(report.slopes, cfg))
    for c in report.slopes.comparisons:
        doc.para(wording.slope_line(c, show, show_ellipse))
    doc.para("**3. Where rectangle_cosine stands** (against rectangle, same MIS and pattern, top of the ladder).")
    for line in [wording.cosine_line(c, show, show_ellipse) for c in report.cosine or []] or \
            ["rectangle_cosine or rectangle was not part of the study."]:
        doc.para(line)
    if report.costlier_maps is not None:
        doc.para("**3b. Where the costlier maps stand** (rectangle_projected, exact projected-solid-angle sampling, "
                 "against rectangle and rectangle_cosine; rectangle_ltc, which follows glossy lobes, against "
                 "rectangle and rectangle_projected; same MIS and pattern, top of the ladder; RMSE at equal time "
                 "from the costs per sample).")
        for line in [wording.cosine_line(c, show, show_ellipse) for c in report.costlier_maps] or \
                ["None of the techniques they are compared with was part of the study."]:
            doc.para(line)
    doc.para("**4. Cycles 3.4 at equal error: time our best configuration needs to reach Cycles' RMSE.**")
    for line in wording.cycles_lines(report.cycles):
        doc.para(line)
    doc.para(COST_NOTE)
    doc.table(["Cycles spp", "Cycles RMSE", "Cycles time [s]", "our best configuration", "its time [s]",
               "time ratio (ours/Cycles)"], wording.cycles_rows(report.cycles, show, show_ellipse, report.show_medium))
    if report.selection is not None:
        doc.para(f"**5. Light selection: {findings.LIGHT_TREE} against {findings.POWER_SELECTION} at equal error** "
                 f"(time each takes to reach the larger of their two RMSEs at the top of the ladder).")
        for line in wording.selection_lines(report.selection):
            doc.para(line)
        doc.table(["technique", "MIS", "pattern"] + (["ellipse technique"] if show_ellipse else [])
                  + ["RMSE", f"{findings.POWER_SELECTION} time [s]", f"{findings.LIGHT_TREE} time [s]",
                     f"time ratio ({findings.LIGHT_TREE}/{findings.POWER_SELECTION})", "verdict (timing noise)"],
                  wording.selection_rows(report.selection, show_ellipse))
    if report.ellipse is not None:
        doc.para(f"**6. Disk and ellipse lights: {findings.ELLIPSE_MAP} against {findings.ELLIPSE_AREA}** (the "
                 f"ellipse technique; each configuration at the top sample count both measured: RMSE at equal "
                 f"samples, fitted slope over the ladder, cost per sample, and the time each takes to reach "
                 f"Cycles' RMSE at the top of its ladder).")
        for line in wording.ellipse_lines(report.ellipse, show):
            doc.para(line)
        doc.para(COST_NOTE + " Efficiency is 1 / (MSE x cost per sample) at that count, its verdict a tie within "
                 "two standard errors of the two costs.")
        doc.table(wording.ellipse_columns(show), wording.ellipse_rows(report.ellipse, show))
    if report.medium is not None:
        doc.para("**7. Medium sampling** (how camera rays through a volume choose their scattering point; each "
                 "configuration at the top sample count all measured: RMSE at equal samples, cost per sample, and "
                 "the time each takes to reach Cycles' RMSE at the top of its ladder, also as a share of Cycles' "
                 "time).")
        for line in wording.medium_lines(report.medium):
            doc.para(line)
        doc.para(COST_NOTE)
        doc.table(wording.medium_columns(report.medium, show, show_ellipse),
                  wording.medium_rows(report.medium, show, show_ellipse))


def target_section(report: Report, target_rmse: Optional[float]) -> None:
    target = equal_error.target_times(report.results.settings, report.curves, report.results.reference_rmse,
                                      report.smallest, target_rmse)
    report.doc.heading("Time to reach a target error")
    report.doc.para(wording.target_line(target, report.show_selection, report.show_ellipse, report.show_medium))
    report.doc.table(["configuration", "time [s]", "how", "samples per pixel"],
                     wording.target_rows(target, report.show_selection, report.show_ellipse, report.show_medium))


def equal_time_section(report: Report) -> None:
    doc = report.doc
    doc.heading("Equal time")
    if not report.results.equal_time:
        doc.para("No equal-time runs were measured.")
        return
    grid = equal_time_grid(report.results)
    plots.plot_equal_time_grid(report.results, grid, report.plot("equal_time_grid.png"))
    doc.image(f"{PLOTS}/equal_time_grid.png", "equal-time renders and their error heat maps")
    doc.table(["configuration", "samples per pixel", "time [s]", "RMSE", "relMSE"],
              wording.equal_time_rows(grid, report.show_selection, report.show_ellipse, report.show_medium))


def cost_model_section(report: Report) -> None:
    """The cost model (cost_model.py): the terms and their check, the break-even ray and shading costs of every pair,
    the efficiency against the ray cost drawn for the headline setting, and Cycles' cost per camera sample."""
    doc, cfg, results = report.doc, report.results.settings, report.results
    show = (report.show_selection, report.show_ellipse, report.show_medium)
    doc.heading("What a sample costs, and at what ray cost accuracy pays")
    model = costs.configuration_costs(report.curves)
    ray_cost = costs.ray_cost_here(model)
    for line in cost_wording.model_lines(costs.checks_within(model), ray_cost):
        doc.para(line)
    if not model:
        return
    doc.table(cost_wording.TERM_HEADER, cost_wording.term_rows(model, *show))
    pairs = costs.pair_costs(cfg, report.curves, model, results.reference_rmse)
    techniques = [p for p in pairs if p.a.technique != p.b.technique]
    headline = CurveKey(cfg.techniques[0], cfg.grid_mis[0] if cfg.grid_mis[0] in cfg.mis else cfg.mis[0],
                        findings.headline_pattern(cfg), *cfg.variants[0])
    doc.para(f"At MIS {headline.mis}, pattern {headline.pattern} (every setting in the table below):")
    for p in techniques:
        if p.a._replace(technique=headline.technique) == headline:
            doc.para(cost_wording.pair_finding(p, ray_cost))
    for p in pairs:  # the light selections of each technique, at the headline's MIS and pattern
        if p.a.light_selection != p.b.light_selection and (p.a.mis, p.a.pattern) == (headline.mis, headline.pattern):
            doc.para(cost_wording.pair_finding(p, ray_cost))
    baseline = costs.BASELINE if costs.BASELINE in cfg.techniques else cfg.techniques[0]
    lines = {t: costs.pair_cost(headline._replace(technique=baseline), headline._replace(technique=t), report.curves,
                                model, results.reference_rmse, ordered=False) for t in cfg.techniques}
    lines = {t: p for t, p in lines.items() if p is not None}
    if lines:
        name = "relative_efficiency.png"
        plots.plot_relative_efficiency(lines, baseline, f"MIS {headline.mis}, {headline.pattern}", ray_cost,
                                       report.plot(name))
        doc.image(f"{PLOTS}/{name}", "efficiency at equal error against the cost of a ray and of shading a hit")
    doc.para("Every pair (B needs no more samples than A for the larger of their top-rung RMSEs; the break-even costs "
             "are where B's time to that error equals A's; efficiency = A's time / B's):")
    doc.table(cost_wording.PAIR_HEADER, cost_wording.pair_rows(pairs, *show))
    width, height = results.config.get("width"), results.config.get("height")
    doc.para(cost_wording.cycles_line(costs.cycles_cost(report.curves, model, (width or 0) * (height or 0)), *show))
    from ..sweep import headline_keys, summaries  # (sweep.py draws on this package: imported when used)
    swept_keys = set(headline_keys(cfg, report.curves))
    swept = summaries(report.out_dir, [p for p in pairs if p.a in swept_keys and p.b in swept_keys])
    if swept:
        doc.para("**The model against a sweep of this scene's cost** (`python -m sphrect.study.sweep`, "
                 "sweep/sweep.md):")
        for line in swept:
            doc.para(line)


def sampler_section(report: Report, sampler_table: bool) -> None:
    doc = report.doc
    doc.heading("The sampler itself: accuracy and cost")
    if not sampler_table:
        doc.para("(skipped: --no-sampler-table)")
        return
    try:
        from ..sampler_table import sampler_tables
        tables, notes = sampler_tables()
        for title, header, rows in tables:
            doc.para(f"**{title}**")
            doc.table(header, rows)
        for note in notes:
            doc.para(note)
    except Exception as e:  # the table is optional; say why it is missing
        doc.para(f"(sampler table unavailable: {type(e).__name__}: {e})")


def files_section(report: Report) -> None:
    report.doc.heading("Files")
    report.doc.para("runs.csv and runs.json: every run (job, times, rays, RMSE, relMSE); reference.json: the "
                    "reference and its error estimate; images/: the reference, its chunks and the equal-time renders "
                    "(.npy, linear radiance, row 0 at the top); plots/: the figures above.")


def write_report(out_dir: str, sampler_table: bool = True, target_rmse: Optional[float] = None) -> str:
    """Write runs.csv, runs.json, the plots and report.md / report.html into out_dir; returns report.md's path."""
    results = load_study(out_dir)
    os.makedirs(os.path.join(out_dir, PLOTS), exist_ok=True)
    write_runs(out_dir, results)
    report = measure(out_dir, results)
    scene_section(report)
    summary_section(report)
    reference_section(report)
    convergence_section(report)
    findings_section(report)
    target_section(report, target_rmse)
    equal_time_section(report)
    cost_model_section(report)
    sampler_section(report, sampler_table)
    files_section(report)
    atomic_write_bytes(os.path.join(out_dir, "report.md"), report.doc.markdown().encode("utf-8"))
    atomic_write_bytes(os.path.join(out_dir, "report.html"), report.doc.to_html("sphrect study").encode("utf-8"))
    return os.path.join(out_dir, "report.md")
