"""The Rendered viewport of a Sky-world scene in a real Blender window (run by test_viewport_world_bake.py under
xvfb-run): the view draws a stand-in while the world's bake runs in the background, the timer notices its end and
the view draws the baked world; an edit of the sky shows the previous bake while the new one runs; leaving Rendered
shading kills that child.  Prints GUI_RESULT <json>; the test judges it."""
import json
import os
import random
import sys
import time

import bpy
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "addon"))
sys.path.insert(0, os.path.join(REPO, "scripts"))
import addon_utils  # noqa: E402
import make_scenes  # noqa: E402

PHASE_TIMEOUT = 120.0  # seconds per phase before giving up (a bake takes a few)

addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
bake = sys.modules["sphrect_blender.io.exporter.world_bake"]
viewport = sys.modules["sphrect_blender.engine.viewport"]
bake.BAKE_WIDTH, bake.BAKE_HEIGHT = 256, 128
bake.CACHE_DIR = os.environ["SPHRECT_BAKE_CACHE"]  # the test's own: nothing is cached yet

scene = bpy.context.scene
scene.render.engine = "SPHRECT"
scene.sphrect.viewport_samples = 4
for obj in list(scene.objects):
    bpy.data.objects.remove(obj)
world = make_scenes.sky_floor_scene(scene, random.uniform(0.2, 1.2))
sky = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeTexSky")
result = {}
state = {"phase": "start", "t": time.time()}


def finish():
    print("GUI_RESULT " + json.dumps(result))
    sys.stdout.flush()
    os._exit(0)


def session():
    sessions = list(viewport._sessions)
    return sessions[0] if sessions else None


def next_phase(name):
    state["phase"], state["t"] = name, time.time()


def step():
    try:
        return phase_step()
    except Exception:
        import traceback
        result["error"] = traceback.format_exc()
        finish()


def phase_step():
    phase, elapsed = state["phase"], time.time() - state["t"]
    if elapsed > PHASE_TIMEOUT:
        result["timeout"] = phase
        finish()
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    space = area.spaces.active
    s = session()
    if phase == "start":
        space.region_3d.view_perspective = "CAMERA"
        space.shading.type = "RENDERED"
        next_phase("baking")
    elif phase == "baking":  # the view's first image: drawn while the bake runs?
        if s is not None and s.drawn is not None:
            result["first_export"] = s.last_update
            result["drawn_while_baking"] = s.bakes.pending
            result["status_while_baking"] = s._stats_text
            result["stand_in_environment"] = s.scene.world.environment is not None
            next_phase("landing")
    elif phase == "landing":  # the timer notices the bake's end; the next draw exports the world with it
        if s.scene.world.environment is not None and s.drawn is not None and not s.changed \
                and s.drawn.generation == s.worker.latest.generation:
            result["landed_status"] = s._stats_text
            result["landed_export"] = s.last_update
            state["first"] = s.scene.textures[s.scene.world.environment.texture].pixels
            sky.sun_elevation += 0.05  # an edit: the previous bake shown while the new one runs
            next_phase("edited")
    elif phase == "edited":
        if s.bakes.pending and s.drawn is not None and not s.changed:
            environment = s.scene.world.environment
            result["edit_stand_in_is_previous_bake"] = environment is not None and bool(
                np.array_equal(s.scene.textures[environment.texture].pixels, state["first"]))
            state["process"] = s.bakes.job.process
            space.shading.type = "SOLID"  # leave Rendered shading while the bake runs
            next_phase("solid")
    elif phase == "solid":
        if elapsed >= 1.0:
            result["child_after_solid"] = state["process"].poll()
            result["sessions_after_solid"] = len(viewport._sessions)
            finish()
    return 0.05


bpy.app.timers.register(step, first_interval=1.0)
