"""Scene description shared by the renderer, the Blender exporter and scripts.

Everything is in world space and in radiometric units, so the renderer needs no
Blender conventions: Blender's light powers are converted once, by the functions
below (area_light_radiance, point_light_intensity, sun_irradiance) that the
exporter and RectLight.from_power call.

Scene file format (``.sphrect.npz``, written by :func:`save_scene`, read by
:func:`load_scene`): a NumPy ``.npz`` archive holding

* ``scene.json`` -- a UTF-8 JSON document: ``{"format": "sphrect-scene",
  "version": 5, "camera": {...}, "world": {...}, "materials": [...],
  "lights": [{"type": "rect"|"ellipse"|"point"|"spot"|"sun", ...}, ...],
  "meshes": [{"name": ..., "arrays": "mesh0"[, "invisible_to": [...]]}, ...]}`` with the fields of the
  dataclasses below (version 1, before Material.emission, loads with emission 0;
  version 2, before the 'principled' kind, with its fields at their defaults; version 3, before the
  'glass' kind and Material.ior, distribution; version 4, before the 'glossy_bsdf' and 'mix' kinds and
  Material.layers);
* for mesh *i*: ``mesh{i}.vertices`` (float32 [V,3]), ``mesh{i}.triangles``
  (int32 [T,3]), and optionally ``mesh{i}.normals`` (float32 [V,3]) and
  ``mesh{i}.material_ids`` (int32 [T]), ``mesh{i}.uvs`` (float32 [V,2]), ``mesh{i}.generated``
  (float32 [V,3]);
* for volume *i* (``"volumes": [{"name": ..., "arrays": "volume0", "medium": {...}}, ...]``): ``volume{i}.vertices``
  (float32 [V,3]) and ``volume{i}.triangles`` (int32 [T,3]);
* for texture *i* with pixels: ``texture{i}.pixels`` (uint8 or float32 [H,W,C]); a texture without them has a
  ``path``, relative to the file's folder unless absolute.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

import numpy as np

from . import _native, scene_file
from .fileio import atomic_write

FORMAT_NAME = "sphrect-scene"
# 2: Material.emission (emissive meshes).  Version-1 files load unchanged (emission 0); readers of
# version 1 refuse version-2 files with a clear message instead of failing on the new field.
# 3: Material kind 'principled' and its fields specular_tint, sheen, sheen_tint, clearcoat,
# clearcoat_roughness.  Older files load unchanged: their kinds 'diffuse' / 'glossy' render as before.
# 4: Material kind 'glass' (Cycles' Glass BSDF at zero bounces) and its fields ior, distribution.  Older files
# load unchanged.
# 5: Material kinds 'glossy_bsdf' (Cycles' Glossy BSDF) and 'mix' (Mix / Add Shader: Material.layers, each a
# MaterialLayer of a weight and a material).  Older files load unchanged.
# 6: Material kinds 'translucent' (Cycles' Translucent BSDF) and 'holdout', Camera.film_transparent; Scene.textures
# (Texture: image pixels in the file, or a path loaded with OpenImageIO), Material.textures,
# normal_map, normal_map_strength and MaterialLayer.factors (TextureLookup), Mesh.uvs, generated and object_linear.
# Older files load unchanged (no textures).
# 7: Material kind 'transparent' (Blender's Transparent BSDF: camera and shadow rays go through, filtered by its
# colour; with a mix, a Principled BSDF's Alpha).  Older files load unchanged.
# 8: Camera.pixel_filter, filter_width (Cycles' Film > Pixel Filter: box, gaussian, blackman_harris).  Older files
# load as a box of width 1, the only filter before.
# 9: Material.anisotropic, anisotropic_rotation (Principled Anisotropic, the Anisotropic BSDF) and the 'principled'
# and 'glossy_bsdf' distribution 'multiscatter_ggx', Material.transmission ('principled', with its ior).
# Older files load unchanged (isotropic GGX, no transmission).
# 10: PointLight.radius, SpotLight.radius, SunLight.angle (soft lights, as Cycles 3.4's) and their visible.  Older
# files load as before: radius and angle 0, delta lights.
# 11: RectLight.spread, EllipseLight.spread (Blender's Spread, radians).  Older files load with spread = pi (none).
# 12: World.environment (an equirectangular image world).  Older files load without one (the constant background).
# 13: Material.textures["emission"] (TEXTURED_INPUTS' 'emission'): an image that multiplies the emission at each point
# of the emitter (textured emitters).  Older files load unchanged (constant emission).
# 14: Mesh.invisible_to and every light's invisible_to, cast_shadow, use_mis (Blender's Ray Visibility, a light's
# Cast Shadow and Multiple Importance, as Cycles 3.4 honours them).  Older files load with everything visible.
# 15: Mesh.shadow_terminator_offset (Blender's Shadow Terminator Geometry Offset).  Older files load with 0 (none).
# 16: RectLight.texture, EllipseLight.texture (an image over the light: a Blender light's node tree).  Older files load
# without (uniform lights).
# 17: World.invisible_to (Blender's World > Ray Visibility).  Older files load with the world seen by every ray.
# 18: Material.programs and MixFactor.program (NodeProgram: a shader node graph compiled for the renderer, Cycles'
# SVM), Mesh.object_translation.  Older files load unchanged (no programs).
# Material.diffuse_roughness (the Diffuse BSDF's Roughness: Oren-Nayar); older files load with 0 (Lambert).
# 19: World.camera_environment (what camera rays see of a world whose Light Path node shows them something else).
# Older files load without one (camera rays see the world's light).
# 19 also: Material.normal_program (a Bump node's graph driving the shading normal) and the node op 'bump'.  Older
# files load unchanged (no normal program).
# 19 also: Mesh.attributes, attributes_fac_x, object_color, object_index, object_random, corners_reversed and
# NodeProgram.attributes (the Attribute, Color Attribute, Object Info and Geometry nodes).  Older files load without
# attributes, object colour white.
# 20: Scene.volumes (Volume: a homogeneous medium bounded by a closed mesh, Blender's object volumes).  Older files
# load without volumes.
FORMAT_VERSION = 20

RGB = Tuple[float, float, float]
V3 = Tuple[float, float, float]

# The values the format's name fields take (the renderer's lists: native/render/material.h).
MATERIAL_KINDS = tuple(_native.material_kinds)  # ("diffuse", "glossy", "principled", ..., "mix")
# Cycles' microfacet distributions the 'glass' and 'glossy_bsdf' kinds evaluate (ggx, beckmann).
GLASS_DISTRIBUTIONS = tuple(_native.glass_distributions)
# The Principled BSDF's: GGX, or Cycles' multiple-scattering GGX (Heitz et al. 2016) above roughness 0.075; the
# Glossy BSDF's (kind 'glossy_bsdf') adds it to the glass ones.
PRINCIPLED_DISTRIBUTIONS = tuple(_native.principled_distributions)
GLOSSY_DISTRIBUTIONS = tuple(_native.glossy_distributions)
CAMERA_TYPES = ("perspective", "orthographic")
PIXEL_FILTERS = tuple(_native.pixel_filters)  # ("box", "gaussian", "blackman_harris"): render/pixel_filter.h
# Image Texture nodes (Cycles 3.4's image lookups): the colour space of a texture's stored values ('srgb': decoded
# to linear after filtering, as Cycles does for byte images; 'linear': used as stored, Blender's Non-Color and
# Linear), the node's interpolation and extension, and the coordinates it reads.
TEXTURE_COLORSPACES = ("srgb", "linear")
TEXTURE_INTERPOLATIONS = tuple(_native.texture_interpolations)  # ("linear", "closest"): render/material.h
TEXTURE_EXTENSIONS = tuple(_native.texture_extensions)          # ("repeat", "extend", "clip")
TEXTURE_COORDINATES = tuple(_native.texture_coordinates)  # ("uv", "generated")
TEXTURE_OUTPUTS = tuple(_native.texture_outputs)  # ("color", "alpha")
# The material inputs a texture can drive (Material.textures' keys): 'base_color' is a colour (its Color output
# as is, Alpha as grey), the others scalars (Color as its luminance, Cycles' rgb_to_gray, or Alpha).
TEXTURED_INPUTS = tuple(_native.textured_inputs)  # ("base_color", "roughness", "metallic", "specular")
# Node programs (NodeProgram, render/svm/program.h): the ops, the hit inputs a 'global' reads, and each op's modes.
NODE_OPS = tuple(_native.node_ops)
NODE_GLOBALS = tuple(_native.node_globals)
NODE_CONVERSIONS = tuple(_native.node_conversions)
NODE_MATH_OPS = tuple(_native.node_math_ops)          # Blender's Math operations
NODE_MIX_BLENDS = tuple(_native.node_mix_blends)      # Blender's blend types
NODE_CLAMP_TYPES = tuple(_native.node_clamp_types)
NODE_MAP_RANGE_TYPES = tuple(_native.node_map_range_types)
NODE_IMAGE_PROJECTIONS = tuple(_native.node_image_projections)  # an Image Texture node's, in a program
NODE_COLOR_MODELS = tuple(_native.node_color_models)
NODE_MAPPING_TYPES = tuple(_native.node_mapping_types)
NODE_ATTRIBUTE_NODES = tuple(_native.node_attribute_nodes)  # the 'attribute' op's modes: which node reads it
MAX_NODE_REGISTERS = int(_native.MAX_NODE_REGISTERS)
SENSOR_FITS = ("AUTO", "HORIZONTAL", "VERTICAL")  # Blender's
# Blender's Ray Visibility (Object Properties > Visibility), the renderer's ray kinds (render/ray_visibility.h):
# ("camera", "shadow", "diffuse", "glossy", "transmission", "volume_scatter").  A mesh's invisible_to names the rays
# that pass through it; a light's the ones it does not light (camera: not seen, as visible = False; never "shadow":
# its cast_shadow).
RAY_KINDS = tuple(_native.ray_kinds)
# The kinds a world can hide from (all but 'shadow': Blender's World > Ray Visibility).
WORLD_RAY_KINDS = tuple(k for k in RAY_KINDS if k != "shadow")


# Blender's light power -> radiometric units, with Cycles 3.4's conventions (power P in Blender's watts,
# colour c; the Cycles parity tests in tests/blender check them): an area light of area A has the radiance
# L = P c / (4 A) on each side it emits; point and spot lights the intensity I = P c / (4 pi); a sun's
# strength is its irradiance, E = strength * c. Computed in float64 in the order written (P * c first).
def area_light_radiance(power: float, color, area: float) -> RGB:
    return _rgb_tuple(power * np.asarray(color, dtype=np.float64) / (4.0 * area))


def point_light_intensity(power: float, color) -> RGB:
    return _rgb_tuple(power * np.asarray(color, dtype=np.float64) / (4.0 * math.pi))


def sun_irradiance(strength: float, color) -> RGB:
    return _rgb_tuple(strength * np.asarray(color, dtype=np.float64))


def _rgb_tuple(v) -> RGB:
    return tuple(float(x) for x in v)


@dataclass
class Material:
    """kind 'diffuse': Lambert; 'glossy': Lambert + GGX with Schlick Fresnel (the common part of Principled
    BSDF, the model before 'principled'); 'principled': Blender's Principled BSDF as Cycles 3.4 evaluates it
    (Burley diffuse with retro-reflection, GGX specular with Cycles' Fresnel blend and tint, sheen, clearcoat;
    the fields below are the node's inputs of the same names); 'glass': Blender's Glass BSDF (base_color =
    its Color, roughness, ior, distribution) as Cycles 3.4 shows it at zero bounces -- the microfacet reflection
    of the lights weighted by the dielectric Fresnel of the view, the transmitted part black; 'glossy_bsdf':
    Blender's Glossy BSDF (base_color = its Color, roughness, distribution), Cycles 3.4's microfacet reflection
    with no Fresnel; 'translucent': Blender's Translucent BSDF (base_color = its Color), Lambertian transmission,
    lit through the surface from the side opposite the viewer; 'holdout': Blender's Holdout, black and of alpha 0
    in the image (in a mix, alpha 1 - its weight); 'transparent': Blender's Transparent BSDF (base_color = its
    Color), which camera and shadow rays go straight through, filtered by the colour (a Principled BSDF's Alpha a is
    a 'mix' of it, white, weighted 1 - a and of the Principled weighted a, as Cycles expands it); 'mix': Mix / Add
    Shader, the sum of `layers`' materials each scaled by its weight (Cycles
    scales each side's closures: (1 - fac) and fac for Mix, 1 and 1 for Add).  A mix holds any number of
    'diffuse' layers, one 'principled' (or a mix holding one), and at most MAX_MIX_GLOSSY_LOBES distinct
    'glass' / 'glossy_bsdf' lobes (equal roughness, distribution and IOR merge); not 'glossy'.  Its own
    emission adds to its layers' (each scaled by its weight)."""
    name: str = "default"
    kind: str = "diffuse"            # one of MATERIAL_KINDS
    base_color: RGB = (0.8, 0.8, 0.8)
    roughness: float = 0.5           # Blender's roughness; GGX alpha = roughness**2
    # 'diffuse' (and a mix's 'diffuse' layers): the Diffuse BSDF's Roughness, 0 Lambert, else Cycles 3.4's Oren-Nayar
    # of sigma = min(diffuse_roughness, 1).
    diffuse_roughness: float = 0.0
    metallic: float = 0.0
    specular: float = 0.5            # Principled 'Specular': F0 = 0.08 * specular for dielectrics
    specular_tint: float = 0.0       # 'principled' only, like the four below (Blender's defaults)
    sheen: float = 0.0
    sheen_tint: float = 0.5
    clearcoat: float = 0.0
    clearcoat_roughness: float = 0.03
    # 'principled': the node's Anisotropic and Anisotropic Rotation (turns); 'glossy_bsdf': the Anisotropic BSDF's
    # Anisotropy and Rotation (0 for a Glossy BSDF; GGX only).  Both stretch the GGX lobe along the mesh's tangent
    # as Cycles does, the tangent being Cycles' default: radial about the object's Z axis from Mesh.generated.
    anisotropic: float = 0.0
    anisotropic_rotation: float = 0.0
    ior: float = 1.45                # 'glass', 'principled': index of refraction (Blender's default)
    # 'principled': Transmission; its glass part (weight transmission x (1 - metallic)) shows the reflection of the
    # lights a Glass BSDF of `ior` and `roughness` shows at zero bounces, the refracted part black.
    transmission: float = 0.0
    # 'glass': one of GLASS_DISTRIBUTIONS, 'glossy_bsdf' GLOSSY_DISTRIBUTIONS, 'principled' PRINCIPLED_DISTRIBUTIONS
    distribution: str = "ggx"
    layers: List["MaterialLayer"] = field(default_factory=list)  # 'mix' only
    # Radiance (W/m^2/sr) from both sides, Cycles' colour x strength; every emissive triangle is a light (files
    # without it load as 0).  With textures["emission"], the radiance at each point is this times the image's colour
    # there (a mix's emission texture is its own: none of its layers may emit then).
    emission: RGB = (0.0, 0.0, 0.0)
    # Image textures driving inputs (keys from TEXTURED_INPUTS; the value replaces the field of that name, but for
    # 'emission', which it multiplies), and a
    # Normal Map node's tangent-space map (its Color read as 2 c - 1 in the frame of the UVs' tangent, the
    # bitangent and the shading normal; strength as the node's); none of a mix's layers has its own normal map.
    textures: Dict[str, "TextureLookup"] = field(default_factory=dict)
    normal_map: Optional["TextureLookup"] = None
    normal_map_strength: float = 1.0
    # Node programs driving inputs (keys from TEXTURED_INPUTS, none also in `textures`): a shader node graph evaluated
    # per hit, its result replacing the field of that name (a colour, or a float), but for 'emission', which it
    # multiplies as a texture does.
    programs: Dict[str, "NodeProgram"] = field(default_factory=dict)
    # A node program whose result, a world-space normal, replaces the shading normal at each hit (a Bump node's graph
    # on the shader's Normal input, with Cycles' bump shadowing of the diffuse lobes); not with normal_map, nor on a
    # mix's layers (the mix's own is theirs).
    normal_program: Optional["NodeProgram"] = None


