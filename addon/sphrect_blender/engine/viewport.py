"""Rendered shading in the 3D view: the engine's view_update / view_draw (render_engine delegates here).

    view_update  exports the scene the first time, then re-exports what the depsgraph updates call for
                 (viewport_updates: lights only, the world, the scene camera, or everything)
    view_draw    notices view changes (the region's matrices and size), restarts the worker when anything
                 changed, uploads its newest images to GPU textures and draws them with the display-space
                 shader, so the view transform and look match F12's; in compare mode two techniques side by
                 side (left: the scene's technique, right: the viewport's compare technique)

The rendering itself runs on a ViewportSession's worker thread (viewport_worker). A main-thread timer
redraws the rendered views when a worker has a new image and stops sessions no view shows any more;
F12 renders pause every worker (render_init .. render_complete / render_cancel).  A world that needs a bake
(io/exporter/world_bake.py) is not waited for: the exports run within world_bake.in_background, a stand-in is
rendered while the child Blender bakes, the timer polls it, and the next draw exports the world again with it."""
import dataclasses
import threading
import time
import weakref

import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from ..names import ENGINE_ID, TECHNIQUE_LABELS, label, sphrect_name
from ..native import load_sphrect
from . import viewport_worker
from .viewport_camera import region_camera, view_signature
from .viewport_updates import (CAMERA, EVERYTHING, LIGHTS, WORLD, contents_signature, reexport_kinds,
                               scene_updated)

REFRESH_SECONDS = 0.05        # how often the timer looks for new images
SPLIT_LINE_PIXELS = 2         # the compare view's dividing line
_sessions = weakref.WeakSet()  # live sessions, for the timer


def settings_signature(settings):
    """The scene settings a viewport image depends on (a change restarts it)."""
    return (tuple(sorted(settings.renderer_options().items())), settings.technique, settings.viewport_samples,
            settings.viewport_compare, settings.viewport_compare_technique)


def viewport_techniques(settings):
    """sphrect names of the techniques the viewport renders: the scene's, and in compare mode the second."""
    first = sphrect_name(settings.technique)
    second = sphrect_name(settings.viewport_compare_technique)
    return (first, second) if settings.viewport_compare and second != first else (first,)


