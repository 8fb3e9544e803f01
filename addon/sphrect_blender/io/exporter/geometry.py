"""Evaluated Blender geometry -> world-space triangle arrays, with numpy `foreach_get` only
(no Python loop over vertices or triangles: a million triangles export in about a second)."""
import numpy as np

from .materials import transparent_surface

# Object types whose evaluated form converts to a mesh with Object.to_mesh().
MESH_LIKE = {"MESH", "CURVE", "SURFACE", "FONT", "META"}


class LocalMesh:
    """Triangles of one evaluated object in its own space (shared by all its instances)."""
    __slots__ = ("vertices", "triangles", "normals", "material_index")

    def __init__(self, vertices, triangles, normals, material_index):
        self.vertices, self.triangles, self.normals, self.material_index = vertices, triangles, normals, material_index


def _transparent_slots(obj):
    """Indices of the object's material slots whose surface is transparent (materials.transparent_surface),
    and the warnings naming why."""
    reasons = [transparent_surface(slot.material) for slot in obj.material_slots]
    return (np.array([i for i, r in enumerate(reasons) if r], dtype=np.int32),
            sorted({r for r in reasons if r}))


def triangulate(obj, log=None):
    """LocalMesh of an evaluated object (modifiers applied), or None if it has no triangles.
    Triangles of transparent surfaces (volume-only materials, a white Transparent BSDF) are left out: Cycles shows
    them as transparent (what is not simulated, the volume or a colour, `log` is told, naming the object).
    Smooth-shaded meshes get per-corner split normals (vertices unwelded so flat and smooth faces and
    sharp edges all keep Blender's normals); fully flat meshes get none (the renderer uses face normals)."""
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
        if tris_kept is not None:
            triangles, material_index = triangles[tris_kept], material_index[tris_kept]
            split = split[tris_kept] if split is not None else None
            n = len(tris_kept)
        normals = None
        if split is not None:
            vertices = vertices[triangles.ravel()]
            triangles = np.arange(3 * n, dtype=np.int32).reshape(-1, 3)
            normals = split.reshape(-1, 3)
        return LocalMesh(vertices, triangles, normals, material_index)
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
