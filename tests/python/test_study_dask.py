"""The study and split renders on a real Dask cluster on this machine (dask_cluster.py: a `dask scheduler` and two
`dask worker` processes on 127.0.0.1, or the executor's own local cluster): a split render is bit-identical to a
local render of the same sample ranges, and survives the death of the only worker holding its scene; a study gives
the records the local pool gives; a worker killed in the middle of a study, a job that kills every worker and an
interrupted client all leave every record whole and once; a worker 2x slower than the other changes no verdict; a
worker of another build refuses jobs."""
import contextlib
import csv
import json
import os
import signal
import threading
import time

import numpy as np
import pytest

import sphrect
from dask_cluster import dask_cluster, worker_pids
from sphrect.build import BuildMismatch
from sphrect.distributed import WorkersLost
from sphrect.study import LocalProcessPool, ReferenceSettings, SerialExecutor, StudyConfig, run_study
from sphrect.study import dask_executor, study as study_module
from sphrect.study.cli import main as study_main
from sphrect.study.dask_executor import DaskExecutor
from sphrect.study.jobs import build_plan
from sphrect.study.machines import SLOWDOWN_ENV, judged_times
from sphrect.study.reference import REFERENCE_IMAGE, SEED_BASE
from sphrect.study.report.equal_error import ellipse_comparisons, selection_comparisons
from sphrect.study.report.results import curves, load_study
from sphrect.study.shared_files import local_path
from sphrect.study.store import ResultStore
from test_study import assert_store_clean, scene_file, study, tiny_config  # noqa: F401  (scene_file: a fixture)
from test_study_render import paper_like_scene

pytestmark = [pytest.mark.study, pytest.mark.cluster]

FAKE_SLEEP = "0.05"  # seconds per fake render on the shared cluster's workers: a study lasts long enough to kill one


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    with dask_cluster(tmp_path_factory.mktemp("cluster"), worker_envs=({"STUDY_FAKE_SLEEP": FAKE_SLEEP},) * 2) as c:
        yield c


@pytest.mark.parametrize("pattern", ["stratified", "sobol"])
def test_split_render_is_bit_identical_to_a_local_render(cluster, pattern):
    _, client = cluster
    scene = paper_like_scene(24, 16)
    options = dict(techniques=["area", "rectangle"], pattern=pattern, mis="balance", light_samples=2, seed=7,
                   threads=1)
    for parts in (1, 2, 3, 5):
        split = sphrect.render_distributed(scene, 13, client=client, parts=parts, **options)
        local = sphrect.render(scene, 13, parts=parts, **options)
        assert list(split) == ["area", "rectangle"]
        for t in split:
            assert split[t].dtype == np.float32 and split[t].shape == (16, 24, 4)
            assert np.array_equal(split[t], local[t]), (pattern, parts, t)
    # By default one part per worker (2).
    split = sphrect.render_distributed(scene, 13, client=client, **options)
    assert all(np.array_equal(split[t], img) for t, img in sphrect.render(scene, 13, parts=2, **options).items())
    if pattern == "sobol":  # one sequence across passes: any split is the single render up to rounding of the sums
        whole = sphrect.render(scene, 13, **options)
        for t in split:
            assert not np.array_equal(split[t], sphrect.render(scene, 13, parts=2, **dict(options, seed=8))[t])
            np.testing.assert_allclose(split[t], whole[t], rtol=1e-5, atol=1e-6)


def kill_once_a_part_is_on(client, pid):
    """Kill the worker process `pid` as soon as the scheduler has given it a part of a split render."""
    deadline = time.monotonic() + 60
    while not any(key.startswith("_render_part") for keys in client.processing().values() for key in keys):
        assert time.monotonic() < deadline, "no part reached the worker"
        time.sleep(0.02)
    os.kill(pid, signal.SIGKILL)


