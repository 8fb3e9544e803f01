"""scripts/render_paper_scene.py at a tiny resolution: it runs and writes its figures, and its MIS row is the
paper's MIS (BSDF samples at the all-diffuse scene's hits), not a copy of the row without MIS."""
import importlib.util
import json
import os

import numpy as np
import pytest

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "render_paper_scene.py")


def load_script():
    spec = importlib.util.spec_from_file_location("render_paper_scene", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_render_paper_scene_writes_figures(tmp_path):
    pytest.importorskip("matplotlib")
    mod = load_script()
    out = str(tmp_path)
    assert mod.main(["--out", out, "--width", "32", "--height", "18", "--samples", "2", "--reference-samples", "16",
                     "--sweep", "1,2"]) == 0
    for name in ["paper_compare.png", "paper_reference.png", "paper_none_area.png", "paper_balance_rectangle.png",
                 "paper_rmse_vs_light_samples.png", "paper_figures.json"]:
        assert os.path.getsize(os.path.join(out, name)) > 0, name
    with open(os.path.join(out, "paper_figures.json")) as f:
        figures = json.load(f)
    assert set(figures["images"]) == {f"{m}/{t}" for m in ("none", "balance") for t in mod.TECHNIQUES}
    assert all(e["rmse"] > 0 and e["samples"] == 2 for e in figures["images"].values())
    assert figures["sweep"]["none"]["light_samples"] == [1, 2]


def test_mis_row_takes_bsdf_samples_on_the_diffuse_scene():
    import sphrect
    mod = load_script()
    scene = mod.paper_scene(32, 18)
    images = {}
    for mis in mod.MIS_MODES:
        r = sphrect.Renderer(scene, techniques=["rectangle"], mis=mis, seed=1,
                             bsdf_samples_on_diffuse=mod.bsdf_samples_on_diffuse(mis))
        r.render(2)
        images[mis] = r.image("rectangle")
    assert mod.bsdf_samples_on_diffuse("balance") and not mod.bsdf_samples_on_diffuse("none")
    assert not np.array_equal(images["none"], images["balance"])
