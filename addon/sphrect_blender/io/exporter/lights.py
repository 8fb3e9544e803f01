"""Blender lights -> sphrect lights. Power becomes radiance, intensity or irradiance by Cycles 3.4's
conventions in `sphrect.scene` (area_light_radiance, point_light_intensity, sun_irradiance), an area
measured after the object's scale. Every light emits along its object's local -Z axis.  A light's node tree
(light_shader): its Emission's colour x strength multiplies the light's; an Image Texture on that colour is a
rectangle or ellipse light's texture, read where Cycles 3.4 reads it on a light (_coordinate_maps).
"""
import math

import numpy as np

from .materials import _active_output, _linked_node, _value
from .node_groups import own_value
from .node_program import compile_socket
from .textures import image_texture_source
from .visibility import LIGHT_RAY_KINDS, invisible_to


# The light settings SPHRECT does not simulate, per light type: (attribute, the value SPHRECT assumes, the
# panel's label, the export warning). One source for the exporter's warnings (given when a light's value is
# not the assumed one) and the light panel's list of what it ignores.
_ALL_TYPES = ("POINT", "SPOT", "SUN", "AREA")
IGNORED_LIGHT_SETTINGS = (
    (_ALL_TYPES, "diffuse_factor", 1.0, "Diffuse factor", "light diffuse factor (1 used)"),
    (_ALL_TYPES, "specular_factor", 1.0, "Specular factor", "light specular factor (1 used)"),
    (_ALL_TYPES, "volume_factor", 1.0, "Volume factor", "light volume factor (1 used)"),
)


def ignored_light_settings(light):
    """[(label, warning, differs)] of the settings of `light` (a bpy Light) that SPHRECT ignores; `differs`:
    the light's value is not the one SPHRECT assumes, so the render differs from Cycles'."""
    out = []
    for types, attr, assumed, label, warning in IGNORED_LIGHT_SETTINGS:
        if light.type in types and hasattr(light, attr):
            out.append((label, warning, abs(float(getattr(light, attr)) - assumed) > 1e-6))
    return out


def _axes(matrix_world):
    m = np.array(matrix_world, dtype=np.float64)
    return m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3]


def _unit(v):
    n = np.linalg.norm(v)
    return v / n if n > 0 else None


def _tuple(v):
    return tuple(float(x) for x in v)


def area_light_edges(light, matrix_world):
    """(centre, edge_x, edge_y, emission direction) of an area light in world space. The edges are the
    full side lengths (the ellipse's diameters) including the object's scale; they are ordered so that
    cross(edge_x, edge_y) points along the emission direction (local -Z), as sphrect's lights expect."""
    x, y, z, centre = _axes(matrix_world)
    size_x = light.size
    size_y = light.size if light.shape in {"SQUARE", "DISK"} else light.size_y
    ex, ey = x * size_x, y * size_y
    direction = _unit(-z)
    if direction is None:
        direction = _unit(np.cross(ey, ex))  # flattened along Z: the edges still tell the facing
    if direction is not None and np.dot(np.cross(ex, ey), direction) < 0:
        ex, ey = ey, ex
    return centre, ex, ey, direction


def light_visibility(obj, parent=None):
    """The light's visibility fields (sphrect.scene.LightVisibility): the ray kinds it (or the object instancing it,
    `parent`) hides from (Object > Visibility), its Cast Shadow and Multiple Importance (Light > Cycles' settings), as
    Cycles 3.4 syncs them."""
    cycles = getattr(obj.data, "cycles", None)
    return dict(invisible_to=invisible_to(obj, LIGHT_RAY_KINDS, parent),
                cast_shadow=bool(getattr(cycles, "cast_shadow", True)),
                use_mis=bool(getattr(cycles, "use_multiple_importance_sampling", True)))


def light_shader(light, log, textures=None, light_coordinates=None):
    """(colour factor, TextureLookup or None) of a light's node tree as Cycles 3.4 shades a light: the Emission on its
    active Light Output emits colour x strength (svm_node_emission_weight), times the light's own colour and power; for
    a rectangle or ellipse light (light_coordinates: _coordinate_maps'), an Image Texture on that colour is the light's
    texture.  Without nodes (1, 1, 1); with no shader on the output (0, 0, 0), as Cycles, which then emits nothing;
    any other shader warned, the light's colour and power alone used."""
    if not light.use_nodes or light.node_tree is None:
        return (1.0, 1.0, 1.0), None
    out = _active_output(light.node_tree, "ShaderNodeOutputLight")
    node = _linked_node(out.inputs["Surface"]) if out is not None else None
    if node is None:
        return (0.0, 0.0, 0.0), None
    if node.bl_idname != "ShaderNodeEmission":
        log.unsupported_feature(f"light shader '{node.bl_label or node.bl_idname}' (the light's colour and power used)",
                                light.name)
        return (1.0, 1.0, 1.0), None
    color_socket = node.inputs["Color"]
    source = image_texture_source(color_socket, projected=True) if light_coordinates is not None and \
        color_socket.is_linked else None
    texture = textures.lookup(*source, light.name, light_coordinates) if source is not None else None
    color = np.ones(3) if texture is not None else np.asarray(_light_input(node, "Color", "color", textures, log,
                                                                            light.name)[:3], dtype=float)
    strength = float(_light_input(node, "Strength", "float", textures, log, light.name))
    if strength < 0:
        log.unsupported_feature("negative emission strength (0 used)", light.name)
        strength = 0.0
    return tuple(float(c) for c in np.clip(color, 0, None) * strength), texture


