"""Where the comparison image goes, and showing it in an Image Editor.

A render in the window runs in a job thread, which must not change bpy data: it queues the image's path
and a persistent main-thread timer (window sessions only) opens it."""
import os
import queue

import bpy

_to_display = queue.Queue()  # comparison images waiting for the main thread


def comparison_path(bl_scene):
    """Where the comparison PNG goes: next to the render output in headless runs, in Blender's
    temporary directory in the window (where it is opened in the Image Editor)."""
    if bpy.app.background:
        out = bpy.path.abspath(bl_scene.render.frame_path(frame=bl_scene.frame_current))
        stem = os.path.splitext(out)[0]
        return stem + "_sphrect_compare.png"
    return os.path.join(bpy.app.tempdir or "/tmp", f"sphrect_compare_{bl_scene.frame_current:04d}.png")


def show_later(path):
    """Open the comparison image at `path` from the main thread's timer (window sessions only)."""
    if not bpy.app.background:
        _to_display.put(path)


def _show_pending_comparisons():
    """The main-thread timer: open the queued comparison images."""
    while True:
        try:
            path = _to_display.get_nowait()
        except queue.Empty:
            return 0.5
        try:
            open_in_image_editor(path)
        except Exception as e:  # a timer must not die: the next comparison should still show
            print(f"SPHRECT: could not open the comparison image {path}: {e}")


def open_in_image_editor(path):
    """Load the comparison PNG as image 'SPHRECT Comparison' and show it in an Image Editor: one that is
    not showing the render result if the window has one, else a new window. Returns the image."""
    name = "SPHRECT Comparison"
    img = bpy.data.images.get(name)
    if img is not None:
        bpy.data.images.remove(img)
    img = bpy.data.images.load(path, check_existing=False)
    img.name = name
    windows = list(bpy.context.window_manager.windows)
    for window in windows:
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                space = area.spaces.active
                if space.image is None or space.image.type != "RENDER_RESULT" or space.image == img:
                    space.image = img
                    fit_later(window, area)
                    return img
    if windows and not bpy.app.background:
        with bpy.context.temp_override(window=windows[0]):
            bpy.ops.wm.window_new()
        new = bpy.context.window_manager.windows[-1]
        if new not in windows:
            area = max(new.screen.areas, key=lambda a: a.width * a.height)
            area.type = "IMAGE_EDITOR"
            area.spaces.active.image = img
            fit_later(new, area)
    return img


def fit_later(window, area, delay=0.2, tries=15):
    """View ▸ Frame All in the editor once it has drawn: the comparison, several images wide, would otherwise
    open at 1:1, cropped to a strip or lost in a corner.  Retried every `delay` seconds until the image fills
    the editor in width or height (a new window's regions, and the image's size, are not known before they
    have drawn; on a loaded machine that takes a while)."""
    state = {"tries": tries}

    def fitted(space, region):
        w, h = space.image.size
        zx, zy = space.zoom
        return w > 0 and h > 0 and (w * zx >= 0.8 * region.width or h * zy >= 0.8 * region.height)

    def fit():
        state["tries"] -= 1
        try:
            space = area.spaces.active
            region = next((r for r in area.regions if r.type == "WINDOW"), None)
            if region is not None and region.width > 1 and space.image is not None:
                # (The editor's own space must be in the context, or the operator zooms another one.)
                with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region,
                                               space_data=space):
                    bpy.ops.image.view_all(fit_view=True)
                if fitted(space, region):
                    return None
        except (ReferenceError, RuntimeError, AttributeError) as e:  # the window closed, the editor changed
            print(f"SPHRECT: could not fit the comparison to its editor: {e}")
            return None
        return delay if state["tries"] > 0 else None
    bpy.app.timers.register(fit, first_interval=delay)


def register():
    if not bpy.app.background:
        bpy.app.timers.register(_show_pending_comparisons, first_interval=1.0, persistent=True)


def unregister():
    if bpy.app.timers.is_registered(_show_pending_comparisons):
        bpy.app.timers.unregister(_show_pending_comparisons)
