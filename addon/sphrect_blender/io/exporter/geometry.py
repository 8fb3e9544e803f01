"""Evaluated Blender geometry -> world-space triangle arrays, with numpy `foreach_get` only
(no Python loop over vertices or triangles: a million triangles export in about a second)."""
import numpy as np

from .materials import transparent_surface

# Object types whose evaluated form converts to a mesh with Object.to_mesh().
MESH_LIKE = {"MESH", "CURVE", "SURFACE", "FONT", "META"}


def is_mesh_data(data):
    """Whether an evaluated object's data is a mesh, what Cycles 3.4 renders as geometry (object_is_geometry): the
    depsgraph hands a curve's, text's, surface's or metaball's triangles over as an instance whose data is a Mesh,
    besides the object itself (its Curve / MetaBall data), which is left out so they are not drawn twice."""
    return data is not None and type(data).__name__ == "Mesh"


class LocalMesh:
    """Triangles of one evaluated object in its own space (shared by all its instances); texture coordinates
    (uvs, generated: per vertex, or None) are the object's own whatever its world matrix."""
    __slots__ = ("vertices", "triangles", "normals", "material_index", "uvs", "generated")

    def __init__(self, vertices, triangles, normals, material_index, uvs=None, generated=None):
        self.vertices, self.triangles, self.normals, self.material_index = vertices, triangles, normals, material_index
        self.uvs, self.generated = uvs, generated


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
    """Indices of the object's material slots whose surface is transparent (materials.transparent_surface),
    and the warnings naming why."""
    reasons = [transparent_surface(slot.material) for slot in obj.material_slots]
    return (np.array([i for i, r in enumerate(reasons) if r], dtype=np.int32),
            sorted({r for r in reasons if r}))


def triangulate(obj, log=None, uvs=False, generated=False):
    """LocalMesh of an evaluated object (modifiers applied), or None if it has no triangles; with the texture
    coordinates its materials read (`uvs`: the render UV map, `generated`: Blender's Generated ones).
    Triangles of transparent surfaces (volume-only materials, a white Transparent BSDF) are left out: Cycles shows
    them as transparent (what is not simulated, the volume or a colour, `log` is told, naming the object).
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
        if uvs:  # the corners' loops give their UVs, and their vertices (quicker than a second foreach_get)
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
        if tris_kept is not None:
            triangles, material_index = triangles[tris_kept], material_index[tris_kept]
            split = split[tris_kept] if split is not None else None
            corner_uvs = corner_uvs[tris_kept] if corner_uvs is not None else None
            n = len(tris_kept)
        normals = None
        if split is not None or corner_uvs is not None:  # unwelded: a vertex per triangle corner
            corners = triangles.ravel()
            vertices = vertices[corners]
            vertex_generated = vertex_generated[corners] if vertex_generated is not None else None
            triangles = np.arange(3 * n, dtype=np.int32).reshape(-1, 3)
            normals = split.reshape(-1, 3) if split is not None else None
        corner_uvs = corner_uvs.reshape(-1, 2) if corner_uvs is not None else None
        return LocalMesh(vertices, triangles, normals, material_index, corner_uvs, vertex_generated)
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