def _light_input(node, name, want, textures, log, owner):
    """An input of a light's Emission: its own value, or the constant its node graph folds to as Cycles folds it
    (a Blackbody, RGB Curves, Math... of constants: node_program.compile_socket); a graph that varies over the light
    (other than the Image Texture a rectangle or ellipse light takes) is warned, the input's own value used."""
    socket = node.inputs[name]
    if socket.is_linked and textures is not None:
        program, value = compile_socket(textures.sphrect, textures, log, owner, socket, want)
        if value is not None:
            return value
        if program is not None:
            log.unsupported_feature(f"a node graph varying over a light on its '{socket.name}' (its own value used)",
                                    owner)
            return own_value(socket)
    return _value(node, name, log, owner)


def has_image_texture(light):
    """Whether a light's node tree holds an Image Texture node (which its export may read as the light's texture)."""
    tree = light.node_tree if light.use_nodes else None
    return tree is not None and any(n.bl_idname == "ShaderNodeTexImage" for n in tree.nodes)


def _coordinate_maps(corner, edge_x, edge_y, axis_u, axis_v):
    """4x4 maps from a rectangle or ellipse light's own coordinates (a, b, 0, 1) -- its point corner + a edge_x +
    b edge_y (an ellipse's bounding rectangle's) -- to what its node tree reads there (TextureExport._light_source):
    'position' the point in world space; 'parametric' Cycles 3.4's (0.5 + light_u, 0.5 + light_v, 0), light_u = (P -
    centre) . axis_u / |axis_u|^2 along the axes Cycles gives the light (the object's X and Y times the sizes:
    kernel/light/light.h), as Geometry > Parametric reads it (svm_node_geometry's (1 - u - v, u)); 'uv' (0, 0, 0),
    the UV map a light lacks."""
    corner, edge_x, edge_y = (np.asarray(v, dtype=np.float64) for v in (corner, edge_x, edge_y))
    position = np.zeros((4, 4))
    position[:3, 0], position[:3, 1], position[:3, 3], position[3, 3] = edge_x, edge_y, corner, 1.0
    centre = corner + 0.5 * edge_x + 0.5 * edge_y
    to_parametric = np.zeros((4, 4))
    to_parametric[3, 3] = 1.0
    for row, axis in ((0, np.asarray(axis_u, dtype=np.float64)), (1, np.asarray(axis_v, dtype=np.float64))):
        k = axis / max(float(np.dot(axis, axis)), 1e-300)
        to_parametric[row, :3], to_parametric[row, 3] = k, 0.5 - float(np.dot(centre, k))
    uv = np.zeros((4, 4))
    uv[3, 3] = 1.0
    return {"position": position, "parametric": to_parametric @ position, "uv": uv}


def export_light(sphrect, obj, matrix_world, name, log, parent=None, textures=None):
    """The sphrect light for a Blender light object (instanced by `parent`, or None), or None (with a logged reason)
    if it emits nothing.  `textures`: the scene's TextureExport, for a rectangle or ellipse light's texture."""
    light = obj.data
    color = np.array(light.color, dtype=np.float64)
    power = float(light.energy)
    if light.type == "AREA":
        return _export_area_light(sphrect, obj, light, matrix_world, name, color, power, log, textures, parent)
    color = color * np.asarray(light_shader(light, log, textures)[0])
    return _export_light_of_a_point(sphrect, obj, light, matrix_world, name, color, power, log, parent)


def _emits(light, name, color, power, matrix_world, log):
    """Whether the light emits (else logged: skipped) and its settings SPHRECT ignores are warned."""
    for _, warning, differs in ignored_light_settings(light):
        if differs:
            log.unsupported_feature(warning, light.name)
    if power <= 0 or not np.any(color > 0):
        log.problem(f"light '{name}' has no power: skipped")
        return False
    if not np.isfinite(np.array(matrix_world)).all():
        log.problem(f"light '{name}' has a transform that is not finite (NaN or infinite): skipped")
        return False
    return True


