"""Rendered shading in a real Blender window: the script test_viewport.py runs under xvfb-run
(`blender --factory-startup --python tests/blender/test_viewport_gui_driver.py`). Not a test module itself:
under pytest it only defines the helpers below.

Phases, driven by a timer: switch the largest 3D view of the paper scene to Rendered shading through the
camera (overlays off) and wait for the viewport's samples; screenshot; F12 the same view and keep its
colour-managed PNG; move the light and screenshot a second later; turn the viewport compare on and
screenshot the split view; switch to Solid shading and back, then the engine to EEVEE, listing the threads.
Prints VP_RESULT <json>; the measurements are the test's to judge. The screenshots go to $SPHRECT_VIEWPORT_OUT
(default /tmp)."""
import json
import os
import sys
import threading
import time

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.environ.get("SPHRECT_VIEWPORT_OUT", "/tmp")
F12_SIZE = (128, 96)    # F12's resolution, 4:3 as the scene's camera
BLOCKS = (16, 12)       # the images are compared by the means of these blocks
VIEWPORT_SAMPLES = int(os.environ.get("SPHRECT_VIEWPORT_SAMPLES", 4))  # more for docs/images/viewport*.png
F12_SAMPLES = 16
PHASE_TIMEOUT = 40.0    # seconds per phase before giving up


def block_means(pixels, blocks=BLOCKS):
    """Mean RGB of blocks x blocks cells of an [H, W, >=3] image (cells of near-equal size)."""
    h, w = pixels.shape[:2]
    ys = np.linspace(0, h, blocks[1] + 1).astype(int)
    xs = np.linspace(0, w, blocks[0] + 1).astype(int)
    return np.array([[pixels[ys[j]:ys[j + 1], xs[i]:xs[i + 1], :3].mean(axis=(0, 1)) for i in range(blocks[0])]
                     for j in range(blocks[1])])


