"""The study's ellipse-technique axis (how disk and ellipse lights are sampled: --ellipse-techniques): the plan,
its keys and labels, the option's validation before any rendering, resuming stored studies (also those made
before the axis existed), the report's finding on the two techniques (with the fake renderer of test_study), and
on the real renderer that the axis reaches it (a disk scene renders differently with each technique)."""
import csv
import math

import numpy as np
import pytest

import sphrect
from sphrect.study import StudyConfig
from sphrect.study.jobs import (CYCLES, CYCLES_CURVE, DEFAULT_ELLIPSE_TECHNIQUE, CurveKey, Job, SPHRECT, build_plan,
                                cost_key, curve_key, equal_time_jobs)
from sphrect.study.report import results as report_results
from sphrect.study.runner import RunContext, render_sphrect
from test_study import (  # noqa: F401 (scene_file: a fixture)
    AREA_DISK_COST, AREA_DISK_NOISE, assert_plots, scene_file, strip_axis, study,
    study_of_two_values_from_the_command_line, tiny_config)
from test_study_render import paper_like_scene

pytestmark = pytest.mark.study

BOTH = ("area", "spherical_ellipse")


def test_ellipse_techniques_are_an_axis_of_the_plan():
    """Two ellipse techniques: every ladder and equal-time job for each, with distinct keys; the default's keys
    are those of a study without the axis (stored results keep their keys), Cycles' jobs are unchanged."""
    assert set(BOTH) == set(sphrect.ellipse_techniques)
    both = tiny_config(cycles=True, ellipse_techniques=BOTH)
    plan, plain = build_plan(both), build_plan(tiny_config(cycles=True))
    assert DEFAULT_ELLIPSE_TECHNIQUE == "spherical_ellipse"
    assert StudyConfig().ellipse_techniques == (DEFAULT_ELLIPSE_TECHNIQUE,) and not StudyConfig().shows_ellipse
    assert both.shows_ellipse
    assert len(plan) == 2 * 4 * 2 * 2 * 4 + 4 and len({j.key for j in plan}) == len(plan)
    ours = [j for j in plan if j.engine == SPHRECT]
    assert {j.key for j in plan if j.ellipse_technique == DEFAULT_ELLIPSE_TECHNIQUE} == {j.key for j in plain}
    area = [j for j in ours if j.ellipse_technique == "area"]
    assert len(area) == len(ours) // 2
    assert all("ell_area" in j.key and j.label.endswith(" / ellipse=area") for j in area)
    assert not any("ellipse" in j.label or "ell_" in j.key for j in plain)
    assert len({j.curve for j in ours}) == 4 * 2 * 2 * 2
    assert [j for j in plan if j.engine == CYCLES] == [j for j in plain if j.engine == CYCLES]
    assert Job.from_dict(area[-1].to_dict()) == area[-1]
    # A record stored before the axis existed has no ellipse technique: it was rendered with the default.
    old = {k: v for k, v in area[0].to_dict().items() if k != "ellipse_technique"}
    assert curve_key(old).ellipse_technique == DEFAULT_ELLIPSE_TECHNIQUE
    assert curve_key({"engine": CYCLES}) == CYCLES_CURVE
    # Each ellipse technique has its own cost per sample and its own equal-time render.
    costs = {cost_key(j.to_dict()): 0.02 if j.engine == CYCLES else 0.01 if j.ellipse_technique == "area" else 0.04
             for j in plan}
    assert len(costs) == 4 * 2 * 2 + 1
    et = equal_time_jobs(both, 0.5, costs)
    assert len(et) == 4 * 2 * 2 + 1 and len({j.key for j in et}) == len(et)
    assert {(j.mis, j.ellipse_technique) for j in et if j.engine == SPHRECT} == \
        {(m, e) for m in both.grid_mis for e in BOTH}
    assert {j.ellipse_technique: j.samples for j in et if j.engine == SPHRECT and j.technique == "area"} == \
        {"area": 49 if both.grid_pattern == "stratified" else 50, "spherical_ellipse": 12}
    # Both axes at once: the label names both.
    two = build_plan(tiny_config(light_selections=("power", "tree"), ellipse_techniques=BOTH))
    assert len(two) == 2 * 2 * 4 * 2 * 2 * 4
    assert any(j.label == "rectangle / mis=none / sobol / selection=power / ellipse=area" for j in two)