def _export_light_of_a_point(sphrect, obj, light, matrix_world, name, color, power, log, parent):
    """A point, spot or sun light (Cycles' own: a disc facing the shading point, a cone of directions)."""
    if not _emits(light, name, color, power, matrix_world, log):
        return None
    vis = light_visibility(obj, parent)
    _, _, z, position = _axes(matrix_world)
    visible = bool(getattr(obj, "visible_camera", True))
    if light.type in {"POINT", "SPOT"}:
        intensity = sphrect.scene.point_light_intensity(power, color)
        # Cycles 3.4 takes the radius as set, unscaled by the object (blender/light.cpp: shadow_soft_size).
        radius = max(float(getattr(light, "shadow_soft_size", 0.0)), 0.0)
        if light.type == "POINT":
            return sphrect.PointLight(position=_tuple(position), intensity=intensity, name=name, radius=radius,
                                      visible=visible, **vis)
        direction = _unit(-z)
        if direction is None:
            log.problem(f"spot light '{name}' has zero scale along Z: skipped")
            return None
        return sphrect.SpotLight(position=_tuple(position), direction=_tuple(direction), intensity=intensity,
                                 spot_size=float(light.spot_size), spot_blend=float(light.spot_blend), name=name,
                                 radius=radius, visible=visible, **vis)
    if light.type == "SUN":
        direction = _unit(-z)
        if direction is None:
            log.problem(f"sun '{name}' has zero scale along Z: skipped")
            return None
        angle = min(max(float(getattr(light, "angle", 0.0)), 0.0), math.pi)
        # Cycles 3.4 finds a sun on escaping rays only with its Multiple Importance on (light_sample_from_distant_ray).
        return sphrect.SunLight(direction=_tuple(direction), irradiance=sphrect.scene.sun_irradiance(power, color),
                                name=name, angle=angle, visible=visible and vis["use_mis"], **vis)
    log.unsupported_feature(f"{light.type.lower()} lights", light.name)
    return None


def _export_area_light(sphrect, obj, light, matrix_world, name, color, power, log, textures, parent):
    centre, ex, ey, direction = area_light_edges(light, matrix_world)
    rect_area = float(np.linalg.norm(np.cross(ex, ey)))
    if not rect_area > 1e-12 or direction is None:
        log.problem(f"area light '{name}' has zero size: skipped")
        return None
    if abs(np.dot(ex, ey)) > 1e-6 * np.linalg.norm(ex) * np.linalg.norm(ey):
        # Sheared by a parent's non-uniform scale: keep the area, the plane and the emitting side (the
        # plane's normal, which local -Z no longer is), make the edges orthogonal.
        log.unsupported_feature("sheared area lights (edges made orthogonal)", light.name)
        ey = np.cross(np.cross(ex, ey) / rect_area, ex) * (rect_area / np.linalg.norm(ex) ** 2)
    corner = centre - 0.5 * ex - 0.5 * ey
    x, y, _, _ = _axes(matrix_world)
    # Cycles' axes (blender/light.cpp): the object's X and Y times the light's sizes.
    axis_u, axis_v = x * light.size, y * (light.size if light.shape in {"SQUARE", "DISK"} else light.size_y)
    maps = _coordinate_maps(corner, ex, ey, axis_u, axis_v) if textures is not None else None
    factor, texture = light_shader(light, log, textures, maps)
    color = color * np.asarray(factor)
    if not _emits(light, name, color, power, matrix_world, log):
        return None
    vis = light_visibility(obj, parent)
    two_sided = bool(getattr(getattr(light, "sphrect", None), "two_sided", False))
    visible = bool(getattr(obj, "visible_camera", True))
    spread = float(light.spread)  # Cycles 3.4's Spread, simulated as it evaluates it (sphrect.RectLight.spread)
    if light.shape in {"SQUARE", "RECTANGLE"}:
        radiance = sphrect.scene.area_light_radiance(power, color, rect_area)
        return sphrect.RectLight(corner=_tuple(corner), edge_x=_tuple(ex), edge_y=_tuple(ey), radiance=radiance,
                                 two_sided=two_sided, visible=visible, name=name, spread=spread, texture=texture, **vis)
    ellipse_area = 0.25 * math.pi * rect_area  # pi * a * b with semi-axes a, b = half the edges
    radiance = sphrect.scene.area_light_radiance(power, color, ellipse_area)
    return sphrect.EllipseLight(center=_tuple(centre), axis_x=_tuple(0.5 * ex), axis_y=_tuple(0.5 * ey),
                                radiance=radiance, two_sided=two_sided, visible=visible, name=name, spread=spread,
                                texture=texture, **vis)
