"""The study machinery (sphrect.study) on a tiny scene and ladder, driven by a fake renderer so it runs in
seconds without the native renderer: outputs exist and are well-formed, the reference's own error estimate is
computed (and is right), resuming skips finished runs, and interrupted or crashing runs leave no corrupt output.
test_report.py tests the report's findings; test_study_render.py runs the same machinery on the real renderer."""
import csv
import json
import math
import os
import zlib
from time import sleep

import numpy as np
import pytest

import sphrect
from sphrect.study import LocalProcessPool, ReferenceSettings, SerialExecutor, StudyConfig, run_study
from sphrect.study import metrics, store as store_module
from sphrect.study.jobs import (CYCLES, CYCLES_CURVE, DEFAULT_LIGHT_SELECTION, DEFAULT_RIS_CANDIDATES, CurveKey, Job,
                                build_plan, cost_key, curve_key, equal_time_jobs, sample_ladder, stratifiable_count)
from sphrect.study.report import results as report_results
from sphrect.study.reference import estimate_error
from sphrect.study.store import ResultStore

pytestmark = pytest.mark.study

HOOK = "test_study:fake_render"
W, H = 16, 12
NOISE = {"area": 0.4, "triangles": 0.2, "rectangle": 0.1, "rectangle_cosine": 0.08}
STUDY_TECHNIQUES = tuple(NOISE)
assert set(STUDY_TECHNIQUES) <= set(sphrect.techniques)
# Light selection 'power' (of the fake renderer): 1.5x the noise at 1/1.2 of the cost per sample, so to reach the
# same error the tree takes 1.2 / 1.5^2 = 0.533x power's time.
POWER_NOISE, POWER_COST = 1.5, 1 / 1.2
# Ellipse technique 'area' (of the fake renderer): 2x the noise at half the cost per sample, so at equal samples
# spherical_ellipse has half the RMSE, twice the cost and (2^2 x 0.5) = 2x the efficiency.
AREA_DISK_NOISE, AREA_DISK_COST = 2.0, 0.5
# The fake's time as the cost model's terms (cost_model.py): a camera ray and an occlusion ray per camera sample at
# T_RAY seconds each, light sampling this share of the rest (rectangle_cosine's costlier sampler most of it), the
# rest fixed work.
T_RAY = 1e-3 / (W * H) / 6
SAMPLER_SHARE = {"rectangle_cosine": 0.75}


def truth(width=W, height=H):
    y, x = np.mgrid[0:height, 0:width]
    img = np.zeros((height, width, 4), np.float32)
    img[..., 0] = 0.5 + 0.5 * x / width
    img[..., 1] = 0.3 + 0.2 * y / height
    img[..., 2] = 0.2
    img[..., 3] = 1
    return img


def fake_render(context, job):
    """Truth + Gaussian noise of std NOISE[technique] / sqrt(samples) (x POWER_NOISE with light selection power,
    x AREA_DISK_NOISE with ellipse technique area): an unbiased 'renderer' with known error.
    Side effects for the tests, by environment variable: STUDY_FAKE_LOG (append each rendered key),
    STUDY_FAKE_INTERRUPT_AFTER (raise KeyboardInterrupt once that many renders are logged),
    STUDY_FAKE_CRASH (kill the worker process on jobs whose key contains it), STUDY_FAKE_NAN (NaN pixels in
    the renders of that technique), STUDY_FAKE_SLEEP (seconds each render takes). Its noise depends on the job
    alone, in every process (no salted hash()), so that runs on different workers compare."""
    log = os.environ.get("STUDY_FAKE_LOG")
    crash = os.environ.get("STUDY_FAKE_CRASH")
    if crash and crash in job.key:
        os._exit(3)
    if log:
        limit = os.environ.get("STUDY_FAKE_INTERRUPT_AFTER")
        if limit and os.path.exists(log) and len(open(log).read().split()) >= int(limit):
            raise KeyboardInterrupt
        with open(log, "a") as f:
            f.write(job.key + "\n")
    sleep(float(os.environ.get("STUDY_FAKE_SLEEP", "0")))
    samples = job.samples
    rng = np.random.default_rng(zlib.crc32(f"{job.key}/{job.seed}".encode()))
    power, area_disks = job.light_selection == "power", job.ellipse_technique == "area"
    sigma = NOISE.get(job.technique, 0.15) / math.sqrt(samples) * (POWER_NOISE if power else 1.0) \
        * (AREA_DISK_NOISE if area_disks else 1.0)
    image = truth(context.width, context.height)
    image[..., :3] += rng.normal(0, sigma, image[..., :3].shape).astype(np.float32)
    if job.technique == os.environ.get("STUDY_FAKE_NAN"):
        image[::2, ::3, 1] = np.nan
    time = samples * 1e-3 * (1.5 if job.technique == "rectangle_cosine" else 1.0) * (POWER_COST if power else 1.0) \
        * (AREA_DISK_COST if area_disks else 1.0)
    n = samples * context.width * context.height
    rest = max(0.0, time - 2 * n * T_RAY)
    light = rest * SAMPLER_SHARE.get(job.technique, 0.5)
    return image, {"build_time": 0.01, "call_time": time, "wall_time": time, "cpu_time": time, "light_time": light,
                   "shading_time": time / 3, "rays": n, "camera_rays": n, "surface_hits": n, "tile_time": time,
                   "trace_time": n * T_RAY, "camera_trace_time": n * T_RAY, "samples_done": samples}