SPLIT_SCENE, SPLIT_SAMPLES = paper_like_scene(32, 24), 4096  # about a second a part on one thread
SPLIT_OPTIONS = dict(techniques=["rectangle"], pattern="sobol", threads=1, seed=5)


@contextlib.contextmanager
def render_killing_the_worker(tmp_path):
    """render_distributed of SPLIT_SCENE in 2 parts on a cluster of one worker, killed once a part is on it (its
    nanny starts another): (the images, the client, the victim's pid), the cluster running."""
    with dask_cluster(tmp_path, worker_envs=({},)) as (_, client):
        (victim,) = worker_pids(client).values()
        killer = threading.Thread(target=kill_once_a_part_is_on, args=(client, victim))
        killer.start()
        try:
            yield sphrect.render_distributed(SPLIT_SCENE, SPLIT_SAMPLES, client=client, parts=2, **SPLIT_OPTIONS), \
                client, victim
        finally:
            killer.join()


@pytest.mark.slow
def test_a_split_render_survives_the_death_of_the_worker_holding_its_scene(tmp_path):
    # The only worker holds the scattered scene; killed while it renders, it took the scene with it: a bare
    # CancelledError: _render_part-<uuid> (issue 27). Now the scene is sent again and the parts rerun.
    with render_killing_the_worker(tmp_path) as (split, client, victim):
        assert victim not in worker_pids(client).values()  # the parts were rendered by the new worker
    expected = sphrect.render(SPLIT_SCENE, SPLIT_SAMPLES, parts=2, **SPLIT_OPTIONS)
    assert np.array_equal(split["rectangle"], expected["rectangle"])


@pytest.mark.slow
def test_a_split_render_whose_scene_is_lost_too_often_says_so(tmp_path, monkeypatch):
    monkeypatch.setattr(sphrect.distributed, "SCENE_SENDS", 1)  # the first loss is one too many
    with pytest.raises(WorkersLost, match="the scene was sent to the workers 1 time, and each time every worker "
                                          "holding it died before 2 of the 2 parts were rendered: see the workers"):
        with render_killing_the_worker(tmp_path):
            pass


def test_a_split_render_reads_the_image_the_client_names(cluster, tmp_path, monkeypatch):
    # A relative texture path was read from each worker's current directory: magenta there (issue 27).
    from test_render_textures import write_ppm
    from test_study_reliability import textured_scene
    _, client = cluster
    write_ppm(tmp_path / "green.ppm", np.tile(np.array([0, 255, 0], np.uint8), (2, 2, 1)))
    monkeypatch.chdir(tmp_path)  # the client's, not the workers'
    image = sphrect.render_distributed(textured_scene(sphrect.Texture(path="green.ppm")), 2, client=client)
    assert image["rectangle"][..., 1].mean() > 0 and not image["rectangle"][..., 0].any()  # green, not magenta


def test_a_split_render_warns_the_workers_warnings(cluster):
    # Samples left out as not finite were warned on the worker alone, in its log (issue 27).
    from test_study_reliability import mirror_scene
    _, client = cluster
    with pytest.warns(RuntimeWarning, match="samples were not finite"):
        sphrect.render_distributed(mirror_scene(), 2, client=client, techniques="rectangle_cosine")


def test_a_worker_of_another_build_refuses_the_job(cluster):
    _, client = cluster
    with pytest.raises(BuildMismatch, match="build"):
        client.submit(dask_executor._run_checked, len, "0" * 16, "job", pure=False).result(timeout=60)
    assert client.submit(dask_executor._run_checked, len, sphrect.build_hash(), "job",
                         pure=False).result(timeout=60) == 3


