"""The study's medium-sampling axis (how camera rays through a volume choose their scattering point:
--medium-samplings): the plan, its keys and labels, the option's validation before any rendering, resuming stored
studies (also those made before the axis existed), the report's finding 7 (its numbers from synthetic curves, its
place in a report with the fake renderer of test_study), and on the real renderer that the axis reaches it (a fog
scene renders differently with each medium sampling, a scene without a medium identically) and a tiny study of a
fog box from the command line."""
import csv
import math

import numpy as np
import pytest

import sphrect
from sphrect.study import StudyConfig
from sphrect.study.jobs import (CYCLES, CYCLES_CURVE, DEFAULT_MEDIUM_SAMPLING, CurveKey, Job, SPHRECT, build_plan,
                                cost_key, curve_key, equal_time_jobs)
from sphrect.study.report import results as report_results
from sphrect.study.runner import RunContext, render_sphrect
from test_object_volumes import box_volume
from test_study import (  # noqa: F401 (scene_file: a fixture)
    assert_plots, scene_file, strip_axis, study, study_of_two_values_from_the_command_line, tiny_config)
from test_study_render import paper_like_scene

pytestmark = pytest.mark.study

TWO = ("distance", "equiangular")


def test_medium_samplings_are_an_axis_of_the_plan():
    """Two medium samplings: every ladder and equal-time job for each, with distinct keys; the default's keys are
    those of a study without the axis (stored results keep their keys), Cycles' jobs are unchanged."""
    assert DEFAULT_MEDIUM_SAMPLING == sphrect.RENDER_DEFAULTS["medium_sampling"] == "mis"
    assert set(TWO) < set(sphrect.medium_samplings)
    plain_config = tiny_config(cycles=True)
    assert plain_config.medium_samplings == (DEFAULT_MEDIUM_SAMPLING,) and not plain_config.shows_medium
    two = tiny_config(cycles=True, medium_samplings=TWO)
    assert two.shows_medium and two.findings_medium_sampling == "distance"  # the default is not among them
    assert tiny_config(medium_samplings=("equiangular", "mis")).findings_medium_sampling == "mis"
    plan, plain = build_plan(two), build_plan(plain_config)
    assert len(plan) == 2 * 4 * 2 * 2 * 4 + 4 and len({j.key for j in plan}) == len(plan)
    ours = [j for j in plan if j.engine == SPHRECT]
    equiangular = [j for j in ours if j.medium_sampling == "equiangular"]
    assert len(equiangular) == len(ours) // 2
    assert all("med_equiangular" in j.key and j.label.endswith(" / medium=equiangular") for j in equiangular)
    assert not any("medium" in j.label or "med_" in j.key for j in plain)
    with_default = build_plan(tiny_config(cycles=True, medium_samplings=("mis", "distance")))
    assert {j.key for j in with_default if j.medium_sampling == "mis"} == {j.key for j in plain}
    assert len({j.curve for j in ours}) == 4 * 2 * 2 * 2
    assert [j for j in plan if j.engine == CYCLES] == [j for j in plain if j.engine == CYCLES]
    assert Job.from_dict(equiangular[-1].to_dict()) == equiangular[-1]
    # A record stored before the axis existed has no medium sampling: it was rendered with the default.
    old = {k: v for k, v in equiangular[0].to_dict().items() if k != "medium_sampling"}
    assert curve_key(old).medium_sampling == DEFAULT_MEDIUM_SAMPLING
    assert curve_key({"engine": CYCLES}) == CYCLES_CURVE
    # Each medium sampling has its own cost per sample and its own equal-time render.
    costs = {cost_key(j.to_dict()): 0.02 if j.engine == CYCLES else 0.01 if j.medium_sampling == "distance" else 0.04
             for j in plan}
    assert len(costs) == 4 * 2 * 2 + 1
    et = equal_time_jobs(two, 0.5, costs)
    assert len(et) == 4 * 2 * 2 + 1 and len({j.key for j in et}) == len(et)
    assert {(j.mis, j.medium_sampling) for j in et if j.engine == SPHRECT} == \
        {(m, v) for m in two.grid_mis for v in TWO}
    assert {j.medium_sampling: j.samples for j in et if j.engine == SPHRECT and j.technique == "area"} == \
        {"distance": 49 if two.grid_pattern == "stratified" else 50, "equiangular": 12}
    # With the other axes: the label names each.
    three = build_plan(tiny_config(light_selections=("power", "tree"), ellipse_techniques=("area",),
                                   medium_samplings=TWO))
    assert len(three) == 2 * 2 * 4 * 2 * 2 * 4
    assert any(j.label == "rectangle / mis=none / sobol / selection=power / ellipse=area / medium=distance"
               for j in three)


