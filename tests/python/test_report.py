"""The study's report (sphrect.study.report): its findings computed as numbers and worded once, on hand-made
curves; a whole report over runs with non-finite errors, which prints placeholders instead of crashing; and a
report that names its scene relative to the directory the study ran from.
The study machinery and its fake renderer are in test_study.py."""
import math
import os

import pytest

import sphrect
from sphrect.study import metrics
from sphrect.study.jobs import CYCLES_CURVE, DEFAULT_LIGHT_SELECTION, CurveKey, StudyConfig
from sphrect.study.report import equal_error, findings, wording
from sphrect.study.report.curves import BEYOND_LONGEST, Reach, curve_cost, systematic_share
from sphrect.study.report.equal_error import SYSTEMATIC_SHARE_LIMIT, cycles_comparison
from sphrect.study.report.findings import cosine_comparisons

from test_study import scene_file, study  # noqa: F401  (scene_file is a fixture)

pytestmark = pytest.mark.study

PLACEHOLDER = wording.PLACEHOLDER


def key(technique, mis, pattern, light_selection=DEFAULT_LIGHT_SELECTION):
    return CurveKey(technique, mis, pattern, light_selection)


def _curve(mse, samples=(1, 2, 4, 8, 16, 32, 64, 128, 256), seconds_per_sample=0.01):
    return [{"job": {"samples": n}, "rmse": math.sqrt(mse(n)), "time": n * seconds_per_sample} for n in samples]


def test_a_plateaued_cycles_error_is_not_reported_as_a_time_ratio():
    assert systematic_share(_curve(lambda n: 1.0 / n)) == pytest.approx(0.0, abs=1e-9)
    biased = _curve(lambda n: 0.01 + 1.0 / n)  # at 256 spp: 0.01 of 0.0139 is systematic
    assert systematic_share(biased) == pytest.approx(0.01 / (0.01 + 1 / 256), rel=1e-9)
    assert systematic_share(biased) > SYSTEMATIC_SHARE_LIMIT
    ours = {key("rectangle", "none", "sobol"): _curve(lambda n: 0.1 / n, seconds_per_sample=0.001)}

    def compare(cycles_curve):  # (lines, rows, ratio at the top) as the report shows them
        comparison = cycles_comparison({**ours, CYCLES_CURVE: cycles_curve}, 1e-6)
        return wording.cycles_lines(comparison), wording.cycles_rows(comparison), comparison.top_ratio
    lines, rows, ratio = compare(_curve(lambda n: 1.0 / n))
    assert ratio == pytest.approx(0.01, rel=0.05) and "meets the goal" in lines[0]
    # Times come from each curve's cost per sample over its 3 largest runs: one slow Cycles run (1.6x) moves
    # the ratio by 1/1.2, not by 1/1.6.
    slow_top = _curve(lambda n: 1.0 / n)
    slow_top[-1]["time"] *= 1.6
    lines, rows, ratio = compare(slow_top)
    assert ratio == pytest.approx(0.01 / 1.2, rel=0.05)
    lines, rows, ratio = compare(biased)
    assert ratio is None and "not measurable" in lines[0] and "systematic" in lines[0]
    assert len(rows) == 9  # the table is still there


def test_cosine_finding_pools_costs_and_reports_ties():
    """rectangle_cosine vs rectangle: the cost per sample is the mean over the top runs, and an efficiency ratio
    inside two standard errors of the timing is a tie, not a win decided by one run's time."""
    def with_costs(curve, costs):  # the top runs' seconds per sample
        for r, c in zip(curve[-len(costs):], costs):
            r["time"] = c * r["job"]["samples"]
        return curve
    steady = _curve(lambda n: 1.0 / n, seconds_per_sample=0.01)
    noisy = with_costs(_curve(lambda n: 1.0 / n, seconds_per_sample=0.01), [0.008, 0.010, 0.012])
    assert metrics.COST_RUNS == 3
    assert curve_cost(steady) == pytest.approx((0.01, 0.0), abs=1e-12)
    cost, rel_se = curve_cost(noisy)
    assert cost == pytest.approx(0.01) and rel_se == pytest.approx(0.2 / math.sqrt(3))
    cfg = StudyConfig(techniques=("rectangle", "rectangle_cosine"), mis=("none",), patterns=("sobol",))

    def verdict(cosine_mse, cosine_cost, rectangle_curve):
        curves = {key("rectangle", "none", "sobol"): rectangle_curve,
                  key("rectangle_cosine", "none", "sobol"): _curve(cosine_mse, seconds_per_sample=cosine_cost)}
        (comparison,) = cosine_comparisons(cfg, curves)
        line = wording.cosine_line(comparison)
        assert line[line.rindex("(") + 1:-2] == comparison.verdict
        return comparison.verdict
    # Efficiency 1 / (MSE x cost): 0.87x the MSE at the same cost is 1.15x as efficient -- a win against steady
    # timings, a tie against timings that scatter by +-20% (two standard errors of the mean: +-23%).
    assert verdict(lambda n: 0.87 / n, 0.01, steady) == "better than rectangle"
    assert verdict(lambda n: 0.87 / n, 0.01, noisy) == "within the timing noise"
    assert verdict(lambda n: 1.0 / n, 0.012, steady) == "worse than rectangle"


