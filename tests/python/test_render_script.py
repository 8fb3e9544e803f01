"""Smoke test of scripts/render_paper_scene.py at a tiny resolution: it runs and writes its figures."""
import importlib.util
import json
import os

import pytest

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "render_paper_scene.py")


def test_render_paper_scene_writes_figures(tmp_path):
    pytest.importorskip("matplotlib")
    spec = importlib.util.spec_from_file_location("render_paper_scene", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
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