@pytest.fixture
def scene_file(tmp_path):
    path = str(tmp_path / "tiny.sphrect.npz")
    sphrect.save_scene(sphrect.Scene(camera=sphrect.Camera(width=W, height=H)), path)
    return path


def tiny_config(**kw):
    # Four techniques: the counts below are 4 (techniques) x 2 (MIS) x 2 (patterns) x 4 (ladder) and so on; the
    # machinery does not depend on which (every name is validated by StudyConfig, test_plan_and_keys).
    args = dict(techniques=STUDY_TECHNIQUES, mis=("none", "balance"),
                patterns=("independent", "sobol"), ladder=(1, 2, 4, 8), equal_time=0.004)
    args.update(kw)
    return StudyConfig(**args)


def assert_plots(out, names):
    """Each of the study's plots `names` is a PNG of some substance."""
    for png in names:
        data = (out / "plots" / png).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, png


def strip_axis(out, job_field, config_field=None):
    """Make the stored runs (and, given config_field, the stored settings) look like a study made before the axis
    `job_field` was recorded."""
    for name in os.listdir(out / "runs"):
        path = out / "runs" / name
        record = json.loads(path.read_text())
        del record["job"][job_field]
        path.write_text(json.dumps(record))
    if config_field:
        config = json.loads((out / "config.json").read_text())
        del config["study"][config_field]
        (out / "config.json").write_text(json.dumps(config))


def study_of_two_values_from_the_command_line(tmp_path, scene, option, values, column):
    """The command line's study (rectangle, power MIS, sobol, 1-8 spp) of `scene` with `option` set to two `values`
    (their column in runs.csv: `column`): both rendered at every count, every run finite, each converging, the two
    different. Returns the report's text."""
    from sphrect.study import cli
    scene_path = str(tmp_path / "scene.sphrect.npz")
    sphrect.save_scene(scene, scene_path)
    out = tmp_path / "study"
    assert cli.main([scene_path, "--out", str(out), "--techniques", "rectangle", "--mis", "power", "--patterns",
                     "sobol", option, ",".join(values), "--max-samples", "8", "--reference-samples", "1024",
                     "--reference-chunks", "4", "--grid-mis", "power", "--grid-pattern", "sobol", "--workers", "2",
                     "--no-sampler-table", "--quiet"]) == 0
    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    ladder = {(r[column], int(r["samples"])): r for r in rows if r["kind"] == "ladder"}
    assert set(ladder) == {(v, n) for v in values for n in (1, 2, 4, 8)}
    for r in rows:
        assert r["finite"] == "True" and 0 < float(r["rmse"]) < math.inf
    for v in values:
        assert float(ladder[(v, 8)]["rmse"]) < float(ladder[(v, 1)]["rmse"]), v
    assert ladder[(values[0], 1)]["rmse"] != ladder[(values[1], 1)]["rmse"]
    return (out / "report.md").read_text()


def study(scene_file, out, executor=None, report=True, **kw):
    """The tiny study (tiny_config(**kw)) of the fake renderer. report=False where the report would be one another
    test writes from the same results (its plots are most of a study's time)."""
    return run_study(scene_file, str(out), tiny_config(**kw), ReferenceSettings(samples=4096, chunks=4),
                     executor=executor or SerialExecutor(), render_hook=HOOK, progress=False,
                     sampler_table=False, report=report)


