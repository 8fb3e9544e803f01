"""What a depsgraph update asks the viewport to re-export.

The native scene is built whole (its BVH, light tree and the camera's light footprints are made at commit),
so every change rebuilds the renderer; what differs is how much of the Blender data is exported again:
lights only (a light moved or edited: the meshes are kept), the world only, the scene camera only (its
depth of field, seen through it), or everything (geometry, materials, objects added or removed, anything
not recognised). View changes re-export nothing (the camera comes from the region, see viewport_camera)."""
import bpy

LIGHTS, WORLD, CAMERA, EVERYTHING = "lights", "world", "camera", "everything"

# Updates that name nothing the exported scene holds (the scene's settings and contents are compared
# separately: viewport.settings_signature, contents_signature).
_IGNORED = (bpy.types.Scene, bpy.types.Screen, bpy.types.WorkSpace, bpy.types.WindowManager)


def _kind(update):
    block = update.id
    if isinstance(block, _IGNORED):
        return None
    if isinstance(block, bpy.types.Light):
        return LIGHTS
    if isinstance(block, bpy.types.Object):
        if block.type == "LIGHT":
            return LIGHTS
        if block.type == "CAMERA":  # the region's matrices follow it; re-read its depth of field
            return CAMERA
        return EVERYTHING
    if isinstance(block, bpy.types.Camera):
        return CAMERA
    if isinstance(block, bpy.types.World):
        return WORLD
    return EVERYTHING  # meshes, materials, node trees, collections (objects added or removed), images, ...


def reexport_kinds(updates):
    """The set of LIGHTS / WORLD / CAMERA / EVERYTHING that `depsgraph.updates` call for (EVERYTHING alone
    when present). A bare Scene update calls for nothing here: see contents_signature."""
    kinds = {k for k in map(_kind, updates) if k is not None}
    return {EVERYTHING} if EVERYTHING in kinds else kinds


def scene_updated(updates):
    return any(isinstance(u.id, bpy.types.Scene) for u in updates)


def contents_signature(depsgraph):
    """What a Scene update may change without naming the objects: which objects are shown (hiding one in the
    view layer updates only the Scene), the world (and the view layer's Environment filter) and the camera.
    Compared on Scene updates."""
    scene = depsgraph.scene
    shown = tuple((i.object.name, i.is_instance) for i in depsgraph.object_instances)
    world = scene.world.name if scene.world and depsgraph.view_layer.use_sky else None
    return shown, world, scene.camera.name if scene.camera else None
