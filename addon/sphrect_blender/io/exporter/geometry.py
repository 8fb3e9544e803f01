"""Evaluated Blender geometry -> world-space triangle arrays, with numpy `foreach_get` only
(no Python loop over vertices or triangles: a million triangles export in about a second)."""
import numpy as np

from .materials import left_out_surface, transparent_surface
from .node_program import OBJECT_ATTRIBUTE_PREFIX, POINTINESS, RANDOM_PER_ISLAND, RENDER_COLOR, UV_TANGENT_PREFIX

# Object types whose evaluated form converts to a mesh with Object.to_mesh().
MESH_LIKE = {"MESH", "CURVE", "SURFACE", "FONT", "META"}


def is_mesh_data(data):
    """Whether an evaluated object's data is a mesh, what Cycles 3.4 renders as geometry (object_is_geometry): the
    depsgraph hands a curve's, text's, surface's or metaball's triangles over as an instance whose data is a Mesh,
    besides the object itself (its Curve / MetaBall data), which is left out so they are not drawn twice."""
    return data is not None and type(data).__name__ == "Mesh"


class LocalMesh:
    """Triangles of one evaluated object in its own space (shared by all its instances); texture coordinates
    (uvs, generated: per vertex, or None) are the object's own whatever its world matrix; `attributes` (name ->
    float32 [V, 4], sphrect.Mesh.attributes) the ones its materials' programs read, `attributes_fac_x` their
    two-component ones."""
    __slots__ = ("vertices", "triangles", "normals", "material_index", "uvs", "generated", "attributes",
                 "attributes_fac_x")

    def __init__(self, vertices, triangles, normals, material_index, uvs=None, generated=None, attributes=None,
                 attributes_fac_x=()):
        self.vertices, self.triangles, self.normals, self.material_index = vertices, triangles, normals, material_index
        self.uvs, self.generated = uvs, generated
        self.attributes, self.attributes_fac_x = attributes or {}, tuple(attributes_fac_x)


def render_uv_layer(mesh):
    """The UV map Cycles reads by default (its 'UV' attribute): the active render one, else the active one."""
    for layer in mesh.uv_layers:
        if layer.active_render:
            return layer
    return mesh.uv_layers.active


def _corner_uvs(mesh, corner_loops, n, log, name):
    """float32 [n, 3, 2]: the render UV map at each triangle corner (its loop's, so seams keep both sides' UVs);
    zeros, warned, without a UV map (Cycles reads (0, 0))."""
    layer = render_uv_layer(mesh)
    if layer is None:
        if log is not None:
            log.unsupported_feature("textured meshes without a UV map (UVs (0, 0), as Cycles reads)", name)
        return np.zeros((n, 3, 2), dtype=np.float32)
    per_loop = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    layer.data.foreach_get("uv", per_loop)
    return per_loop.reshape(-1, 2)[corner_loops].reshape(n, 3, 2)


def _generated(mesh):
    """float32 [V, 3]: Blender's Generated coordinates of each vertex, the undeformed position mapped by the mesh's
    texture space to [0, 1] (Cycles' mesh_texture_space: (co - (location - size)) / (2 size), 0.5 on an axis of
    size 0)."""
    undeformed = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("undeformed_co", undeformed)
    location = np.array(mesh.texspace_location, dtype=np.float64)
    size = np.array(mesh.texspace_size, dtype=np.float64)
    half_inverse = np.divide(0.5, size, out=np.zeros(3), where=size != 0)
    generated = undeformed.reshape(-1, 3) * half_inverse - (location * half_inverse - 0.5)
    return generated.astype(np.float32)


def _transparent_slots(obj):
    """Indices of the object's material slots whose surface is left out (materials.left_out_surface), and the
    warnings naming why (materials.transparent_surface; none for a volume-only material's, exact)."""
    left_out = [i for i, slot in enumerate(obj.material_slots) if left_out_surface(slot.material)]
    reasons = {transparent_surface(obj.material_slots[i].material) for i in left_out}
    return np.array(left_out, dtype=np.int32), sorted(r for r in reasons if r)


# Blender's attribute types -> (foreach_get key, components kept, whether the Fac is the first component).
_ATTRIBUTE_TYPES = {"FLOAT": ("value", 1, False), "INT": ("value", 1, False), "BOOLEAN": ("value", 1, False),
                    "INT8": ("value", 1, False), "FLOAT_VECTOR": ("vector", 3, False), "FLOAT2": ("vector", 2, True),
                    "FLOAT_COLOR": ("color", 4, False), "BYTE_COLOR": ("color", 4, False)}