@dataclass
class TextureLookup:
    """An Image Texture node read by a material input: Scene.textures[texture] at the mesh's coordinates
    (Mesh.uvs or Mesh.generated, as (u, v, 0) or (x, y, z)) mapped by `transform` (3x4 affine, row-major: a
    Mapping node of type Point; the identity by default), then the node's interpolation and extension; its
    Color or Alpha output."""
    texture: int
    output: str = "color"            # one of TEXTURE_OUTPUTS
    coordinates: str = "uv"          # one of TEXTURE_COORDINATES
    transform: List[List[float]] = field(default_factory=lambda: np.eye(3, 4).tolist())
    interpolation: str = "linear"    # one of TEXTURE_INTERPOLATIONS
    extension: str = "repeat"        # one of TEXTURE_EXTENSIONS


@dataclass
class NodeInstruction:
    """One instruction of a NodeProgram (the renderer's render/svm/program.h documents each op's operands): its op
    (one of NODE_OPS), the registers it reads then writes (-1: an output nobody reads), its mode (an index into the
    op's name list: NODE_MATH_OPS, NODE_MIX_BLENDS, ...), option flags, a table's offset and rows in
    NodeProgram.data (or an image: an index into Scene.textures), and a constant's value."""
    op: str
    regs: List[int]
    mode: int = 0
    flags: int = 0
    data: int = 0
    size: int = 0
    value: V3 = (0.0, 0.0, 0.0)


