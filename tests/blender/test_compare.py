"""Compare mode: every technique (x light selection x ellipse technique, when several are ticked) as a named pass
(also in multilayer EXR), the comparison image with a reference, equal-time budgets."""
import os
import struct

import bpy
import numpy as np
import pytest

import sphrect
from conftest import addon_module, engine_module, open_blend

TECHNIQUES = list(sphrect.techniques)


def compare_only(settings, *techniques):
    """Tick the compare switches of `techniques` and untick every other technique's."""
    compare_switch = addon_module("properties").compare_switch
    for t in sphrect.techniques:
        setattr(settings, compare_switch(t), t in techniques)


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


def test_compare_equal_samples_with_reference(tmp_path):
    scene = open_blend("01_paper", 32, 24)
    s = scene.sphrect
    s.compare, s.samples, s.passes, s.reference, s.reference_samples = True, 4, 2, "RENDER", 64
    scene.render.filepath = str(tmp_path / "paper_")
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    bpy.ops.render.render(write_still=True)
    rec = engine_module().last_render
    assert rec["errors"] == []
    (exr,) = tmp_path.glob("paper_*.exr")  # paper_.exr (F12 + write_still) or paper_0001.exr (blender -b -f 1)
    header = exr.read_bytes()[:20000]
    for t in TECHNIQUES + ["reference"]:
        assert f"{engine_module().technique_pass_name(t)}.R".encode() in header, t
        assert np.isfinite(rec["images"][t]).all()
    assert rec["comparison"] == str(tmp_path / "paper_0001_sphrect_compare.png")  # next to the output
    width, height = png_size(rec["comparison"])
    assert width > 5 * 32 and height > 2 * 24  # four techniques + reference, images over error maps
    # What the window session does:
    shown = addon_module("engine.display").open_in_image_editor(rec["comparison"])
    assert tuple(shown.size) == (width, height) and shown.name == "SPHRECT Comparison"
    rmse = {t: rec["stats"][t]["rmse"] for t in TECHNIQUES}
    assert all(np.isfinite(v) and v > 0 for v in rmse.values())
    # The paper's point: near a light close to the ground, area sampling is far noisier than spherical
    # rectangle sampling. Fixed seeds, so this is deterministic; it held with a wide margin when written.
    assert rmse["rectangle"] < rmse["area"]
    assert all(rec["stats"][t]["samples"] == 4 for t in TECHNIQUES)


def test_an_unwritable_comparison_path_is_a_warning(tmp_path):
    """The comparison PNG cannot be written (its folder would be inside a regular file, which even root cannot
    create): the render still succeeds with every technique's image and pass, and a warning names the path."""
    scene = open_blend("01_paper", 16, 12)
    s = scene.sphrect
    s.compare, s.samples, s.passes, s.reference = True, 2, 1, "NONE"
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("a file where the output folder should be")
    scene.render.filepath = str(blocker / "paper_")
    bpy.ops.render.render(write_still=False)
    rec = engine_module().last_render
    assert rec["errors"] == [] and not rec["cancelled"]
    assert rec["comparison"] is None
    assert all(np.isfinite(rec["images"][t]).all() and rec["images"][t][..., :3].max() > 0 for t in TECHNIQUES)
    assert any("could not write the comparison image" in w and str(blocker) in w for w in rec["warnings"])


# setting -> (scene, its values as sphrect names, the compare_<setting>s() method): what compare mode can put
# side by side besides the techniques.
SIDE_BY_SIDE = {
    "light_selection": ("07_studio", sphrect.light_selections, "compare_light_selections"),
    "ellipse_technique": ("11_paper_disk", sphrect.ellipse_techniques, "compare_ellipse_techniques"),
}


