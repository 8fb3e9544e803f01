"""Blender lights -> sphrect lights. Power becomes radiance, intensity or irradiance by Cycles 3.4's
conventions in `sphrect.scene` (area_light_radiance, point_light_intensity, sun_irradiance), an area
measured after the object's scale. Every light emits along its object's local -Z axis.
"""
import math

import numpy as np

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


def export_light(sphrect, obj, matrix_world, name, log, parent=None):
    """The sphrect light for a Blender light object (instanced by `parent`, or None), or None (with a logged reason)
    if it emits nothing."""
    light = obj.data
    color = np.array(light.color, dtype=np.float64)
    power = float(light.energy)
    if light.use_nodes and light.node_tree is not None and len(light.node_tree.nodes) > 2:
        log.unsupported_feature("light node trees (colour and power used)", light.name)
    for _, warning, differs in ignored_light_settings(light):
        if differs:
            log.unsupported_feature(warning, light.name)
    if power <= 0 or not np.any(color > 0):
        log.problem(f"light '{name}' has no power: skipped")
        return None
    if not np.isfinite(np.array(matrix_world)).all():
        log.problem(f"light '{name}' has a transform that is not finite (NaN or infinite): skipped")
        return None
    vis = light_visibility(obj, parent)
    if light.type == "AREA":
        return _export_area_light(sphrect, obj, light, matrix_world, name, color, power, log, vis)
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


def _export_area_light(sphrect, obj, light, matrix_world, name, color, power, log, vis):
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
    two_sided = bool(getattr(getattr(light, "sphrect", None), "two_sided", False))
    visible = bool(getattr(obj, "visible_camera", True))
    spread = float(light.spread)  # Cycles 3.4's Spread, simulated as it evaluates it (sphrect.RectLight.spread)
    if light.shape in {"SQUARE", "RECTANGLE"}:
        radiance = sphrect.scene.area_light_radiance(power, color, rect_area)
        return sphrect.RectLight(corner=_tuple(centre - 0.5 * ex - 0.5 * ey), edge_x=_tuple(ex), edge_y=_tuple(ey),
                                 radiance=radiance, two_sided=two_sided, visible=visible, name=name, spread=spread,
                                 **vis)
    ellipse_area = 0.25 * math.pi * rect_area  # pi * a * b with semi-axes a, b = half the edges
    radiance = sphrect.scene.area_light_radiance(power, color, ellipse_area)
    return sphrect.EllipseLight(center=_tuple(centre), axis_x=_tuple(0.5 * ex), axis_y=_tuple(0.5 * ey),
                                radiance=radiance, two_sided=two_sided, visible=visible, name=name, spread=spread,
                                 **vis)