def test_study_on_the_cluster_gives_the_local_pools_records(cluster, tmp_path):
    address, _ = cluster
    scene_path = str(tmp_path / "paper_like.sphrect.npz")
    sphrect.save_scene(paper_like_scene(), scene_path)
    config = dict(techniques=("area", "rectangle"), mis=("balance",), patterns=("stratified",), ladder=(1, 2, 4),
                  grid_mis=("balance",), equal_time=0.01)
    reference = ReferenceSettings(samples=256, chunks=2)
    runs = {}
    for name, executor in (("local", LocalProcessPool(2)), ("dask", DaskExecutor(scheduler=address))):
        out = tmp_path / name
        summary = run_study(scene_path, str(out), StudyConfig(**config), reference, executor=executor, progress=False,
                            report=False)
        assert summary["failures"] == [] and summary["ladder_runs"] == 2 * 3
        runs[name] = {r["key"]: r for r in ResultStore(str(out)).runs() if r["job"]["kind"] == "ladder"}
        if isinstance(executor, DaskExecutor):
            executor.close()
    assert sorted(runs["dask"]) == sorted(runs["local"]) == sorted(j.key for j in build_plan(StudyConfig(**config)))
    for key, record in runs["dask"].items():
        assert record["rmse"] == runs["local"][key]["rmse"] and record["relmse"] == runs["local"][key]["relmse"]
        machine = record["machine"]
        assert machine["host"] and machine["cpu_model"] and machine["cores"] >= 1 and machine["calibration"] > 0
    # The reference's chunks are the sample ranges of one render, rendered on the workers: it is that render (up to
    # the float32 rounding of the chunks' images).
    single = sphrect.render(paper_like_scene(), reference.samples, techniques=[reference.technique],
                            parts=reference.chunks, light_samples=reference.light_samples, pattern=reference.pattern,
                            mis=reference.mis, seed=SEED_BASE, threads=1)[reference.technique]
    for name in runs:
        image = ResultStore(str(tmp_path / name)).load_image(REFERENCE_IMAGE)
        np.testing.assert_allclose(image, single, rtol=1e-6, atol=1e-7)


def test_a_worker_killed_in_the_middle_of_a_study_loses_nothing(cluster, scene_file, tmp_path):
    address, client = cluster
    out = tmp_path / "study"
    victim = sorted(worker_pids(client).values())[0]

    finished = threading.Event()

    def kill_when_started():
        while not finished.wait(0.02):
            if os.path.isdir(out / "runs") and len(os.listdir(out / "runs")) >= 10:
                os.kill(victim, signal.SIGKILL)
                return

    killer = threading.Thread(target=kill_when_started)
    killer.start()
    try:
        with DaskExecutor(scheduler=address) as executor:
            summary = study(scene_file, out, executor=executor, report=False)
    finally:
        finished.set()
        killer.join()
    with pytest.raises(ProcessLookupError):
        os.kill(victim, 0)  # it was killed mid-study
    assert summary["failures"] == []
    keys = sorted(j.key for j in build_plan(tiny_config()))
    records = [r for r in ResultStore(str(out)).runs() if r["job"]["kind"] == "ladder"]
    assert sorted(r["key"] for r in records) == keys  # every one, once
    assert all(np.isfinite(r["rmse"]) for r in records)
    assert_store_clean(out)
    client.wait_for_workers(2, timeout=60)  # the nanny restarted it, for the next tests


def test_an_interrupted_client_resumes(cluster, scene_file, tmp_path, monkeypatch):
    address, _ = cluster
    out = tmp_path / "study"
    recorded = []
    record_result = study_module.record_result

    def interrupt_after_15(store, record, image):
        if len(recorded) == 15:
            raise KeyboardInterrupt  # Ctrl-C in the client while the cluster renders
        record_result(store, record, image)
        recorded.append(record["key"])

    monkeypatch.setattr(study_module, "record_result", interrupt_after_15)
    with DaskExecutor(scheduler=address) as executor, pytest.raises(KeyboardInterrupt):
        study(scene_file, out, executor=executor, report=False)
    monkeypatch.undo()
    assert_store_clean(out)
    before = {name: os.stat(out / "runs" / name).st_mtime_ns for name in os.listdir(out / "runs")}
    assert len(before) == 15
    with DaskExecutor(scheduler=address) as executor:
        summary = study(scene_file, out, executor=executor, report=False)
    assert summary["failures"] == []
    after = {name: os.stat(out / "runs" / name).st_mtime_ns for name in os.listdir(out / "runs")}
    assert {k: after[k] for k in before} == before  # what was recorded was not run again
    ladder = sorted(r["key"] for r in ResultStore(str(out)).runs() if r["job"]["kind"] == "ladder")
    assert ladder == sorted(j.key for j in build_plan(tiny_config()))
    assert_store_clean(out)