def test_tree_against_power_at_equal_error():
    """The light tree against power selection per (technique, MIS, pattern): the time each needs for the larger of
    their top errors. Tree at half power's MSE and the same cost per sample needs half the samples, so half the
    time; with a third of power's cost per sample it is slower; the labels and rows name the selections."""
    cfg = StudyConfig(techniques=("rectangle",), mis=("none",), patterns=("sobol",), light_selections=("power", "tree"))
    assert cfg.shows_selection and not StudyConfig().shows_selection

    def compare(tree_mse, tree_cost):
        curves = {key("rectangle", "none", "sobol", "power"): _curve(lambda n: 1.0 / n),
                  key("rectangle", "none", "sobol", "tree"): _curve(tree_mse, seconds_per_sample=tree_cost)}
        return equal_error.selection_comparisons(cfg, curves, 1e-9)
    (c,) = compare(lambda n: 0.5 / n, 0.01)
    assert c.rmse == pytest.approx(1 / 16) and c.power.how == "measured" and c.tree.how == "measured"
    assert c.power.time == pytest.approx(2.56) and c.ratio == pytest.approx(0.5, rel=1e-6) and c.verdict == "faster"
    line = wording.selection_lines([c])[0]
    assert line.startswith("- Light selection: to reach the same RMSE, tree takes **0.5x** the time of power")
    assert "faster in 1, slower in 0" in line
    assert wording.selection_rows([c]) == [["rectangle", "none", "sobol", "0.0625", "2.56", "1.28", "0.5",
                                            "faster (+-0%)"]]
    assert compare(lambda n: 0.5 / n, 0.03)[0].verdict == "slower"  # 1.5x power's time
    summary = wording.summary_lines([], findings.slopes(cfg, {}, 1e-9), None, None, 1e-9, math.nan, [c], True)
    assert summary[-1] == line
    # A study without both: no comparison, no summary line, and the findings say how to get one.
    assert equal_error.selection_comparisons(StudyConfig(), {}, 1e-9) is None
    assert "--light-selections power,tree" in wording.selection_lines(None)[0]
    assert not any(l.startswith("- Light selection") for l in wording.summary_lines([], findings.slopes(
        StudyConfig(), {}, 1e-9), None, None, 1e-9, math.nan))
    target = equal_error.target_times(cfg, {key("rectangle", "none", "sobol", s): _curve(lambda n: 1.0 / n)
                                            for s in ("power", "tree")}, 1e-9, math.nan)
    assert target.key == key("rectangle", "none", "sobol", "tree")
    assert [r[0] for r in wording.target_rows(target, cfg.shows_selection)] == \
        ["rectangle / mis=none / sobol / selection=power", "rectangle / mis=none / sobol / selection=tree"]
    assert [r[0] for r in wording.target_rows(target)] == ["rectangle / mis=none / sobol"] * 2