@dataclass
class NodeProgram:
    """A material input's shader node graph compiled once (the Blender exporter's node_program.py), run per hit as
    Cycles runs SVM code: `instructions` in order over `num_registers` registers of three floats (at most
    MAX_NODE_REGISTERS), tables in `data`; the result is register `output` (a float input reads its first
    component)."""
    instructions: List[NodeInstruction]
    output: int
    num_registers: int
    data: List[float] = field(default_factory=list)
    attributes: List[str] = field(default_factory=list)  # the Mesh.attributes its 'attribute' ops read (their data)


@dataclass
class MixFactor:
    """A Mix Shader's factor read from a texture or a node program (its scalar, clamped to [0, 1] as Cycles does): the
    layer's weight is multiplied by fac, or by 1 - fac for the node's first shader (complement)."""
    lookup: Optional[TextureLookup] = None
    complement: bool = False
    program: Optional[NodeProgram] = None


@dataclass
class MaterialLayer:
    """One shader of a 'mix' material and the weight its closures are scaled by (times its factors', when
    textures drive the Mix Shaders above it)."""
    weight: float
    material: Material
    factors: List[MixFactor] = field(default_factory=list)


@dataclass
class Texture:
    """An image: `pixels` (uint8 or float32 [H, W, C], C in 1..4, row 0 the image's bottom as in Blender's
    Image.pixels, values as stored: see TEXTURE_COLORSPACES), or `path`, a file OpenImageIO reads when the scene
    is rendered (magenta, Cycles' missing-image colour, with a warning, when it cannot; a relative path is read from
    the current directory, and in a scene file is relative to the file's folder: save_scene, load_scene)."""
    name: str = "image"
    pixels: Optional[np.ndarray] = None
    path: str = ""
    colorspace: str = "srgb"         # one of TEXTURE_COLORSPACES


