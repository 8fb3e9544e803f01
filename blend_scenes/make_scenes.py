"""Build the SPHRECT test scenes headless and save them (compressed) next to this script:

    blender -b --factory-startup --python blend_scenes/make_scenes.py [-- NAME ...]

01_paper         the paper's scene: Lambertian objects on a ground plane, a two-sided rectangle light
                 perpendicular to the ground and close to it, invisible to the camera
02_room          a closed room lit by a ceiling rectangle light
03_glossy_floor  a glossy floor under a rectangle light (where MIS matters)
04_foggy_room    the room filled with a homogeneous medium (world Volume Scatter)
05_hard_cases    a tiny, distant light; a light seen at grazing angles; a huge light close to a surface
06_mixed_lights  every light shape and type, instanced geometry (collection instances, linked
                 duplicates) and modifiers (array, subdivision, mirror)
07_studio        a product studio: four large rectangle softboxes of equal power (10 W each) around
                 Principled objects on a curved backdrop, inside a closed room box
08_disk_room     a closed room lit by two ceiling disk lights of different power
"""
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

HERE = os.path.dirname(os.path.abspath(__file__))
ADDON_DIR = os.path.join(HERE, "..", "addon")


def enable_addon():
    if ADDON_DIR not in sys.path:
        sys.path.insert(0, ADDON_DIR)
    import addon_utils
    addon_utils.enable("sphrect_blender", default_set=True)


def black_world(scene):
    """A world whose background emits nothing (only the scene's lights light it)."""
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    scene.world = world


def fresh_scene(name):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    enable_addon()
    scene = bpy.context.scene
    scene.name = name
    scene.render.engine = "SPHRECT"
    scene.render.resolution_x, scene.render.resolution_y = 160, 120
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.sphrect.samples = 16
    black_world(scene)
    return scene


def material(name, color=(0.8, 0.8, 0.8), kind="diffuse", roughness=0.5, metallic=0.0, specular=0.5):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    if kind == "diffuse":
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Color"].default_value = (*color, 1)
    else:
        bsdf = nodes.new("ShaderNodeBsdfPrincipled")
        bsdf.inputs["Base Color"].default_value = (*color, 1)
        bsdf.inputs["Roughness"].default_value = roughness
        bsdf.inputs["Metallic"].default_value = metallic
        bsdf.inputs["Specular"].default_value = specular
    links.new(bsdf.outputs[0], out.inputs["Surface"])
    mat.diffuse_color = (*color, 1)
    return mat


def link(obj, collection=None):
    (collection or bpy.context.scene.collection).objects.link(obj)
    return obj


def mesh_object(name, primitive, mat=None, location=(0, 0, 0), rotation=(0, 0, 0), scale=(1, 1, 1), **kw):
    getattr(bpy.ops.mesh, "primitive_" + primitive + "_add")(location=location, rotation=rotation, **kw)
    obj = bpy.context.active_object
    obj.name = name
    obj.scale = scale
    if mat is not None:
        obj.data.materials.append(mat)
    return obj


def area_light(name, shape="RECTANGLE", size=1.0, size_y=1.0, power=100.0, location=(0, 0, 0),
               rotation=(0, 0, 0), color=(1, 1, 1), two_sided=False, visible=True, scale=(1, 1, 1)):
    light = bpy.data.lights.new(name, "AREA")
    light.shape, light.size, light.size_y = shape, size, size_y
    light.energy, light.color = power, color
    light.sphrect.two_sided = two_sided
    obj = link(bpy.data.objects.new(name, light))
    obj.location, obj.rotation_euler, obj.scale = location, rotation, scale
    obj.visible_camera = visible
    return obj


def aim(obj, target):
    """Points obj's -Z (where lights emit and cameras look) at target, its Y up."""
    direction = Vector(target) - obj.location
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def other_light(name, kind, power, location=(0, 0, 0), rotation=(0, 0, 0), color=(1, 1, 1), **props):
    light = bpy.data.lights.new(name, kind)
    light.energy, light.color = power, color
    if hasattr(light, "shadow_soft_size"):
        light.shadow_soft_size = 0.0
    if kind == "SUN":
        light.angle = 0.0
    for k, v in props.items():
        setattr(light, k, v)
    obj = link(bpy.data.objects.new(name, light))
    obj.location, obj.rotation_euler = location, rotation
    return obj


