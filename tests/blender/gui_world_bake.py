"""F12 of a Sky-world scene in a real Blender window (run by test_world_bake.py under xvfb-run): the export runs on
the render job's thread, the world's bake writes it to a .blend through the main thread and renders it in a child
Blender.  Prints GUI_RESULT <json>."""
import json
import os
import random
import sys
import threading
import time

import bpy

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "addon"))
sys.path.insert(0, os.path.join(REPO, "scripts"))
import addon_utils  # noqa: E402
import make_scenes  # noqa: E402

addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
bake = sys.modules["sphrect_blender.io.exporter.world_bake"]
bake.BAKE_WIDTH, bake.BAKE_HEIGHT = 64, 32
calls = []
real = bake._render_world
bake._render_world = lambda *a: calls.append(threading.current_thread() is threading.main_thread()) or real(*a)

bpy.ops.wm.read_homefile(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "SPHRECT"
scene.render.resolution_x, scene.render.resolution_y = 32, 24
scene.sphrect.samples = 4
world = make_scenes.sky_floor_scene(scene, random.uniform(0.2, 1.2))  # a world no earlier run has baked
before = {k: len(getattr(bpy.data, k)) for k in ("scenes", "objects", "cameras", "worlds", "images", "meshes")}
state = {"phase": "start", "t": time.time()}


def finish(result):
    print("GUI_RESULT " + json.dumps(result))
    sys.stdout.flush()
    os._exit(0)


def step():
    if time.time() - state["t"] > 120:
        finish({"timeout": state["phase"]})
    if state["phase"] == "start":
        win = bpy.context.window_manager.windows[0]
        with bpy.context.temp_override(window=win, area=win.screen.areas[0]):
            bpy.ops.render.render("INVOKE_DEFAULT")
        state["phase"] = "rendering"
        return 0.5
    if bpy.app.is_job_running("RENDER"):
        return 0.2
    record = sys.modules["sphrect_blender.engine.render_engine"].last_render
    after = {k: len(getattr(bpy.data, k)) for k in before if k != "images"}  # (+ Render Result, Render Result view)
    finish({"bakes_on_main_thread": calls, "errors": record.get("errors"), "warnings": record.get("warnings"),
            "data_unchanged": after == {k: v for k, v in before.items() if k != "images"},
            "scene": bpy.context.window.scene.name == scene.name})


bpy.app.timers.register(step, first_interval=1.0)