def _lookup_from_dict(d) -> "TextureLookup":
    return TextureLookup(**d)


def _program_from_dict(d) -> "NodeProgram":
    d = dict(d)
    d["instructions"] = [NodeInstruction(**{**i, "value": tuple(i.get("value", (0.0, 0.0, 0.0)))})
                         for i in d["instructions"]]
    return NodeProgram(**d)


def _factor_from_dict(f) -> "MixFactor":
    return MixFactor(lookup=_lookup_from_dict(f["lookup"]) if f.get("lookup") is not None else None,
                     complement=f["complement"],
                     program=_program_from_dict(f["program"]) if f.get("program") is not None else None)


def _material_from_dict(d) -> Material:
    d = dict(d)
    d["layers"] = [MaterialLayer(weight=l["weight"], material=_material_from_dict(l["material"]),
                                 factors=[_factor_from_dict(f) for f in l.get("factors", [])])
                   for l in d.get("layers", [])]
    d["textures"] = {k: _lookup_from_dict(v) for k, v in d.get("textures", {}).items()}
    d["programs"] = {k: _program_from_dict(v) for k, v in d.get("programs", {}).items()}
    if d.get("normal_map") is not None:
        d["normal_map"] = _lookup_from_dict(d["normal_map"])
    if d.get("normal_program") is not None:
        d["normal_program"] = _program_from_dict(d["normal_program"])
    return Material(**d)