def camera(location, target, lens=35.0):
    cam = bpy.data.cameras.new("Camera")
    cam.lens = lens
    obj = link(bpy.data.objects.new("Camera", cam))
    obj.location = location
    direction = Vector(target) - Vector(location)
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.camera = obj
    return obj


def smooth(obj):
    for p in obj.data.polygons:
        p.use_smooth = True


def room(mat_walls, size=(6, 6, 3)):
    """A closed box (floor, ceiling, four walls) from a cube seen from inside."""
    obj = mesh_object("Room", "cube", mat_walls, location=(0, 0, size[2] / 2), scale=(size[0] / 2, size[1] / 2,
                                                                                         size[2] / 2))
    return obj


def save(scene_name):
    path = os.path.join(HERE, scene_name + ".blend")
    bpy.context.preferences.filepaths.save_version = 0  # no .blend1 backups next to the committed files
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True, check_existing=False)
    print("wrote", path, os.path.getsize(path), "bytes")


# ------------------------------------------------------------------ the scenes
def paper():
    fresh_scene("paper")
    white = material("Ground", (0.8, 0.8, 0.8))
    mesh_object("Ground", "plane", white, size=12)
    smooth(mesh_object("Sphere", "uv_sphere", material("Red", (0.7, 0.15, 0.1)), location=(-1.2, 0.8, 0.6),
                       radius=0.6, segments=32, ring_count=16))
    mesh_object("Box", "cube", material("Green", (0.2, 0.6, 0.2)), location=(1.3, 0.9, 0.5), size=1.0,
                rotation=(0, 0, 0.5))
    smooth(mesh_object("Cylinder", "cylinder", material("Blue", (0.15, 0.25, 0.7)), location=(0.1, 2.0, 0.7),
                       radius=0.35, depth=1.4, vertices=32))
    # Perpendicular to the ground (rotated 90 degrees about X: its plane holds X and Z), bottom edge
    # 5 cm above the ground, emitting on both faces and hidden from the camera.
    area_light("Light", "RECTANGLE", size=3.0, size_y=0.6, power=50.0, location=(0, -0.2, 0.35),
               rotation=(math.pi / 2, 0, 0), two_sided=True, visible=False)
    camera((0.0, -7.0, 3.2), (0.0, 0.8, 0.4))
    save("01_paper")


def room_scene(name, fog):
    scene = fresh_scene(name)
    room(material("Walls", (0.75, 0.75, 0.7)))
    mesh_object("Box", "cube", material("Orange", (0.8, 0.45, 0.15)), location=(1.0, 1.0, 0.6), size=1.2,
                rotation=(0, 0, 0.4))
    smooth(mesh_object("Sphere", "uv_sphere", material("Grey", (0.6, 0.6, 0.6)), location=(-1.1, 0.3, 0.7),
                       radius=0.7, segments=32, ring_count=16))
    area_light("Ceiling Light", "RECTANGLE", size=1.6, size_y=0.8, power=300.0, location=(0, 0.5, 2.98))
    camera((0.0, -2.8, 1.5), (0.0, 0.8, 0.9), lens=20.0)
    if fog:
        nodes, links = scene.world.node_tree.nodes, scene.world.node_tree.links
        scatter = nodes.new("ShaderNodeVolumeScatter")
        scatter.inputs["Density"].default_value = 0.15
        scatter.inputs["Color"].default_value = (0.9, 0.9, 0.9, 1)
        scatter.inputs["Anisotropy"].default_value = 0.3
        links.new(scatter.outputs[0], nodes["World Output"].inputs["Volume"])
    save(name)


def glossy_floor():
    fresh_scene("glossy_floor")
    mesh_object("Floor", "plane", material("Glossy Floor", (0.3, 0.3, 0.35), kind="principled", roughness=0.15,
                                           metallic=1.0), size=10)
    mesh_object("Back", "plane", material("Wall", (0.7, 0.7, 0.7)), location=(0, 3, 2), rotation=(math.pi / 2, 0, 0),
                size=10)
    smooth(mesh_object("Sphere", "uv_sphere", material("Plastic", (0.1, 0.3, 0.8), kind="principled",
                                                       roughness=0.4), location=(0.8, 0.6, 0.5), radius=0.5,
                       segments=32, ring_count=16))
    area_light("Light", "RECTANGLE", size=2.0, size_y=0.5, power=200.0, location=(-0.5, 1.2, 2.2),
               rotation=(-0.5, 0, 0))
    camera((0.0, -5.0, 1.6), (0.0, 1.0, 0.5), lens=40.0)
    save("03_glossy_floor")