def test_unknown_ellipse_technique_is_refused_before_rendering(scene_file, tmp_path, capsys):
    from sphrect.study import cli
    with pytest.raises(ValueError, match="unknown ellipse technique 'disk'; choose from area, spherical_ellipse"):
        StudyConfig(ellipse_techniques=("disk",))
    with pytest.raises(ValueError, match="no ellipse technique chosen"):
        StudyConfig(ellipse_techniques=())
    args = cli.parser().parse_args(["scene.npz", "--out", "o", "--ellipse-techniques", "area,spherical_ellipse"])
    assert args.ellipse_techniques == list(BOTH)
    assert cli.parser().parse_args(["scene.npz", "--out", "o"]).ellipse_techniques == [DEFAULT_ELLIPSE_TECHNIQUE]
    out = tmp_path / "o"
    assert cli.main([scene_file, "--out", str(out), "--ellipse-techniques", "area,disk", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "error: --ellipse-techniques: unknown ellipse technique 'disk'; choose from area, spherical_ellipse" in err
    assert not out.exists()  # refused before anything was rendered or written
    # The other list options are named the same way.
    assert cli.main([scene_file, "--out", str(out), "--light-selections", "all", "--quiet"]) == 2
    assert "error: --light-selections: unknown light selection 'all'" in capsys.readouterr().err
    assert not out.exists()


def test_study_of_two_ellipse_techniques_resumes_a_study_of_one(scene_file, tmp_path, monkeypatch):
    """A study of the default ellipse technique (its records stripped of the field, as if stored before the axis)
    still resumes with nothing rendered again; adding --ellipse-techniques area renders only area's runs. Both are
    then kept apart in the curves, the CSV, the labels and the equal-time grid, and compared in finding 6. The
    fake renderer's area has 2x spherical_ellipse's noise at half its cost: each RMSE ratio comes from RMSEs over
    576 values (~3% noise each), so a median within 0.42 ... 0.6 and 'better in 16' (the efficiency ratio is ~2,
    the fake's costs have no noise) fail far less than once in 1e6."""
    out = tmp_path / "study"
    log = tmp_path / "renders.log"
    monkeypatch.setenv("STUDY_FAKE_LOG", str(log))
    study(scene_file, out)
    first = log.read_text().split()
    plain = (out / "report.md").read_text()
    assert not any(word in plain for word in ("ellipse=", "ellipse technique", "Disk and ellipse", "disk and ellipse"))
    strip_axis(out, "ellipse_technique")
    study(scene_file, out)
    assert log.read_text().split() == first  # an old study resumes: nothing rendered again
    summary = study(scene_file, out, ellipse_techniques=BOTH, report=False)  # the next study's, which renders nothing
    new = log.read_text().split()[len(first):]
    assert len(new) == 4 * 2 * 2 * 4 + 4 * 2 and all("ell_area" in k for k in new)  # ladder + equal time of area
    assert summary["failures"] == [] and summary["ladder_runs"] == 2 * 4 * 2 * 2 * 4
    assert summary["equal_time_runs"] == 2 * 4 * 2
    study(scene_file, out, ellipse_techniques=BOTH)
    assert len(log.read_text().split()) == len(first) + len(new)  # and that study resumes too

    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    assert sum(r["ellipse_technique"] == "area" for r in rows) == len(rows) // 2
    assert {r["ellipse_technique"] for r in rows} == set(BOTH)  # also of the records without the field
    curves = report_results.curves(report_results.load_study(str(out)).ladder)
    assert len(curves) == 4 * 2 * 2 * 2 and all(len(c) == 4 for c in curves.values())
    area, ours = (curves[CurveKey("rectangle", "none", "sobol", "tree", e)] for e in BOTH)
    assert area[-1]["rmse"] > 1.6 * ours[-1]["rmse"]  # 2x the noise
    report = (out / "report.md").read_text()
    assert "disk and ellipse lights sampled by area, spherical_ellipse;" in report
    assert "| rectangle / mis=balance / sobol / ellipse=area |" in report  # time to a target
    assert "| rectangle / mis=none / ellipse=spherical_ellipse |" in report  # the equal-time grid
    assert "| MIS | pattern | ellipse technique | order holds at |" in report
    assert "**6. Disk and ellipse lights: spherical_ellipse against area**" in report
    assert "| RMSE area | RMSE spherical_ellipse | RMSE ratio spherical_ellipse/area |" in report
    (line,) = [l for l in report.splitlines() if l.startswith("- Disk and ellipse lights: ")][1:]  # summary, then 6
    assert "(median over 16 (technique, MIS, pattern) configurations" in line
    assert f"at {1 / AREA_DISK_COST:g}x the cost per sample" in line and "better in 16, worse in 0" in line
    median = float(line.split("**")[1])
    assert 0.42 < median < 0.6 and 1 / AREA_DISK_NOISE == 0.5, line
    html = (out / "report.html").read_text()
    assert "ellipse=area" in html and "6. Disk and ellipse lights" in html
    assert_plots(out, ("rmse_vs_samples_sobol.png", "slopes.png", "equal_time_grid.png"))


def disk_scene(width=24, height=16):
    """The paper-like scene of test_study_render with its rectangle replaced by a disk of the same size, close to
    the ground and tilted towards it: where sampling the disk by area and by solid angle differ most."""
    scene = paper_like_scene(width, height)
    scene.lights = [sphrect.EllipseLight(center=(0.0, 0.0, 0.35), axis_x=(0.8, 0.0, 0.0), axis_y=(0.0, 0.25, 0.25),
                                         radiance=(5.0, 5.0, 5.0), two_sided=True, visible=False)]
    return scene


def test_the_ellipse_technique_reaches_the_renderer(tmp_path):
    """A study job renders the disk scene differently with each ellipse technique (same seed, pattern, samples),
    the rectangle scene identically: the job's ellipse technique is the renderer's."""
    images = {}
    for name, scene in (("disk", disk_scene()), ("rectangle", paper_like_scene())):
        path = str(tmp_path / f"{name}.sphrect.npz")
        sphrect.save_scene(scene, path)
        context = RunContext(store_root=str(tmp_path), scene_path=path, width=24, height=16, fingerprint="")
        for e in BOTH:
            job = Job(SPHRECT, "rectangle", "power", "sobol", 4, ellipse_technique=e)
            images[(name, e)], _ = render_sphrect(context, job)
    for image in images.values():
        assert np.all(np.isfinite(image)) and image[..., :3].max() > 0
    assert not np.array_equal(images[("disk", "area")], images[("disk", "spherical_ellipse")])
    assert np.array_equal(images[("rectangle", "area")], images[("rectangle", "spherical_ellipse")])


def test_study_of_both_ellipse_techniques_from_the_command_line(tmp_path):
    """The command line with both ellipse techniques on the disk scene: both rendered, every run finite and
    converging, the report compares them."""
    report = study_of_two_values_from_the_command_line(tmp_path, disk_scene(), "--ellipse-techniques", BOTH,
                                                       "ellipse_technique")
    assert "rectangle / mis=power / sobol / ellipse=spherical_ellipse" in report
    assert "rectangle / mis=power / sobol / ellipse=area" in report
    assert "- Disk and ellipse lights: at equal samples RMSE(spherical_ellipse) / RMSE(area) = **" in report


def test_an_error_beaten_at_the_fewest_samples_is_reached_at_most_in_their_time():
    """On the disk room (analytic light coverage) our 1-spp error is below Cycles' 64-spp error: the time to reach
    it is at most our 1-spp time (no render takes a fraction of a sample), not a backward extrapolation, and the
    Cycles comparison reports it as such instead of 'not reached'."""
    from sphrect.study.report import equal_error, findings, wording
    from sphrect.study.report.curves import BELOW_FEWEST, time_to_target

    def curve(rmse_at_1, seconds_per_sample, samples=(1, 2, 4, 8)):
        return [{"job": {"samples": n}, "rmse": rmse_at_1 / math.sqrt(n), "time": n * seconds_per_sample}
                for n in samples]
    ours = curve(0.05, 0.002)
    reach = time_to_target(ours, 0.1, 1e-6)
    assert reach.how == BELOW_FEWEST and reach.samples == 1 and reach.time == pytest.approx(0.002)
    assert time_to_target(ours, 0.02, 1e-6).how == "measured"  # inside the ladder: as before
    comparison = equal_error.cycles_comparison({CurveKey("rectangle", "none", "sobol", "tree"): ours,
                                                CYCLES_CURVE: curve(0.8, 0.01)}, 1e-6)
    assert comparison.top_ratio == pytest.approx(0.002 / 0.08) and comparison.meets_goal
    line = wording.cycles_lines(comparison)[0]
    assert "our best configuration needs at most **0.025x** Cycles' time" in line
    assert wording.cycles_rows(comparison)[-1][-2:] == ["0.002 (at most: already below at 1 spp)", "0.025"]
    summary = wording.summary_lines([], findings.slopes(StudyConfig(), {}, 1e-6), None, comparison,
                                    1e-6, math.nan)
    assert "measured ratio at most **0.025** -> **met**." in summary[0]