def _as_rgba(values, components):
    """float32 [N, 4] of an attribute's values as Cycles' Attribute node reads them: a scalar repeated on the three
    colour components, a 2D vector (x, y, 0), alpha 1 where the attribute has none."""
    values = np.asarray(values, dtype=np.float32).reshape(-1, components)
    out = np.ones((len(values), 4), dtype=np.float32)
    if components == 1:
        out[:, :3] = values
    elif components == 2:
        out[:, :2], out[:, 2] = values, 0.0
    else:
        out[:, :components] = values
    return out


def _domain_values(mesh, name):
    """(float32 [N, 4] values, domain, fac_is_x) of the mesh's attribute or UV map `name`, or None if it has none
    Cycles reads; an edge attribute comes to the points as Blender's attribute API gives it (the mean of the
    vertex's edges)."""
    uv = mesh.uv_layers.get(name) if name else None
    if uv is not None:
        per_loop = np.empty(len(mesh.loops) * 2, dtype=np.float32)
        uv.data.foreach_get("uv", per_loop)
        return _as_rgba(per_loop, 2), "CORNER", True
    if name == RENDER_COLOR:
        index = mesh.color_attributes.render_color_index
        if index < 0:
            return None
        name = mesh.color_attributes[index].name
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.data_type not in _ATTRIBUTE_TYPES:
        return None
    key, components, fac_x = _ATTRIBUTE_TYPES[attribute.data_type]
    values = np.empty(len(attribute.data) * components, dtype=np.float32)
    attribute.data.foreach_get(key, values)
    values = _as_rgba(values, components)
    if attribute.domain == "EDGE":
        edges = np.empty(len(mesh.edges) * 2, dtype=np.int32)
        mesh.edges.foreach_get("vertices", edges)
        total = np.zeros((len(mesh.vertices), 4))
        count = np.zeros(len(mesh.vertices))
        for end in (edges[0::2], edges[1::2]):
            np.add.at(total, end, values)
            np.add.at(count, end, 1)
        return (total / np.maximum(count, 1)[:, None]).astype(np.float32), "POINT", fac_x
    return values, attribute.domain, fac_x


def _object_property(obj, name):
    """float32 [4] of an Attribute node of type Object named `name`: the object's (else its data's) custom property,
    a number or 3 / 4 numbers, as Cycles reads it (alpha 1 where it has none), or None."""
    for owner in (obj, getattr(obj, "data", None)):
        value = owner.get(name) if owner is not None and hasattr(owner, "get") else None
        if value is None:
            continue
        try:
            v = np.array(value if np.ndim(value) else [value], dtype=np.float64).ravel()
        except (TypeError, ValueError):
            return None
        if len(v) in (1, 3, 4) and np.isfinite(v).all():
            return _as_rgba(v, len(v))[0]
        return None
    return None


def _uv_tangents(mesh, uv_map, obj, log):
    """float32 [loops, 3]: the MikkTSpace tangents of UV map `uv_map` ('' the render one) per loop, as Cycles computes
    them for the Tangent node; None (warned) without that map or where Blender cannot (n-gons)."""
    layer = mesh.uv_layers.get(uv_map) if uv_map else render_uv_layer(mesh)
    if layer is None:
        return None
    try:
        mesh.calc_tangents(uvmap=layer.name)
    except RuntimeError as e:
        if log is not None:
            log.unsupported_feature(f"UV map tangents ({e}: 0)", obj.name)
        return None
    tangents = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    mesh.loops.foreach_get("tangent", tangents)
    mesh.free_tangents()
    return tangents