def test_plan_and_keys():
    config = tiny_config(cycles=True)
    plan = build_plan(config)
    assert len(plan) == 4 * 2 * 2 * 4 + 4
    assert len({j.key for j in plan}) == len(plan)  # keys identify runs
    assert [j.samples for j in plan] == sorted(j.samples for j in plan)  # cheapest first
    assert Job.from_dict(plan[5].to_dict()) == plan[5]
    assert sample_ladder(20) == [1, 2, 4, 8, 16]
    costs = {cost_key(j.to_dict()): 0.02 if j.engine == CYCLES else 0.01 for j in plan}
    et = equal_time_jobs(config, 0.5, costs)
    assert len(et) == 4 * 2 + 1
    # budget / time per sample: Cycles 25; ours 50, laid out as a 7 x 7 grid when the grid's pattern is stratified
    ours = stratifiable_count(50) if config.grid_pattern == "stratified" else 50
    assert sorted({j.samples for j in et}) == [25, ours]
    with pytest.raises(ValueError, match="unknown technique"):
        StudyConfig(techniques=("rect",))
    with pytest.raises(ValueError, match="unknown sample pattern"):
        StudyConfig(patterns=("halton",))


def test_light_selections_are_an_axis_of_the_plan():
    """Two light selections: every ladder and equal-time job for each, with distinct keys; the default selection's
    keys are those of a study without the axis (stored results keep their keys), Cycles' jobs are unchanged."""
    both = tiny_config(cycles=True, light_selections=("power", "tree"))
    plan, plain = build_plan(both), build_plan(tiny_config(cycles=True))
    assert DEFAULT_LIGHT_SELECTION == "tree" and StudyConfig().light_selections == ("tree",)
    assert len(plan) == 2 * 4 * 2 * 2 * 4 + 4 and len({j.key for j in plan}) == len(plan)
    ours = [j for j in plan if j.engine == "sphrect"]
    assert {j.light_selection for j in ours} == {"power", "tree"}
    assert {j.key for j in plan if j.light_selection == "tree"} == {j.key for j in plain}
    assert all("sel_power" in j.key and j.label.endswith(" / selection=power") for j in ours
               if j.light_selection == "power")
    assert len({j.curve for j in ours}) == 4 * 2 * 2 * 2
    assert [j for j in plan if j.engine == CYCLES] == [j for j in plain if j.engine == CYCLES]
    assert Job.from_dict(ours[-1].to_dict()) == ours[-1]
    # A record stored before the axis existed has no light selection: it was rendered with the default.
    old = {k: v for k, v in ours[0].to_dict().items() if k != "light_selection"}
    assert curve_key(old).light_selection == DEFAULT_LIGHT_SELECTION
    assert curve_key({"engine": CYCLES}) == CYCLES_CURVE
    costs = {cost_key(j.to_dict()): 0.02 if j.engine == CYCLES else 0.01 for j in plan}
    et = equal_time_jobs(both, 0.5, costs)
    assert len(et) == 4 * 2 * 2 + 1 and len({j.key for j in et}) == len(et)
    assert {(j.mis, j.light_selection) for j in et if j.engine == "sphrect"} == \
        {(m, s) for m in both.grid_mis for s in ("power", "tree")}
    # The add-on's MIS default alone: the grid takes the MIS modes the ladder measures, not the default grid's.
    assert StudyConfig(mis=("power",)).grid_mis == ("power",)
    assert StudyConfig(mis=("none", "power")).grid_mis == ("none",)
    with pytest.raises(ValueError, match="unknown light selection 'uniform'; choose from power, tree"):
        StudyConfig(light_selections=("uniform",))
    with pytest.raises(ValueError, match="no light selection chosen"):
        StudyConfig(light_selections=())