class ViewportSession:
    """One rendered 3D view: the exported scene, its worker and the textures of the newest image."""

    def __init__(self):
        self.scene = None          # sphrect.Scene as exported (camera: the scene camera)
        self.settings = None
        self.contents = None       # viewport_updates.contents_signature of the exported scene
        self.scene_version = 0     # counts the exports that changed more than the scene camera (Job.scene_version)
        self.techniques = ()
        self.view = None           # view_signature of the running job
        self.changed = True        # restart the worker at the next draw
        self.frame_ready = threading.Event()
        self.worker = None
        self._textures = None      # (frame, [GPUTexture]) of the newest drawn frame
        self._reported = None      # the export warning last printed
        self.last_update = None    # (what was re-exported, seconds): the cost of the last edit, for tests and docs
        self.drawn = None          # the worker's Frame last drawn, and when (time.perf_counter())
        self.drawn_at = None
        self._stats_text = None
        self.error = None          # why the last update failed (shown instead of an image)
        self.bakes = _background_bakes()  # the world's bake running in the background (world_bake.BackgroundBakes)
        self.world_stale = False   # a background bake ended: the next draw exports the world again

    def free(self):
        """Stop the worker and kill the world's bake (the engine is freed or no view shows SPHRECT any more)."""
        self.bakes.cancel()
        if self.worker is not None:
            self.worker.stop()
        self._textures = None
        _sessions.discard(self)

    # ---------------------------------------------------------------- view_update
    def update(self, depsgraph):
        start = time.perf_counter()
        settings = depsgraph.scene.sphrect
        updates = list(depsgraph.updates)
        kinds = {EVERYTHING} if self.scene is None else reexport_kinds(updates)
        if EVERYTHING not in kinds and scene_updated(updates) and contents_signature(depsgraph) != self.contents:
            kinds = {EVERYTHING}  # an object was hidden or shown, the world or the camera replaced
        signature = settings_signature(settings)
        if not kinds and signature == self.settings:
            return
        self.settings, self.techniques = signature, viewport_techniques(settings)
        from ..io.exporter import world_bake
        with world_bake.in_background(self.bakes):
            self._export(depsgraph, kinds)
        self.last_update = (sorted(kinds), time.perf_counter() - start)

    def poll_bake(self):
        """Whether the world's background bake has ended since the last call (then the next draw exports the world
        again, with the bake or, if it failed, the stand-in and a warning).  Called by the timer."""
        if not self.bakes.poll():
            return False
        self.world_stale = True
        return True

    def refresh_world(self, depsgraph):
        """Export the world again after its background bake ended (the draw calls it)."""
        start = time.perf_counter()
        self.world_stale = False
        kinds = {WORLD} if self.scene is not None else {EVERYTHING}
        from ..io.exporter import world_bake
        with world_bake.in_background(self.bakes):
            self._export(depsgraph, kinds)
        self.last_update = (sorted(kinds), time.perf_counter() - start)

    def _export(self, depsgraph, kinds):
        """Export what `kinds` (viewport_updates) names into self.scene; the worker restarts at the next draw."""
        sphrect = load_sphrect()
        from ..io.exporter import rendered_world, scene_from_depsgraph
        from ..io.exporter.camera import export_camera
        from ..io.exporter.lights import export_light, has_image_texture
        from ..io.exporter.log import ExportLog
        from ..io.exporter.materials import export_world

        bl_scene = depsgraph.scene
        self.changed = True
        log = ExportLog()
        if EVERYTHING in kinds:
            self.scene, log = scene_from_depsgraph(depsgraph)
            self.contents = contents_signature(depsgraph)
            self.scene_version += 1
        else:
            if LIGHTS in kinds and (any(getattr(l, "texture", None) is not None for l in self.scene.lights) or
                                    any(has_image_texture(i.object.data) for i in depsgraph.object_instances
                                        if i.object.type == "LIGHT")):
                # A light's image is one of the scene's textures: everything again.
                self.scene, log = scene_from_depsgraph(depsgraph)
                self.contents = contents_signature(depsgraph)
            elif LIGHTS in kinds:
                lights = (export_light(sphrect, i.object, i.matrix_world, i.object.name, log,
                                       i.parent if i.is_instance else None)
                          for i in depsgraph.object_instances if i.object.type == "LIGHT")
                self.scene = dataclasses.replace(self.scene, lights=[l for l in lights if l is not None])
            if WORLD in kinds:
                world = export_world(sphrect, rendered_world(depsgraph), log)
                images = (world.environment, world.camera_environment, self.scene.world.environment,
                          self.scene.world.camera_environment)
                if all(image is None for image in images):
                    self.scene = dataclasses.replace(self.scene, world=world)
                else:  # an image world's image is one of the scene's textures: everything again
                    self.scene, log = scene_from_depsgraph(depsgraph)
                    self.contents = contents_signature(depsgraph)
            if kinds & {LIGHTS, WORLD}:
                self.scene_version += 1  # (the scene camera's alone keeps the native scene: the view replaces it)
            if CAMERA in kinds:
                cam = bl_scene.camera.evaluated_get(depsgraph) if bl_scene.camera is not None else None
                self.scene = dataclasses.replace(self.scene, camera=export_camera(sphrect, bl_scene, cam, log))
        if kinds & {EVERYTHING, WORLD}:
            self.bakes.world_exported()
        text = log.warning_text()
        if text and text != self._reported:
            print(text)
        self._reported = text or self._reported

    # ---------------------------------------------------------------- view_draw
    def draw(self, engine, context, depsgraph):
        if self.world_stale:
            _guarded(self, lambda: self.refresh_world(depsgraph))
        if self.error:
            self._stats(engine, self.error)
            return
        region, region_3d = context.region, context.region_data
        from ..io.exporter.camera import film_settings
        pixel_size = viewport_pixel_size(depsgraph.scene, context)
        film = film_settings(depsgraph.scene)
        pixel_filter = dict(pixel_filter=film["pixel_filter"], filter_width=film["filter_width"])  # F12's
        view = (view_signature(region, region_3d), pixel_size, tuple(pixel_filter.values()))
        if self.worker is None or not self.worker.alive:  # the first draw, or the timer stopped it
            self.worker, self.changed = viewport_worker.ProgressiveWorker(on_frame=self.frame_ready.set), True
            _sessions.add(self)
            _start_timer()
        if self.scene is not None and (self.changed or view != self.view):
            self.view, self.changed = view, False
            camera = dataclasses.replace(region_camera(load_sphrect(), region, region_3d, self.scene.camera),
                                         **pixel_filter)
            settings = depsgraph.scene.sphrect
            self.worker.restart(viewport_worker.Job(dataclasses.replace(self.scene, camera=camera), self.techniques,
                                                    settings.renderer_options(), settings.viewport_samples,
                                                    pixel_size, self.scene_version))
        frame = self.worker.latest
        if frame is None:
            self._stats(engine, f"SPHRECT | Starting{self._bake_state()}")
            return
        if frame.error:
            self._stats(engine, f"SPHRECT | {frame.error}")
            return
        textures = self._upload(frame)
        _draw_textures(engine, depsgraph.scene, region, textures)
        self.drawn, self.drawn_at = frame, time.perf_counter()
        if len(textures) > 1 and len(textures) == len(self.techniques):
            _draw_labels(region, self.techniques)
        state = "Preview" if frame.preview else f"Sample {frame.samples}/{frame.total_samples}"
        skipped = f" | skipped: {'; '.join(frame.warnings)}" if frame.warnings else ""  # lights it cannot render
        self._stats(engine, f"SPHRECT | {state} | {frame.seconds:.1f} s{self._bake_state()}{skipped}")

    def _bake_state(self):
        """The world's bake in the status text: running (a stand-in shown), or failed (said on the console)."""
        if self.bakes.pending:
            return " | Baking world…"
        if self.bakes.failed_world:
            return " | World bake failed (see the console)"
        return ""

    def _stats(self, engine, text):
        """The view's status text; set only when it changes (setting it redraws the view)."""
        if text != self._stats_text:
            self._stats_text = text
            engine.update_stats("", text)

    def _upload(self, frame):
        """GPU textures of the frame's images (uploaded once per frame)."""
        if self._textures is None or self._textures[0] is not frame:
            self._textures = (frame, [_texture(image) for image in frame.images])
        return self._textures[1]