def corner_attributes(obj, mesh, names, corner_loops, tri_polys, tri_vertices, log=None):
    """({name: float32 [T, 3, 4] per triangle corner}, names read first-component Fac) for the attribute names a
    program reads (sphrect.Mesh.attributes; 'object:NAME' an Object attribute); names the mesh lacks are left out
    (read as Cycles reads a missing one)."""
    from ...native import load_sphrect
    native = load_sphrect()._native
    out, fac_x = {}, []
    n = len(tri_polys)
    for name in sorted(names):
        if name.startswith(OBJECT_ATTRIBUTE_PREFIX):
            value = _object_property(obj, name[len(OBJECT_ATTRIBUTE_PREFIX):])
            if value is not None:
                out[name] = np.broadcast_to(value, (n, 3, 4))
            continue
        if name.startswith(UV_TANGENT_PREFIX):
            tangents = _uv_tangents(mesh, name[len(UV_TANGENT_PREFIX):], obj, log)
            if tangents is not None:
                out[name] = _as_rgba(tangents, 3)[corner_loops]
            continue
        if name in (POINTINESS, RANDOM_PER_ISLAND):
            edges = np.empty(len(mesh.edges) * 2, dtype=np.int32)
            mesh.edges.foreach_get("vertices", edges)
            if name == POINTINESS:
                co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
                mesh.vertices.foreach_get("co", co)
                normals = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
                mesh.vertices.foreach_get("normal", normals)
                per_vertex = np.asarray(native._pointiness(co.reshape(-1, 3), normals.reshape(-1, 3),
                                                           edges.reshape(-1, 2)), dtype=np.float32)
            else:
                per_vertex = np.asarray(native._random_per_island(len(mesh.vertices), edges.reshape(-1, 2)),
                                        dtype=np.float32)
            out[name] = _as_rgba(per_vertex, 1)[tri_vertices]
            continue
        found = _domain_values(mesh, name)
        if found is None:
            if log is not None and name != RENDER_COLOR:
                log.unsupported_feature(f"attribute '{name}' a node reads, which the mesh lacks (0, as Cycles "
                                        "reads)", obj.name)
            continue
        values, domain, is_x = found
        index = {"POINT": tri_vertices, "CORNER": corner_loops, "FACE": tri_polys[:, None].repeat(3, 1)}[domain]
        out[name] = values[index]
        if is_x:
            fac_x.append(name)
    return out, fac_x