@pytest.mark.parametrize("setting", sorted(SIDE_BY_SIDE))
def test_compare_settings_side_by_side(tmp_path, setting):
    """Both values of a setting ticked (light selection on a scene of several lights, ellipse technique on a disk
    scene): a pass, an image and a comparison panel per technique x value, named by both; the two values render
    the same camera samples differently. None ticked: the scene's own value, under the technique's own pass
    name."""
    blend, values, chosen = SIDE_BY_SIDE[setting]
    scene = open_blend(blend, 32, 24)
    s = scene.sphrect
    s.compare, s.samples, s.passes, s.reference, s.reference_samples = True, 4, 2, "RENDER", 32
    compare_only(s, "area", "rectangle")
    switch = lambda value: f"compare_{setting}_{value}"
    setattr(s, setting, values[0].upper())
    assert getattr(s, chosen)() == [values[0]]  # nothing ticked: the Sampling panel's value
    for value in values:
        setattr(s, switch(value), True)
    assert getattr(s, chosen)() == list(values)
    entries = [f"{t} {value}" for t in ("area", "rectangle") for value in values]
    scene.use_nodes = True  # the Render Layers node lists the passes the engine declares
    outputs = {o.name for o in scene.node_tree.nodes["Render Layers"].outputs if o.enabled}
    assert {engine_module().technique_pass_name(e) for e in entries} <= outputs, outputs
    scene.render.filepath = str(tmp_path / "compare_")
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    bpy.ops.render.render(write_still=True)
    rec = engine_module().last_render
    assert rec["errors"] == []
    assert set(rec["images"]) == set(entries) | {"reference"}
    (exr,) = tmp_path.glob("compare_*.exr")
    header = exr.read_bytes()[:20000]
    for name in entries + ["reference"]:
        assert f"{engine_module().technique_pass_name(name)}.R".encode() in header, name
    for t in ("area", "rectangle"):
        images = [rec["images"][f"{t} {value}"] for value in values]
        assert all(np.isfinite(image).all() for image in images)
        assert all(not np.array_equal(images[0], other) for other in images[1:]), t
        for value in values:
            stats = rec["stats"][f"{t} {value}"]
            assert stats[setting] == value and stats["samples"] == 4 and np.isfinite(stats["rmse"])
    width, height = png_size(rec["comparison"])
    assert width == 4 + (len(entries) + 1) * (32 + 4)  # the entries and the reference (scale 1, 4 pixels of padding)
    # Unticked again: the scene's value alone, with the pass names of a single value.
    for value in values:
        setattr(s, switch(value), False)
    setattr(s, setting, values[1].upper())
    bpy.ops.render.render(write_still=False)
    rec = engine_module().last_render
    assert set(rec["images"]) == {"area", "rectangle", "reference"}
    assert rec["stats"]["area"][setting] == values[1]
    # Panels for the two techniques alone, and one label line (7 pixels at scale 1) less over images and error maps.
    assert png_size(rec["comparison"]) == (4 + 3 * (32 + 4), height - 2 * 7)


@pytest.mark.parametrize("selections", [(), ("power", "tree")])
def test_compare_equal_time(tmp_path, selections):
    """Each technique (x light selection, when both are ticked) gets the whole time budget."""
    scene = open_blend("02_room", 32, 24)
    s = scene.sphrect
    s.compare, s.equal_time, s.time_budget, s.passes, s.reference = True, True, 0.2, 2, "NONE"
    compare_only(s, "area", "rectangle")
    for name in selections:
        setattr(s, f"compare_light_selection_{name}", True)
    scene.render.filepath = str(tmp_path / "room_")
    bpy.ops.render.render(write_still=False)
    rec = engine_module().last_render
    assert rec["errors"] == []
    entries = [f"{t} {sel}" if selections else t for t in ("area", "rectangle") for sel in selections or ("",)]
    assert set(rec["images"]) == set(entries)
    for name in entries:
        assert rec["stats"][name]["samples"] >= 1
        assert rec["stats"][name]["time"] >= 0.9 * 0.2  # each entry had (at least) the whole budget
        assert "rmse" not in rec["stats"][name]
    assert os.path.isfile(rec["comparison"])


def test_compare_with_reference_exr(tmp_path):
    scene = open_blend("02_room", 32, 24)
    s = scene.sphrect
    s.samples, s.passes = 16, 1
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    scene.render.filepath = str(tmp_path / "ref.exr")
    bpy.ops.render.render(write_still=True)
    reference = engine_module().last_render["images"]["rectangle"]
    s.compare, s.reference, s.reference_path = True, "FILE", str(tmp_path / "ref.exr")
    compare_only(s, "rectangle")
    s.seed = 0
    scene.render.filepath = str(tmp_path / "cmp_")
    settings.file_format = "OPEN_EXR_MULTILAYER"
    bpy.ops.render.render(write_still=True)
    rec = engine_module().last_render
    (exr,) = tmp_path.glob("cmp_*.exr")
    header = exr.read_bytes()[:20000]
    for t in ("rectangle", "reference"):  # a single compared technique still gets its pass
        assert f"{engine_module().technique_pass_name(t)}.R".encode() in header, t
    # Same settings and seed as the reference render: the technique reproduces it exactly.
    assert np.allclose(rec["images"]["reference"][..., :3], reference[..., :3], rtol=1e-6)
    assert rec["stats"]["rectangle"]["rmse"] < 1e-5
    # A reference of another size is reported, and the comparison is made without it.
    scene.render.resolution_x, scene.render.resolution_y = 16, 12
    bpy.ops.render.render(write_still=False)
    rec = engine_module().last_render
    assert any("reference image is 32x24, the render is 16x12" in w for w in rec["warnings"])
    assert "reference" not in rec["images"] and os.path.isfile(rec["comparison"])