def test_a_job_that_kills_every_worker_fails_and_the_study_finishes(scene_file, tmp_path, monkeypatch):
    crasher = "ladder-sphrect-triangles-balance-sobol-n000004"
    monkeypatch.setenv("STUDY_FAKE_CRASH", crasher)  # in the local cluster's worker processes too
    monkeypatch.setattr(dask_executor, "ALLOWED_FAILURES", 0)  # one death per round, not four: a quicker test
    out = tmp_path / "study"
    with DaskExecutor(workers=2) as executor:
        summary = study(scene_file, out, executor=executor, report=False)
    assert [k for k, _ in summary["failures"]] == [k for k in [j.key for j in build_plan(tiny_config())]
                                                   if crasher in k]
    assert "WorkerCrashed" in summary["failures"][0][1]
    assert summary["ladder_runs"] == len(build_plan(tiny_config())) - 1
    assert_store_clean(out)


def verdicts(out):
    """The report's time-based verdicts: light tree against power, spherical ellipse against area sampling."""
    results = load_study(str(out))
    all_curves = curves(results.ladder)
    comparisons = (selection_comparisons(results.settings, all_curves, results.reference_rmse)
                   + ellipse_comparisons(results.settings, all_curves, results.reference_rmse))
    return [(type(c).__name__, c.verdict) for c in comparisons], results


def test_a_worker_twice_as_slow_changes_no_verdict(scene_file, tmp_path):
    axes = dict(techniques=("area", "rectangle"), mis=("balance",), patterns=("independent",),
                light_selections=("tree", "power"), ellipse_techniques=("spherical_ellipse", "area"))
    study(scene_file, tmp_path / "one", executor=SerialExecutor(), report=False, **axes)
    with dask_cluster(tmp_path, worker_envs=({}, {SLOWDOWN_ENV: "2", "STUDY_FAKE_SLEEP": "0.01"})) as (address, _):
        with DaskExecutor(scheduler=address) as executor:
            study(scene_file, tmp_path / "two", executor=executor, report=False, **axes)
    one, single = verdicts(tmp_path / "one")
    two, mixed = verdicts(tmp_path / "two")
    assert one == two and len(one) == 2 * 2 + 2 * 2
    assert "as measured" in single.time_basis and "normalised" in mixed.time_basis
    # Both workers measured runs: the slow one's raw times are twice the fake renderer's; normalised, the two workers'
    # times agree, up to the calibrations' noise (+-30% on this shared machine).
    calibration = {bool(r["machine"].get("slowdown")): r["machine"]["calibration"] for r in mixed.ladder}
    assert 1.3 < calibration[True] / calibration[False] < 3.0  # 2, and timing noise
    serial = {r["key"]: r for r in single.ladder}
    ratios = {True: [], False: []}  # slow worker -> time / the single-worker study's time
    for r in mixed.ladder:
        slow = bool(r["machine"].get("slowdown"))
        assert r["wall_time"] == pytest.approx(serial[r["key"]]["wall_time"] * (2 if slow else 1))
        ratios[slow].append(r["time"] / serial[r["key"]]["time"])
    assert ratios[True] and ratios[False]
    assert 1 / 1.5 < np.median(ratios[True]) / np.median(ratios[False]) < 1.5


