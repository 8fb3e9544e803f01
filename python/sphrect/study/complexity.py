"""Scenes made costlier to trace without changing their image, for the cost model's sweep (sweep.py).

subdivide_scene splits every triangle of the meshes that emit nothing into four at its edges' midpoints, `levels`
times (4^levels triangles for one), each new vertex shared by the two triangles of its edge and its attributes --
position, normal, texture coordinates, the node programs' attributes -- the mean of the edge's two ends.  Every
attribute the renderer interpolates across a triangle is linear in the barycentrics, so each point of the new surface
has the same interpolated values as before (normals included: they are renormalised after interpolation), and the
image is the same up to rounding; only the BVH is deeper, so rays cost more.  Left as they are: emissive meshes (their
triangles are lights: splitting them would change the light sampling).  What is not exact: a mesh's shadow terminator
offset (Cycles' offset from each triangle's own vertex normals) and programs reading the Parametric output, both rare
in the scenes the sweep runs on.
"""
from __future__ import annotations

import dataclasses
from typing import Dict, List

import numpy as np

from ..scene import Material, Mesh, Scene


def material_emits(m: Material) -> bool:
    """Whether a material emits: its emission, an emission texture or program, or a layer's."""
    if any(float(c) > 0 for c in (m.emission or (0.0, 0.0, 0.0))):
        return True
    if "emission" in (m.textures or {}) or "emission" in (m.programs or {}):
        return True
    return any(material_emits(layer.material) for layer in (m.layers or []))


def mesh_emits(mesh: Mesh, materials: List[Material]) -> bool:
    ids = np.zeros(1, np.int32) if mesh.material_ids is None else np.unique(np.asarray(mesh.material_ids))
    return any(material_emits(materials[int(i)]) for i in ids if 0 <= int(i) < len(materials))


def split_once(triangles: np.ndarray, per_vertex: Dict[str, np.ndarray], material_ids):
    """One midpoint split: (triangles [4T, 3], the per-vertex arrays with a vertex per edge appended, the material ids
    repeated)."""
    t = np.asarray(triangles, np.int64)
    edges = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])  # edge k of triangle i at k T + i
    ends = np.sort(edges, axis=1)
    unique, inverse = np.unique(ends, axis=0, return_inverse=True)
    n = len(next(iter(per_vertex.values())))
    out = {name: np.concatenate([v, (0.5 * (v[unique[:, 0]].astype(np.float64) + v[unique[:, 1]])).astype(v.dtype)])
           for name, v in per_vertex.items()}
    mid = (n + inverse.reshape(3, len(t))).T  # [T, 3]: the midpoints of edges 01, 12, 20
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    m01, m12, m20 = mid[:, 0], mid[:, 1], mid[:, 2]
    new = np.concatenate([np.stack([a, m01, m20], 1), np.stack([m01, b, m12], 1), np.stack([m20, m12, c], 1),
                          np.stack([m01, m12, m20], 1)])
    ids = None if material_ids is None else np.tile(np.asarray(material_ids), 4)
    return new.astype(np.int32), out, ids


def subdivide_mesh(mesh: Mesh, levels: int) -> Mesh:
    """The mesh with every triangle split `levels` times (the triangles' order: each level's four pieces in blocks)."""
    per_vertex = {"vertices": np.asarray(mesh.vertices, np.float32)}
    for name in ("normals", "uvs", "generated"):
        if getattr(mesh, name) is not None:
            per_vertex[name] = np.asarray(getattr(mesh, name), np.float32)
    for name, values in (mesh.attributes or {}).items():
        per_vertex["attribute:" + name] = np.asarray(values, np.float32)
    triangles, ids = mesh.triangles, mesh.material_ids
    for _ in range(levels):
        triangles, per_vertex, ids = split_once(triangles, per_vertex, ids)
    attributes = {name[len("attribute:"):]: v for name, v in per_vertex.items() if name.startswith("attribute:")}
    return dataclasses.replace(mesh, vertices=per_vertex["vertices"], triangles=triangles,
                               normals=per_vertex.get("normals"), uvs=per_vertex.get("uvs"),
                               generated=per_vertex.get("generated"), material_ids=ids, attributes=attributes)


def subdivide_scene(scene: Scene, levels: int) -> Scene:
    """The scene with every mesh that emits nothing split `levels` times (subdivide_mesh)."""
    if levels < 0:
        raise ValueError(f"levels must be >= 0, got {levels}")
    meshes = [m if levels == 0 or mesh_emits(m, scene.materials) else subdivide_mesh(m, levels) for m in scene.meshes]
    return dataclasses.replace(scene, meshes=meshes)


def triangle_count(scene: Scene) -> int:
    return sum(len(m.triangles) for m in scene.meshes)


def subdivided_triangle_count(scene: Scene, levels: int) -> int:
    """The triangles subdivide_scene(scene, levels) would have (without building it)."""
    return sum(len(m.triangles) * (1 if mesh_emits(m, scene.materials) else 4 ** levels) for m in scene.meshes)