def test_comparison_image_layout_rmse_and_shared_heat_scale():
    compare = __import__("sphrect_blender.engine.compare", fromlist=["compare"])
    rng = np.random.default_rng(7)
    reference = np.full((20, 30, 4), 0.5, dtype=np.float32)
    noisy = reference + rng.normal(0, 0.1, reference.shape).astype(np.float32)
    entries = [dict(name="area", image=noisy, samples=4, time=0.5, light_time=0.1),
               dict(name="rectangle", image=reference.copy(), samples=4, time=0.5, light_time=0.2)]
    canvas = compare.comparison_image(entries, reference)
    d = noisy[..., :3].astype(np.float64) - 0.5
    assert entries[0]["rmse"] == np.sqrt(np.mean(d * d)) and entries[1]["rmse"] == 0.0
    pad = 4
    assert canvas.shape[1] == pad + 3 * (30 + pad)  # two techniques and the reference
    assert canvas.shape[0] > 2 * 20  # images over error maps
    # Heat maps share one scale: the exact technique's map is black, the noisy one's is not.
    label_h = (canvas.shape[0] - pad) // 2 - 20 - pad  # height = pad + 2 * (image + labels + pad)
    y = pad + 20 + label_h + pad
    assert canvas[y:y + 20, pad + 34:pad + 64].max() == 0.0
    assert canvas[y:y + 20, pad:pad + 30].max() > 0.5
    # Labels are drawn (ink under the first image).
    assert canvas[pad + 20:pad + 40, pad:pad + 30].max() == 1.0
    # An entry's label replaces its name, and a light selection adds a line under it.
    for e in entries:
        e.update(label=e["name"], name=e["name"] + " tree", light_selection="tree")
    assert compare._label_lines(entries[0])[0] == "LIGHTS BY tree"
    taller = compare.comparison_image(entries, reference)
    assert taller.shape[1] == canvas.shape[1] and taller.shape[0] == canvas.shape[0] + 2 * (compare.GLYPH_H + 2)
    assert np.array_equal(taller[:pad + 20 + 7], canvas[:pad + 20 + 7])  # the same image and name line
    # An ellipse technique adds one more.
    for e in entries:
        e.update(ellipse_technique="spherical_ellipse")
    assert compare._label_lines(entries[0])[:2] == ["LIGHTS BY tree", "DISKS BY spherical_ellipse"]
    assert compare.comparison_image(entries, reference).shape[0] == taller.shape[0] + 2 * (compare.GLYPH_H + 2)


def test_compare_with_a_rendered_reference_from_a_script_exits_cleanly(tmp_path):
    # Issue 27: Debian's Blender 3.4.1 segfaults at exit (139) once a --python file has imported
    # concurrent.futures.process; the comparison's RMSE imported it through sphrect.study's executors.  The add-on
    # now imports only the study's metrics, and the script's Blender exits 0.
    import subprocess
    from conftest import BLEND_DIR, REPO
    script = tmp_path / "compare.py"
    script.write_text(
        "import sys, addon_utils, bpy\n"
        f"sys.path[:0] = [{os.path.join(REPO, 'addon')!r}, {os.environ['SPHRECT_PYTHON_PATH']!r}]\n"
        "addon_utils.enable('sphrect_blender', handle_error=None)\n"
        f"bpy.ops.wm.open_mainfile(filepath={os.path.join(BLEND_DIR, '01_paper.blend')!r})\n"
        "scene = bpy.context.scene\n"
        "scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 24, 16, 100\n"
        "s = scene.sphrect\n"
        "s.compare, s.samples, s.reference, s.reference_samples = True, 2, 'RENDER', 4\n"
        f"scene.render.filepath = {str(tmp_path / 'out_')!r}\n"
        "bpy.ops.render.render(write_still=True)\n"
        "print('STUDY_EXECUTORS_IMPORTED', 'concurrent.futures.process' in sys.modules, flush=True)\n")
    run = subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                          str(script)], capture_output=True, text=True, timeout=300)
    assert "STUDY_EXECUTORS_IMPORTED False" in run.stdout, run.stdout[-2000:] + run.stderr[-2000:]
    assert run.returncode == 0, (run.returncode, run.stderr[-2000:])
    assert list(tmp_path.glob("out_*_sphrect_compare.png"))