def test_time_basis_is_one_kind_of_machine_or_normalised():
    def run(cpu, calibration, seconds, **extra):
        return {"cpu_time": seconds, "wall_time": seconds,
                "machine": {"host": "h", "cpu_model": cpu, "cores": 8, "calibration": calibration, **extra}}

    # One kind of machine: times as measured, whatever the noise of its workers' calibrations.
    runs = [run("A", 1.0, 3.0), run("A", 1.4, 5.0)]
    basis = judged_times(runs, threads=1)
    assert not basis.normalised and "one kind of machine" in basis.description
    assert [r["time"] for r in runs] == [3.0, 5.0]
    # Two kinds: normalised to the kind with the most runs by each kind's median calibration.
    runs = [run("A", 1.0, 3.0), run("A", 1.2, 3.0), run("A", 1.1, 3.0), run("B", 2.0, 6.0),
            run("A", 1.1, 3.0, slowdown=2)]
    basis = judged_times(runs, threads=1)
    assert basis.normalised and "2 kinds" not in basis.description and "3 kinds of machine" in basis.description
    assert [r["time"] for r in runs] == pytest.approx([3.0, 3.0, 3.0, 3.3, 3.0 * 1.1 / 1.1])
    # Runs recorded before runs said where: as measured.
    assert not judged_times([run("A", 1.0, 3.0), {"cpu_time": 2.0, "wall_time": 2.0}], threads=1).normalised


def test_command_line_runs_the_study_on_a_local_dask_cluster(scene_file, tmp_path, capsys):
    out = tmp_path / "study"
    scene_path = str(tmp_path / "paper_like.sphrect.npz")
    sphrect.save_scene(paper_like_scene(), scene_path)
    assert study_main([scene_path, "--out", str(out), "--executor", "dask-local", "--workers", "2", "--techniques",
                       "rectangle", "--mis", "balance", "--patterns", "stratified", "--grid-mis", "balance",
                       "--max-samples", "2", "--reference-samples", "64", "--reference-chunks", "2", "--equal-time",
                       "0.005", "--no-sampler-table", "--quiet"]) == 0
    assert (out / "report.html").is_file()
    assert json.load(open(out / "config.json"))["executor"] == "DaskExecutor"
    assert "Time basis: times as measured" in (out / "report.md").read_text()
    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    assert rows and all(r["host"] and r["cpu_model"] and int(r["cores"]) >= 1 and float(r["calibration"]) > 0
                        for r in rows)
    # Contradicting options end the study before it starts, naming the option.
    assert study_main([scene_file, "--out", str(tmp_path / "s"), "--executor", "local", "--scheduler",
                       "tcp://127.0.0.1:1"]) == 2
    assert "--scheduler" in capsys.readouterr().err
    assert study_main([scene_file, "--out", str(tmp_path / "s"), "--executor", "dask"]) == 2


def read_shared_file(path):
    """A job reading a file of the study (test_a_worker_reads_the_files_sent_to_it)."""
    with open(local_path(path), "rb") as f:
        return f.read()


def test_a_worker_reads_the_files_sent_to_it(cluster, tmp_path):
    """A worker that cannot see the study's folder (here: a path that exists nowhere) reads the copy sent to it."""
    address, _ = cluster
    absent = str(tmp_path / "elsewhere" / "scene.sphrect.npz")
    present = tmp_path / "here.bin"
    present.write_bytes(b"the study's file")
    with DaskExecutor(scheduler=address) as executor:
        executor.client.wait_for_workers(2, timeout=60)
        # The executor reads the study's files where the study runs; stand in for an absent path with another one.
        executor.client.register_worker_plugin(dask_executor.StudyFiles({absent: b"scene bytes"}),
                                               name=dask_executor.StudyFiles.name)
        results = executor.client.gather([executor.client.submit(dask_executor._run_checked, read_shared_file,
                                                                 sphrect.build_hash(), absent, pure=False)
                                          for _ in range(4)])
        assert results == [b"scene bytes"] * 4
        done = dict(executor.run(read_shared_file, [str(present)], files=[str(present)]))
        assert done == {str(present): b"the study's file"}