def test_ris_candidates_are_a_setting_of_the_ris_jobs():
    """--ris-candidates M reaches every "ris" job (ladder and equal time) and its key; the other selections' jobs,
    and "ris" at the default M, keep the keys they had before the setting existed; M is checked."""
    assert DEFAULT_RIS_CANDIDATES == sphrect.RENDER_DEFAULTS["ris_candidates"]
    config = tiny_config(light_selections=("tree", "ris"), ris_candidates=9)
    plan = build_plan(config)
    ris = [j for j in plan if j.light_selection == "ris"]
    tree = [j for j in plan if j.light_selection == "tree"]
    assert ris and tree and len({j.key for j in plan}) == len(plan)
    assert all(j.ris_candidates == 9 and "-ris9-" in j.key for j in ris)
    assert all(j.ris_candidates == DEFAULT_RIS_CANDIDATES and "-ris" not in j.key for j in tree)
    assert {j.key for j in tree} == {j.key for j in build_plan(tiny_config())}
    default = build_plan(tiny_config(light_selections=("tree", "ris")))
    assert all("-ris" not in j.key.replace("sel_ris", "") for j in default)
    assert Job.from_dict(ris[0].to_dict()) == ris[0]
    old = {k: v for k, v in ris[0].to_dict().items() if k != "ris_candidates"}  # a record from before the setting
    assert Job.from_dict(old).ris_candidates == DEFAULT_RIS_CANDIDATES
    costs = {cost_key(j.to_dict()): 0.01 for j in plan}
    assert {j.ris_candidates for j in equal_time_jobs(config, 0.5, costs) if j.light_selection == "ris"} == {9}
    for bad in (0, sphrect.MAX_RIS_CANDIDATES + 1):
        with pytest.raises(ValueError, match=f"in 1..{sphrect.MAX_RIS_CANDIDATES}") as error:
            tiny_config(ris_candidates=bad)
        assert error.value.setting == "ris_candidates"


def test_light_selections_on_the_command_line(tmp_path, capsys):
    from sphrect.study import cli
    args = cli.parser().parse_args(["scene.npz", "--out", "o", "--light-selections", "power,tree"])
    assert args.light_selections == ["power", "tree"]
    assert cli.parser().parse_args(["scene.npz", "--out", "o"]).light_selections == [DEFAULT_LIGHT_SELECTION]
    assert cli.parser().parse_args(["scene.npz", "--out", "o"]).ris_candidates == DEFAULT_RIS_CANDIDATES
    assert cli.parser().parse_args(["scene.npz", "--out", "o", "--ris-candidates", "16"]).ris_candidates == 16
    assert cli.main([str(tmp_path / "scene.npz"), "--out", str(tmp_path / "o"), "--light-selections", "tree,all"]) == 2
    assert "unknown light selection 'all'" in capsys.readouterr().err


