"""The study on the real renderer (and Cycles, when Blender is installed), on a tiny scene and ladder:
outputs exist and are well-formed, the reference's error estimate is computed and is well under the errors
measured, and a Cycles render of a .blend comes back as a linear image with its timings."""
import csv
import json
import math
import os
import shutil

import numpy as np
import pytest

import sphrect
from sphrect.study import LocalProcessPool, ReferenceSettings, StudyConfig, run_study

pytestmark = pytest.mark.study

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PAPER_BLEND = os.path.join(ROOT, "blend_scenes", "01_paper.blend")
BLENDER_SCRIPT = os.path.join(ROOT, "addon", "sphrect_blender", "headless.py")  # the add-on's headless entry


def paper_like_scene(width=24, height=16):
    """A ground plane lit by a one-sided rectangle perpendicular to it, close to it (the paper's setup)."""
    ground = sphrect.Mesh(vertices=np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], np.float32),
                          triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32))
    light = sphrect.RectLight(corner=(-1.0, 0.0, 0.05), edge_x=(2.0, 0.0, 0.0), edge_y=(0.0, 0.0, 0.6),
                              radiance=(5.0, 5.0, 5.0), two_sided=True, visible=False)
    # Camera 4 units back and 3 up, looking at the origin (Blender camera: looks down -Z, +Y up).
    eye = np.array([0.0, -4.0, 3.0])
    forward = -eye / np.linalg.norm(eye)
    right = np.cross(forward, [0, 0, 1])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    to_world = np.eye(4)
    to_world[:3, 0], to_world[:3, 1], to_world[:3, 2], to_world[:3, 3] = right, up, -forward, eye
    return sphrect.Scene(camera=sphrect.Camera(width=width, height=height, to_world=to_world.tolist(), lens=35),
                         meshes=[ground], lights=[light])