def main():
    import bpy
    from bpy_extras import view3d_utils
    sys.path.insert(0, os.path.join(REPO, "addon"))
    import addon_utils

    addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
    bpy.ops.wm.open_mainfile(filepath=os.path.join(REPO, "blend_scenes", "01_paper.blend"))
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = F12_SIZE
    scene.render.resolution_percentage = 100
    scene.sphrect.samples, scene.sphrect.viewport_samples = F12_SAMPLES, VIEWPORT_SAMPLES
    # Colour management that shows if the viewport skipped it: Filmic with a look and an exposure.
    view = scene.view_settings
    view.view_transform, view.look, view.exposure = "Filmic", "Medium High Contrast", 0.7
    viewport = sys.modules["sphrect_blender.engine.viewport"]
    worker_module = sys.modules["sphrect_blender.engine.viewport_worker"]
    result = {}
    state = {"phase": "start", "t": time.time()}

    def view3d():
        window = bpy.context.window_manager.windows[0]
        area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
        return window, area, next(r for r in area.regions if r.type == "WINDOW")

    def session():
        sessions = list(viewport._sessions)
        return sessions[0] if sessions else None

    def frame():
        """The worker's frame last drawn in the view."""
        s = session()
        return s.drawn if s is not None else None

    def region_pixels(name):
        """The 3D view's region in a screenshot of the window: float [H, W, 4], row 0 = bottom."""
        window, area, region = view3d()
        path = os.path.join(OUT, f"sphrect_viewport_{name}.png")
        with bpy.context.temp_override(window=window):
            bpy.ops.screen.screenshot(filepath=path)
        image = bpy.data.images.load(path, check_existing=False)
        pixels = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)
        bpy.data.images.remove(image)
        return pixels[region.y:region.y + region.height, region.x:region.x + region.width]

    def camera_frame_box():
        """(x0, y0, x1, y1) of the camera's frame in the region's pixels."""
        window, area, region = view3d()
        cam = scene.camera
        corners = [view3d_utils.location_3d_to_region_2d(region, area.spaces.active.region_3d, cam.matrix_world @ v)
                   for v in cam.data.view_frame(scene=scene)]
        xs, ys = [c.x for c in corners], [c.y for c in corners]
        return [int(round(min(xs))), int(round(min(ys))), int(round(max(xs))), int(round(max(ys)))]

    def finish():
        print("VP_RESULT " + json.dumps(result))
        sys.stdout.flush()
        os._exit(0)

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
        phase = state["phase"]
        elapsed = time.time() - state["t"]
        if elapsed > PHASE_TIMEOUT:
            result["timeout"] = phase
            finish()
        window, area, region = view3d()
        space = area.spaces.active
        if phase == "start":
            space.overlay.show_overlays = False
            space.show_gizmo = False
            space.region_3d.view_perspective = "CAMERA"
            with bpy.context.temp_override(window=window, area=area, region=region):
                bpy.ops.view3d.view_center_camera()
            space.shading.type = "RENDERED"
            state["rendered_at"] = time.perf_counter()
            result["region"] = [region.width, region.height]
            next_phase("converge")
        elif phase == "converge":
            f = frame()
            if f is not None and "first_image_seconds" not in result:
                result["first_image_seconds"] = session().drawn_at - state["rendered_at"]
                # What the worker published first (a preview); what was drawn first depends on how soon
                # the window redrew, which a loaded machine delays past the previews.
                result["first_image_scale"] = session().worker.first_scale
                result["first_drawn_scale"] = f.scale
            s = session()
            if s is not None and s.worker is not None and s.worker.latest is not None and s.worker.latest.error:
                result["error"] = s.worker.latest.error
                finish()
            if f is not None and f.scale == 1 and f.samples >= f.total_samples:
                result["converged_seconds"] = session().drawn_at - state["rendered_at"]
                result["worker_seconds"] = f.seconds
                result["export"] = session().last_update
                pixels = region_pixels("rendered")
                state["rendered"] = pixels
                result["region_std"] = float(pixels[..., :3].std())
                box = camera_frame_box()
                result["camera_frame"] = box
                state["viewport_blocks"] = block_means(pixels[box[1]:box[3], box[0]:box[2]])
                next_phase("f12")
        elif phase == "f12":
            start = time.perf_counter()
            bpy.ops.render.render(write_still=False)
            result["f12_seconds"] = time.perf_counter() - start
            path = os.path.join(OUT, "sphrect_viewport_f12.png")
            bpy.data.images["Render Result"].save_render(path)
            image = bpy.data.images.load(path, check_existing=False)
            f12 = np.array(image.pixels[:], dtype=np.float32).reshape(image.size[1], image.size[0], 4)
            bpy.data.images.remove(image)
            diff = np.abs(block_means(f12) - state["viewport_blocks"])
            result["f12_block_mean_abs_diff"] = float(diff.mean())
            result["f12_block_max_abs_diff"] = float(diff.max())
            result["f12_block_range"] = float(np.ptp(block_means(f12)))
            light = bpy.data.objects["Light"]
            state["generation"] = session().worker.latest.generation
            state["moved_at"] = time.perf_counter()
            light.location.x += 1.5
            next_phase("moved")
        elif phase == "moved":
            f = frame()
            if "edit_first_image_seconds" not in result and f is not None and f.generation > state["generation"]:
                # From the move to the draw of the first image that shows it (the view's own clock).
                result["edit_first_image_seconds"] = session().drawn_at - state["moved_at"]
                result["edit_first_image_scale"] = f.scale
                result["edit_export"] = session().last_update
            # Once the move's first image is drawn (its time is a measurement, not a pass mark: the window's
            # redraws slow down with the machine's load), or after 10 s without it.
            shown = "edit_first_image_seconds" in result
            if (shown and elapsed >= result["edit_first_image_seconds"] + 0.1) or elapsed >= 10.0:
                pixels = region_pixels("moved")
                result["moved_mean_abs_diff"] = float(np.abs(pixels[..., :3] - state["rendered"][..., :3]).mean())
                scene.sphrect.viewport_compare = True
                next_phase("compare")
        elif phase == "compare":
            f = frame()
            if f is not None and len(f.images) == 2 and f.scale == 1 and f.samples >= f.total_samples:
                pixels = region_pixels("compare")
                middle = region.width // 2
                result["compare_techniques"] = list(session().techniques)
                result["compare_line"] = float(pixels[:, middle - 1:middle + 1, :3].mean())
                result["compare_halves_std"] = [float(pixels[:, :middle - 2, :3].std()),
                                                float(pixels[:, middle + 2:, :3].std())]
                result["threads_rendering"] = [t.name for t in threading.enumerate()]
                space.shading.type = "SOLID"
                next_phase("solid")
        elif phase == "solid":
            if elapsed >= 1.0:
                result["threads_after_solid"] = [t.name for t in threading.enumerate()]
                space.shading.type = "RENDERED"
                next_phase("rendered_again")
        elif phase == "rendered_again":
            if frame() is not None:  # a new session (the engine is new) has drawn
                result["threads_rendering_again"] = [t.name for t in threading.enumerate()]
                scene.render.engine = "BLENDER_EEVEE"
                next_phase("switched")
        elif phase == "switched":
            if elapsed >= 1.0:
                result["threads_after_switch"] = [t.name for t in threading.enumerate()]
                result["live_workers_after_switch"] = len(worker_module.live_workers())
                result["sessions_after_switch"] = len(viewport._sessions)
                finish()
        return 0.05

    bpy.app.timers.register(step, first_interval=1.0)


if __name__ == "__main__":
    try:
        main()
    except Exception:  # a window would stay open: say what failed and quit
        import traceback
        print("VP_RESULT " + json.dumps({"error": traceback.format_exc()}))
        sys.stdout.flush()
        os._exit(1)
