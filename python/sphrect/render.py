"""The Embree direct-lighting renderer (C++), driven from a :class:`sphrect.Scene`.

Example::

    r = sphrect.Renderer(scene, techniques=["area", "rectangle"], mis="balance")
    r.render(64)                      # 64 more camera samples per pixel, all techniques
    img = r.image("rectangle")        # float32 [H, W, 4] RGBA, row 0 at the top
    r.stats("rectangle")              # samples, wall_time, light_time, shading_time, rays, ...

Light selection (light_selection, one of LIGHT_SELECTIONS): one emitter per light sample, chosen by
the v of the light sample's pattern point, which is then rescaled for the point on the light (so the
choice is stratified with the pattern).  "tree" (default): a light tree over the area lights
(rectangles, ellipses, emissive triangles) and, when there are more than MAX_DELTA_LIGHTS_BESIDE_TREE, the point
and spot lights picks one in proportion to an estimate of its contribution at the shading point (power, distance,
orientation), a TREE_FLUX_SHARE of the choices by flux so that no light starves; "ris": at surface hits,
ris_candidates (1..MAX_RIS_CANDIDATES) of the tree's choices with a point on each, one kept in proportion to its
unshadowed contribution over its pdf (resampled importance sampling; docs/light_selection_ris.md), scattering points
in a medium as "tree"; "power": an area light with probability proportional to its power (luminance x area x
sides), and point and spot lights evaluated once per camera sample each.  Suns are evaluated once per camera sample
with each.  Pixels are filtered as Camera.pixel_filter says (box, gaussian or blackman_harris of Camera.filter_width
pixels, as Cycles' Film > Pixel Filter): camera samples land around the pixel centre as the filter is distributed.

Disk and ellipse lights (ellipse_technique, one of ELLIPSE_TECHNIQUES, for every technique's pass):
"spherical_ellipse" (default) samples the solid angle they subtend with the area-preserving map of
the spherical ellipse (Guillen et al., EGSR 2017; sphrect.sample_ellipse); "area" uniformly by area.

Lights seen by the camera (analytic_light_coverage, default True): in pixels that a rectangle's or an
ellipse's image partly covers, the share it covers is computed exactly (a control variate: the image
stays unbiased, and the noise of its edges is left only where something occludes the light).  It
applies to a pinhole or orthographic camera with the 1-px box filter, outside a medium; False estimates it from
the camera samples as before.

MIS at diffuse hits (bsdf_samples_on_diffuse, default False): with MIS on and the lights sampled by
solid angle (every technique but "area", and ellipse_technique "spherical_ellipse"), a hit on a purely
diffuse (Lambert) material takes light samples alone, and BSDF samples only to find the background;
glossy and Principled hits keep both, and so does every hit of a scene with an emissive mesh (near its
small emitters only MIS keeps light samples from being fireflies).  True gives diffuse hits their BSDF
samples too.

Textured emitters (an emissive mesh whose Material.textures["emission"] drives its colour): evaluated per point
for camera rays, BSDF rays and light samples.  A textured rectangle (an image on a quad) is sampled by the power of
its blocks and the solid angle of each (emission_blocks, default True; every technique but "area"); False samples it
by the technique over the whole light.

The study's cost-model sweep (added_shading_cost and added_ray_cost, seconds, default 0): a busy wait at every surface
hit shaded and for every ray traced, a costlier shader's and a costlier scene's stand-ins that change no image
(sphrect.study.sweep).

Defaults (mis="power", pattern="sobol": best at equal samples; light_samples=2: best at equal time over
the blend_scenes, the lights in view and their edges' coverage exact): docs/renderer.md, "Light selection and
defaults".

Resources: the images (per technique RGB sums in double and the RGBA float image a caller copies out) must fit
memory_limit bytes (default None: sphrect.default_memory_limit(), half the physical memory), else ValueError
names the figures before anything is allocated; threads is at most MAX_THREADS.  cancel() stops the render in
progress at its next tile, or, called when none is running, the next render() call, which then returns False
at once: each cancel() stops exactly one render, so one from another thread just before render() is not lost.

Progressive rendering: each render() call (or each pass of a time budget) adds samples; the
'sobol' pattern continues one sequence across calls, the other patterns stratify within a call.
progress(done_tiles, total_tiles) counts the tiles of the current pass.  The image is identical
for any thread count and tile size (samples are seeded by seed, pixel and sample index).
"""
from __future__ import annotations