def test_study_of_two_light_selections(scene_file, tmp_path):
    """Both selections measured, kept apart in the curves, the CSV, the labels, the equal-time grid, and compared
    at equal error. The fake renderer's tree takes 1.2 / 1.5^2 = 0.533x power's time for the same error; each
    configuration's ratio comes from RMSEs over 576 values (a few % noise, the seed varies with the process's
    string hashing), so 'faster in all 16' and a median within 0.42 ... 0.68 fail far less than once in 1e6."""
    out = tmp_path / "study"
    summary = study(scene_file, out, light_selections=("power", "tree"))
    assert summary["failures"] == [] and summary["ladder_runs"] == 2 * 4 * 2 * 2 * 4
    assert summary["equal_time_runs"] == 2 * 4 * 2
    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    assert {r["light_selection"] for r in rows} == {"power", "tree"}
    assert sum(r["light_selection"] == "power" for r in rows) == len(rows) // 2
    curves = report_results.curves(report_results.load_study(str(out)).ladder)
    assert len(curves) == 4 * 2 * 2 * 2 and all(len(c) == 4 for c in curves.values())
    power, tree = (curves[CurveKey("rectangle", "none", "sobol", s)] for s in ("power", "tree"))
    assert power[-1]["rmse"] > 1.3 * tree[-1]["rmse"]  # 1.5x the noise
    report = (out / "report.md").read_text()
    assert "light selection power, tree;" in report
    assert "| rectangle / mis=balance / sobol / selection=power |" in report
    assert "| rectangle / mis=none / selection=tree |" in report  # the equal-time grid
    assert "| MIS | pattern | light selection | order holds at |" in report
    assert "**5. Light selection: tree against power at equal error**" in report
    (line,) = [l for l in report.splitlines() if l.startswith("- Light selection: ")][1:]  # summary, then finding 5
    assert "(median over 16 (technique, MIS, pattern) configurations" in line and "faster in 16, slower in 0" in line
    median = float(line.split("**")[1].rstrip("x"))
    assert 0.42 < median < 0.68, line
    data = (out / "plots" / "equal_time_grid.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000


def test_metrics():
    ref = truth()
    img = ref.copy()
    img[..., :3] += 0.1
    assert metrics.rmse(img, ref) == pytest.approx(0.1, rel=1e-5)
    assert metrics.relmse(img, ref) > 0
    assert metrics.error_map(img, ref).shape == (H, W)
    slope, _ = metrics.fit_slope([1, 2, 4, 8], [1, 2 ** -0.5, 0.5, 8 ** -0.5])
    assert slope == pytest.approx(-0.5)
    t, how = metrics.cost_to_reach([1, 2, 4], [1.0, 0.5, 0.25], 0.35)
    assert how == "measured" and 2 < t < 4
    t, how = metrics.cost_to_reach([1, 2, 4], [1.0, 0.5, 0.25], 0.1)
    assert how == "extrapolated" and t == pytest.approx(10, rel=1e-6)
    with pytest.raises(ValueError):
        metrics.rmse(img, ref[:4])


def test_reference_error_estimate_is_right():
    # 8 chunks of truth + N(0, 0.2): the mean's true RMSE is 0.2/sqrt(8) = 0.0707. With 16x12x3 pixels the
    # estimate's relative standard deviation is ~ sqrt(2/(7*576)) = 2.4%; 15% is > 6 sigma (false failure
    # rate < 1e-8, and the seed is fixed).
    rng = np.random.default_rng(1)
    chunks = np.stack([truth() + np.pad(rng.normal(0, 0.2, (H, W, 3)), ((0, 0), (0, 0), (0, 1)))
                       for _ in range(8)])
    estimate = estimate_error(chunks)
    actual = metrics.rmse(chunks.mean(axis=0), truth())
    assert estimate["rmse"] == pytest.approx(0.2 / math.sqrt(8), rel=0.15)
    assert estimate["rmse"] == pytest.approx(actual, rel=0.15)


def test_study_outputs_are_well_formed(scene_file, tmp_path):
    out = tmp_path / "study"
    summary = study(scene_file, out)
    assert summary["failures"] == []
    assert summary["ladder_runs"] == 4 * 2 * 2 * 4
    assert summary["equal_time_runs"] == 4 * 2
    # Reference: error estimate computed, and close to the truth (4 chunks x 1024 spp of sigma 0.1 noise:
    # true RMSE 0.1/64 = 0.0016; the estimate from 4 chunks over 576 values is within 15% (> 5 sigma)).
    ref = json.load(open(out / "reference.json"))
    assert ref["estimated_rmse"] == pytest.approx(0.1 / 64, rel=0.15)
    reference = np.load(out / "images" / "reference.npy")
    assert reference.shape == (H, W, 4) and np.all(np.isfinite(reference))
    # Every run: one record with the measurements.
    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4 * 2 * 2 * 4 + 4 * 2
    for r in rows:
        assert float(r["rmse"]) > 0 and float(r["relmse"]) > 0 and float(r["wall_time"]) > 0
        assert int(r["rays"]) > 0 and float(r["light_time"]) > 0
    data = json.load(open(out / "runs.json"))
    assert len(data["runs"]) == len(rows)
    # Errors behave like the fake renderer's: area is worst, RMSE falls ~ N^-1/2.
    by = {(r["technique"], r["mis"], r["pattern"], int(r["samples"])): float(r["rmse"]) for r in rows
          if r["kind"] == "ladder"}
    assert by[("area", "none", "sobol", 8)] > by[("rectangle", "none", "sobol", 8)]
    slope, _ = metrics.fit_slope([1, 2, 4, 8], [by[("area", "none", "independent", n)] for n in (1, 2, 4, 8)])
    assert -0.65 < slope < -0.35
    # Report and plots exist and are non-trivial.
    report = (out / "report.md").read_text()
    for needle in ("Reference", "rmse_vs_samples_sobol.png", "rmse_vs_time_independent.png", "equal_time_grid.png",
                   "Time to reach a target error", "rectangle < triangles < area", "relative_efficiency.png",
                   "B faster at a ray cost", "A ray costs **868 ns** here"):
        assert needle in report, needle
    assert "reproduces" in report
    assert "selection" not in report.lower()  # a study of the default light selection only does not name it
    assert (out / "report.html").read_text().count("<img") >= 5
    assert_plots(out, ("rmse_vs_samples_sobol.png", "rmse_vs_time_sobol.png", "slopes.png", "equal_time_grid.png"))
    assert_store_clean(out)  # the report's files too (the interrupted study's resume writes this same report)


def test_resume_skips_finished_runs(scene_file, tmp_path, monkeypatch):
    out = tmp_path / "study"
    log = tmp_path / "renders.log"
    monkeypatch.setenv("STUDY_FAKE_LOG", str(log))
    # Until the bigger ladder, the results (the fake renderer is deterministic) and so the report are
    # test_study_outputs_are_well_formed's.
    study(scene_file, out, report=False)
    first = log.read_text().split()
    assert len(first) == 4 + 4 * 2 * 2 * 4 + 4 * 2  # reference chunks + ladder + equal time
    before = {p: os.path.getmtime(out / "runs" / p) for p in os.listdir(out / "runs")}
    study(scene_file, out, report=False)
    assert log.read_text().split() == first  # nothing rendered again
    assert {p: os.path.getmtime(out / "runs" / p) for p in os.listdir(out / "runs")} == before
    # A bigger ladder renders only the new sample count.
    study(scene_file, out, ladder=(1, 2, 4, 8, 16))
    new = log.read_text().split()[len(first):]
    assert len(new) == 4 * 2 * 2 and all("n000016" in k for k in new)


def assert_store_clean(out):
    """Every file under the study directory is whole: no temporaries, every JSON parses, every .npy loads."""
    for root, _, files in os.walk(out):
        for name in files:
            path = os.path.join(root, name)
            assert not name.endswith(".tmp"), path
            if name.endswith(".json"):
                json.load(open(path))
            elif name.endswith(".npy"):
                assert np.all(np.isfinite(np.load(path)))


def test_interrupted_study_leaves_no_corrupt_output_and_resumes(scene_file, tmp_path, monkeypatch):
    out = tmp_path / "study"
    log = tmp_path / "renders.log"
    monkeypatch.setenv("STUDY_FAKE_LOG", str(log))
    monkeypatch.setenv("STUDY_FAKE_INTERRUPT_AFTER", "30")
    with pytest.raises(KeyboardInterrupt):
        study(scene_file, out)
    assert_store_clean(out)
    done = len(os.listdir(out / "runs"))
    assert done == 30  # every render that finished was recorded, nothing else
    monkeypatch.delenv("STUDY_FAKE_INTERRUPT_AFTER")
    study(scene_file, out, report=False)  # its results, and so its report, are test_study_outputs_are_well_formed's
    rendered = log.read_text().split()
    assert len(rendered) == 4 + 4 * 2 * 2 * 4 + 4 * 2  # the 30 recorded runs were not rendered again
    assert len(set(rendered)) == len(rendered)
    assert_store_clean(out)


def test_interrupted_write_leaves_nothing(tmp_path, monkeypatch):
    store = ResultStore(str(tmp_path / "s"))
    record = {"key": "k", "fingerprint": "f", "job": {}}

    def broken_replace(src, dst):
        raise KeyboardInterrupt  # as if the process were interrupted between writing and renaming

    monkeypatch.setattr(store_module.os, "replace", broken_replace)
    with pytest.raises(KeyboardInterrupt):
        store.write_run(record)
    monkeypatch.undo()
    assert os.listdir(tmp_path / "s" / "runs") == []  # neither the record nor a temporary
    assert not store.is_done("k", "f")
    store.write_run(record)
    assert store.is_done("k", "f") and not store.is_done("k", "other fingerprint")


def test_killed_worker_is_reported_and_others_finish(scene_file, tmp_path, monkeypatch):
    out = tmp_path / "study"
    # Every attempt at one job kills its worker process; the pool is rebuilt, the other jobs finish and the
    # job is reported as failed (not recorded), then succeeds on resume.
    monkeypatch.setenv("STUDY_FAKE_CRASH", "ladder-sphrect-triangles-balance-sobol-n000004")
    summary = study(scene_file, out, executor=LocalProcessPool(2))
    failed = [k for k, _ in summary["failures"]]
    assert any("triangles-balance-sobol-n000004" in k for k in failed)
    assert summary["ladder_runs"] == 4 * 2 * 2 * 4 - len(failed)
    assert_store_clean(out)
    monkeypatch.delenv("STUDY_FAKE_CRASH")
    summary = study(scene_file, out, executor=LocalProcessPool(2))
    assert summary["failures"] == [] and summary["ladder_runs"] == 4 * 2 * 2 * 4
    assert os.listdir(out / "failed") == []


def test_equal_time_counts_for_stratified_are_near_square_grids():
    for n in range(1, 2000):
        m = stratifiable_count(n)
        k = int(round(m ** 0.5 - 0.25))
        assert m <= n and m in (k * k, k * (k + 1)), (n, m)
        assert n - m <= 2 * n ** 0.5 + 1, (n, m)  # loses at most ~2 sqrt(n) samples of the budget
