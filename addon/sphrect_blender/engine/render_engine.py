"""The SPHRECT render engine: export the evaluated depsgraph, render progressively with the native
renderer, and (in compare mode) one render pass per technique (x light selection x ellipse technique, when
several are ticked) plus a comparison image."""
import os
import time
import warnings
from typing import NamedTuple

import bpy
import numpy as np

from ..images import load_reference_exr
from ..names import ENGINE_ID, sphrect_name
from ..native import load_sphrect
from . import compare, display, viewport
from .schedule import (cancel_requested, clear_cancel_request, request_cancel, run_call, sample_schedule,
                       split_samples)

# A render that would need more than this much memory for its images is refused (absurd resolutions).
MAX_IMAGE_BYTES = 4 << 30
PASS_PREFIX = "SPHRECT "
REFERENCE_TECHNIQUE = "rectangle"  # of the compare mode's rendered reference

# What the last render did, for scripts and tests: reports, effects, per-entry stats and final images
# (float32 [H, W, 4], row 0 = top) keyed by entry name, the comparison image's path, whether it was cancelled.
last_render = {}


def technique_pass_name(name):
    """The render pass of an entry (Entry.name: a technique, then the light selection and the ellipse technique
    when several are compared: 'rectangle tree spherical_ellipse') or the reference."""
    return PASS_PREFIX + name


class Entry(NamedTuple):
    """One image the render makes: a technique with a light selection and an ellipse technique."""
    name: str              # its pass, its key in last_render: the technique, + the selection, + the ellipse
    technique: str         # technique, each only when several are compared
    light_selection: str
    ellipse_technique: str

    @property
    def renderer_key(self):
        """What one Renderer fixes (several techniques share it)."""
        return self.light_selection, self.ellipse_technique


def chosen_techniques(settings):
    if settings.compare:
        return settings.compare_techniques()
    return [sphrect_name(settings.technique)]


def chosen_light_selections(settings):
    if settings.compare:
        return settings.compare_light_selections()
    return [sphrect_name(settings.light_selection)]


def chosen_ellipse_techniques(settings):
    if settings.compare:
        return settings.compare_ellipse_techniques()
    return [sphrect_name(settings.ellipse_technique)]


def chosen_entries(settings):
    """Every technique x light selection x ellipse technique to render, technique by technique (its selections
    and ellipse techniques side by side)."""
    selections, ellipses = chosen_light_selections(settings), chosen_ellipse_techniques(settings)

    def name(technique, selection, ellipse):
        return " ".join([technique] + [selection] * (len(selections) > 1) + [ellipse] * (len(ellipses) > 1))

    return [Entry(name(t, s, k), t, s, k) for t in chosen_techniques(settings) for s in selections for k in ellipses]


def display_entry(settings, entries):
    """The entry shown in the Combined pass: the engine's technique (with the scene's light selection and ellipse
    technique) when it is being rendered."""
    technique = sphrect_name(settings.technique)
    key = sphrect_name(settings.light_selection), sphrect_name(settings.ellipse_technique)
    return (next((e for e in entries if e.technique == technique and e.renderer_key == key), None)
            or next((e for e in entries if e.technique == technique), entries[0]))


def _flat_rgba(image):
    """sphrect image (row 0 = top) -> contiguous float32 [H*W, 4] in Blender's order (bottom row first)."""
    return np.ascontiguousarray(np.flipud(np.asarray(image, dtype=np.float32))).reshape(-1, 4)