@dataclass
class Mesh:
    vertices: np.ndarray                       # float32 [V, 3], world space
    triangles: np.ndarray                      # int32 [T, 3]
    normals: Optional[np.ndarray] = None       # float32 [V, 3] or None (flat shading)
    material_ids: Optional[np.ndarray] = None  # int32 [T] into Scene.materials, or None (all 0)
    name: str = "mesh"
    uvs: Optional[np.ndarray] = None           # float32 [V, 2]: texture coordinates 'uv', or None
    generated: Optional[np.ndarray] = None     # float32 [V, 3]: texture coordinates 'generated', or None
    # The linear part L of the matrix of the object the mesh comes from (world = L local + offset), or None (the
    # identity): tangent-space normal maps are applied in the object's space, as Cycles does, which differs from
    # world space where L scales non-uniformly.
    object_linear: Optional[List[List[float]]] = None
    # With object_linear, the object's location (world = L local + object_translation), which node programs' Object
    # coordinates undo; None: the origin.
    object_translation: Optional[V3] = None
    invisible_to: Tuple[str, ...] = ()        # RAY_KINDS that pass through it (camera: not seen; shadow: casts none)
    # Blender's Object > Shading > Shadow Terminator > Geometry Offset, in [0, 1] (0: none; Blender's default 0.1): a
    # smooth-shaded mesh's light samples near its terminator leave from the smooth surface its triangles approximate,
    # as Cycles 3.4 does (docs/renderer.md, shadow terminator).  Needs normals.
    shadow_terminator_offset: float = 0.0
    # What node programs read of the mesh (the Attribute and Color Attribute nodes): attributes by name, float32
    # [V, 4] per vertex, the value as the nodes' Color / Vector give it and its Alpha (1 where it has none); their Fac
    # is the mean of the first three, or the first for the names in attributes_fac_x (UV maps, Cycles' float2).
    attributes: Dict[str, np.ndarray] = field(default_factory=dict)
    attributes_fac_x: Tuple[str, ...] = ()
    # Its object, as the Object Info node reads it: Blender's object colour (RGBA), pass index and random number in
    # [0, 1] (Cycles' from the instance's random_id); Location is object_translation.
    object_color: Tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)
    object_index: int = 0
    object_random: float = 0.0
    # Whether its triangles list the corners of Blender's in reverse (the exporter's, for a mirroring object: the
    # winding kept outward), which Geometry > Parametric undoes.
    corners_reversed: bool = False


# Every light's visibility fields, as Cycles 3.4's light shader flags (scene/light.cpp): the RAY_KINDS it does not
# light (its closures of that class, BSDF rays of that kind, the medium for "volume_scatter"), whether its samples
# trace shadow rays (Cast Shadow), whether BSDF rays find it and weigh against its samples (Multiple Importance).
@dataclass(kw_only=True)  # after each light's own fields, keyword-only
class LightVisibility:
    invisible_to: Tuple[str, ...] = ()
    cast_shadow: bool = True
    use_mis: bool = True


@dataclass
class RectLight(LightVisibility):
    """Corner + two orthogonal edges. A one-sided light emits on the side cross(edge_x, edge_y) points to."""
    corner: V3
    edge_x: V3
    edge_y: V3
    radiance: RGB
    two_sided: bool = False
    visible: bool = True             # seen by camera rays
    name: str = "rect"
    # Blender's Spread (radians, [0, pi]; pi: none), as Cycles 3.4 evaluates it: emission attenuated away from the
    # normal (max(1 - tan(angle) / tan(spread / 2), 0), normalised to keep the power; at least 1 degree), each
    # shading point sampling only the sub-rectangle it receives light from (docs/renderer.md).
    spread: float = math.pi
    # An image over the light: the radiance at a point is `radiance` x the lookup's colour there, the lookup reading
    # coordinates 'uv' = (a, b, 0), the point's fractions along edge_x and edge_y from the corner, through its
    # transform (a Blender light's node tree: Geometry > Parametric, Texture Coordinate > Object...).
    texture: Optional["TextureLookup"] = None

    @property
    def area(self) -> float:
        return float(np.linalg.norm(np.cross(self.edge_x, self.edge_y)))

    @staticmethod
    def from_power(center, edge_x, edge_y, power: float, color: RGB = (1, 1, 1), **kw) -> "RectLight":
        """A light of Blender's `power` (watts) and `color`: radiance by area_light_radiance."""
        c, ex, ey = (np.asarray(a, dtype=np.float64) for a in (center, edge_x, edge_y))
        area = float(np.linalg.norm(np.cross(ex, ey)))
        if not area > 0:
            raise ValueError("a rectangle light needs two non-zero edges")
        return RectLight(corner=tuple(c - 0.5 * ex - 0.5 * ey), edge_x=tuple(ex), edge_y=tuple(ey),
                         radiance=area_light_radiance(power, color, area), **kw)


@dataclass
class EllipseLight(LightVisibility):
    """Ellipse (disc when the semi-axes are equal): centre and two orthogonal semi-axis vectors."""
    center: V3
    axis_x: V3
    axis_y: V3
    radiance: RGB
    two_sided: bool = False
    visible: bool = True
    name: str = "ellipse"
    spread: float = math.pi          # as RectLight.spread (sampled on its bounding rectangle's sub-rectangle)
    # As RectLight.texture, (a, b) the fractions along its bounding rectangle's edges 2 axis_x and 2 axis_y from its
    # corner center - axis_x - axis_y.
    texture: Optional["TextureLookup"] = None


@dataclass
class PointLight(LightVisibility):
    """A point, or with a radius Cycles 3.4's soft point light: a disc of that radius facing the shading point,
    of radiance intensity / (pi radius^2), sampled by the cone it subtends."""
    position: V3
    intensity: RGB                   # W/sr
    name: str = "point"
    radius: float = 0.0              # Blender's Radius (shadow_soft_size); 0: a delta light
    visible: bool = True             # with a radius: seen by camera rays