import dataclasses
import math
import numbers
import warnings
from typing import Callable, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np

from . import _native
from .arguments import int_argument, one_of, rgb
from .sample_ranges import Accumulation, sample_ranges
from .scene import (CAMERA_TYPES, PIXEL_FILTERS, SENSOR_FITS, TEXTURE_COLORSPACES, TEXTURE_INTERPOLATIONS,
                    WORLD_RAY_KINDS, Camera,
                    EllipseLight, Environment, Material, Medium, PointLight, RectLight, Scene, SpotLight, SunLight,
                    Texture, TextureLookup, Volume, World)

TECHNIQUES = tuple(_native.techniques)
PATTERNS = tuple(_native.patterns)
MIS_MODES = tuple(_native.mis_modes)
MEDIUM_SAMPLING = tuple(_native.medium_samplings)
LIGHT_SELECTIONS = tuple(_native.light_selections)
ELLIPSE_TECHNIQUES = tuple(_native.ellipse_techniques)

_MAX_SIDE = _native.MAX_IMAGE_SIDE
# Every render option's default, by keyword: one place, render/options.h's RenderOptions.  The add-on and the study
# read them from here too.
RENDER_DEFAULTS = dict(_native._render_defaults())
_DEFAULTS = RENDER_DEFAULTS


def _int_array(a, what: str, upper: Optional[int] = None) -> np.ndarray:
    """int32 copy-free when possible; range-checked before narrowing so nothing wraps around."""
    a = np.asarray(a)
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"{what} must be integers (got dtype {a.dtype})")
    if a.size:
        lo, hi = int(a.min()), int(a.max())
        if lo < 0 or (upper is not None and hi >= upper) or hi > np.iinfo(np.int32).max:
            bound = f"[0, {upper})" if upper is not None else "[0, 2^31)"
            raise ValueError(f"{what}: index out of range {bound} (min {lo}, max {hi})")
    return np.ascontiguousarray(a, dtype=np.int32)


def _set_camera(native, cam: Camera) -> None:
    """The camera to the native scene or renderer (their set_camera takes the same arguments)."""
    if not isinstance(cam, Camera):
        raise ValueError(f"camera must be a sphrect.Camera, got {type(cam).__name__}")
    for name in ("width", "height"):
        v = getattr(cam, name)
        if not isinstance(v, numbers.Integral) or not 1 <= int(v) <= _MAX_SIDE:
            raise ValueError(f"camera {name} must be an integer in 1..{_MAX_SIDE}, got {v!r}")
    if cam.type not in CAMERA_TYPES:
        raise ValueError(f"camera type must be {one_of(CAMERA_TYPES)}, got {cam.type!r}")
    if cam.sensor_fit not in SENSOR_FITS:
        raise ValueError(f"camera sensor_fit must be {one_of(SENSOR_FITS, quote=False)}, got {cam.sensor_fit!r}")
    for name in ("lens", "aperture_radius", "focus_distance", "clip_start", "clip_end"):
        v = getattr(cam, name)
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            raise ValueError(f"camera {name} must be a number, got {v!r}")
    if cam.type == "perspective" and not cam.lens > 0:
        raise ValueError("camera lens (focal length) must be positive")
    m = np.asarray(cam.to_world, dtype=np.float64)
    if m.shape != (4, 4):
        raise ValueError(f"camera to_world must be 4x4, got shape {m.shape}")
    if cam.pixel_filter not in PIXEL_FILTERS:
        raise ValueError(f"camera pixel_filter must be {one_of(PIXEL_FILTERS)}, got {cam.pixel_filter!r}")
    lo, hi = _native.MIN_PIXEL_FILTER_WIDTH, _native.MAX_PIXEL_FILTER_WIDTH
    if (isinstance(cam.filter_width, bool) or not isinstance(cam.filter_width, numbers.Real)
            or not lo <= float(cam.filter_width) <= hi):
        raise ValueError(f"camera filter_width must be a number of pixels in [{lo:g}, {hi:g}], "
                         f"got {cam.filter_width!r}")
    hw, hh, ox, oy = cam.image_plane()
    native.set_camera(int(cam.width), int(cam.height), m, cam.type == "orthographic", float(hw), float(hh),
                      float(ox), float(oy), float(cam.aperture_radius), float(cam.focus_distance),
                      float(cam.clip_start), float(min(cam.clip_end, 1e30)), cam.pixel_filter, float(cam.filter_width))