def test_study_on_the_renderer(tmp_path):
    scene_path = str(tmp_path / "paper_like.sphrect.npz")
    sphrect.save_scene(paper_like_scene(), scene_path)
    out = tmp_path / "study"
    config = StudyConfig(techniques=("area", "rectangle"), mis=("none", "balance"), patterns=("independent",
                         "stratified"), ladder=(1, 2, 4, 8), grid_mis=("none",), grid_pattern="stratified")
    summary = run_study(scene_path, str(out), config, ReferenceSettings(samples=2048, chunks=4),
                        executor=LocalProcessPool(2), progress=False, sampler_table=False)
    assert summary["failures"] == []
    assert summary["ladder_runs"] == 2 * 2 * 2 * 4 and summary["equal_time_runs"] == 2
    reference = json.load(open(out / "reference.json"))
    assert 0 < reference["estimated_rmse"] < math.inf
    with open(out / "runs.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["kind"] == "ladder"]
    for r in rows:
        assert r["finite"] == "True"
        assert float(r["wall_time"]) > 0 and int(r["rays"]) > 0 and float(r["light_time"]) > 0
        assert float(r["build_time"]) >= 0 and int(r["samples_done"]) == int(r["samples"])
        assert 0 < float(r["rmse"]) < math.inf and 0 < float(r["relmse"]) < math.inf
    # The reference (2048 spp) is far more converged than any run (<= 8 spp).
    smallest = min(float(r["rmse"]) for r in rows)
    assert reference["estimated_rmse"] < 0.5 * smallest
    # More samples, less error: each curve falls from 1 to 8 spp.
    by = {(r["technique"], r["mis"], r["pattern"], int(r["samples"])): float(r["rmse"]) for r in rows}
    for t in ("area", "rectangle"):
        for m in ("none", "balance"):
            for p in ("independent", "stratified"):
                assert by[(t, m, p, 8)] < by[(t, m, p, 1)], (t, m, p)
    report = (out / "report.md").read_text()
    assert "rmse_vs_samples_stratified.png" in report and "equal_time_grid.png" in report
    for png in os.listdir(out / "plots"):
        assert (out / "plots" / png).read_bytes()[:4] == b"\x89PNG"


def test_study_of_both_light_selections_from_the_command_line(tmp_path):
    """The command line with the add-on's defaults (4 light samples, MIS power, sobol) and both light selections,
    on the rectangle plus more point lights than stay beside the tree: both are rendered (the renderer gets the job's
    selection: with the tree a point light is one of the tree's emitters, with power it is evaluated on every sample,
    so the images differ), every run is finite and converges, and the report compares them."""
    from sphrect.study import cli
    scene = paper_like_scene()
    scene.lights += [sphrect.PointLight(position=(1.5, 1.0, 1.2), intensity=(2.0, 2.0, 2.0)),
                     sphrect.PointLight(position=(-1.5, 0.5, 0.8), intensity=(0.5, 0.5, 0.5))]
    # More point lights than stay beside the tree, so that the tree chooses among them.
    scene.lights += [sphrect.PointLight(position=(-2.0 + 0.5 * i, -1.5, 1.0), intensity=(0.1, 0.1, 0.1))
                     for i in range(sphrect.MAX_DELTA_LIGHTS_BESIDE_TREE - 1)]
    scene_path = str(tmp_path / "lights.sphrect.npz")
    sphrect.save_scene(scene, scene_path)
    out = tmp_path / "study"
    assert cli.main([scene_path, "--out", str(out), "--techniques", "rectangle", "--mis", "power", "--patterns",
                     "sobol", "--light-samples", "4", "--light-selections", "power,tree", "--max-samples", "8",
                     "--reference-samples", "1024", "--reference-chunks", "4", "--grid-mis", "power",
                     "--grid-pattern", "sobol", "--workers", "2", "--no-sampler-table", "--quiet"]) == 0
    with open(out / "runs.csv") as f:
        rows = list(csv.DictReader(f))
    ladder = {(r["light_selection"], int(r["samples"])): r for r in rows if r["kind"] == "ladder"}
    assert set(ladder) == {(s, n) for s in ("power", "tree") for n in (1, 2, 4, 8)}
    for r in rows:
        assert r["finite"] == "True" and int(r["light_samples"]) == 4 and 0 < float(r["rmse"]) < math.inf
    for s in ("power", "tree"):
        assert float(ladder[(s, 8)]["rmse"]) < float(ladder[(s, 1)]["rmse"]), s
    assert ladder[("power", 1)]["rmse"] != ladder[("tree", 1)]["rmse"]
    images = [np.load(out / "images" / f"{r['key']}.npy") for r in rows if r["kind"] == "equal_time"]
    assert len(images) == 2 and not np.array_equal(images[0], images[1])
    report = (out / "report.md").read_text()
    assert "rectangle / mis=power / sobol / selection=tree" in report and "tree takes **" in report


def test_a_job_renders_with_its_ris_candidates(tmp_path):
    """The runner hands a job's RIS candidates to the renderer: "ris" with one candidate is the tree's image (up to
    rounding), with the default four another estimate of it."""
    from sphrect.study.jobs import Job
    from sphrect.study.runner import RunContext, render_sphrect
    scene_path = str(tmp_path / "paper_like.sphrect.npz")
    sphrect.save_scene(paper_like_scene(), scene_path)
    context = RunContext(store_root=str(tmp_path), scene_path=scene_path, width=24, height=16, fingerprint="")
    image = {}
    for selection, candidates in (("tree", 1), ("ris", 1), ("ris", 4)):
        job = Job("sphrect", "rectangle", "power", "sobol", 8, 2, light_selection=selection,
                  ris_candidates=candidates)
        image[selection, candidates] = render_sphrect(context, job)[0]
    assert np.allclose(image["ris", 1], image["tree", 1], rtol=1e-4, atol=1e-6)
    assert not np.allclose(image["ris", 4], image["tree", 1], rtol=1e-3, atol=1e-4)


@pytest.mark.skipif(shutil.which("blender") is None or not os.path.exists(PAPER_BLEND),
                    reason="needs Blender and blend_scenes/01_paper.blend")
def test_cycles_render_of_a_blend():
    from sphrect.study.cycles import render_cycles
    image, timing = render_cycles(PAPER_BLEND, 4, 32, 18, seed=0, threads=1, blender_script=BLENDER_SCRIPT)
    assert image.shape == (18, 32, 4) and image.dtype == np.float32
    assert np.all(np.isfinite(image)) and image[..., :3].max() > 0
    assert timing["samples_done"] == 4 and timing["timing_source"] == "cycles status"
    assert 0 < timing["wall_time"] <= timing["operator_time"] + 0.01
    assert timing["blender_version"].startswith("3.")


@pytest.mark.skipif(shutil.which("blender") is None or not os.path.exists(PAPER_BLEND),
                    reason="needs Blender and blend_scenes/01_paper.blend")
def test_study_of_a_blend_with_cycles(tmp_path):
    out = tmp_path / "study"
    config = StudyConfig(techniques=("rectangle",), mis=("balance",), patterns=("stratified",), ladder=(1, 4),
                         grid_mis=("balance",), grid_pattern="stratified", cycles=True, equal_time=0.02)
    summary = run_study(PAPER_BLEND, str(out), config, ReferenceSettings(samples=256, chunks=4),
                        resolution=(32, 18), executor=LocalProcessPool(2), progress=False, sampler_table=False,
                        blender_script=BLENDER_SCRIPT)
    assert summary["failures"] == []
    assert summary["ladder_runs"] == 2 + 2 and summary["equal_time_runs"] == 2
    assert os.path.exists(out / "scene.sphrect.npz")
    with open(out / "runs.csv") as f:
        cycles = [r for r in csv.DictReader(f) if r["engine"] == "cycles"]
    assert len(cycles) == 3
    for r in cycles:
        assert float(r["wall_time"]) > 0 and 0 < float(r["rmse"]) < math.inf
    report = (out / "report.md").read_text()
    assert "Cycles 3.4" in report and "time ratio (ours/Cycles)" in report


def test_cost_model_and_sweep_on_the_renderer(tmp_path):
    """The report's cost-model section on real runs (the terms from the renderer's timers), and the sweep: the scene
    subdivided (16x the triangles at level 2) and a shading cost added, each configuration rendered again, the
    predicted and measured ratios written for every pair."""
    from sphrect.study.sweep import run_sweep
    scene_path = str(tmp_path / "paper_like.sphrect.npz")
    sphrect.save_scene(paper_like_scene(), scene_path)
    out = tmp_path / "study"
    config = StudyConfig(techniques=("area", "rectangle"), mis=("power",), patterns=("sobol",), ladder=(1, 2, 4, 8),
                         grid_mis=("power",), grid_pattern="sobol")
    run_study(scene_path, str(out), config, ReferenceSettings(samples=512, chunks=2), executor=LocalProcessPool(1),
              progress=False, sampler_table=False)
    report = (out / "report.md").read_text()
    assert "What a sample costs" in report and "relative_efficiency.png" in report
    assert "| rectangle / mis=power / sobol | area / mis=power / sobol |" in report
    path = run_sweep(str(out), geometry_levels=(0, 2), shading_costs=(0.0, 1e-6), repeats=1, ray_costs=(0.0, 1e-6))
    sweep = json.load(open(os.path.join(os.path.dirname(path), "sweep.json")))
    geometry = sweep["geometry"]["levels"]
    assert geometry[1]["triangles"] == 16 * geometry[0]["triangles"]
    assert all(len(lv["costs"]) == 2 and all(c > 0 for c in lv["costs"].values()) for lv in geometry)
    (pair,) = sweep["added shading cost"]["pairs"]
    assert pair["b"] == "rectangle / mis=power" and len(pair["measured"]) == len(pair["predicted"]) == 2
    assert len(sweep["added ray cost"]["levels"]) == 2
    assert os.path.exists(os.path.join(os.path.dirname(path), "sweep.png"))
    # The study's report, written again, summarises the sweep.
    from sphrect.study.report import write_report
    write_report(str(out), sampler_table=False)
    assert "against a sweep of this scene's cost" in (out / "report.md").read_text()
