"""Cycles 3.4 as the study's peer: the open scene rendered in direct-lighting settings, the linear image
saved as .npy and the render's timings as JSON (headless.py's 'render_cycles' command). Needs bpy and numpy
only: the add-on need not be registered.

Arguments (a dict): samples, seed, threads, width, height, time_limit (seconds or None), npy, json, exr (where
the render is saved before it is read back)."""
import json
import math
import time

import bpy
import numpy as np
from mathutils import Matrix

from .names import DEFAULT_FILTER_WIDTH, DEFAULT_PIXEL_FILTER, PIXEL_FILTERS, identifier


def use_direct_lighting(scene, args):
    """Cycles settings for a direct-lighting render comparable with sphrect's: CPU, no adaptive sampling,
    no denoising, no bounces, no light threshold or clamping, a fixed seed, SPHRECT's pixel filter (use_pixel_filter),
    the Standard view transform, a 32-bit EXR."""
    render = scene.render
    render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.max_bounces = 0            # direct lighting only: emission seen + light at the first hit
    cycles.light_sampling_threshold = 0.0
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.seed = int(args["seed"])
    cycles.use_animated_seed = False
    use_pixel_filter(scene)
    cycles.time_limit = float(args.get("time_limit") or 0.0)
    if args["threads"] > 0:
        render.threads_mode = "FIXED"
        render.threads = int(args["threads"])
    else:
        render.threads_mode = "AUTO"
    render.use_persistent_data = False
    render.resolution_x = int(args["width"])
    render.resolution_y = int(args["height"])
    render.resolution_percentage = 100
    render.use_border = False
    render.use_compositing = False
    render.use_sequencer = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"


def use_pixel_filter(scene):
    """Cycles' pixel filter set to the scene's SPHRECT one (the Film panel's), read as raw ID properties so that
    the add-on need not be registered: an enum is stored as its item's number, its place in sphrect.pixel_filters
    (names.py), and an unset one is the add-on's default (Cycles' own, Blackman-Harris 1.5), which is what the
    exporter then reads too.  Cycles makes a box 1 pixel wide whatever the width, as the exporter does."""
    settings = scene.get("sphrect") or {}
    number = settings.get("pixel_filter")
    known = isinstance(number, int) and 0 <= number < len(PIXEL_FILTERS)
    name = PIXEL_FILTERS[number] if known else DEFAULT_PIXEL_FILTER
    scene.cycles.pixel_filter_type = identifier(name)  # Cycles' identifiers: BOX, GAUSSIAN, BLACKMAN_HARRIS
    scene.cycles.filter_width = float(settings.get("filter_width", DEFAULT_FILTER_WIDTH))


def split_two_sided_lights(scene):
    """Cycles 3.4's area lights emit on one side only. A light sphrect renders two-sided (the add-on's switch,
    read as a raw ID property so the add-on need not be registered) becomes two back-to-back lights, each
    with the full power: each side then has the radiance P / (4 A) the two-sided light has on both."""
    for obj in list(scene.objects):
        if obj.type == "LIGHT" and obj.data.type == "AREA" and (obj.data.get("sphrect") or {}).get("two_sided"):
            back = obj.copy()
            back.data = obj.data.copy()
            back.matrix_world = obj.matrix_world @ Matrix.Rotation(math.pi, 4, "X")
            for collection in obj.users_collection:
                collection.objects.link(back)


def render_direct_lighting(scene, args):
    use_direct_lighting(scene, args)
    split_two_sided_lights(scene)
    # Timing: the operator's time includes scene sync and the BVH build; the host (the study's cycles.py)
    # splits it using the status lines Cycles prints ("Time:mm:ss.ss | ... | Sample k/N"). Persistent data is
    # NOT used to skip the build: Blender 3.4 in background mode ignores changed integrator settings (samples,
    # seed) on a persistent re-render, so a warm-up render would be returned again.
    cycles = scene.cycles
    cycles.samples = int(args["samples"])
    t0, c0 = time.perf_counter(), time.process_time()
    bpy.ops.render.render()
    t1, c1 = time.perf_counter(), time.process_time()

    bpy.data.images["Render Result"].save_render(args["exr"], scene=scene)
    image = bpy.data.images.load(args["exr"])
    image.colorspace_settings.name = "Linear"  # EXR holds linear scene radiance; read it back unchanged
    w, h = image.size
    pixels = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(h, w, 4)[::-1].copy()  # Blender stores rows bottom-up; ours: row 0 = top
    np.save(args["npy"], pixels)
    with open(args["json"], "w") as f:
        json.dump({"operator_time": t1 - t0, "operator_cpu_time": c1 - c0, "blender_version": bpy.app.version_string,
                   "sampling_pattern": getattr(cycles, "sampling_pattern", None), "width": w, "height": h,
                   "samples": int(args["samples"]), "time_limit": cycles.time_limit}, f)