def _texture(image):
    """A GPU texture of a sphrect image (row 0 = top; the texture's row 0 is the bottom)."""
    height, width = image.shape[:2]
    data = np.ascontiguousarray(np.flipud(image), dtype=np.float32).ravel()
    return gpu.types.GPUTexture((width, height), format="RGBA16F", data=gpu.types.Buffer("FLOAT", data.size, data))


def _quad(shader, x0, x1, height, u0, u1):
    return batch_for_shader(shader, "TRI_FAN", {"pos": ((x0, 0), (x1, 0), (x1, height), (x0, height)),
                                                "texCoord": ((u0, 0), (u1, 0), (u1, 1), (u0, 1))})


def _draw_textures(engine, scene, region, textures):
    """The images over the whole region: one, or each technique's half of its own image (left / right)."""
    width, height = region.width, region.height
    gpu.state.blend_set("ALPHA_PREMULT")
    engine.bind_display_space_shader(scene)
    shader = gpu.shader.from_builtin("2D_IMAGE")
    n = len(textures)
    for i, texture in enumerate(textures):
        shader.uniform_sampler("image", texture)
        _quad(shader, width * i / n, width * (i + 1) / n, height, i / n, (i + 1) / n).draw(shader)
    engine.unbind_display_space_shader()
    gpu.state.blend_set("NONE")
    if n > 1:
        line = gpu.shader.from_builtin("2D_UNIFORM_COLOR")
        line.uniform_float("color", (1.0, 1.0, 1.0, 1.0))
        for i in range(1, n):
            x = width * i / n
            batch_for_shader(line, "TRI_FAN", {"pos": ((x - SPLIT_LINE_PIXELS / 2, 0), (x + SPLIT_LINE_PIXELS / 2, 0),
                                                       (x + SPLIT_LINE_PIXELS / 2, height),
                                                       (x - SPLIT_LINE_PIXELS / 2, height))}).draw(line)


