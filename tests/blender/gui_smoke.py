"""F12 in a real Blender window (run by test_gui.py under xvfb-run): render the paper scene in compare
mode as the render job, check the comparison opens in an Image Editor, then start a long render and
cancel it the way Esc does (render.view_cancel in the render window). Prints GUI_RESULT <json>."""
import json
import os
import sys
import time

import bpy

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "addon"))
import addon_utils  # noqa: E402

addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
bpy.ops.wm.open_mainfile(filepath=os.path.join(REPO, "blend_scenes", "01_paper.blend"))
scene = bpy.context.scene
scene.render.resolution_x, scene.render.resolution_y = 64, 48
scene.sphrect.compare, scene.sphrect.samples, scene.sphrect.reference_samples = True, 16, 64
result = {}
state = {"phase": "start", "t": time.time()}


def engine():
    return sys.modules["sphrect_blender.engine"]


def f12():
    win = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=win, area=win.screen.areas[0]):
        bpy.ops.render.render("INVOKE_DEFAULT")


def finish():
    print("GUI_RESULT " + json.dumps(result))
    sys.stdout.flush()
    os._exit(0)


def step():
    phase = state["phase"]
    if time.time() - state["t"] > 60:
        result["timeout"] = phase
        finish()
    if phase == "start":
        f12()
        state["phase"] = "compare"
        return 0.5
    if bpy.app.is_job_running("RENDER"):
        if phase == "long" and time.time() - state["t"] > 1.5:
            for w in bpy.context.window_manager.windows:  # Esc in the render window
                for a in w.screen.areas:
                    if a.type == "IMAGE_EDITOR" and a.spaces.active.image and \
                            a.spaces.active.image.type == "RENDER_RESULT":
                        with bpy.context.temp_override(window=w, area=a):
                            bpy.ops.render.view_cancel()
                        state["phase"] = "cancelling"
        return 0.2
    if phase == "compare":
        if "SPHRECT Comparison" not in bpy.data.images:
            return 0.5  # the main-thread timer opens it shortly after the render
        state["phase"], state["opened"] = "fitted", time.time()
        return 0.2
    if phase == "fitted":
        fits = []
        for w in bpy.context.window_manager.windows:
            for a in w.screen.areas:
                image = a.spaces.active.image if a.type == "IMAGE_EDITOR" else None
                if image is not None and image.name == "SPHRECT Comparison":
                    region = next(r for r in a.regions if r.type == "WINDOW")
                    zoom = tuple(a.spaces.active.zoom)
                    fits.append(dict(shown=[image.size[0] * zoom[0], image.size[1] * zoom[1]],
                                     region=[region.width, region.height]))
        fitted = fits and all(f["shown"][0] >= 0.8 * f["region"][0] or f["shown"][1] >= 0.8 * f["region"][1]
                              for f in fits)
        if not fitted and time.time() - state["opened"] < 5.0:
            return 0.2  # the editor fits the image (View > Frame All) once it has drawn
        result["comparison_fit"] = fits
        result["fit_seconds"] = time.time() - state["opened"]
        rec = engine().last_render
        result["compare_errors"] = rec["errors"]
        result["compare_cancelled"] = rec["cancelled"]
        result["editors"] = [a.spaces.active.image.name for w in bpy.context.window_manager.windows
                             for a in w.screen.areas if a.type == "IMAGE_EDITOR" and a.spaces.active.image]
        scene.sphrect.compare, scene.sphrect.samples, scene.sphrect.passes = False, 200000, 1
        state["phase"], state["t"] = "long", time.time()
        f12()
        return 0.2
    if phase == "cancelling":
        rec = engine().last_render
        result["cancelled"] = rec["cancelled"]
        result["cancel_seconds"] = time.time() - state["t"]
        result["samples"] = rec["stats"]["rectangle"]["samples"] if rec["stats"] else None
        result["partial_max"] = float(rec["images"]["rectangle"][..., :3].max()) if rec["images"] else None
        finish()
    return 0.2


bpy.app.timers.register(step, first_interval=2.0)