def _add_textures(native, scene: Scene) -> None:
    """The scene's images, in order (a path read by OpenImageIO natively: a missing file is magenta and warned)."""
    for i, t in enumerate(scene.textures):
        if not isinstance(t, Texture):
            raise ValueError(f"scene.textures[{i}] is not a sphrect.Texture")
        if t.colorspace not in TEXTURE_COLORSPACES:
            raise ValueError(f"texture '{t.name}': colorspace must be {one_of(TEXTURE_COLORSPACES)}, "
                             f"got {t.colorspace!r}")
        srgb = t.colorspace == "srgb"
        if t.pixels is None:
            if not t.path:
                raise ValueError(f"texture '{t.name}' has neither pixels nor a path")
            native.load_image(t.name, str(t.path), srgb)
            continue
        pixels = np.asarray(t.pixels)
        if pixels.ndim == 2:
            pixels = pixels[:, :, None]
        if pixels.dtype != np.uint8:
            if np.issubdtype(pixels.dtype, np.unsignedinteger):  # e.g. a 16-bit PNG: its values over its range
                pixels = pixels / np.float64(np.iinfo(pixels.dtype).max)
            elif not np.issubdtype(pixels.dtype, np.floating):
                raise ValueError(f"texture '{t.name}': pixels must be uint8, another unsigned integer type (read "
                                 f"over its range) or floats, got dtype {pixels.dtype}")
            pixels = np.ascontiguousarray(pixels, dtype=np.float32)
        native.add_image(t.name, np.ascontiguousarray(pixels), srgb)


def _set_environment(native, env, n_textures: int, field: str = "environment") -> None:
    """An image world (scene.world.environment, or `field` 'camera_environment') to the native scene, after its
    textures."""
    what = "world " + field.replace("_", " ")
    if not isinstance(env, Environment):
        raise ValueError(f"scene.world.{field} must be a sphrect.Environment, got {type(env).__name__}")
    if isinstance(env.texture, bool) or not isinstance(env.texture, numbers.Integral) \
            or not 0 <= int(env.texture) < n_textures:
        raise ValueError(f"{what} texture must be an index into scene.textures (it has {n_textures}), "
                         f"got {env.texture!r}")
    if env.interpolation not in TEXTURE_INTERPOLATIONS:
        raise ValueError(f"{what} interpolation must be {one_of(TEXTURE_INTERPOLATIONS)}, "
                         f"got {env.interpolation!r}")
    try:
        m = np.asarray(env.to_world, dtype=np.float64)
    except (TypeError, ValueError):
        m = None
    if m is None or m.shape != (3, 3) or not np.all(np.isfinite(m)) or not np.allclose(m @ m.T, np.eye(3), atol=1e-5) \
            or not np.linalg.det(m) > 0:
        raise ValueError(f"{what} to_world must be a 3x3 rotation (orthonormal, determinant +1), "
                         f"got {env.to_world!r}")
    setter = native.set_environment if field == "environment" else native.set_camera_environment
    setter(int(env.texture), rgb(env.strength, what + " strength"), m, env.interpolation)


def _triangle_arrays(vertices, triangles, what: str):
    """(vertices, int32 triangles) of a mesh or a volume, checked: numbers of shape [V, 3], indices [T, 3] of them."""
    v = np.asarray(vertices)
    if v.ndim != 2 or v.shape[1] != 3 or (v.size and not np.issubdtype(v.dtype, np.number)):
        raise ValueError(f"{what}: vertices must have shape [V, 3], got {v.shape}")
    t = np.asarray(triangles)
    if t.ndim != 2 or t.shape[1] != 3:
        raise ValueError(f"{what}: triangles must have shape [T, 3], got {t.shape}")
    return v, _int_array(t, f"{what} triangles", upper=len(v))


