"""The report's figures (matplotlib, written as PNG): RMSE against samples or time, the fitted slopes, and the
equal-time renders with their error heat maps."""
from __future__ import annotations

from typing import Dict, List, Tuple

import numpy as np

from ...fileio import atomic_write
from ...render import TECHNIQUES
from .. import metrics
from ..jobs import CYCLES, CYCLES_CURVE, CurveKey
from .curves import curve_x, fitted_slope
from .findings import Slopes
from .results import REFERENCE_COLUMN, Curves, EqualTimeGrid, StudyResults
from .wording import CYCLES_NAME, fmt

# A colour per technique, in the order of sphrect.render.TECHNIQUES; Cycles is black.
PALETTE = ("tab:red", "tab:orange", "tab:blue", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive")
# A line style and a bar hatch per variant (light selection x ellipse technique) of the study, in its order: the
# technique keeps its colour.
VARIANT_LINES = ("o-", "^--", "v-.", "d:")
VARIANT_HATCHES = (None, "//", "..", "xx")
DPI = 110


def technique_colour(technique: str) -> str:
    if technique == CYCLES:
        return "black"
    return PALETTE[TECHNIQUES.index(technique) % len(PALETTE)]


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(plt, fig, path: str) -> None:
    fig.tight_layout()
    atomic_write(path, lambda f: fig.savefig(f, format="png", dpi=DPI))
    plt.close(fig)


def variants(cfg) -> List[Tuple[int, str, str, str, str]]:
    """(index, light selection, ellipse technique, medium sampling, its name in a legend) of every variant of a
    technique's curve: the style of its line or bar; the name is empty in a study of one."""
    out = []
    for s, e, v in cfg.variants:
        name = ", ".join(([s] if cfg.shows_selection else []) + ([e] if cfg.shows_ellipse else [])
                         + ([f"medium {v}"] if cfg.shows_medium else []))
        out.append((len(out), s, e, v, name))
    return out


def legend_name(technique: str, variant_name: str) -> str:
    return f"{technique}, {variant_name}" if variant_name else technique


def time_label(threads: int) -> str:
    return ("CPU time of the render [s] (1 thread)" if threads == 1
            else f"render wall time [s] ({threads or 'all'} threads)")


def plot_convergence(results: StudyResults, all_curves: Curves, pattern: str, x: str, path: str) -> None:
    """RMSE against `x` ("samples" or "time"), log-log, a panel per MIS mode, a line per technique (and light
    selection x ellipse technique x medium sampling: its line style) and Cycles."""
    plt = _plt()
    cfg = results.settings
    ref_rmse = results.reference_rmse
    fig, axes = plt.subplots(1, len(cfg.mis), figsize=(5.2 * len(cfg.mis), 4.4), squeeze=False, sharey=True)
    cycles = all_curves.get(CYCLES_CURVE)
    for ax, mis in zip(axes[0], cfg.mis):
        for technique in cfg.techniques:
            for i, selection, ellipse, medium, variant in variants(cfg):
                curve = all_curves.get(CurveKey(technique, mis, pattern, selection, ellipse, medium))
                if not curve:
                    continue
                ax.loglog([curve_x(r, x) for r in curve], [r["rmse"] for r in curve],
                          VARIANT_LINES[i % len(VARIANT_LINES)], color=technique_colour(technique), ms=3,
                          label=f"{legend_name(technique, variant)} (slope "
                                f"{fmt(fitted_slope(curve, x, ref_rmse), 2)})")
        if cycles:
            ax.loglog([curve_x(r, x) for r in cycles], [r["rmse"] for r in cycles], "s--",
                      color=technique_colour(CYCLES), ms=3,
                      label=f"{CYCLES_NAME} (slope {fmt(fitted_slope(cycles, x, ref_rmse), 2)})")
        ax.axhline(ref_rmse, color="grey", ls=":", lw=1, label="reference's own RMSE")
        ax.set_title(f"MIS: {mis}, pattern: {pattern}")
        ax.set_xlabel("samples per pixel" if x == "samples" else time_label(cfg.threads))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("RMSE")
    _save(plt, fig, path)


def plot_slopes(results: StudyResults, slopes: Slopes, path: str) -> None:
    """Bar chart: fitted RMSE-vs-samples slope for every technique (and light selection x ellipse technique: its
    hatch), per pattern (one panel per MIS mode)."""
    plt = _plt()
    cfg = results.settings
    fig, axes = plt.subplots(1, len(cfg.mis), figsize=(4.8 * len(cfg.mis), 3.6), squeeze=False, sharey=True)
    bars = [(t, *v) for t in cfg.techniques for v in variants(cfg)]
    width = 0.8 / len(bars)
    for ax, mis in zip(axes[0], cfg.mis):
        for i, (technique, j, selection, ellipse, medium, variant) in enumerate(bars):
            ax.bar(np.arange(len(cfg.patterns)) + (i - (len(bars) - 1) / 2) * width,
                   [slopes.table[CurveKey(technique, mis, p, selection, ellipse, medium)] for p in cfg.patterns],
                   width,
                   color=technique_colour(technique), hatch=VARIANT_HATCHES[j % len(VARIANT_HATCHES)],
                   label=legend_name(technique, variant))
        ax.axhline(-0.5, color="grey", ls=":", lw=1)
        ax.set_xticks(np.arange(len(cfg.patterns)))
        ax.set_xticklabels(cfg.patterns)
        ax.set_title(f"RMSE ~ N^slope, MIS: {mis}")
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel("fitted slope (-0.5 = plain Monte Carlo)")
    _save(plt, fig, path)


def plot_equal_time_grid(results: StudyResults, grid: EqualTimeGrid, path: str) -> None:
    """A pair of rows per MIS mode, light selection and ellipse technique: the equal-time renders (one white point,
    the reference's) and below each its error heat map, all maps on one colour scale (the largest 99th percentile of
    their finite values)."""
    plt = _plt()
    reference = grid.reference
    white = metrics.white_point(reference)
    errors = {key: metrics.error_map(image, reference) for key, image in grid.images.items()}
    vmax = max([float(np.percentile(m[np.isfinite(m)], 99)) for m in errors.values() if np.isfinite(m).any()]
               + [1e-12])
    rows = len(grid.rows) * 2
    h, w = reference.shape[:2]
    fig, axes = plt.subplots(rows, len(grid.columns), figsize=(2.6 * len(grid.columns), 2.6 * rows * h / w + 0.6),
                             squeeze=False)
    for row_index, row in enumerate(grid.rows):
        for col, name in enumerate(grid.columns):
            ax_img, ax_err = axes[2 * row_index][col], axes[2 * row_index + 1][col]
            for ax in (ax_img, ax_err):
                ax.set_xticks([])
                ax.set_yticks([])
            if name == REFERENCE_COLUMN:
                ax_img.imshow(metrics.tonemap(reference, white))
                ax_img.set_title(f"reference\n{results.reference['settings']['samples']} spp", fontsize=8)
                ax_err.axis("off")
                continue
            r = grid.cells.get((row, name))
            if r is None:
                ax_img.axis("off")
                ax_err.axis("off")
                continue
            ax_img.imshow(metrics.tonemap(grid.images[r["key"]], white))
            spp = r.get("samples_done")
            cfg = results.settings
            setting = f"mis={row.mis}" + (f", {row.light_selection}" if cfg.shows_selection else "") \
                + (f", {row.ellipse_technique}" if cfg.shows_ellipse else "") \
                + (f", medium {row.medium_sampling}" if cfg.shows_medium else "")
            title = (CYCLES_NAME if name == CYCLES else f"{name}\n{setting}") + \
                f"\n{fmt(spp) if spp else '?'} spp, RMSE {fmt(r['rmse'])}"
            ax_img.set_title(title, fontsize=8)
            ax_err.imshow(errors[r["key"]], cmap="inferno", vmin=0, vmax=vmax)
            ax_err.set_title("|error| (RMS over RGB)", fontsize=7)
    fig.suptitle(f"Equal time: {fmt(results.state.get('equal_time_budget'))} s per image (sample counts "
                 f"predicted from the ladder's time per sample) "
                 f"(pattern {results.settings.grid_pattern}); heat maps share one colour scale", fontsize=9)
    _save(plt, fig, path)


def plot_relative_efficiency(lines: Dict[str, object], baseline: str, setting: str, ray_cost: float,
                             path: str) -> None:
    """Each technique's efficiency at equal error over `baseline`'s (costs.PairCost, B the technique), against the
    cost of a ray (left: shading as measured) and against a shading cost added per hit (right: rays as measured),
    log-log; this renderer's own ray cost marked."""
    from .costs import RAY_COSTS, SHADING_COSTS
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), squeeze=False, sharey=True)
    ray_ax, shading_ax = axes[0]
    for technique, pair in lines.items():
        colour = technique_colour(technique)
        ray_ax.loglog([x * 1e9 for x in RAY_COSTS], [pair.efficiency(x) for x in RAY_COSTS], color=colour,
                      label=technique)
        shading_ax.loglog([y * 1e9 for y in SHADING_COSTS], [pair.efficiency(None, y) for y in SHADING_COSTS],
                          color=colour, label=technique)
    ray_ax.axvline(ray_cost * 1e9, color="grey", ls="--", lw=1, label="a ray here")
    for ax, xlabel in ((ray_ax, "cost of a ray [ns]"), (shading_ax, "shading cost added per hit [ns]")):
        ax.axhline(1.0, color="grey", ls=":", lw=1)
        ax.set_xlabel(xlabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    ray_ax.set_ylabel(f"efficiency at equal error / {baseline}'s")
    fig.suptitle(f"Time to the same error, {setting}: above 1 the technique reaches it sooner than {baseline}")
    _save(plt, fig, path)


def plot_sweep(panels, path: str) -> None:
    """The cost model's sweep (sweep.py): a panel per axis (title, x label, the levels' positions on it [s], the pairs'
    verdicts), each pair's time ratio at equal error predicted (line) and measured (dots) against the position."""
    plt = _plt()
    fig, axes = plt.subplots(1, len(panels), figsize=(5.5 * len(panels), 4.4), squeeze=False)
    for ax, (title, xlabel, positions, verdicts) in zip(axes[0], panels):
        xs = [max(x, 1e-9) * 1e9 for x in positions]
        for v in verdicts:
            colour = technique_colour(v.b.split(" / ")[0])
            ax.semilogx(xs, v.predicted, "-", color=colour, lw=1)
            ax.semilogx(xs, v.measured, "o", color=colour, ms=4, label=f"{v.b} / {v.a}")
        ax.axhline(1.0, color="grey", ls=":", lw=1)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("A's time to the error / B's (line: predicted, dots: measured)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    _save(plt, fig, path)