@dataclass
class SpotLight(LightVisibility):
    """Cycles 3.4 spot: intensity * cos(angle to axis) * smoothstep blend inside the cone."""
    position: V3
    direction: V3                    # unit, the cone's axis
    intensity: RGB
    spot_size: float = math.pi / 4   # full cone angle, radians
    spot_blend: float = 0.15
    name: str = "spot"
    radius: float = 0.0              # as PointLight.radius, the falloff taken towards each shading point
    visible: bool = True


@dataclass
class SunLight(LightVisibility):
    """A sun; with an angle Cycles 3.4's: the cone of directions within angle / 2 of it, of radiance
    irradiance / (pi tan^2(angle / 2) cos^3(theta)) at theta from its direction, sampled uniformly in that cone."""
    direction: V3                    # unit, the direction light travels
    irradiance: RGB                  # W/m^2 on a surface facing the sun
    name: str = "sun"
    angle: float = 0.0               # angular diameter, radians in [0, pi]; 0: a delta light
    visible: bool = True             # with an angle: seen by camera rays that escape


@dataclass
class Medium:
    """Homogeneous medium filling the scene."""
    sigma_s: RGB = (0.1, 0.1, 0.1)   # scattering coefficient, 1/m
    sigma_a: RGB = (0.0, 0.0, 0.0)   # absorption coefficient, 1/m
    g: float = 0.0                   # Henyey-Greenstein anisotropy


@dataclass
class Volume:
    """A homogeneous medium bounded by a closed triangle mesh (Blender's object volume: a mesh whose material has a
    Volume output).  The triangles' winding gives the outward normal (counter-clockwise seen from outside, as
    Blender's); the surface itself is invisible, only the medium inside it is drawn.  Where volumes overlap their
    coefficients add, and a World.medium adds to them (as in Cycles)."""
    vertices: np.ndarray                       # float32 [V, 3], world space
    triangles: np.ndarray                      # int32 [T, 3], into vertices
    medium: Medium = field(default_factory=Medium)
    name: str = "volume"


@dataclass
class Environment:
    """An equirectangular image of the radiance arriving from infinitely far away, as Cycles 3.4's Environment
    Texture (equirectangular projection) maps it: a unit direction d in the image's own frame falls at
    u = (atan2(d.y, d.x) - pi) / (-2 pi), v = (acos(d.z) - pi/2) / (-pi) + 1/2, so +X is the image's middle column and
    +Z its top row (row 0 of Texture.pixels is the image's bottom).  A world direction w is looked up at
    d = to_world^T w (to_world: a rotation, row-major; the Mapping / Vector Rotate nodes in front of the texture).
    The radiance is the image's value times `strength` (the Background's Strength times any constant colour
    factor); `interpolation` is the texture node's."""
    texture: int                       # into Scene.textures
    strength: RGB = (1.0, 1.0, 1.0)
    to_world: List[List[float]] = field(default_factory=lambda: np.eye(3).tolist())
    interpolation: str = "linear"      # one of TEXTURE_INTERPOLATIONS


@dataclass
class World:
    background: RGB = (0.0, 0.0, 0.0)  # constant radiance seen where rays escape (and lighting the scene)
    medium: Optional[Medium] = None
    # An image world: where set, rays that escape see it instead of `background`.
    environment: Optional[Environment] = None
    # Blender's World > Ray Visibility, for the background and the image world alike: the kinds of WORLD_RAY_KINDS that
    # do not see it -- camera rays that escape show black; BSDF and phase rays of a hidden kind find nothing, and it
    # lights none of the closures of a hidden class (as a light's LightVisibility.invisible_to).
    invisible_to: Tuple[str, ...] = ()
    # What camera rays that escape see instead of `background` / `environment`, where the world shows the camera
    # something else than the light it gives (a Light Path node's Is Camera Ray in Blender's world); None: the same.
    camera_environment: Optional[Environment] = None


@dataclass
class Camera:
    """Blender's camera model: looks down its local -Z with +Y up; to_world is its 4x4 matrix."""
    width: int = 64
    height: int = 64
    to_world: List[List[float]] = field(default_factory=lambda: np.eye(4).tolist())
    type: str = "perspective"        # one of CAMERA_TYPES
    lens: float = 50.0               # mm
    sensor_width: float = 36.0       # mm
    sensor_height: float = 24.0      # mm
    sensor_fit: str = "AUTO"         # one of SENSOR_FITS
    shift_x: float = 0.0
    shift_y: float = 0.0
    ortho_scale: float = 7.0
    aperture_radius: float = 0.0     # world units; 0 = pinhole
    focus_distance: float = 10.0
    clip_start: float = 0.0
    clip_end: float = 1e30
    film_transparent: bool = False   # Blender's Film > Transparent: escaping camera rays give alpha 0 and no colour
    # Cycles' Film > Pixel Filter: one of PIXEL_FILTERS, of filter_width pixels (box: its side; gaussian: 4 sigma,
    # cut at 6 sigma; blackman_harris: its support is 2 x the width).  Camera samples land around their pixel
    # centre as the filter is distributed (filter importance sampling, weight 1).  Blender's default: Blackman-Harris
    # 1.5; this default, the 1-px box, is the renderer's before filters.
    pixel_filter: str = "box"
    filter_width: float = 1.0        # pixels, in [MIN_PIXEL_FILTER_WIDTH, MAX_PIXEL_FILTER_WIDTH]

    def image_plane(self):
        """(half_width, half_height, offset_x, offset_y) of the image at distance 1 (perspective)
        or in world units (orthographic), following Blender's sensor fit and shift rules."""
        aspect = self.width / self.height
        fit = self.sensor_fit
        if fit == "AUTO":
            fit = "HORIZONTAL" if self.width >= self.height else "VERTICAL_WIDTH"
        if self.type == "orthographic":
            full = self.ortho_scale
        elif fit == "VERTICAL":
            full = self.sensor_height / self.lens
        else:
            full = self.sensor_width / self.lens
        if fit == "HORIZONTAL":
            hw = 0.5 * full
            hh = hw / aspect
        else:
            hh = 0.5 * full
            hw = hh * aspect
        larger = 2.0 * max(hw, hh) if self.sensor_fit == "AUTO" else (2.0 * hw if fit == "HORIZONTAL" else 2.0 * hh)
        return hw, hh, self.shift_x * larger, self.shift_y * larger