def triangulate(obj, log=None, uvs=False, generated=False, attributes=()):
    """LocalMesh of an evaluated object (modifiers applied), or None if it has no triangles; with the texture
    coordinates its materials read (`uvs`: the render UV map, `generated`: Blender's Generated ones).
    Triangles of transparent surfaces (volume-only materials, a white Transparent BSDF) are left out: Cycles shows
    them as transparent (the volume is volumes.py's; `log` is told of what is not simulated, naming the object).
    Smooth-shaded meshes get per-corner split normals (vertices unwelded so flat and smooth faces and
    sharp edges all keep Blender's normals), as do meshes with UVs (seams); fully flat meshes get no normals (the
    renderer uses face normals)."""
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return None
        mesh.calc_loop_triangles()
        tris = mesh.loop_triangles
        n = len(tris)
        if n == 0:
            return None
        vertex_count = len(mesh.vertices)
        vertices = np.empty(vertex_count * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", vertices)
        vertices = vertices.reshape(-1, 3)
        corner_loops = None
        if uvs or attributes:  # the corners' loops give their UVs, their vertices (quicker than a second foreach_get)
            corner_loops = np.empty(n * 3, dtype=np.int32)
            tris.foreach_get("loops", corner_loops)
            loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
            mesh.loops.foreach_get("vertex_index", loop_vertex)
            triangles = loop_vertex[corner_loops].reshape(-1, 3)
        else:
            triangles = np.empty(n * 3, dtype=np.int32)
            tris.foreach_get("vertices", triangles)
            triangles = triangles.reshape(-1, 3)
        material_index = np.empty(n, dtype=np.int32)
        tris.foreach_get("material_index", material_index)
        transparent, reasons = _transparent_slots(obj)
        if len(transparent):
            slot_count = max(len(obj.material_slots), 1)
            kept = ~np.isin(np.clip(material_index, 0, slot_count - 1), transparent)
            for reason in reasons if log is not None else ():
                log.unsupported_feature(reason, obj.name)
            if not kept.any():
                return None
            tris_kept = np.flatnonzero(kept)
        else:
            tris_kept = None
        smooth = np.empty(n, dtype=bool)
        tris.foreach_get("use_smooth", smooth)
        split = None
        if smooth.any():
            if hasattr(mesh, "calc_normals_split"):
                mesh.calc_normals_split()
            split = np.empty(n * 9, dtype=np.float32)
            tris.foreach_get("split_normals", split)
            split = split.reshape(n, 3, 3)
        corner_uvs = _corner_uvs(mesh, corner_loops, n, log, obj.name) if uvs else None
        vertex_generated = _generated(mesh) if generated else None
        corner_attrs, fac_x = {}, ()
        if attributes:
            tri_polys = np.empty(n, dtype=np.int32)
            tris.foreach_get("polygon_index", tri_polys)
            corner_attrs, fac_x = corner_attributes(obj, mesh, attributes, corner_loops.reshape(-1, 3), tri_polys,
                                                    triangles, log)
        if tris_kept is not None:
            triangles, material_index = triangles[tris_kept], material_index[tris_kept]
            split = split[tris_kept] if split is not None else None
            corner_uvs = corner_uvs[tris_kept] if corner_uvs is not None else None
            corner_attrs = {k: v[tris_kept] for k, v in corner_attrs.items()}
            n = len(tris_kept)
        normals = None
        if split is not None or corner_uvs is not None or corner_attrs:  # unwelded: a vertex per triangle corner
            corners = triangles.ravel()
            vertices = vertices[corners]
            vertex_generated = vertex_generated[corners] if vertex_generated is not None else None
            triangles = np.arange(3 * n, dtype=np.int32).reshape(-1, 3)
            normals = split.reshape(-1, 3) if split is not None else None
        corner_uvs = corner_uvs.reshape(-1, 2) if corner_uvs is not None else None
        vertex_attrs = {k: np.ascontiguousarray(v, dtype=np.float32).reshape(-1, 4) for k, v in corner_attrs.items()}
        return LocalMesh(vertices, triangles, normals, material_index, corner_uvs, vertex_generated, vertex_attrs,
                         fac_x)
    finally:
        obj.to_mesh_clear()


def slot_triangles(obj):
    """(vertices float32 [V, 3], triangles int32 [T, 3], material_index int32 [T], (texture space location, size))
    of an evaluated object in its own space, every triangle kept (an object volume's: volumes.py), or None if it has
    none."""
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return None
        mesh.calc_loop_triangles()
        n = len(mesh.loop_triangles)
        if n == 0:
            return None
        vertices = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", vertices)
        triangles = np.empty(n * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", triangles)
        material_index = np.empty(n, dtype=np.int32)
        mesh.loop_triangles.foreach_get("material_index", material_index)
        texspace = (np.array(mesh.texspace_location, dtype=np.float64), np.array(mesh.texspace_size, dtype=np.float64))
        return vertices.reshape(-1, 3), triangles.reshape(-1, 3), material_index, texspace
    finally:
        obj.to_mesh_clear()


def to_world(local, matrix_world):
    """(vertices, triangles, normals) in world space; None for a degenerate (zero-scale) matrix.
    A mirroring matrix (negative determinant) reverses the winding so geometric normals stay outward."""
    m = np.array(matrix_world, dtype=np.float64)
    linear, offset = m[:3, :3], m[:3, 3]
    det = np.linalg.det(linear)
    if not abs(det) > 1e-20:
        return None
    vertices = (local.vertices @ linear.T.astype(np.float32)) + offset.astype(np.float32)
    triangles = local.triangles[:, ::-1].copy() if det < 0 else local.triangles
    normals = None
    if local.normals is not None:
        normals = local.normals @ np.linalg.inv(linear).astype(np.float32)  # inverse transpose, row vectors
        length = np.linalg.norm(normals, axis=1, keepdims=True)
        normals = np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)
    return np.ascontiguousarray(vertices, dtype=np.float32), np.ascontiguousarray(triangles), normals


def shadow_terminator_offset(obj, normals, log):
    """The object's Shadow Terminator Geometry Offset (Object > Shading, `obj.cycles`; Cycles 3.4 applies it to
    smooth-shaded triangles: a mesh with normals), clamped to its [0, 1].  Its Shading Offset (which softens the
    shading itself) is not simulated: warned."""
    settings = getattr(getattr(obj, "original", obj), "cycles", None)  # an evaluated copy may hold stale settings
    if getattr(settings, "shadow_terminator_offset", 0.0) > 0:
        log.unsupported_feature("Shadow Terminator Shading Offset (ignored)", obj.name)
    offset = getattr(settings, "shadow_terminator_geometry_offset", 0.0)
    return 0.0 if normals is None else float(min(max(offset, 0.0), 1.0))