def _add_volume(native, volume, index: int) -> None:
    """scene.volumes[index] to the native scene (which checks that it is closed and its coefficients)."""
    if not isinstance(volume, Volume):
        raise ValueError(f"scene.volumes[{index}] is not a sphrect.Volume (got {type(volume).__name__})")
    what = f"volume '{volume.name}'"
    v, t = _triangle_arrays(volume.vertices, volume.triangles, what)
    med = volume.medium
    if not isinstance(med, Medium):
        raise ValueError(f"{what}: medium must be a sphrect.Medium, got {type(med).__name__}")
    native.add_volume(str(volume.name), np.ascontiguousarray(v, dtype=np.float32), t,
                      rgb(med.sigma_s, what + " sigma_s"), rgb(med.sigma_a, what + " sigma_a"), float(med.g))


def _add_material(native, mat, index: int, slots) -> None:
    """scene.materials[index] to the native scene: its fields, read and checked there (render/material.h); its
    programs' attribute names become the scene's attribute `slots` (name -> index, grown here)."""
    if not isinstance(mat, Material):
        raise ValueError(f"scene.materials[{index}] is not a sphrect.Material (got {type(mat).__name__})")
    _refuse_layer_cycles(mat, [])
    fields = dataclasses.asdict(mat)
    _slot_attributes(fields, slots)
    native.add_material(fields)


def _slot_attributes(fields, slots) -> None:
    """Rewrites, in a material's fields (dataclasses.asdict), each program's 'attribute' instructions to read the
    scene's slot of the name they read (NodeProgram.attributes[data]): the renderer knows attributes by slot."""
    if isinstance(fields, dict):
        if "instructions" in fields and "attributes" in fields:
            names = fields["attributes"]
            for i in fields["instructions"]:
                if i.get("op") == "attribute":
                    data = i.get("data")
                    if not isinstance(data, int) or not 0 <= data < len(names) or not isinstance(names[data], str):
                        raise ValueError(f"an 'attribute' instruction's data {data!r} names none of the program's "
                                         f"attributes {names!r}")
                    i["data"] = slots.setdefault(names[data], len(slots))
            return
        for v in fields.values():
            _slot_attributes(v, slots)
    elif isinstance(fields, (list, tuple)):
        for v in fields:
            _slot_attributes(v, slots)


def _add_mesh_program_inputs(native, mesh, slots) -> None:
    """The last mesh's attributes that programs read (by slot) and its object's Object Info."""
    fac_x = set(mesh.attributes_fac_x)
    for name, values in (mesh.attributes or {}).items():
        if name in slots:
            a = np.ascontiguousarray(values, dtype=np.float32)
            if a.ndim != 2 or a.shape != (len(mesh.vertices), 4) or not np.isfinite(a).all():
                raise ValueError(f"mesh '{mesh.name}': attribute '{name}' must be a finite [V, 4] array")
            native.set_last_mesh_attribute(slots[name], a, name in fac_x)
    color = tuple(float(x) for x in mesh.object_color)
    if len(color) != 4:
        raise ValueError(f"mesh '{mesh.name}': object_color must be RGBA")
    if color != (1.0, 1.0, 1.0, 1.0) or mesh.object_index or mesh.object_random or mesh.corners_reversed:
        native.set_last_mesh_object_info(color[:3], color[3], float(mesh.object_index), float(mesh.object_random),
                                         bool(mesh.corners_reversed))


def _refuse_layer_cycles(mat, path) -> None:
    """ValueError naming the materials of a cycle of mix layers (a material among its own layers)."""
    if any(m is mat for m in path):
        names = " -> ".join(f"'{m.name}'" for m in path[next(i for i, m in enumerate(path) if m is mat):] + [mat])
        raise ValueError(f"material '{path[0].name}': its layers hold it again ({names})")
    for layer in getattr(mat, "layers", None) or ():
        child = getattr(layer, "material", None)
        if isinstance(child, Material):
            _refuse_layer_cycles(child, path + [mat])