def test_unknown_medium_sampling_is_refused_before_rendering(scene_file, tmp_path, capsys):
    from sphrect.study import cli
    with pytest.raises(ValueError, match="unknown medium sampling 'tracking'; choose from mis, distance, equiangular"):
        StudyConfig(medium_samplings=("tracking",))
    with pytest.raises(ValueError, match="no medium sampling chosen"):
        StudyConfig(medium_samplings=())
    args = cli.parser().parse_args(["scene.npz", "--out", "o", "--medium-samplings", "distance,equiangular"])
    assert args.medium_samplings == list(TWO)
    assert cli.parser().parse_args(["scene.npz", "--out", "o"]).medium_samplings == [DEFAULT_MEDIUM_SAMPLING]
    out = tmp_path / "o"
    assert cli.main([scene_file, "--out", str(out), "--medium-samplings", "mis,tracking", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "error: --medium-samplings: unknown medium sampling 'tracking'; choose from mis, distance, " \
           "equiangular" in err
    assert not out.exists()  # refused before anything was rendered or written


@pytest.mark.slow
def test_study_of_two_medium_samplings_resumes_a_study_of_one(scene_file, tmp_path, monkeypatch):
    """A study of the default medium sampling (its records stripped of the field, as if stored before the axis)
    still resumes with nothing rendered again; adding --medium-samplings distance renders only distance's runs.
    Both are then kept apart in the curves, the CSV, the labels and the equal-time grid, and compared in finding
    7. (The fake renderer has no medium: both have the same noise; only the bookkeeping is tested here.)"""
    out = tmp_path / "study"
    log = tmp_path / "renders.log"
    monkeypatch.setenv("STUDY_FAKE_LOG", str(log))
    study(scene_file, out, techniques=("area", "rectangle"), report=False)
    first = log.read_text().split()
    strip_axis(out, "medium_sampling", "medium_samplings")
    old = report_results.load_study(str(out))  # an old study's results load: the default's
    assert old.settings.medium_samplings == ("mis",)
    assert {curve_key(r["job"]).medium_sampling for r in old.ladder} == {"mis"}
    study(scene_file, out, techniques=("area", "rectangle"), report=False)
    assert log.read_text().split() == first  # an old study resumes: nothing rendered again
    both = ("mis", "distance")
    study(scene_file, out, techniques=("area", "rectangle"), medium_samplings=both)
    new = log.read_text().split()[len(first):]
    assert len(new) == 2 * 2 * 2 * 4 + 2 * 2 and all("med_distance" in k for k in new)  # ladder + equal time

    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    assert sum(r["medium_sampling"] == "distance" for r in rows) == len(rows) // 2
    assert {r["medium_sampling"] for r in rows} == set(both)  # also of the records without the field
    curves = report_results.curves(report_results.load_study(str(out)).ladder)
    assert len(curves) == 2 * 2 * 2 * 2 and all(len(c) == 4 for c in curves.values())
    assert CurveKey("rectangle", "none", "sobol", "tree", "spherical_ellipse", "distance") in curves
    report = (out / "report.md").read_text()
    assert "medium sampling mis, distance;" in report
    assert "| rectangle / mis=balance / sobol / medium=distance |" in report  # time to a target
    assert "| rectangle / mis=none / medium=mis |" in report  # the equal-time grid
    assert "| technique | MIS | medium sampling | independent | sobol |" in report  # the slopes
    assert "Findings 1-3, 5 and 6 compare light sampling at medium sampling mis" in report
    assert "**7. Medium sampling**" in report
    assert "| RMSE mis | RMSE distance | cost per sample [ms per spp] mis |" in report
    assert sum(l.startswith("- Medium sampling (rectangle, MIS none, sobol): RMSE at 8 spp: mis ")
               for l in report.splitlines()) == 2  # the summary's and finding 7's (no Cycles: no time ratio)
    assert_plots(out, ("rmse_vs_samples_sobol.png", "slopes.png", "equal_time_grid.png"))


def test_finding_7_gives_each_medium_samplings_time_to_cycles_error_as_a_share_of_cycles_time():
    """Synthetic curves RMSE = a / sqrt(n) with known costs: the time each needs for Cycles' top RMSE and its
    share of Cycles' time are exact (interpolation on a power law of slope -1/2 is exact in log-log)."""
    from sphrect.study.report import equal_error, wording

    def curve(rmse_at_1, seconds_per_sample, samples=(1, 2, 4, 8, 16)):
        return [{"job": {"samples": n}, "rmse": rmse_at_1 / math.sqrt(n), "time": n * seconds_per_sample}
                for n in samples]
    cfg = StudyConfig(techniques=("rectangle",), mis=("power",), patterns=("sobol",),
                      medium_samplings=("mis", "distance", "equiangular"))
    key = CurveKey("rectangle", "power", "sobol", cfg.light_selections[0], cfg.ellipse_techniques[0])
    all_curves = {key._replace(medium_sampling="mis"): curve(0.15, 0.001),
                  key._replace(medium_sampling="distance"): curve(0.4, 0.001),
                  key._replace(medium_sampling="equiangular"): curve(0.2, 0.002),
                  CYCLES_CURVE: curve(0.8, 0.01)}
    # Cycles' top: 16 spp, RMSE 0.2, 0.16 s. mis is below it at 1 spp (at most its time), distance reaches it at
    # 4 spp, equiangular at 1.
    (c,) = equal_error.medium_comparisons(cfg, all_curves, 1e-6)
    assert (c.samples, c.cycles_samples) == (16, 16) and c.cycles_time == pytest.approx(0.16)
    assert c.cycles_ratio("distance") == pytest.approx(4 * 0.001 / 0.16)
    assert c.cycles_ratio("equiangular") == pytest.approx(1 * 0.002 / 0.16)
    assert c.rmse_ratio("distance", "equiangular") == pytest.approx(2)
    assert c.efficiency("equiangular", "distance") == pytest.approx(2)
    (line,) = wording.medium_lines([c])
    assert line == ("- Medium sampling (rectangle, MIS power, sobol): to reach Cycles' RMSE at 16 spp: mis "
                    "0.00625x (at most: already below at 1 spp), distance 0.025x, equiangular 0.0125x Cycles' time.")
    row = wording.medium_rows([c])[0]
    assert row[-4:] == ["0.16", "0.00625", "0.025", "0.0125"]
    assert len(row) == len(wording.medium_columns([c]))
    assert equal_error.medium_comparisons(StudyConfig(), all_curves, 1e-6) is None  # one medium sampling


def fog_scene(width=24, height=16):
    """The paper-like scene of test_study_render filled up to 1.5 m with fog (scattering, a little absorption) and
    a point light in it: where distance and equi-angular sampling differ most, near the point light."""
    scene = paper_like_scene(width, height)
    scene.lights.append(sphrect.PointLight(position=(0.5, 0.5, 0.6), intensity=(3.0, 3.0, 3.0)))
    scene.volumes = [box_volume((-2, -2, -0.5), (2, 2, 1.5), (0.4, 0.4, 0.4), (0.05, 0.05, 0.05))]
    return scene


def test_the_medium_sampling_reaches_the_renderer(tmp_path):
    """A study job renders the fog scene differently with each medium sampling (same seed, pattern, samples), the
    scene without fog identically: the job's medium sampling is the renderer's."""
    images = {}
    for name, scene in (("fog", fog_scene()), ("clear", paper_like_scene())):
        path = str(tmp_path / f"{name}.sphrect.npz")
        sphrect.save_scene(scene, path)
        context = RunContext(store_root=str(tmp_path), scene_path=path, width=24, height=16, fingerprint="")
        for v in sphrect.medium_samplings:
            job = Job(SPHRECT, "rectangle", "power", "sobol", 2, medium_sampling=v)
            images[(name, v)], _ = render_sphrect(context, job)
    for image in images.values():
        assert np.all(np.isfinite(image)) and image[..., :3].max() > 0
    fog = [images[("fog", v)] for v in sphrect.medium_samplings]
    assert all(not np.array_equal(a, b) for i, a in enumerate(fog) for b in fog[i + 1:])
    clear = [images[("clear", v)] for v in sphrect.medium_samplings]
    assert all(np.array_equal(clear[0], c) for c in clear[1:])


@pytest.mark.slow
def test_study_of_two_medium_samplings_from_the_command_line(tmp_path):
    """The command line with two medium samplings on the fog scene: both rendered, every run finite and converging,
    the report compares them in finding 7."""
    report = study_of_two_values_from_the_command_line(tmp_path, fog_scene(), "--medium-samplings", TWO,
                                                       "medium_sampling")
    assert "rectangle / mis=power / sobol / medium=distance" in report
    assert "rectangle / mis=power / sobol / medium=equiangular" in report
    assert "- Medium sampling (rectangle, MIS power, sobol): RMSE at 8 spp: distance " in report