class SphrectRenderEngine(bpy.types.RenderEngine):
    bl_idname = ENGINE_ID
    bl_label = "SPHRECT"
    bl_use_preview = False
    bl_use_postprocess = True
    bl_use_shading_nodes_custom = False  # materials use Blender's shader nodes

    def update_render_passes(self, scene=None, renderlayer=None):
        """Declare the per-entry passes (Image Editor pass menu, compositor, multilayer EXR)."""
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        settings = scene.sphrect
        if settings.compare:
            for e in chosen_entries(settings):
                self.register_pass(scene, renderlayer, technique_pass_name(e.name), 4, "RGBA", "COLOR")
            if settings.reference != "NONE":
                self.register_pass(scene, renderlayer, technique_pass_name("reference"), 4, "RGBA", "COLOR")

    # ---------------------------------------------------------------- viewport (Rendered shading)
    def view_update(self, context, depsgraph):
        viewport.view_update(self, context, depsgraph)

    def view_draw(self, context, depsgraph):
        viewport.view_draw(self, context, depsgraph)

    def __del__(self):  # Blender frees the engine: the view left Rendered shading, the engine was switched
        viewport.free(self)

    # ---------------------------------------------------------------- render
    def render(self, depsgraph):
        last_render.clear()
        last_render.update(errors=[], warnings=[], features=[], stats={}, images={}, comparison=None,
                           cancelled=False, time_limited=False)
        try:
            self._render(depsgraph)
        except Exception as e:  # never a traceback in the user's face; the message names the problem
            import traceback
            traceback.print_exc()
            self._error(f"SPHRECT render failed: {type(e).__name__}: {e}")
        finally:
            clear_cancel_request()  # the request that stopped this render, or came while it ran, is used up

    def _stats_line(self, text):
        last_render["stats_line"] = text
        self.update_stats("", text)

    def _error(self, text):
        last_render["errors"].append(text)
        self.report({"ERROR"}, text)

    def _warning(self, text):
        last_render["warnings"].append(text)
        self.report({"WARNING"}, text)

    def _render(self, depsgraph):
        try:
            sphrect = load_sphrect()
        except ImportError as e:
            self._error(str(e))
            return
        if not hasattr(sphrect, "Renderer"):
            self._error(f"SPHRECT: the sphrect module at {os.path.dirname(sphrect.__file__)} has no renderer "
                        f"(an old or partial build); rebuild it")
            return
        from ..io.exporter import scene_from_depsgraph

        bl_scene = depsgraph.scene
        settings = bl_scene.sphrect
        entries = chosen_entries(settings)
        techniques = list(dict.fromkeys(e.technique for e in entries))
        selections = list(dict.fromkeys(e.light_selection for e in entries))
        ellipses = list(dict.fromkeys(e.ellipse_technique for e in entries))
        keys = list(dict.fromkeys(e.renderer_key for e in entries))
        with_reference = settings.compare and settings.reference != "NONE"
        equal_time = settings.compare and settings.equal_time
        self.update_stats("SPHRECT", "Exporting scene")
        t0 = time.perf_counter()
        scene, log = scene_from_depsgraph(depsgraph)
        export_time = time.perf_counter() - t0
        width, height = scene.camera.width, scene.camera.height
        self._pixels = width * height
        image_count = len(entries) + 2 + (1 if with_reference else 0)
        needed = width * height * 16 * image_count
        if needed > MAX_IMAGE_BYTES:
            self._error(f"SPHRECT: resolution {width}x{height} needs {needed / 2**30:.1f} GiB of images "
                        f"(limit {MAX_IMAGE_BYTES / 2**30:.0f} GiB); lower the resolution")
            return
        warning = log.warning_text()
        if warning:
            self._warning(warning)
        reference = None
        if with_reference and settings.reference == "FILE":
            try:
                reference = load_reference_exr(settings.reference_path, width, height)
            except ValueError as e:
                self._warning(f"SPHRECT: no reference: {e}")
                with_reference = False

        options = settings.renderer_options()
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                # A renderer takes one light selection and one ellipse technique: one per such pair, or one per
                # entry for equal time.
                make = lambda ts, key: sphrect.Renderer(scene, techniques=list(ts), **dict(
                    options, light_selection=key[0], ellipse_technique=key[1]))
                if equal_time:
                    renderers = {e.name: make([e.technique], e.renderer_key) for e in entries}
                else:
                    shared = {k: make(techniques, k) for k in keys}
                    renderers = {e.name: shared[e.renderer_key] for e in entries}
        except (ValueError, RuntimeError, TypeError) as e:
            self._error(f"SPHRECT: the scene cannot be rendered: {e}")
            return
        skipped = sorted({str(w.message) for w in caught})
        if skipped:
            self._warning("SPHRECT skipped: " + "; ".join(skipped))
        features = list(next(iter(renderers.values())).features)
        last_render["features"] = features
        self._effects = ", ".join(features) if features else "direct diffuse lighting"
        self._header = (f"SPHRECT | {len(scene.lights)} lights, {sum(len(m.triangles) for m in scene.meshes)} "
                        f"triangles (export {export_time:.2f}s) | effects: {self._effects}")

        layer_name = depsgraph.view_layer.name
        self._compare = settings.compare
        if self._compare:
            for e in entries:
                self.add_pass(technique_pass_name(e.name), 4, "RGBA", layer=layer_name)
        if with_reference:
            self.add_pass(technique_pass_name("reference"), 4, "RGBA", layer=layer_name)
        result = self.begin_result(0, 0, width, height, layer=layer_name)
        layer = result.layers[0]
        shown = display_entry(settings, entries)
        self._cancelled = False
        try:
            if equal_time:
                self._render_equal_time(renderers, entries, settings, result, layer, shown)
            else:
                self._render_equal_samples(renderers, entries, settings, result, layer, shown)
            # With several light selections (ellipse techniques) a panel of the comparison image is labelled by
            # its technique and its selection (ellipse technique) (compare._label_lines).
            several = len(selections) > 1 or len(ellipses) > 1
            images = [dict(name=e.name, image=renderers[e.name].image(e.technique),
                           **(dict(label=e.technique) if several else {}),
                           **(dict(light_selection=e.light_selection) if len(selections) > 1 else {}),
                           **(dict(ellipse_technique=e.ellipse_technique) if len(ellipses) > 1 else {}),
                           **self._stats(renderers[e.name], e.technique)) for e in entries]
            last_render["images"] = {i["name"]: i["image"] for i in images}
            if with_reference and settings.reference == "RENDER" and not self._cancelled:
                reference = self._render_reference(sphrect, scene, options, settings)
            if reference is not None:
                last_render["images"]["reference"] = reference
                self._write_pass(layer, technique_pass_name("reference"), reference)
            last_render["stats"] = {i["name"]: {k: v for k, v in i.items() if k not in ("image", "label")}
                                    for i in images}
            for e in entries:
                last_render["stats"][e.name].update(light_selection=e.light_selection,
                                                    ellipse_technique=e.ellipse_technique)
            self._warn_of_dropped_samples(sphrect, images)
            if settings.compare and not self._cancelled:
                self._comparison(bl_scene, images, reference, settings)
        finally:
            self.end_result(result)
        last_render["cancelled"] = self._cancelled
        if self._cancelled:
            self._stats_line(f"{self._header} | Cancelled: partial image kept")

    def _warn_of_dropped_samples(self, sphrect, images):
        """Non-finite samples left out of an image (an input beyond float32), said in the render's report."""
        for i in images:
            dropped = int(i["raw"].get("dropped_samples", 0))
            if dropped:
                self._warning(f"SPHRECT {i['name']}: {sphrect.dropped_samples_message(dropped)}")

    def _stats(self, renderer, technique):
        s = dict(renderer.stats(technique))
        return dict(samples=int(s.get("samples", 0)), time=float(s.get("wall_time", 0.0)),
                    light_time=float(s.get("light_time", 0.0)), raw=s)

    def _stop_requested(self):
        return self.test_break() or cancel_requested()

    def _progress_callback(self, call_index, call_count):
        """Called by the renderer on this thread after each tile: progress bar and Esc."""
        def progress(done, total):
            self.update_progress((call_index + done / max(total, 1)) / call_count)
            if self.test_break():
                request_cancel()
        return progress

    def _show(self, result, layer, renderers, entries, shown):
        """Copy the current (partial) images of `entries` into the result and send it to the display."""
        for e in entries:
            image = renderers[e.name].image(e.technique)
            if self._compare:
                self._write_pass(layer, technique_pass_name(e.name), image)
            if e == shown:
                self._write_pass(layer, "Combined", image)
        self.update_result(result)

    @staticmethod
    def _write_pass(layer, name, image):
        render_pass = layer.passes.find_by_name(name, "")
        if render_pass is None:
            return
        render_pass.rect.foreach_set(_flat_rgba(image))

    def _render_equal_samples(self, renderers, entries, settings, result, layer, shown):
        # One renderer for all techniques of a light selection; each call renders the same samples with each.
        shared = list({id(r): r for r in renderers.values()}.values())
        names = "/".join(e.name for e in entries)
        calls = sample_schedule(settings.samples, settings.passes, self._pixels)
        pass_ends = set(np.cumsum(split_samples(settings.samples, settings.passes)).tolist())
        done, last_show = 0, time.perf_counter()
        deadline = time.perf_counter() + settings.time_limit if settings.time_limit > 0 else None
        for i, n in enumerate(calls):
            if deadline is not None and done > 0 and time.perf_counter() >= deadline:
                # The time limit: keep the samples done (not a cancellation: the image is complete for them).
                self._show(result, layer, renderers, entries, shown)
                last_render["time_limited"] = True
                break
            self._stats_line(f"{self._header} | {names} | samples {done}/{settings.samples}")
            finished = all(run_call(r, n, self._progress_callback(i * len(shared) + j, len(calls) * len(shared)))
                           for j, r in enumerate(shared))
            done += n
            stop = not finished or self._stop_requested()
            # Display at the end of each pass, and at most once a second in between (copying every
            # technique's image costs ~50 ms per megapixel).
            if stop or done in pass_ends or time.perf_counter() - last_show > 1.0:
                self._show(result, layer, renderers, entries, shown)
                last_show = time.perf_counter()
            if stop:
                self._cancelled = True
                break
        limited = " (time limit)" if last_render.get("time_limited") else ""
        self._stats_line(f"{self._header} | {names} | samples {done}/{settings.samples}{limited}")

    def _render_equal_time(self, renderers, entries, settings, result, layer, shown):
        budget = settings.time_budget
        chunks = max(1, settings.passes)
        steps = len(entries) * chunks
        step = 0
        for e in entries:
            r = renderers[e.name]
            for i in range(chunks):
                self._stats_line(f"{self._header} | equal time {budget:.2f}s | {e.name} part {i + 1}/{chunks}")
                # Passes of one sample each while this part's share of the budget lasts.
                finished = run_call(r, 1, self._progress_callback(step, steps), time_budget=budget / chunks)
                step += 1
                self._show(result, layer, renderers, [e], shown)
                if not finished or self._stop_requested():
                    self._cancelled = True
                    return

    def _render_reference(self, sphrect, scene, options, settings):
        self._stats_line(f"{self._header} | reference: {REFERENCE_TECHNIQUE}, {settings.reference_samples} samples")
        opts = dict(options, seed=options["seed"] + 7919)  # independent of the compared images
        r = sphrect.Renderer(scene, techniques=[REFERENCE_TECHNIQUE], **opts)
        calls = sample_schedule(settings.reference_samples, 1, self._pixels)
        for i, n in enumerate(calls):
            if not run_call(r, n, self._progress_callback(i, len(calls))) or self._stop_requested():
                self._cancelled = True
                return None
        return r.image(REFERENCE_TECHNIQUE)

    def _comparison(self, bl_scene, entries, reference, settings):
        label = "REFERENCE" if settings.reference != "RENDER" else f"REFERENCE {settings.reference_samples} SPP"
        canvas = compare.comparison_image(entries, reference, reference_label=label)
        for e in entries:
            if "rmse" in e:
                last_render["stats"][e["name"]]["rmse"] = e["rmse"]
        summary = ", ".join(f"{e['name']} {e['samples']}spp {e['time']:.2f}s"
                            + (f" RMSE {e['rmse']:.4g}" if "rmse" in e else "") for e in entries)
        self._stats_line(f"{self._header} | {summary}")
        path = display.comparison_path(bl_scene)
        try:
            os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
            compare.write_png(path, canvas)
        except OSError as e:  # the renders and their passes are done and kept: only the PNG is lost
            self._warning(f"SPHRECT: could not write the comparison image to {path}: {e.strerror or e}")
            return
        last_render["comparison"] = path
        print(f"SPHRECT comparison: {summary}\nSPHRECT comparison image: {path}")
        display.show_later(path)