def mix_lobe_slots(materials: Sequence[Material]) -> List[int]:
    """For materials mixed together (a 'mix' material's layers): the index of the distinct microfacet lobe each one's
    glossy or glass lobe takes in the mix, equal lobes sharing one as the renderer merges them, or -1 for one without
    such a lobe.  A mix holds MAX_MIX_GLOSSY_LOBES distinct lobes (the Blender exporter keeps the heaviest)."""
    return list(_native._mix_lobe_slots([dataclasses.asdict(m) for m in materials]))


def build_native_scene(scene: Scene, image_memory_limit: int = 0):
    """A committed ``_native._Scene`` for `scene`, and the list of skipped-light messages.  Its textures may take
    image_memory_limit bytes together (0: no limit), each checked before it is copied or decoded (ValueError)."""
    if not isinstance(scene, Scene):
        raise ValueError(f"expected a sphrect.Scene, got {type(scene).__name__}")
    if not isinstance(scene.world, World):
        raise ValueError(f"scene.world must be a sphrect.World, got {type(scene.world).__name__}")
    native = _native._Scene()
    skipped = []
    _set_camera(native, scene.camera)
    native.set_background(rgb(scene.world.background, "world background"))
    hidden = tuple(scene.world.invisible_to)
    if any(k not in WORLD_RAY_KINDS for k in hidden):
        raise ValueError(f"world invisible_to must name kinds of {one_of(WORLD_RAY_KINDS)}, got {hidden!r}")
    if hidden:
        native.set_world_visibility(list(hidden))
    native.set_film_transparent(bool(scene.camera.film_transparent))
    med = scene.world.medium
    if med is not None:
        native.set_medium(rgb(med.sigma_s, "medium sigma_s"), rgb(med.sigma_a, "medium sigma_a"), float(med.g))
    for i, volume in enumerate(scene.volumes):
        _add_volume(native, volume, i)
    native.set_image_memory_limit(max(0, int(image_memory_limit)))
    _add_textures(native, scene)
    if scene.world.environment is not None:
        _set_environment(native, scene.world.environment, len(scene.textures))
    if scene.world.camera_environment is not None:
        _set_environment(native, scene.world.camera_environment, len(scene.textures), "camera_environment")
    slots = {}  # attribute name -> the scene's slot (programs read attributes by slot)
    for i, mat in enumerate(scene.materials):
        _add_material(native, mat, i, slots)
    n_materials = max(1, len(scene.materials))
    for mesh in scene.meshes:
        v, t = _triangle_arrays(mesh.vertices, mesh.triangles, f"mesh '{mesh.name}'")
        ids = None
        if mesh.material_ids is not None:
            ids = _int_array(mesh.material_ids, f"mesh '{mesh.name}' material_ids", upper=n_materials)
        linear = None
        if mesh.object_linear is not None:
            linear = np.asarray(mesh.object_linear, dtype=np.float64)
            if linear.shape != (3, 3) or not np.all(np.isfinite(linear)) or not abs(np.linalg.det(linear)) > 0:
                raise ValueError(f"mesh '{mesh.name}': object_linear must be an invertible finite 3x3 matrix")
        offset = mesh.shadow_terminator_offset
        if isinstance(offset, bool) or not isinstance(offset, (int, float)) or not 0 <= offset <= 1:
            raise ValueError(f"mesh '{mesh.name}': shadow_terminator_offset must be a number in [0, 1], got {offset!r}")
        native.add_mesh(mesh.name, v, t, mesh.normals, ids, mesh.uvs, mesh.generated, list(mesh.invisible_to))
        if linear is not None and len(t):  # a mesh without triangles is not kept
            translation = (0.0, 0.0, 0.0) if mesh.object_translation is None else mesh.object_translation
            native.set_last_mesh_object_linear(linear, np.linalg.inv(linear),
                                               tuple(float(x) for x in translation))
        if offset and len(t):
            native.set_last_mesh_shadow_terminator_offset(float(offset))
        if len(t):
            _add_mesh_program_inputs(native, mesh, slots)
    for light in scene.lights:
        msg = ""
        # What every light lights and how (scene.LightVisibility's fields).
        vis = dict(invisible_to=list(getattr(light, "invisible_to", ())),
                   cast_shadow=bool(getattr(light, "cast_shadow", True)), use_mis=bool(getattr(light, "use_mis", True)))
        if isinstance(light, RectLight):
            msg = native.add_rect_light(rgb(light.corner, "corner"), rgb(light.edge_x, "edge_x"),
                                        rgb(light.edge_y, "edge_y"), rgb(light.radiance, "radiance"),
                                        bool(light.two_sided), bool(light.visible), float(light.spread), **vis)
        elif isinstance(light, EllipseLight):
            msg = native.add_ellipse_light(rgb(light.center, "center"), rgb(light.axis_x, "axis_x"),
                                           rgb(light.axis_y, "axis_y"), rgb(light.radiance, "radiance"),
                                           bool(light.two_sided), bool(light.visible), float(light.spread), **vis)
        elif isinstance(light, PointLight):
            native.add_point_light(rgb(light.position, "position"), rgb(light.intensity, "intensity"),
                                   float(light.radius), bool(light.visible), **vis)
        elif isinstance(light, SpotLight):
            native.add_spot_light(rgb(light.position, "position"), rgb(light.direction, "direction"),
                                  rgb(light.intensity, "intensity"), float(light.spot_size), float(light.spot_blend),
                                  float(light.radius), bool(light.visible), **vis)
        elif isinstance(light, SunLight):
            native.add_sun_light(rgb(light.direction, "direction"), rgb(light.irradiance, "irradiance"),
                                 float(light.angle), bool(light.visible), **vis)
        else:
            raise ValueError(f"unknown light type {type(light).__name__}")
        texture = getattr(light, "texture", None)  # a rectangle's or an ellipse's (RectLight.texture)
        if texture is not None and not msg:
            if not isinstance(texture, TextureLookup):
                raise ValueError(f"light '{light.name}': texture must be a sphrect.TextureLookup or None, got "
                                 f"{type(texture).__name__}")
            native.set_last_light_texture(dataclasses.asdict(texture))
        if msg:
            skipped.append(f"light '{getattr(light, 'name', '?')}': {msg}")
    native.commit()
    skipped.extend(native.warnings)
    return native, skipped