def hard_cases():
    fresh_scene("hard_cases")
    mesh_object("Ground", "plane", material("Ground", (0.8, 0.8, 0.8)), size=30)
    mesh_object("Table", "cube", material("Table", (0.7, 0.6, 0.5)), location=(4.0, 4.0, 0.25),
                scale=(1.5, 1.5, 0.25))
    # Tiny (2 cm) and distant (60 m): subtends ~5e-8 sr from the ground.
    area_light("Tiny Distant", "SQUARE", size=0.02, power=2.0e4, location=(-30.0, 20.0, 50.0),
               rotation=(0.5, -0.4, 0))
    # Seen at grazing angles: a wide light standing 1 cm above the ground, tilted 88 degrees.
    area_light("Grazing", "RECTANGLE", size=4.0, size_y=0.3, power=200.0, location=(0.0, 0.0, 0.16),
               rotation=(math.radians(88), 0, 0))
    # Huge and close: 3 m x 3 m, 2 cm above the table top (hidden from the camera to show the top).
    area_light("Huge Close", "SQUARE", size=3.0, power=100.0, location=(4.0, 4.0, 0.52), visible=False)
    camera((0.0, -9.0, 5.0), (1.0, 1.5, 0.0), lens=28.0)
    save("05_hard_cases")


def mixed_lights():
    scene = fresh_scene("mixed_lights")
    mesh_object("Ground", "plane", material("Ground", (0.8, 0.8, 0.8)), size=16)
    # Modifiers: an array of boxes, a subdivided (smooth) cube, a mirrored pair.
    boxes = mesh_object("Array", "cube", material("Boxes", (0.7, 0.3, 0.2)), location=(-3, 2, 0.25), size=0.5)
    arr = boxes.modifiers.new("Array", "ARRAY")
    arr.count, arr.relative_offset_displace = 5, (1.6, 0, 0)
    blob = mesh_object("Subdivided", "cube", material("Blob", (0.2, 0.5, 0.7)), location=(2.0, -0.5, 0.6), size=1.0)
    blob.modifiers.new("Subsurf", "SUBSURF").levels = 2
    smooth(blob)
    pair = mesh_object("Mirrored", "cone", material("Cone", (0.6, 0.6, 0.2)), location=(0.8, -1.5, 0.5), radius1=0.3,
                       depth=1.0, vertices=16)
    pair.data.transform(Matrix.Translation((0.45, 0.0, 0.0)))  # off the mirror plane: two separate cones
    pair.modifiers.new("Mirror", "MIRROR")
    # Instancing: one collection instanced three times (one with negative scale) and linked duplicates.
    coll = bpy.data.collections.new("Pillar")
    pillar = mesh_object("Pillar", "cylinder", material("Pillar", (0.75, 0.75, 0.75)), radius=0.15, depth=1.5,
                         vertices=16, location=(0, 0, 0.75))
    scene.collection.objects.unlink(pillar)
    coll.objects.link(pillar)
    for i, (x, y, s) in enumerate([(-2.5, -1.0, 1.0), (-1.5, -1.5, -1.0), (-0.5, -2.0, 0.7)]):
        inst = link(bpy.data.objects.new(f"Pillar Instance {i}", None))
        inst.instance_type, inst.instance_collection = "COLLECTION", coll
        inst.location, inst.scale = (x, y, 0), (s, 1, 1)
    ball = mesh_object("Ball", "ico_sphere", material("Ball", (0.8, 0.8, 0.8)), location=(3.0, 2.0, 0.3),
                       radius=0.3, subdivisions=2)
    for i in range(1, 3):
        dup = link(bpy.data.objects.new(f"Ball Duplicate {i}", ball.data))
        dup.location = (3.0 - 0.8 * i, 2.5, 0.3)
    # Every light shape and type.
    area_light("Square", "SQUARE", size=0.8, power=80.0, location=(-2.5, 1.0, 2.0), color=(1.0, 0.9, 0.8))
    area_light("Rectangle", "RECTANGLE", size=1.2, size_y=0.4, power=80.0, location=(0.0, 1.0, 2.0),
               scale=(1.0, 1.5, 1.0))
    area_light("Disk", "DISK", size=0.8, power=80.0, location=(2.5, 1.0, 2.0), color=(0.8, 0.9, 1.0))
    area_light("Ellipse", "ELLIPSE", size=1.0, size_y=0.5, power=80.0, location=(2.0, -2.0, 2.0),
               rotation=(0.3, 0.2, 0))
    other_light("Point", "POINT", 60.0, location=(-1.0, -2.5, 1.5))
    other_light("Spot", "SPOT", 300.0, location=(0.0, -4.0, 3.0), rotation=(math.radians(50), 0, 0),
                spot_size=math.radians(40), spot_blend=0.2)
    other_light("Sun", "SUN", 0.3, rotation=(0.6, 0.3, 0.0), color=(1.0, 0.95, 0.9))
    camera((0.0, -8.0, 4.5), (0.0, 0.0, 0.5), lens=30.0)
    save("06_mixed_lights")


