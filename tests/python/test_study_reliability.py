"""The study under bad input and faults (issue 15): every option is checked before anything renders and named in
the message; every MIS mode and every pattern alone gives a report; a damaged file in the output folder is
reported and recomputed on the next run; killing the study's process with -9 leaves no worker running; a second
study of the same folder is refused, and one restarted after a kill waits for the earlier workers."""
import fcntl
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest

import sphrect
from sphrect.study import SerialExecutor, cli
from sphrect.study.lock import STUDY_LOCK, WORKERS_LOCK, StudyBusy, StudyLock
from test_study import H, W, fake_render, scene_file, study  # noqa: F401 (fixture; the hook's module)
from test_study_render import paper_like_scene

pytestmark = pytest.mark.study

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture
def real_scene(tmp_path):
    path = str(tmp_path / "tiny.sphrect.npz")
    sphrect.save_scene(paper_like_scene(8, 6), path)
    return path


QUICK = ["--max-samples", "2", "--reference-samples", "16", "--reference-chunks", "2", "--cycles", "off",
         "--workers", "1", "--no-sampler-table", "--quiet"]


@pytest.mark.parametrize("options, named", [
    (["--seed", "-1"], "--seed"),
    (["--seed", str(2 ** 64)], "--seed"),
    (["--equal-time", "-1"], "--equal-time"),
    (["--equal-time", "nan"], "--equal-time"),
    (["--equal-time", "0"], "--equal-time"),
    (["--resolution", "32768x32768"], "--resolution"),
    (["--light-samples", "0"], "--light-samples"),
    (["--light-samples", "100000"], "--light-samples"),
    (["--threads", "-1"], "--threads"),
    (["--workers", "0"], "--workers"),
    (["--workers", "-3"], "--workers"),
    (["--max-samples", "0"], "--max-samples"),
    (["--max-samples", str(2 ** 21)], "--max-samples"),
    (["--min-samples", "4", "--max-samples", "2"], "--min-samples"),
    (["--reference-samples", "1"], "--reference-samples"),
    (["--reference-samples", "0"], "--reference-samples"),
    (["--reference-chunks", "1"], "--reference-chunks"),
    (["--reference-technique", "rect"], "--reference-technique"),
    (["--reference-mis", "always"], "--reference-mis"),
    (["--reference-pattern", "halton"], "--reference-pattern"),
    (["--target-rmse", "-1"], "--target-rmse"),
    (["--mis", "none,bogus"], "--mis"),
    (["--grid-pattern", "halton"], "--grid-pattern"),
])
def test_bad_options_are_refused_before_anything_renders(real_scene, tmp_path, capsys, options, named):
    out = tmp_path / "out"
    base = list(QUICK)
    if "--max-samples" in options:  # the option under test replaces the quick one
        i = base.index("--max-samples")
        del base[i:i + 2]
    assert cli.main([real_scene, "--out", str(out), *base, *options]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {named}: "), err
    assert not (out / "runs").exists()  # nothing rendered, nothing written


def test_a_missing_scene_and_a_file_as_out_are_refused(tmp_path, capsys):
    assert cli.main([str(tmp_path / "none.sphrect.npz"), "--out", str(tmp_path / "o"), *QUICK]) == 2
    assert capsys.readouterr().err.startswith("error: scene: ")
    (tmp_path / "file").write_text("x")
    assert cli.main([str(tmp_path / "none.sphrect.npz"), "--out", str(tmp_path / "file"), *QUICK]) == 2
    assert capsys.readouterr().err.startswith("error: --out: ")


@pytest.mark.parametrize("options", [["--mis", m] for m in sphrect.mis_modes]
                         + [["--patterns", p] for p in sphrect.patterns])
def test_each_mis_mode_and_each_pattern_alone_gives_a_report(real_scene, tmp_path, options):
    """On the real renderer. Before the fix of the equal-time budget's MIS mode, --mis none or power alone rendered
    the whole ladder and then stopped with 'no ladder run measured'."""
    out = tmp_path / "out"
    assert cli.main([real_scene, "--out", str(out), "--techniques", "area,rectangle", *QUICK, *options]) == 0
    report = (out / "report.md").read_text()
    assert "Equal time" in report or "equal_time_grid.png" in report
    assert any(name.startswith("equal_time-") for name in os.listdir(out / "images"))


# -- damaged files ------------------------------------------------------------------------------------------------

def _files_read_back(out):
    """Every file a rerun reads back (one of each kind)."""
    runs = sorted(os.listdir(out / "runs"))
    images = sorted(os.listdir(out / "images"))
    return ["config.json", "state.json", "reference.json", "images/reference.npy",
            "runs/" + next(n for n in runs if n.startswith("ladder-")),
            "runs/" + next(n for n in runs if n.startswith("reference-")),
            "runs/" + next(n for n in runs if n.startswith("equal_time-")),
            "images/" + next(n for n in images if n.startswith("reference-")),
            "images/" + next(n for n in images if n.startswith("equal_time-"))]


# The damage tests' study: every kind of file a rerun reads back, in a smaller study than test_study's tiny one
# (two techniques, one MIS mode and pattern) since each of their 27 reruns writes the report, whose plots cost
# most of a rerun; the whole tiny study's report is test_study.py's.
DAMAGE_STUDY = dict(techniques=("area", "rectangle"), mis=("balance",), patterns=("sobol",))


@pytest.fixture(scope="module")
def studied(tmp_path_factory):
    """(scene file, folder of a finished DAMAGE_STUDY of it), made once for the module: tests damage a copy."""
    root = tmp_path_factory.mktemp("studied")
    scene = str(root / "tiny.sphrect.npz")
    sphrect.save_scene(sphrect.Scene(camera=sphrect.Camera(width=W, height=H)), scene)  # test_study's scene_file
    study(scene, root / "out", **DAMAGE_STUDY)
    return scene, root / "out"


def copy_of_study(studied, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(studied[1], out)
    return out


@pytest.mark.parametrize("damage", ["truncated", "empty", "garbage"])
def test_a_damaged_file_is_reported_and_recomputed(studied, tmp_path, monkeypatch, capfd, damage):
    scene, out = studied[0], copy_of_study(studied, tmp_path)
    log = tmp_path / "renders.log"
    monkeypatch.setenv("STUDY_FAKE_LOG", str(log))
    for name in _files_read_back(out):
        path = out / name
        whole = path.read_bytes()
        path.write_bytes({"truncated": whole[:len(whole) // 2], "empty": b"", "garbage": b"[1, 2"}[damage])
        capfd.readouterr()
        log.write_text("")
        summary = study(scene, out, **DAMAGE_STUDY)  # completes
        err = capfd.readouterr().err
        assert summary["failures"] == [] and (out / "report.md").exists(), name
        assert f"damaged file {path}" in err or name in ("config.json",), (name, err)
        if name.endswith(".npy"):
            assert np.load(path).shape == (12, 16, 4), name  # recomputed, whole
        elif name != "config.json":  # config.json is rewritten by every run, never read first
            assert isinstance(json.loads(path.read_text()), dict), name
        if name.startswith(("runs/", "images/")) and "reference.npy" not in name:
            key = os.path.splitext(os.path.basename(name))[0]
            assert key in log.read_text().split(), name  # the run was redone
        if name != "config.json":
            assert os.listdir(out / "damaged"), name  # set aside, not deleted


def test_report_only_names_a_damaged_file(studied, tmp_path, capsys):
    out = copy_of_study(studied, tmp_path)
    (out / "state.json").write_text("{")
    assert cli.main([studied[0], "--out", str(out), "--report-only"]) == 2
    assert "state.json is missing or damaged" in capsys.readouterr().err


# -- processes ----------------------------------------------------------------------------------------------------

def _children(pid):
    """Pids of the live processes whose parent is `pid` (from /proc)."""
    found = []
    for name in os.listdir("/proc"):
        if name.isdigit():
            try:
                with open(f"/proc/{name}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid and fields[0] != "Z":
                found.append(int(name))
    return found


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_killing_the_study_leaves_no_worker(tmp_path):
    scene = str(tmp_path / "scene.sphrect.npz")
    sphrect.save_scene(paper_like_scene(64, 48), scene)
    out = tmp_path / "out"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    # A reference of 2 x 2^19 samples keeps both workers rendering (in native code) far longer than this test.
    study_process = subprocess.Popen([sys.executable, "-m", "sphrect.study", scene, "--out", str(out),
                                      "--max-samples", "2", "--reference-samples", str(2 ** 20),
                                      "--reference-chunks", "2", "--workers", "2", "--cycles", "off", "--quiet"],
                                     env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    descendants = []
    try:
        deadline = time.monotonic() + 120
        workers = []
        while time.monotonic() < deadline and study_process.poll() is None:
            workers = [p for p in _children(study_process.pid)
                       if b"spawn_main" in open(f"/proc/{p}/cmdline", "rb").read()]
            if len(workers) == 2 and os.path.exists(out / WORKERS_LOCK):
                break
            time.sleep(0.1)
        assert len(workers) == 2, "the study did not start its workers"
        time.sleep(1.0)  # let them start rendering
        descendants = _children(study_process.pid)
        os.kill(study_process.pid, signal.SIGKILL)
        study_process.wait()
        deadline = time.monotonic() + 10  # they end within a second or so; generous for a loaded machine
        while time.monotonic() < deadline and any(_alive(p) for p in descendants):
            time.sleep(0.1)
        assert not [p for p in descendants if _alive(p)], "processes of the killed study still run"
    finally:
        if study_process.poll() is None:
            study_process.kill()
        for p in descendants + _children(study_process.pid):  # whatever survived a failure, not to run on
            if _alive(p):
                os.kill(p, signal.SIGKILL)


def test_a_second_study_of_the_same_folder_is_refused(real_scene, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    with StudyLock(str(out)):
        assert cli.main([real_scene, "--out", str(out), *QUICK]) == 2
        err = capsys.readouterr().err
        assert "is in use by another study" in err and f"pid {os.getpid()}" in err
    assert not (out / "runs").exists()


def test_a_restarted_study_waits_for_the_earlier_workers(scene_file, tmp_path, capfd):
    out = tmp_path / "out"
    out.mkdir()
    # A leftover worker of a killed study holds the workers lock shared, as runner.hold_worker_lock does.
    leftover = os.open(out / WORKERS_LOCK, os.O_RDWR | os.O_CREAT)
    fcntl.flock(leftover, fcntl.LOCK_SH)
    with pytest.raises(StudyBusy, match="worker processes of an earlier study"):
        StudyLock(str(out), wait=0.3).__enter__()
    threading.Timer(1.0, os.close, (leftover,)).start()  # it ends a second later
    capfd.readouterr()
    summary = study(scene_file, out, report=False)  # the report of these results is test_study.py's
    assert summary["failures"] == [] and "waiting for the worker processes" in capfd.readouterr().err
    assert (out / STUDY_LOCK).exists()


def failing_ladder_render(context, job):
    """The fake renderer, but every ladder run raises (as every run did with a negative seed)."""
    if job.kind == "ladder":
        raise RuntimeError("this ladder run fails")
    return fake_render(context, job)


def test_a_study_whose_ladder_runs_all_fail_still_writes_its_report(scene_file, tmp_path, capfd):
    from sphrect.study import ReferenceSettings, run_study
    from test_study import tiny_config
    out = tmp_path / "out"
    summary = run_study(scene_file, str(out), tiny_config(equal_time=None), ReferenceSettings(samples=256, chunks=2),
                        executor=SerialExecutor(), render_hook="test_study_reliability:failing_ladder_render",
                        progress=False, sampler_table=False)
    assert len(summary["failures"]) == len(os.listdir(out / "failed")) > 0 and summary["equal_time_runs"] == 0
    assert "equal-time renders skipped" in capfd.readouterr().err
    assert (out / "report.md").exists()


# -- issue 27: scenes that cannot be built, warnings, texture paths -----------------------------------------------

def study_command(scene, out, *options):
    """scripts/study.py as a user runs it, in a subprocess: its exit status and stderr as they are."""
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(sphrect.__file__)))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), SPHRECT_PYTHON_PATH=package_root)
    return subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "study.py"), scene, "--out", str(out),
                           *QUICK, *options], env=env, capture_output=True, text=True, timeout=300)


def nan_radiance_scene(folder):
    scene = paper_like_scene(8, 6)
    scene.lights[0].radiance = (float("nan"), 1.0, 1.0)
    path = str(folder / "nan.sphrect.npz")
    sphrect.save_scene(scene, path)
    return path


def truncated_blend(folder):
    path = str(folder / "truncated.blend")
    with open(os.path.join(ROOT, "blend_scenes", "01_paper.blend"), "rb") as f:
        content = f.read()
    with open(path, "wb") as f:
        f.write(content[:len(content) // 2])
    return path


@pytest.mark.parametrize("make_scene", [nan_radiance_scene, truncated_blend])
def test_a_scene_that_cannot_be_built_is_refused_before_any_job(tmp_path, make_scene):
    # Every reference chunk was rendered, and failed, then a traceback and exit status 1 (the NaN radiance), or a
    # traceback at once (the .blend Blender cannot read; issue 27): now the scene is read and built once, first.
    scene, out = make_scene(tmp_path), tmp_path / "out"
    run = study_command(scene, out)
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    errors = [line for line in run.stderr.splitlines() if line.startswith("error")]
    assert len(errors) == 1 and run.stderr.splitlines()[-1] == errors[0], run.stderr
    assert errors[0].startswith(f"error: scene: {scene}: ") and (
        "radiance must be finite" in errors[0] or "Blender could not export it" in errors[0]), errors[0]
    assert not (out / "runs").exists()  # no job ran


# A study of one configuration on the real renderer, as small as a report allows.
ONE_CONFIGURATION = ["--techniques", "rectangle", "--mis", "balance", "--patterns", "sobol", "--grid-mis", "balance"]


def textured_scene(texture, material=None):
    """test_render_textures' lit plane of 8x6 pixels, its base colour from `texture`."""
    from test_render_textures import lit_scene
    material = material or sphrect.Material(textures={"base_color": sphrect.TextureLookup(0)})
    return lit_scene(material, [texture], width=8, height=6)


def test_every_warning_of_a_study_is_in_its_report(tmp_path):
    # A missing image rendered magenta, warned on the workers' stderr alone: the study exited 0 and its report
    # said nothing (issue 27).
    scene = str(tmp_path / "missing.sphrect.npz")
    sphrect.save_scene(textured_scene(sphrect.Texture(name="gone", path=str(tmp_path / "gone.png"))), scene)
    out = tmp_path / "out"
    assert cli.main([scene, "--out", str(out), *QUICK, *ONE_CONFIGURATION]) == 0
    report = (out / "report.md").read_text()
    assert "image 'gone'" in report and "magenta" in report and "the scene check and " in report, report[:3000]


def mirror_scene():
    """A near mirror (roughness 0.03: a rough lobe the light samples see, not a singular one) under a light so
    bright that some of rectangle_cosine's samples on it overflow float."""
    mirror = textured_scene(sphrect.Texture(pixels=np.full((1, 1, 3), 200, np.uint8)),
                            sphrect.Material(kind="principled", roughness=0.03, metallic=1.0))
    mirror.lights[0].radiance = (3e37,) * 3
    return mirror


def test_a_study_whose_runs_drop_samples_says_so_in_its_report(tmp_path):
    # Non-finite samples were left out of the images in silence, but for stats()['dropped_samples'] (issue 27).
    scene = str(tmp_path / "mirror.sphrect.npz")
    sphrect.save_scene(mirror_scene(), scene)
    out = tmp_path / "out"
    assert cli.main([scene, "--out", str(out), *QUICK, *ONE_CONFIGURATION, "--techniques", "rectangle_cosine"]) == 0
    assert "samples were not finite (NaN or infinite) and were left out of the image" in (out / "report.md").read_text()
    records = [json.loads((out / "runs" / name).read_text()) for name in os.listdir(out / "runs")]
    assert any(r["dropped_samples"] > 0 for r in records)


def green_image_scene(folder):
    """A scene file in `folder` reading a green image beside it by the relative path 'green.ppm'."""
    from test_render_textures import write_ppm
    write_ppm(folder / "green.ppm", np.tile(np.array([0, 255, 0], np.uint8), (2, 2, 1)))
    path = str(folder / "green.sphrect.npz")
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        sphrect.save_scene(textured_scene(sphrect.Texture(path="green.ppm")), path)
    finally:
        os.chdir(cwd)
    return path


def test_a_study_run_from_elsewhere_reads_the_scene_files_images(tmp_path, monkeypatch):
    # The relative path was read from the study's current directory: magenta (issue 27).
    (tmp_path / "scene").mkdir()
    (tmp_path / "elsewhere").mkdir()
    scene = green_image_scene(tmp_path / "scene")
    monkeypatch.chdir(tmp_path / "elsewhere")
    out = tmp_path / "out"
    assert cli.main([scene, "--out", str(out), *QUICK, *ONE_CONFIGURATION]) == 0
    reference = np.load(out / "images" / "reference.npy")
    assert reference[..., 1].mean() > 0 and not reference[..., 0].any()  # green, not magenta
    assert "magenta" not in (out / "report.md").read_text()


def test_a_worker_reads_its_copies_of_the_scene_and_its_images(tmp_path, monkeypatch):
    # A Dask worker reads a copy of the scene file in a folder of its own (shared_files.py): a relative texture path
    # is resolved against the study's scene folder, and the image read from the worker's copy of it too.
    from sphrect.study import runner, shared_files
    from sphrect.study.jobs import Job
    (tmp_path / "scene").mkdir()
    scene = green_image_scene(tmp_path / "scene")
    context = runner.RunContext(store_root=str(tmp_path / "out"), scene_path=scene, width=8, height=6,
                                fingerprint="", texture_files=runner.scene_texture_files(sphrect.load_scene(scene)))
    assert context.texture_files == (str(tmp_path / "scene" / "green.ppm"),)
    monkeypatch.setattr(shared_files, "_copies", {})
    monkeypatch.setattr(runner, "_scene_cache", {})
    shared_files.use_copies(shared_files.read_files(runner.job_files(context, [])), str(tmp_path / "worker"))
    shutil.rmtree(tmp_path / "scene")  # the study's folder is not on the worker's machine
    monkeypatch.chdir(tmp_path / "worker")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no missing image
        image, _ = runner.render_sphrect(context, Job("sphrect", "rectangle", "balance", "sobol", 2))
    assert image[..., 1].mean() > 0 and not image[..., 0].any()


def test_the_exporters_warnings_are_in_the_report(scene_file, tmp_path):
    # A .blend's exporter warnings were kept in config.json, but the report did not show them (issue 27).
    from sphrect.study.report import write_report
    out = tmp_path / "out"
    study(scene_file, out, report=False, **DAMAGE_STUDY)
    config = json.loads((out / "config.json").read_text())
    config["exporter_warnings"] = "SPHRECT does not support, ignored: particle hair (Cube)"  # as export_blend gives
    (out / "config.json").write_text(json.dumps(config))
    write_report(str(out), sampler_table=False)
    assert "- SPHRECT does not support, ignored: particle hair (Cube) (the exporter)" in (out / "report.md").read_text()