def dropped_samples_message(dropped: int) -> str:
    """What a render that left `dropped` non-finite samples out of its image says (stats' dropped_samples)."""
    return (f"{dropped} samples were not finite (NaN or infinite) and were left out of the image: some input is "
            "beyond what float32 computes (an emission, an IOR, a coordinate)")


class Renderer:
    """Progressive direct-lighting renderer of a :class:`sphrect.Scene` with one or more
    light-sampling techniques sharing camera rays and first hits (see the module docstring)."""

    def __init__(self, scene: Scene, techniques: Union[str, Sequence[str]] = _DEFAULTS["techniques"],
                 light_samples: int = _DEFAULTS["light_samples"], pattern: str = _DEFAULTS["pattern"],
                 mis: str = _DEFAULTS["mis"], seed: int = _DEFAULTS["seed"], threads: int = _DEFAULTS["threads"],
                 medium_sampling: str = _DEFAULTS["medium_sampling"], tile_size: int = _DEFAULTS["tile_size"],
                 light_selection: str = _DEFAULTS["light_selection"],
                 ellipse_technique: str = _DEFAULTS["ellipse_technique"],
                 analytic_light_coverage: bool = _DEFAULTS["analytic_light_coverage"],
                 bsdf_samples_on_diffuse: bool = _DEFAULTS["bsdf_samples_on_diffuse"],
                 memory_limit: Optional[int] = _DEFAULTS["memory_limit"],
                 emission_blocks: bool = _DEFAULTS["emission_blocks"],
                 added_shading_cost: float = _DEFAULTS["added_shading_cost"],
                 added_ray_cost: float = _DEFAULTS["added_ray_cost"],
                 ris_candidates: int = _DEFAULTS["ris_candidates"]):
        if not isinstance(scene, Scene):
            raise ValueError(f"expected a sphrect.Scene, got {type(scene).__name__}")
        if isinstance(techniques, str):
            techniques = [techniques]
        techniques = list(techniques)
        if not techniques:
            raise ValueError("at least one technique is needed")
        for t in techniques:
            if not isinstance(t, str):
                raise ValueError(f"techniques must be names ({one_of(TECHNIQUES)}), got {t!r}")
        if not isinstance(scene.camera, Camera):
            raise ValueError(f"camera must be a sphrect.Camera, got {type(scene.camera).__name__}")
        light_samples = int_argument("light_samples", light_samples, 1, _native.MAX_LIGHT_SAMPLES)
        ris_candidates = int_argument("ris_candidates", ris_candidates, 1, _native.MAX_RIS_CANDIDATES)
        threads = int_argument("threads", threads, 0, _native.MAX_THREADS)
        tile_size = int_argument("tile_size", tile_size, 1)
        seed = int_argument("seed", seed, 0, 2 ** 64 - 1)
        memory_limit = 0 if memory_limit is None else int_argument("memory_limit", memory_limit, 1, 2 ** 64 - 1)
        # Before the scene is built (its BVH can take long): the images must fit the memory limit.
        _native.check_render_memory(len(techniques), int(scene.camera.width), int(scene.camera.height),
                                    memory_limit)
        film = _native.render_memory_bytes(len(techniques), int(scene.camera.width), int(scene.camera.height))
        # What the limit leaves beside the film (at least 1 byte: 0 would mean no limit for the textures).
        native, skipped = build_native_scene(scene, max(1, (memory_limit or _native.default_memory_limit()) - film))
        for msg in skipped:
            warnings.warn(msg, RuntimeWarning, stacklevel=2)
        self._scene = native
        self._film_transparent = bool(scene.camera.film_transparent)
        self._r = _native._Renderer(native, techniques, light_samples, str(pattern), str(mis), str(medium_sampling),
                                    str(light_selection), str(ellipse_technique), seed, threads, tile_size,
                                    bool(analytic_light_coverage), bool(bsdf_samples_on_diffuse), memory_limit,
                                    bool(emission_blocks), float(added_shading_cost), float(added_ray_cost),
                                    ris_candidates)
        self._techniques = techniques
        self._memory_limit = memory_limit

    @property
    def techniques(self):
        return list(self._techniques)

    @property
    def features(self):
        """Effects the scene calls for and the kernel simulates (e.g. 'glossy', 'medium', 'dof')."""
        return list(self._r.features)

    @property
    def resolution(self):
        return self._r.width, self._r.height

    def _index(self, technique) -> int:
        if technique is None:
            return 0
        if isinstance(technique, numbers.Integral):
            if not 0 <= technique < len(self._techniques):
                raise ValueError(f"technique index {technique} out of range")
            return int(technique)
        try:
            return self._techniques.index(technique)
        except ValueError:
            raise ValueError(f"technique {technique!r} is not rendered by this Renderer "
                             f"(it renders {self._techniques})") from None

    def render(self, samples: int, time_budget: Optional[float] = None,
               progress: Optional[Callable[[int, int], None]] = None) -> bool:
        """Add `samples` camera samples per pixel (or passes of them until `time_budget` seconds
        are spent).  progress(done_tiles, total_tiles) runs on this thread.  False if cancelled.

        The budget counts whole passes: the first pass always runs to its end, so a budget shorter than one pass
        of `samples` is overrun by that pass; later passes start only while one more would more likely end
        within the budget than not.  For a tight bound, make a pass short (samples=1)."""
        samples = int_argument("samples", samples, 1, _native.MAX_SAMPLES_PER_CALL)
        budget = 0.0
        if time_budget is not None:
            budget = float(time_budget)
            if not (budget > 0 and math.isfinite(budget)):
                raise ValueError(f"time_budget must be a positive number of seconds, got {time_budget!r}")
        dropped_before = self._dropped_samples()
        finished = self._r.render(samples, budget, progress)
        dropped = self._dropped_samples() - dropped_before
        if dropped:
            warnings.warn(dropped_samples_message(dropped), RuntimeWarning, stacklevel=2)
        return finished

    def _dropped_samples(self) -> int:
        return sum(int(self._r.stats(k)["dropped_samples"]) for k in range(len(self._techniques)))

    def start_at(self, first_sample: int, pass_index: int) -> None:
        """Make the next render() call render camera samples [first_sample, first_sample + samples) as pass
        `pass_index` of a longer render, exactly as that render's own pass does (sample_ranges.py). Only
        before anything is rendered (RuntimeError otherwise)."""
        first_sample = int_argument("first_sample", first_sample, 0, _native.SAMPLE_INDEX_LIMIT - 1)
        pass_index = int_argument("pass_index", pass_index, 0, 2 ** 32 - 1)
        self._r.start_at(first_sample, pass_index)

    def accumulation(self):
        """The buffers the images are the means of (a sample_ranges.Accumulation): merging several renderers'
        disjoint sample ranges of one render gives exactly that render's image."""
        return Accumulation({t: self._r.sums(k) for k, t in enumerate(self._techniques)}, self._r.counts(),
                            self._r.alpha_sums(), bool(self._r.film_alpha))

    def set_camera(self, camera: Camera) -> None:
        """Render from `camera` from now on, with the same scene (its BVH, lights and light tree are kept: a view
        change costs only the lights' images on the new film).  The images start again, empty, at the camera's
        resolution, as a new Renderer's would: samples, stats and the sample sequence too, so the images equal a
        new Renderer's of the scene with this camera, bit for bit.  ValueError for a camera the scene could not
        take (as Renderer(scene) would say) or whose film_transparent differs from the scene's (a property of the
        scene: build a new Renderer); RuntimeError while render() runs."""
        if not isinstance(camera, Camera):
            raise ValueError(f"camera must be a sphrect.Camera, got {type(camera).__name__}")
        if bool(camera.film_transparent) != self._film_transparent:
            raise ValueError("camera film_transparent differs from the scene's: it is the scene's setting, "
                             "so a new Renderer is needed to change it")
        _native.check_render_memory(len(self._techniques), int(camera.width), int(camera.height), self._memory_limit)
        _set_camera(self._r, camera)

    def cancel(self) -> None:
        """Stop the render() in progress at its next tile, or, if none is, the next render() call before it
        renders anything (thread-safe; each cancel stops one render)."""
        self._r.cancel()

    def image(self, technique=None) -> np.ndarray:
        """float32 [H, W, 4] RGBA, row 0 at the top: the mean of the samples so far.  Alpha is the film's: 1 but
        where the camera sees a 'holdout' material, or escapes with Camera.film_transparent."""
        return self._r.image(self._index(technique))

    def stats(self, technique=None) -> dict:
        """samples, wall_time (s, shared), light_time and shading_time (thread-seconds of this
        technique), trace_time (the part of shading_time tracing its rays: the occlusion stream, and the emitter
        search of BSDF rays in a scene with emissive meshes), rays (its shadow/BSDF rays),
        camera_time, camera_trace_time (the part tracing the camera rays), tile_time (the tiles whole: every stage and
        technique, the image's accumulation), camera_rays and surface_hits (camera rays that hit a surface; all
        shared), dropped_samples (non-finite samples left out of the image; expected 0)."""
        return dict(self._r.stats(self._index(technique)))


def render(scene: Scene, samples: int = 16, techniques: Union[str, Iterable[str]] = _DEFAULTS["techniques"],
           parts: int = 1, **kw) -> Dict[str, np.ndarray]:
    """Render `scene` with each technique; {technique: float32 [H, W, 4]}. `parts` > 1 renders the samples as
    that many passes (sample_ranges.sample_ranges), as sphrect.render_distributed does on a cluster."""
    ranges = sample_ranges(int_argument("samples", samples, 1), int_argument("parts", parts, 1))
    r = Renderer(scene, techniques=techniques, **kw)
    for sample_range in ranges:
        r.render(sample_range.samples)
    return {t: r.image(t) for t in r.techniques}