def test_costlier_map_findings_compare_with_the_cheaper_maps():
    """rectangle_projected against rectangle and rectangle_cosine (rectangle_ltc against rectangle and
    rectangle_projected): one comparison per (setting, technique it is
    compared with), the equal-time RMSE ratio from the costs, and a summary line per technique."""
    cfg = StudyConfig(techniques=("rectangle", "rectangle_cosine", "rectangle_projected"), mis=("none",),
                      patterns=("sobol",))
    curves = {key("rectangle", "none", "sobol"): _curve(lambda n: 1.0 / n, seconds_per_sample=0.01),
              key("rectangle_cosine", "none", "sobol"): _curve(lambda n: 0.5 / n, seconds_per_sample=0.012),
              key("rectangle_projected", "none", "sobol"): _curve(lambda n: 0.04 / n, seconds_per_sample=0.03)}
    against_rectangle, against_cosine = findings.costlier_map_comparisons(cfg, curves)
    assert (against_rectangle.against, against_cosine.against) == ("rectangle", "rectangle_cosine")
    assert against_rectangle.rmse_ratio == pytest.approx(0.2) and against_rectangle.cost_ratio == pytest.approx(3)
    assert against_rectangle.equal_time_rmse_ratio == pytest.approx(0.2 * math.sqrt(3))
    assert against_rectangle.efficiency == pytest.approx(1 / (0.04 * 3))
    assert against_rectangle.verdict == "better than rectangle"
    # 0.08x the MSE at 2.5x the cost: 5x as efficient as rectangle_cosine.
    assert against_cosine.efficiency == pytest.approx(5) and against_cosine.verdict == "better than rectangle_cosine"
    assert "RMSE ratio at equal time 0.346" in wording.cosine_line(against_rectangle)
    lines = wording.costlier_map_summary_lines([against_rectangle, against_cosine])
    assert lines[1].startswith("- rectangle_projected is more efficient (1 / (MSE x time)) than rectangle_cosine "
                               "in 1 of 1")
    # Not in the study: no finding.
    assert findings.costlier_map_comparisons(StudyConfig(techniques=("rectangle",), mis=("none",),
                                                         patterns=("sobol",)), curves) is None
    # rectangle_ltc is set against rectangle and rectangle_projected.
    cfg = StudyConfig(techniques=("rectangle", "rectangle_projected", "rectangle_ltc"), mis=("none",),
                      patterns=("sobol",))
    curves[key("rectangle_ltc", "none", "sobol")] = _curve(lambda n: 0.01 / n, seconds_per_sample=0.045)
    pairs = [(c.technique, c.against) for c in findings.costlier_map_comparisons(cfg, curves)]
    assert pairs == [("rectangle_projected", "rectangle"), ("rectangle_ltc", "rectangle"),
                     ("rectangle_ltc", "rectangle_projected")]


