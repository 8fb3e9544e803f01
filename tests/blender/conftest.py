"""Shared helpers of the Blender tests (run by run_tests.py inside Blender)."""
import os
import sys

import addon_utils
import bpy
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BLEND_DIR = os.path.join(REPO, "blend_scenes")
SCENES = sorted(f[:-len(".blend")] for f in os.listdir(BLEND_DIR) if f.endswith(".blend"))
for _path in (os.path.join(REPO, "scripts"), os.path.join(REPO, "tests")):
    if _path not in sys.path:
        sys.path.insert(0, _path)

import make_scenes as builders  # noqa: E402  (the scene generator's object/light/material helpers)
import tier_markers  # noqa: E402  (tests/tier_markers.py: the markers both suites register)


def pytest_configure(config):
    tier_markers.register(config)


def ensure_addon():
    if not addon_utils.check("sphrect_blender")[1]:
        addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)


def addon_module(name):
    """The add-on's module `name` ('engine.schedule', 'images', ...), as the enabled add-on loaded it."""
    return sys.modules["sphrect_blender." + name]


def engine_module():
    return addon_module("engine.render_engine")


def exporter():
    return sys.modules["sphrect_blender.io.exporter"]


def set_resolution(scene, width, height):
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100


@pytest.fixture
def empty_scene():
    """An empty scene rendered by SPHRECT at 32x24, black world, with a camera looking down -Y at the origin."""
    bpy.ops.wm.read_homefile(use_empty=True)
    ensure_addon()
    scene = bpy.context.scene
    scene.render.engine = "SPHRECT"
    set_resolution(scene, 32, 24)
    scene.view_settings.view_transform = "Standard"
    builders.black_world(scene)
    builders.camera((0.0, -6.0, 2.0), (0.0, 0.0, 0.3), lens=35.0)
    bpy.context.view_layer.update()
    return scene


def open_blend(name, width=32, height=24):
    bpy.ops.wm.open_mainfile(filepath=os.path.join(BLEND_DIR, name + ".blend"))
    ensure_addon()
    scene = bpy.context.scene
    set_resolution(scene, width, height)
    return scene


def export():
    """(sphrect.Scene, ExportLog) of the current scene's evaluated depsgraph."""
    return exporter().scene_from_depsgraph(bpy.context.evaluated_depsgraph_get())


def render():
    """F12 without writing: returns the engine's record of the render (reports, stats, images)."""
    bpy.ops.render.render(write_still=False)
    return engine_module().last_render


def lit_test_scene(scene):
    """Ground plane, a box and a one-sided rectangle light facing down: the smallest useful scene."""
    builders.mesh_object("Ground", "plane", builders.material("Ground", (0.8, 0.8, 0.8)), size=8)
    builders.mesh_object("Box", "cube", builders.material("Box", (0.7, 0.4, 0.2)), location=(0.3, 0.5, 0.5),
                         size=1.0, rotation=(0, 0, 0.4))
    builders.area_light("Light", "RECTANGLE", size=1.5, size_y=0.8, power=200.0, location=(-0.5, 0.0, 2.0),
                        rotation=(0.2, -0.3, 0.0))
    return scene