@dataclass
class Scene:
    camera: Camera = field(default_factory=Camera)
    world: World = field(default_factory=World)
    materials: List[Material] = field(default_factory=lambda: [Material()])
    meshes: List[Mesh] = field(default_factory=list)
    lights: list = field(default_factory=list)  # RectLight | EllipseLight | PointLight | SpotLight | SunLight
    textures: List[Texture] = field(default_factory=list)  # read by Material.textures through TextureLookup
    volumes: List[Volume] = field(default_factory=list)  # media bounded by closed meshes


_LIGHT_TYPES = {"rect": RectLight, "ellipse": EllipseLight, "point": PointLight, "spot": SpotLight, "sun": SunLight}
_LIGHT_NAMES = {cls: name for name, cls in _LIGHT_TYPES.items()}


def save_scene(scene: Scene, path: str) -> None:
    """Write `scene` to `path` (see the module docstring). Written to a temporary file
    and renamed, so an interrupted save never leaves a half-written scene behind. A relative texture path (read from
    the current directory) is stored relative to the file's folder, naming the same file."""
    meta = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "camera": dataclasses.asdict(scene.camera),
        "world": dataclasses.asdict(scene.world),
        "materials": [dataclasses.asdict(m) for m in scene.materials],
        "lights": [dict(type=_LIGHT_NAMES[type(l)], **dataclasses.asdict(l)) for l in scene.lights],
        "meshes": [],
        "textures": [],
        "volumes": [],
    }
    arrays = {}
    for i, t in enumerate(scene.textures):
        key = f"texture{i}" if t.pixels is not None else None
        meta["textures"].append({"name": t.name, "colorspace": t.colorspace, "arrays": key,
                                 "path": scene_file.texture_path_to_store(t.path, path)})
        if key:
            arrays[f"{key}.pixels"] = np.asarray(t.pixels)
    for i, m in enumerate(scene.meshes):
        key = f"mesh{i}"
        meta["meshes"].append({"name": m.name, "arrays": key})
        if m.invisible_to:
            meta["meshes"][-1]["invisible_to"] = list(m.invisible_to)
        if m.shadow_terminator_offset:
            meta["meshes"][-1]["shadow_terminator_offset"] = float(m.shadow_terminator_offset)
        if m.object_linear is not None:
            meta["meshes"][-1]["object_linear"] = np.asarray(m.object_linear, dtype=np.float64).tolist()
        if m.object_translation is not None:
            meta["meshes"][-1]["object_translation"] = [float(x) for x in m.object_translation]
        if m.attributes:
            meta["meshes"][-1]["attributes"] = list(m.attributes)
            meta["meshes"][-1]["attributes_fac_x"] = [n for n in m.attributes_fac_x if n in m.attributes]
            for j, values in enumerate(m.attributes.values()):
                arrays[f"{key}.attribute{j}"] = np.asarray(values, dtype=np.float32)
        if tuple(m.object_color) != (1.0, 1.0, 1.0, 1.0) or m.object_index or m.object_random:
            meta["meshes"][-1]["object_info"] = {"color": [float(x) for x in m.object_color],
                                                 "index": int(m.object_index), "random": float(m.object_random)}
        if m.corners_reversed:
            meta["meshes"][-1]["corners_reversed"] = True
        arrays[f"{key}.vertices"] = np.asarray(m.vertices, dtype=np.float32)
        arrays[f"{key}.triangles"] = np.asarray(m.triangles, dtype=np.int32)
        if m.normals is not None:
            arrays[f"{key}.normals"] = np.asarray(m.normals, dtype=np.float32)
        if m.material_ids is not None:
            arrays[f"{key}.material_ids"] = np.asarray(m.material_ids, dtype=np.int32)
        if m.uvs is not None:
            arrays[f"{key}.uvs"] = np.asarray(m.uvs, dtype=np.float32)
        if m.generated is not None:
            arrays[f"{key}.generated"] = np.asarray(m.generated, dtype=np.float32)
    for i, v in enumerate(scene.volumes):
        key = f"volume{i}"
        meta["volumes"].append({"name": v.name, "arrays": key, "medium": dataclasses.asdict(v.medium)})
        arrays[f"{key}.vertices"] = np.asarray(v.vertices, dtype=np.float32)
        arrays[f"{key}.triangles"] = np.asarray(v.triangles, dtype=np.int32)
    arrays["scene.json"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)
    atomic_write(path, lambda f: np.savez_compressed(f, **arrays))