def _draw_labels(region, techniques):
    import blf
    scale = bpy.context.preferences.system.ui_scale
    blf.size(0, int(13 * scale))
    blf.color(0, 1.0, 1.0, 1.0, 1.0)
    blf.enable(0, blf.SHADOW)
    blf.shadow(0, 3, 0.0, 0.0, 0.0, 1.0)
    n = len(techniques)
    for i, technique in enumerate(techniques):
        blf.position(0, region.width * i / n + 12 * scale, 12 * scale, 0)
        blf.draw(0, label(technique, TECHNIQUE_LABELS)[0])
    blf.disable(0, blf.SHADOW)


# -------------------------------------------------------------------- the engine's hooks
def viewport_pixel_size(bl_scene, context):
    """Blender's Viewport > Pixel Size (scene.render.preview_pixel_size): 1, 2, 4 or 8, or AUTO, the interface's
    pixel size (2 on a high-DPI screen), as Cycles reads it."""
    value = bl_scene.render.preview_pixel_size
    if value == "AUTO":
        return max(1, int(round(context.preferences.system.pixel_size)))
    return int(value)


def _background_bakes():
    from ..io.exporter.world_bake import BackgroundBakes
    return BackgroundBakes()


def _guarded(session, export):
    """Run an export of the session; a failure is shown in the view (as F12 reports it), not a traceback at every
    edit."""
    try:
        export()
        session.error = None
    except Exception as e:
        message = f"SPHRECT: {e}" if isinstance(e, ImportError) else f"SPHRECT export failed: {type(e).__name__}: {e}"
        if message != session.error:
            import traceback
            traceback.print_exc()
        session.error, session.changed = message, True


def view_update(engine, context, depsgraph):
    session = getattr(engine, "_viewport_session", None)
    if session is None:
        session = engine._viewport_session = ViewportSession()
    _guarded(session, lambda: session.update(depsgraph))


def view_draw(engine, context, depsgraph):
    session = getattr(engine, "_viewport_session", None)
    if session is not None:
        session.draw(engine, context, depsgraph)


def free(engine):
    """The engine is freed (the view left Rendered shading, the engine was switched, the file closed)."""
    session = getattr(engine, "_viewport_session", None)
    if session is not None:
        engine._viewport_session = None
        session.free()


# -------------------------------------------------------------------- main-thread timer, F12 handlers
def _rendered_views():
    """The 3D view areas showing Rendered shading with SPHRECT."""
    return [area for window in bpy.context.window_manager.windows if window.scene.render.engine == ENGINE_ID
            for area in window.screen.areas
            if area.type == "VIEW_3D" and area.spaces.active.shading.type == "RENDERED"]


def _refresh():
    """Redraw the rendered views when a worker has a new image or a world's bake ended; stop sessions no view
    shows."""
    sessions = list(_sessions)
    if not sessions:
        return None
    views = _rendered_views()
    if not views:  # the engine is normally freed first (free); this catches what was not
        for session in sessions:
            session.free()
        return None
    baked = [s for s in sessions if s.poll_bake()]  # (each polled)
    if baked or any(s.frame_ready.is_set() for s in sessions):
        for session in sessions:
            session.frame_ready.clear()
        for area in views:
            area.tag_redraw()
    return REFRESH_SECONDS


def _pause_for_f12(*_):
    viewport_worker.pause_all()


def _resume_after_f12(*_):
    viewport_worker.resume_all()


_F12_HANDLERS = (("render_init", _pause_for_f12), ("render_complete", _resume_after_f12),
                 ("render_cancel", _resume_after_f12))


def _start_timer():
    if not bpy.app.timers.is_registered(_refresh):
        bpy.app.timers.register(_refresh, first_interval=REFRESH_SECONDS)
    for name, handler in _F12_HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if handler not in handlers:
            handlers.append(handler)


def unregister():
    """Stop every viewport (the add-on is disabled)."""
    for session in list(_sessions):
        session.free()
    viewport_worker.stop_all()
    if bpy.app.timers.is_registered(_refresh):
        bpy.app.timers.unregister(_refresh)
    for name, handler in _F12_HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if handler in handlers:
            handlers.remove(handler)