def studio():
    fresh_scene("studio")
    room(material("Room", (0.6, 0.6, 0.6)), size=(10, 10, 5))
    # A backdrop (cyclorama): a floor sheet bending up into a back wall, one smooth mesh, 2 cm above the
    # room's floor (coplanar with it, shadow rays would start under one of the two).
    backdrop = mesh_object("Backdrop", "plane", material("Backdrop", (0.85, 0.85, 0.85)), size=1.0)
    mesh = backdrop.data
    mesh.clear_geometry()
    rows, radius = 12, 1.0
    profile = [(y, 0.0) for y in (-3.0, -1.5, 0.0)]  # (y, z) along the floor, then a quarter circle up
    profile += [(radius * math.sin(a), radius * (1 - math.cos(a)))
                for a in (math.pi / 2 * (i + 1) / rows for i in range(rows))]
    profile += [(radius, 3.0)]
    lift = 0.02
    verts = [(x, y, z + lift) for (y, z) in profile for x in (-3.0, 3.0)]
    faces = [(2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2) for i in range(len(profile) - 1)]
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(bpy.data.materials["Backdrop"])
    smooth(backdrop)
    target = (0.0, -0.6, 0.5)
    smooth(mesh_object("Product Sphere", "uv_sphere", material("Plastic", (0.7, 0.1, 0.1), kind="principled",
                                                               roughness=0.3), location=(-0.5, -0.6, 0.45 + lift),
                       radius=0.45, segments=32, ring_count=16))
    mesh_object("Product Box", "cube", material("Satin", (0.2, 0.3, 0.6), kind="principled", roughness=0.5),
                location=(0.55, -0.4, 0.35 + lift), size=0.7, rotation=(0, 0, 0.6))
    # Four softboxes of 10 W each, all aimed at the product: key and fill in front, a rim behind, a top light.
    for name, loc, (w, h) in [("Key", (-2.0, -2.6, 1.8), (1.2, 1.6)), ("Fill", (2.2, -2.4, 1.4), (1.2, 1.6)),
                              ("Rim Left", (-2.2, 0.6, 2.2), (0.6, 1.8)), ("Top", (0.3, -0.8, 3.2), (1.6, 1.0))]:
        aim(area_light(name, "RECTANGLE", size=w, size_y=h, power=10.0, location=loc), target)
    camera((0.0, -4.6, 1.3), target, lens=40.0)
    save("07_studio")


def disk_room():
    fresh_scene("disk_room")
    room(material("Walls", (0.75, 0.72, 0.68)))
    mesh_object("Table", "cube", material("Wood", (0.55, 0.35, 0.2)), location=(0.4, 0.8, 0.4), scale=(0.8, 0.5, 0.4))
    smooth(mesh_object("Vase", "uv_sphere", material("Ceramic", (0.2, 0.5, 0.5), kind="principled", roughness=0.35),
                       location=(-1.2, 0.2, 0.5), radius=0.5, segments=32, ring_count=16))
    area_light("Disk Left", "DISK", size=0.6, power=150.0, location=(-1.2, 0.6, 2.98))
    area_light("Disk Right", "DISK", size=0.4, power=60.0, location=(1.4, 1.2, 2.98))
    camera((0.0, -2.8, 1.5), (0.0, 0.8, 0.8), lens=20.0)
    save("08_disk_room")


SCENES = {"01_paper": paper, "02_room": lambda: room_scene("02_room", fog=False), "03_glossy_floor": glossy_floor,
          "04_foggy_room": lambda: room_scene("04_foggy_room", fog=True), "05_hard_cases": hard_cases,
          "06_mixed_lights": mixed_lights, "07_studio": studio, "08_disk_room": disk_room}

if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    for name in argv or SCENES:
        SCENES[name]()