def test_non_finite_and_missing_numbers_print_a_placeholder():
    """An infinite RMSE (a run with NaN pixels), a slope that cannot be fitted (too few points) and a study
    without Cycles: every finding still computes, and what is no number prints as the placeholder."""
    assert [wording.fmt(x) for x in (float("nan"), math.inf, -math.inf, None)] == [PLACEHOLDER] * 4
    assert wording.fmt(3) == "3" and wording.fmt(0.123456) == "0.123"
    cfg = StudyConfig(techniques=tuple(sphrect.techniques), mis=("none",),
                      patterns=("independent", "sobol"))
    curves = {}
    for pattern in cfg.patterns:
        curves[key("rectangle", "none", pattern)] = _curve(lambda n: 0.01 / n)
        curves[key("triangles", "none", pattern)] = _curve(lambda n: 0.02 / n)
        curves[key("area", "none", pattern)] = [dict(r, rmse=math.inf) for r in _curve(lambda n: 0.1 / n)]
        curves[key("rectangle_cosine", "none", pattern)] = _curve(lambda n: 0.01 / n, samples=(4,))  # one point
    rows = findings.ordering(cfg, curves)
    assert [r.area_ratio for r in rows] == [math.inf] * 2 and all(r.area_worst for r in rows)
    table = wording.ordering_rows(rows)
    assert [r[-1] for r in table] == [PLACEHOLDER] * 2 and table[0][-2] == "1.41"
    lines = wording.ordering_lines(rows, findings.triangles_comparisons(cfg, rows))
    assert "in 2 of 2 (MIS, pattern) cases: **reproduces**" in lines[1]
    # No finite ratio: the span is the placeholder, the verdict follows from the counts alone.
    comparison = findings.TrianglesComparison("sobol", 1, 2, *findings.finite_span([math.nan, math.inf]))
    assert "top – ... –" in wording.ordering_lines([], [comparison])[-1]
    assert comparison.verdict == "does NOT reproduce"
    slopes = findings.slopes(cfg, curves, reference_rmse=1e-9)
    assert math.isnan(slopes.table[key("rectangle_cosine", "none", "sobol")]) and slopes.cycles is None
    slope_table = wording.slope_rows(slopes, cfg)
    assert slope_table[0] == ["area", "none", PLACEHOLDER, PLACEHOLDER]  # infinite errors: no fit
    assert slope_table[3][2:] == [PLACEHOLDER, PLACEHOLDER] and len(slope_table) == len(cfg.techniques)  # no Cycles row
    assert slopes.comparisons == []  # area's slope is no number: no stratification verdict
    (cosine_independent, _) = cosine_comparisons(cfg, curves)
    assert cosine_independent.samples == 4 and cosine_independent.verdict == "within the timing noise"
    cycles = cycles_comparison(curves, 1e-9)
    assert cycles is None and wording.cycles_rows(cycles) == []
    summary = wording.summary_lines(lines, slopes, [], cycles, 1e-9, math.nan)
    assert summary[0] == "- Cycles was not part of this study (no Blender, no .blend, or --no-cycles)."
    target = equal_error.target_times(cfg, curves, 1e-9, smallest=math.nan)
    assert target.source == "middle" and target.key == key("rectangle", "none", "sobol")
    area_rows = [r for r in wording.target_rows(target) if r[0].startswith("area /")]
    assert area_rows == [[f"area / mis=none / {p}", PLACEHOLDER, "unreachable", PLACEHOLDER] for p in cfg.patterns]
    assert wording.target_rows(target)[-1][1] == PLACEHOLDER  # the unreachable last
    beyond = Reach(math.nan, BEYOND_LONGEST, math.nan, 2.5)
    assert wording.reach_how(beyond) == "beyond 100x the longest run (2.5 s)"
    assert CYCLES_CURVE not in curves


def test_report_of_runs_with_nan_pixels(scene_file, tmp_path, monkeypatch):  # noqa: F811
    """Every area render has NaN pixels (infinite RMSE): the report is written, says so, and prints the
    placeholder where a ratio to them would be."""
    monkeypatch.setenv("STUDY_FAKE_NAN", "area")
    out = tmp_path / "study"
    study(scene_file, out)
    report = (out / "report.md").read_text()
    assert "runs produced NaN/Inf pixels" in report
    ordering = [line for line in report.splitlines() if line.startswith(("| none |", "| balance |"))]
    assert len(ordering) == 4 and all(line.endswith(f"| {PLACEHOLDER} |") for line in ordering)
    assert f"| area | none | {PLACEHOLDER} | {PLACEHOLDER} |" in report
    assert "| area / mis=none / sobol | – | unreachable | – |" in report
    assert os.path.getsize(out / "plots" / "equal_time_grid.png") > 5000
    assert (out / "report.html").read_text().count("<img") >= 5


def test_report_names_no_absolute_path_of_the_run_directory(scene_file, tmp_path, monkeypatch):  # noqa: F811
    """The report shows the scene relative to the directory the study ran from, so a report copied into the
    repository names no path of the machine that wrote it."""
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "study"
    study(scene_file, out)
    for name in ("report.md", "report.html"):
        text = (out / name).read_text()
        assert str(tmp_path) not in text, name
        assert "`tiny.sphrect.npz`" in text or "<code>tiny.sphrect.npz</code>" in text, name


def test_the_names_the_findings_are_about_are_the_renderers():
    """The findings name the paper's techniques and the unstratified pattern; every other name comes from the
    study's configuration, which takes them from sphrect.render."""
    from sphrect.render import LIGHT_SELECTIONS, PATTERNS, TECHNIQUES
    from sphrect.study.report.plots import technique_colour
    assert set(findings.PAPER_ORDER) | {findings.COSINE} <= set(TECHNIQUES)
    assert findings.UNSTRATIFIED in PATTERNS
    assert {findings.LIGHT_TREE, findings.POWER_SELECTION} <= set(LIGHT_SELECTIONS)
    assert len({technique_colour(t) for t in TECHNIQUES + ("cycles",)}) == len(TECHNIQUES) + 1
