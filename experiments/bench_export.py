"""Exporter speed (a benchmark, not a test): a million-triangle mesh, flat and smooth, and 100 instances of
a 10k-triangle mesh, through scene_from_depsgraph and save_scene. Run:

    SPHRECT_PYTHON_PATH=build/python blender -b --factory-startup --python experiments/bench_export.py
"""
import os
import sys
import tempfile
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path[:0] = [os.path.join(REPO, "addon"),
                os.environ.get("SPHRECT_PYTHON_PATH", os.path.join(REPO, "build", "python"))]
import addon_utils  # noqa: E402

addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
import sphrect_blender  # noqa: E402


def timed(label, repeat=3):
    best, scene = 1e30, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        scene, _ = sphrect_blender.scene_from_depsgraph(bpy.context.evaluated_depsgraph_get())
        best = min(best, time.perf_counter() - t0)
    tris = sum(len(m.triangles) for m in scene.meshes)
    print(f"{label:<40} {tris:>9} triangles  {len(scene.meshes):>4} meshes  export {best:.3f} s (best of {repeat})")
    return scene


bpy.ops.wm.read_homefile(use_empty=True)
bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=10)
grid = bpy.context.active_object
scene = timed("grid, flat shading")
path = os.path.join(tempfile.mkdtemp(), "bench.sphrect.npz")
t0 = time.perf_counter()
sphrect_blender.load_sphrect().save_scene(scene, path)
print(f"{'save_scene of that scene':<40} {os.path.getsize(path) / 1e6:>9.1f} MB  {time.perf_counter() - t0:.3f} s")
for p in grid.data.polygons:
    p.use_smooth = True
timed("grid, smooth shading (split normals)")
bpy.data.objects.remove(grid)
bpy.ops.mesh.primitive_uv_sphere_add(segments=100, ring_count=51)
sphere = bpy.context.active_object
coll = bpy.data.collections.new("C")
bpy.context.scene.collection.objects.unlink(sphere)
coll.objects.link(sphere)
for i in range(100):
    e = bpy.data.objects.new(f"I{i}", None)
    e.instance_type, e.instance_collection = "COLLECTION", coll
    e.location = (i % 10 * 3, i // 10 * 3, 0)
    bpy.context.scene.collection.objects.link(e)
timed("100 collection instances of a sphere")