def load_scene(path: str, relative_to: Optional[str] = None) -> Scene:
    """Read a scene written by :func:`save_scene`; ValueError saying what is wrong if it is not one (sizes and
    shapes are checked before any array is read: scene_file.py). Relative texture paths are resolved against the
    folder `relative_to` (default: the file's own, wherever the process runs) and made absolute."""
    try:
        headers = scene_file.member_headers(path)
        data = np.load(path, allow_pickle=False)
    except scene_file.MalformedScene:
        raise
    except (ValueError, *scene_file.MALFORMED) as e:
        raise ValueError(f"{path}: not a sphrect scene file ({type(e).__name__}: {e})") from None
    try:
        with data:
            return _scene_from_file(path, data, headers, os.path.dirname(os.path.abspath(path))
                                    if relative_to is None else relative_to)
    except scene_file.MalformedScene:
        raise
    except (ValueError, *scene_file.MALFORMED) as e:
        raise ValueError(f"{path}: malformed sphrect scene file ({type(e).__name__}: {e})") from None


def _scene_from_file(path, data, headers, relative_to) -> Scene:
    meta = scene_file.read_meta(path, data, headers, FORMAT_NAME, FORMAT_VERSION)
    for key in ("camera", "world", "materials", "lights", "meshes"):
        if key not in meta:
            raise ValueError(f"{path}: scene.json has no '{key}'")
    world = dict(meta["world"])
    medium = world.pop("medium", None)
    environment = world.pop("environment", None)
    camera_environment = world.pop("camera_environment", None)
    if "invisible_to" in world:
        world["invisible_to"] = tuple(world["invisible_to"])
    scene = Scene(
        camera=Camera(**meta["camera"]),
        world=World(medium=Medium(**medium) if medium else None,
                    environment=Environment(**environment) if environment else None,
                    camera_environment=Environment(**camera_environment) if camera_environment else None, **world),
        materials=[_material_from_dict(m) for m in meta["materials"]],
    )
    for l in meta["lights"]:
        l = dict(l)
        cls = _LIGHT_TYPES.get(l.pop("type", None))
        if cls is None:
            raise ValueError(f"{path}: unknown light type")
        if "invisible_to" in l:
            l["invisible_to"] = tuple(l["invisible_to"])
        if l.get("texture") is not None:
            l["texture"] = _lookup_from_dict(l["texture"])
        scene.lights.append(cls(**l))
    for m in meta["meshes"]:
        key = m["arrays"]
        if not isinstance(key, str):
            raise ValueError(f"{path}: a mesh's 'arrays' is {key!r}, not a name")
        scene_file.check_mesh_arrays(path, headers, key)
        get = lambda name: data[f"{key}.{name}"] if f"{key}.{name}" in data.files else None
        names = m.get("attributes", [])
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise ValueError(f"{path}: mesh {key}'s 'attributes' is not a list of names")
        attributes = {}
        for j, name in enumerate(names):
            values = get(f"attribute{j}")
            if values is None or values.ndim != 2 or values.shape != (len(get("vertices")), 4):
                raise ValueError(f"{path}: mesh {key}'s attribute '{name}' is not a [V, 4] array")
            attributes[name] = values
        info = m.get("object_info", {})
        scene.meshes.append(Mesh(vertices=get("vertices"), triangles=get("triangles"), normals=get("normals"),
                                 material_ids=get("material_ids"), name=m["name"], uvs=get("uvs"),
                                 generated=get("generated"), object_linear=m.get("object_linear"),
                                 object_translation=(tuple(m["object_translation"]) if "object_translation" in m
                                                     else None),
                                 invisible_to=tuple(m.get("invisible_to", ())),
                                 shadow_terminator_offset=float(m.get("shadow_terminator_offset", 0.0)),
                                 attributes=attributes, attributes_fac_x=tuple(m.get("attributes_fac_x", ())),
                                 object_color=tuple(info.get("color", (1.0, 1.0, 1.0, 1.0))),
                                 object_index=int(info.get("index", 0)), object_random=float(info.get("random", 0.0)),
                                 corners_reversed=bool(m.get("corners_reversed", False))))
    for t in meta.get("textures", []):
        key = t.get("arrays")
        if key is not None and not isinstance(key, str):
            raise ValueError(f"{path}: a texture's 'arrays' is {key!r}, not a name")
        pixels = None
        if key is not None:
            scene_file.check_texture_arrays(path, headers, key)
            pixels = data[f"{key}.pixels"]
        scene.textures.append(Texture(name=t["name"], pixels=pixels, colorspace=t["colorspace"],
                                      path=scene_file.texture_path_loaded(path, t.get("path", ""), relative_to)))
    for v in meta.get("volumes", []):  # version 20
        key = v.get("arrays") if isinstance(v, dict) else None
        if not isinstance(key, str):
            raise ValueError(f"{path}: a volume's 'arrays' is {key!r}, not a name")
        scene_file.check_mesh_arrays(path, headers, key, "volume", scene_file.VOLUME_ARRAYS)
        medium = v.get("medium")
        if not isinstance(medium, dict):
            raise ValueError(f"{path}: volume {key} has no 'medium' object")
        scene.volumes.append(Volume(vertices=data[f"{key}.vertices"], triangles=data[f"{key}.triangles"],
                                    medium=Medium(**medium), name=v.get("name", "volume")))
    return scene
