"""Build the SPHRECT test scenes headless and save them (compressed) in blend_scenes/:

    blender -b --factory-startup --python scripts/make_scenes.py [-- NAME ...]

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
09_hall          a hall lit by a 20 x 20 grid of small ceiling panels (400 area lights: rectangles and
                 some disks) over pillars, crates and Principled spheres
10_night_street  a night street: 1,000 point and spot lights (street lamps, string lights across the
                 street, shop-front downlights) and lit windows (mesh quads with an Emission shader),
                 a dark blue night sky
11_paper_disk    the paper's scene with its light replaced by a two-sided disk of the same area and
                 power, its lowest point 5 cm above the ground
12_disk_ceiling  the room of 02_room lit by a ceiling disk of the rectangle's area and power
13_textured_room a room of image textures made here with numpy and packed into the .blend: a glossy wooden
                 floor (sRGB planks, a Non-Color roughness map), a tiled back wall (UVs scaled by a Mapping
                 node), a normal-mapped side wall (tangent space, smooth bumps) and a checkered crate
                 (Generated coordinates, closest filtering), lit by a ceiling rectangle and a ceiling disk
14_still_life    glass and metal on a wooden table: a Glass BSDF sphere, a brushed-metal can (Principled,
                 metallic), a polished Glossy BSDF ring, a clearcoated ceramic vase and a box of a diffuse +
                 glossy Mix Shader, under a rectangle softbox and a disk light
15_fog_stage     a stage in a fog box (a cube of Volume Scatter + Volume Absorption, no surface) seen from
                 outside it: a spot light's visible cone, a street lamp (a point light in an emissive globe) and a
                 dim rectangle light
16_fog_room      the room of 02_room filled by a Principled Volume box around it and the camera, lit by the
                 ceiling rectangle and a disk light
17_warehouse     10,000 area lights: a 60 x 60 m warehouse under a grid of 3,600 ceiling panels, its eight rows
                 of racks lined with 6,400 small LED strips facing the aisles (32 light datablocks shared by
                 linked duplicates), a glossy floor and Principled crates; the camera high in a corner
"""
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Matrix, Vector

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
ADDON_DIR = os.path.join(REPO, "addon")
BLEND_DIR = os.path.join(REPO, "blend_scenes")  # where the scenes are written


def enable_addon():
    if ADDON_DIR not in sys.path:
        sys.path.insert(0, ADDON_DIR)
    import addon_utils
    addon_utils.enable("sphrect_blender", default_set=True)


def sky_floor_scene(scene, elevation):
    """A 10 m floor, a camera 1 m above it looking at the horizon, and a Nishita sky of sun `elevation` (radians) as
    the world: the world-bake scripts' scene (a world no earlier run baked when the elevation is new)."""
    floor = bpy.data.meshes.new("Floor")
    floor.from_pydata([(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("Floor", floor))
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    cam.location, cam.rotation_euler = (0, -5, 1), (1.4, 0, 0)
    scene.camera = cam
    world = bpy.data.worlds.new("Sky")
    world.use_nodes = True
    sky = world.node_tree.nodes.new("ShaderNodeTexSky")
    sky.sun_elevation = elevation
    world.node_tree.links.new(sky.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
    scene.world = world
    return world


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
    # The 1-px box, not Blender's Blackman-Harris: the study's figures are the box's, and it keeps Exact Light
    # Edges (the Cycles peer renders the scene's filter too).
    scene.sphrect.pixel_filter = "BOX"
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
    path = os.path.join(BLEND_DIR, scene_name + ".blend")
    bpy.context.preferences.filepaths.save_version = 0  # no .blend1 backups next to the committed files
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True, check_existing=False)
    print("wrote", path, os.path.getsize(path), "bytes")


# ------------------------------------------------------------------ the scenes
def disk_diameter(area):
    """Blender's DISK size (its diameter) for a disk of `area`."""
    return 2.0 * math.sqrt(area / math.pi)


def paper_objects():
    white = material("Ground", (0.8, 0.8, 0.8))
    mesh_object("Ground", "plane", white, size=12)
    smooth(mesh_object("Sphere", "uv_sphere", material("Red", (0.7, 0.15, 0.1)), location=(-1.2, 0.8, 0.6),
                       radius=0.6, segments=32, ring_count=16))
    mesh_object("Box", "cube", material("Green", (0.2, 0.6, 0.2)), location=(1.3, 0.9, 0.5), size=1.0,
                rotation=(0, 0, 0.5))
    smooth(mesh_object("Cylinder", "cylinder", material("Blue", (0.15, 0.25, 0.7)), location=(0.1, 2.0, 0.7),
                       radius=0.35, depth=1.4, vertices=32))


def paper():
    fresh_scene("paper")
    paper_objects()
    # Perpendicular to the ground (rotated 90 degrees about X: its plane holds X and Z), bottom edge
    # 5 cm above the ground, emitting on both faces and hidden from the camera.
    area_light("Light", "RECTANGLE", size=3.0, size_y=0.6, power=50.0, location=(0, -0.2, 0.35),
               rotation=(math.pi / 2, 0, 0), two_sided=True, visible=False)
    camera((0.0, -7.0, 3.2), (0.0, 0.8, 0.4))
    save("01_paper")


def paper_disk():
    fresh_scene("paper_disk")
    paper_objects()
    # The 3 m x 0.6 m light's area (1.8 m^2) and power, in the same vertical plane, its lowest point
    # 5 cm above the ground as the rectangle's bottom edge.
    d = disk_diameter(3.0 * 0.6)
    area_light("Light", "DISK", size=d, power=50.0, location=(0, -0.2, 0.05 + d / 2),
               rotation=(math.pi / 2, 0, 0), two_sided=True, visible=False)
    camera((0.0, -7.0, 3.2), (0.0, 0.8, 0.4))
    save("11_paper_disk")


def room_scene(name, fog, disk=False):
    scene = fresh_scene(name)
    room(material("Walls", (0.75, 0.75, 0.7)))
    mesh_object("Box", "cube", material("Orange", (0.8, 0.45, 0.15)), location=(1.0, 1.0, 0.6), size=1.2,
                rotation=(0, 0, 0.4))
    smooth(mesh_object("Sphere", "uv_sphere", material("Grey", (0.6, 0.6, 0.6)), location=(-1.1, 0.3, 0.7),
                       radius=0.7, segments=32, ring_count=16))
    if disk:  # the rectangle's area (1.28 m^2) and power
        area_light("Ceiling Light", "DISK", size=disk_diameter(1.6 * 0.8), power=300.0, location=(0, 0.5, 2.98))
    else:
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


def hall():
    fresh_scene("hall")
    room(material("Hall", (0.7, 0.7, 0.68)), size=(24, 24, 6))
    # Pillars in two rows, crates and three Principled spheres on the floor.
    concrete, wood = material("Concrete", (0.6, 0.6, 0.6)), material("Wood", (0.55, 0.38, 0.2))
    for i in range(4):
        for x in (-4.0, 4.0):
            mesh_object(f"Pillar {x:+.0f} {i}", "cylinder", concrete, location=(x, -6.0 + 5.0 * i, 3.0), radius=0.3,
                        depth=6.0, vertices=12)
    for k, (x, y, s, a) in enumerate([(-1.5, -3.0, 1.0, 0.3), (1.8, 0.5, 1.4, -0.2), (-2.2, 3.5, 0.8, 0.8),
                                      (0.5, 6.0, 1.2, 0.1)]):
        mesh_object(f"Crate {k}", "cube", wood, location=(x, y, s / 2), size=s, rotation=(0, 0, a))
    for k, (x, y, color, rough) in enumerate([(0.2, -4.5, (0.7, 0.1, 0.1), 0.3), (-0.8, 1.0, (0.1, 0.4, 0.7), 0.5),
                                              (2.5, 4.0, (0.8, 0.7, 0.2), 0.2)]):
        smooth(mesh_object(f"Sphere {k}", "uv_sphere", material(f"Plastic {k}", color, kind="principled",
                                                                  roughness=rough), location=(x, y, 0.5),
                           radius=0.5, segments=24, ring_count=12))
    # 20 x 20 ceiling panels, 1.1 m apart, 2 cm under the ceiling, facing down: 60 x 30 cm rectangles,
    # a diagonal pattern of 40 cm disks (57 of them); 6 W each (2.4 kW in all).
    for i in range(20):
        for j in range(20):
            x, y = 1.1 * (j - 9.5), 1.1 * (i - 9.5)
            if (i + 2 * j) % 7 == 3:
                area_light(f"Panel {i:02d} {j:02d}", "DISK", size=0.4, power=6.0, location=(x, y, 5.98))
            else:
                area_light(f"Panel {i:02d} {j:02d}", "RECTANGLE", size=0.6, size_y=0.3, power=6.0,
                           location=(x, y, 5.98))
    camera((0.0, -11.0, 1.7), (0.0, 2.0, 2.0), lens=22.0)
    save("09_hall")


def emission_material(name, color, strength):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*color, 1)
    emission.inputs["Strength"].default_value = strength
    links.new(emission.outputs[0], out.inputs["Surface"])
    mat.diffuse_color = (*color, 1)
    return mat


def night_street():
    scene = fresh_scene("night_street")
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.002, 0.003, 0.008, 1)
    mesh_object("Road", "plane", material("Asphalt", (0.12, 0.12, 0.13)), size=120)
    kerb = material("Pavement", (0.35, 0.34, 0.32))
    for x in (-4.5, 4.5):
        mesh_object(f"Pavement {x:+.1f}", "cube", kerb, location=(x, 0.0, 0.075), scale=(1.5, 40.0, 0.075))
    # Eight buildings a side, their facades at x = +-6 facing the street; windows on floors 1-4, six a
    # building and floor, lit (emissive quads 1 cm in front of the facade) where a fixed hash says so.
    walls = material("Facade", (0.45, 0.4, 0.35))
    warm, cool = emission_material("Window Warm", (1.0, 0.72, 0.4), 2.0), emission_material("Window Cool",
                                                                                               (0.6, 0.7, 1.0), 1.5)
    for side in (-1, 1):
        verts, faces, mat_index = [], [], []
        for b in range(8):
            y0 = -40.0 + 10.0 * b
            height = 10.0 + 2.0 * ((3 * b + (side > 0)) % 4)
            mesh_object(f"Building {side:+d} {b}", "cube", walls, location=(side * 11.0, y0 + 4.875, height / 2),
                        scale=(5.0, 4.75, height / 2))
            for floor in range(1, 5):
                for w in range(6):
                    h = (b * 131 + floor * 37 + w * 17 + (side > 0) * 59) % 10
                    if h >= 6:
                        continue  # a dark window
                    x = side * 5.99
                    ya, yb = y0 + 0.6 + 1.5 * w, y0 + 1.5 + 1.5 * w
                    za, zb = 2.5 * floor + 0.8, 2.5 * floor + 2.2
                    k = len(verts)
                    verts += [(x, ya, za), (x, yb, za), (x, yb, zb), (x, ya, zb)]
                    faces.append((k, k + 1, k + 2, k + 3) if side > 0 else (k, k + 3, k + 2, k + 1))
                    mat_index.append(0 if h < 4 else 1)
        mesh = bpy.data.meshes.new(f"Windows {side:+d}")
        mesh.from_pydata(verts, [], faces)
        mesh.materials.append(warm)
        mesh.materials.append(cool)
        for poly, m in zip(mesh.polygons, mat_index):
            poly.material_index = m
        link(bpy.data.objects.new(f"Windows {side:+d}", mesh))
    # 40 street lamps along both kerbs: a 5.6 m post, an arm reaching 60 cm over the road and, 5 cm under
    # the arm's end, a 150 W spot aimed down (clear of the post, whose surface it would graze).
    post = material("Lamp Post", (0.2, 0.2, 0.22))
    for side in (-1, 1):
        for k in range(20):
            y = -38.0 + 4.0 * k + (2.0 if side > 0 else 0.0)
            mesh_object(f"Post {side:+d} {k:02d}", "cylinder", post, location=(side * 3.5, y, 2.8), radius=0.06,
                        depth=5.6, vertices=8)
            mesh_object(f"Arm {side:+d} {k:02d}", "cube", post, location=(side * 3.2, y, 5.59), size=1.0,
                        scale=(0.7, 0.08, 0.06))
            other_light(f"Street Lamp {side:+d} {k:02d}", "SPOT", 150.0, location=(side * 2.9, y, 5.5),
                        color=(1.0, 0.8, 0.55), spot_size=math.radians(110), spot_blend=0.3)
    # 12 strings of 40 bulbs across the street (0.3 W points), sagging from 6.5 m to 5.3 m.
    for s in range(12):
        y = -33.0 + 6.0 * s
        for k in range(40):
            t = (k + 0.5) / 40
            x = -5.9 + 11.8 * t
            z = 6.5 - 4.8 * t * (1 - t)
            color = [(1.0, 0.6, 0.3), (1.0, 0.9, 0.6), (0.6, 0.8, 1.0), (1.0, 0.4, 0.5)][(s + k) % 4]
            other_light(f"Bulb {s:02d} {k:02d}", "POINT", 0.3, location=(x, y + 0.2 * math.sin(7 * t), z),
                        color=color)
    # Shop fronts: along every ground floor, 30 downlights (0.5 W spots) 40 cm in front of the facade.
    for side in (-1, 1):
        for b in range(8):
            for k in range(30):
                y = -40.0 + 10.0 * b + 0.3 + 9.15 * k / 29
                other_light(f"Downlight {side:+d} {b} {k:02d}", "SPOT", 0.5, location=(side * 5.6, y, 3.0),
                            color=(1.0, 0.85, 0.7), spot_size=math.radians(90), spot_blend=0.5)
    camera((1.0, -44.0, 1.7), (0.0, -10.0, 3.5), lens=28.0)
    save("10_night_street")


# ------------------------------------------------------------------ image textures, made here with numpy
def packed_image(name, rgb, non_color=False):
    """A byte image of an (h, w, 3) array in [0, 1] whose row 0 is the top (values as stored: sRGB-encoded
    colours, or data for Non-Color), packed into the .blend (as PNG), so the scene needs no other file."""
    h, w = rgb.shape[:2]
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[..., :3] = np.clip(rgb, 0.0, 1.0)
    image = bpy.data.images.new(name, w, h, alpha=False)
    image.pixels.foreach_set(np.flipud(rgba).ravel())  # Blender's rows go bottom to top
    image.file_format = "PNG"
    image.pack()
    if non_color:
        image.colorspace_settings.name = "Non-Color"
    return image


def texel_grid(height, width):
    """(u, v) of each texel's centre, (h, w) arrays in [0, 1), v = 1 on row 0 (the top) as UVs run."""
    u = (np.arange(width) + 0.5) / width
    v = 1.0 - (np.arange(height) + 0.5) / height
    return np.meshgrid(u, v)


def smooth_noise(u, v, rng, octaves=4, base=2):
    """Tileable smooth noise in [-1, 1]: a sum of sines of integer frequencies with random phases."""
    total, norm = np.zeros_like(u), 0.0
    for k in range(octaves):
        f, a = base * 2 ** k, 0.5 ** k
        for _ in range(2):
            fu, fv = rng.integers(-f, f + 1, size=2)
            total += a * np.sin(2 * np.pi * (fu * u + fv * v) + rng.uniform(0, 2 * np.pi))
            norm += a
    return total / norm


def wood_planks(width, height, planks, seed):
    """(colour, roughness) images (height x width) of `planks` rows of planks along u, each row with its own
    tone, grain, end joint and roughness, dark gaps between them (sRGB colour; roughness as data)."""
    rng = np.random.default_rng(seed)
    u, v = texel_grid(height, width)
    row = np.minimum((v * planks).astype(int), planks - 1)
    across = v * planks - row                                     # 0..1 across a plank
    along = (u - rng.uniform(0, 1, planks)[row]) % 1.0            # 0 at the row's end joint
    tone, rough = rng.uniform(0.8, 1.15, planks)[row], rng.uniform(0.25, 0.45, planks)[row]
    phase = rng.uniform(0, 1, planks)[row]
    wobble = 0.35 * smooth_noise(u, v, rng, octaves=3)           # grain lines meandering along the plank
    grain = 0.5 + 0.5 * np.sin(2 * np.pi * (2.5 * across + wobble + phase + 0.6 * along))
    light, dark = np.array([0.80, 0.58, 0.36]), np.array([0.55, 0.34, 0.18])
    color = (dark + (light - dark) * grain[..., None] ** 1.5) * tone[..., None]
    gap = (np.minimum(across, 1 - across) * height / planks < 1.0) | (np.minimum(along, 1 - along) * width < 0.75)
    color[gap] = (0.15, 0.09, 0.05)
    roughness = rough + 0.1 * (grain - 0.5)
    roughness[gap] = 0.8
    return np.clip(color, 0, 1), np.repeat(np.clip(roughness, 0, 1)[..., None], 3, axis=2)


def wall_tile(size, seed):
    """One square ceramic tile (2 x 2 of slightly different tones) with grey grout at its border; repeats."""
    rng = np.random.default_rng(seed)
    u, v = texel_grid(size, size)
    quadrant = (2 * u).astype(int) + 2 * (2 * v).astype(int)
    tones = np.array([[0.86, 0.84, 0.78], [0.80, 0.83, 0.84], [0.84, 0.80, 0.74], [0.78, 0.80, 0.76]])
    color = tones[quadrant] * (1 + 0.03 * smooth_noise(u, v, rng))[..., None]
    fu, fv = (2 * u) % 1.0, (2 * v) % 1.0
    grout = (np.minimum(fu, 1 - fu) < 0.03) | (np.minimum(fv, 1 - fv) < 0.03)
    color[grout] = (0.45, 0.44, 0.42)
    return np.clip(color, 0, 1)


def bump_normal_map(size, bumps, slope):
    """A tangent-space normal map (Non-Color, (n + 1) / 2) of the height field sin^2(pi k u) sin^2(pi k v):
    `bumps` x `bumps` smooth round bumps that tile, tilting the normal by up to atan(slope)."""
    u, v = texel_grid(size, size)
    k = np.pi * bumps
    su, sv = np.sin(k * u), np.sin(k * v)
    dh_du = slope * np.sin(2 * k * u) * sv ** 2   # d/du of (slope / k) sin^2(k u) sin^2(k v)
    dh_dv = slope * su ** 2 * np.sin(2 * k * v)
    n = np.stack([-dh_du, -dh_dv, np.ones_like(u)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return 0.5 * (n + 1.0)


def checker(size, squares, a, b):
    u, v = texel_grid(size, size)
    odd = ((u * squares).astype(int) + (v * squares).astype(int)) % 2 == 1
    return np.where(odd[..., None], np.array(b), np.array(a))


def node_material(name, shader, viewport_color=(0.8, 0.8, 0.8), **inputs):
    """A material whose Surface is one `shader` node (a bl_idname) of the given input values (socket names with
    spaces as underscores); returns (material, shader node) for linking textures into it."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    node = tree.nodes.new(shader)
    for socket, value in inputs.items():
        node.inputs[socket.replace("_", " ")].default_value = value
    tree.links.new(node.outputs[0], out.inputs["Surface"])
    mat.diffuse_color = (*viewport_color, 1)
    return mat, node


def image_texture(mat, image, socket, vector=None, interpolation="Linear", extension="REPEAT"):
    """An Image Texture node of `image` whose Color drives `socket` (an input of a node of mat's tree), read at
    `vector` (a socket giving texture coordinates; None: the mesh's active UV map)."""
    tree = mat.node_tree
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation, tex.extension = image, interpolation, extension
    if vector is not None:
        tree.links.new(vector, tex.inputs["Vector"])
    tree.links.new(tex.outputs["Color"], socket)
    return tex


def texture_coordinate(mat, output):
    """The given output ('UV', 'Generated', ...) of a Texture Coordinate node in mat's tree."""
    return mat.node_tree.nodes.new("ShaderNodeTexCoord").outputs[output]


def scaled_uvs(mat, scale):
    """UVs through a Mapping node scaling them by `scale` (x, y, z): the texture repeats that many times."""
    tree = mat.node_tree
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = scale
    tree.links.new(texture_coordinate(mat, "UV"), mapping.inputs["Vector"])
    return mapping.outputs["Vector"]


def wall(name, mat, location, rotation, width, height):
    """A rectangle (one quad, UVs 0..1 over it) of width x height, a rotated XY plane."""
    return mesh_object(name, "plane", mat, location=location, rotation=rotation, scale=(width / 2, height / 2, 1),
                       size=2.0)


def textured_room():
    fresh_scene("textured_room")
    w, d, h = 6.0, 5.0, 3.0
    # Floor: wooden planks (sRGB) on a Principled BSDF whose roughness is a Non-Color map of the same planks.
    wood, roughness = wood_planks(256, 512, 16, seed=13)  # 31 cm planks
    floor, bsdf = node_material("Wood Floor", "ShaderNodeBsdfPrincipled", (0.6, 0.4, 0.25), Specular=0.5)
    image_texture(floor, packed_image("Wood Planks", wood), bsdf.inputs["Base Color"])
    image_texture(floor, packed_image("Wood Roughness", roughness, non_color=True), bsdf.inputs["Roughness"])
    wall("Floor", floor, (0, 0, 0), (0, 0, 0), w, d)
    # Back wall: one tile image repeated 12 x 6 times (50 cm tiles) by a Mapping node on the UVs.
    tiles, bsdf = node_material("Tiles", "ShaderNodeBsdfDiffuse", (0.8, 0.8, 0.78))
    image_texture(tiles, packed_image("Wall Tile", wall_tile(128, seed=14)), bsdf.inputs["Color"],
                  vector=scaled_uvs(tiles, (12.0, 6.0, 1.0)))
    wall("Back Wall", tiles, (0, d / 2, h / 2), (math.pi / 2, 0, 0), w, h)
    # Left wall: plaster of 10 x 5 smooth bumps (60 cm) through a tangent-space Normal Map node.
    plaster, bsdf = node_material("Bumpy Plaster", "ShaderNodeBsdfPrincipled", (0.7, 0.66, 0.6),
                                  Base_Color=(0.7, 0.66, 0.6, 1), Roughness=0.6)
    normal_map = plaster.node_tree.nodes.new("ShaderNodeNormalMap")
    normal_map.space = "TANGENT"
    plaster.node_tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    image_texture(plaster, packed_image("Wall Bumps", bump_normal_map(128, 1, slope=0.8), non_color=True),
                  normal_map.inputs["Color"], vector=scaled_uvs(plaster, (d / 0.6, h / 0.6, 1.0)))
    wall("Left Wall", plaster, (-w / 2, 0, h / 2), (math.pi / 2, 0, math.pi / 2), d, h)
    paint = material("Paint", (0.75, 0.75, 0.72))
    wall("Right Wall", paint, (w / 2, 0, h / 2), (math.pi / 2, 0, -math.pi / 2), d, h)
    wall("Front Wall", paint, (0, -d / 2, h / 2), (math.pi / 2, 0, math.pi), w, h)
    wall("Ceiling", paint, (0, 0, h), (math.pi, 0, 0), w, d)
    # A crate checkered through its Generated coordinates (0..1 over its bounds), closest-texel filtering.
    crate, bsdf = node_material("Checker Crate", "ShaderNodeBsdfDiffuse", (0.6, 0.3, 0.2))
    image_texture(crate, packed_image("Checker", checker(64, 8, (0.85, 0.75, 0.55), (0.45, 0.2, 0.12))),
                  bsdf.inputs["Color"], vector=texture_coordinate(crate, "Generated"), interpolation="Closest")
    mesh_object("Crate", "cube", crate, location=(1.1, 1.0, 0.45), size=0.9, rotation=(0, 0, 0.35))
    smooth(mesh_object("Ball", "uv_sphere", material("Red Plastic", (0.7, 0.12, 0.08), kind="principled",
                                                      roughness=0.35), location=(-1.0, 0.2, 0.5), radius=0.5,
                       segments=32, ring_count=16))
    area_light("Ceiling Panel", "RECTANGLE", size=1.6, size_y=0.8, power=200.0, location=(0.4, 0.2, h - 0.02))
    area_light("Ceiling Disk", "DISK", size=0.6, power=120.0, location=(-1.6, 1.4, h - 0.02))
    camera((0.6, -2.3, 1.6), (-0.6, 1.0, 0.8), lens=20.0)
    save("13_textured_room")


def still_life():
    fresh_scene("still_life")
    room(material("Studio Walls", (0.55, 0.55, 0.55)), size=(5, 5, 3))
    # A table: a wooden top (the planks image on the cube's UVs) on four legs.
    wood, _ = wood_planks(128, 128, 6, seed=7)
    top_mat, bsdf = node_material("Table Top", "ShaderNodeBsdfPrincipled", (0.55, 0.35, 0.2), Roughness=0.45)
    image_texture(top_mat, packed_image("Table Wood", wood), bsdf.inputs["Base Color"])
    top_z = 0.78
    mesh_object("Table Top", "cube", top_mat, location=(0, 0, top_z - 0.03), scale=(0.8, 0.45, 0.03), size=2.0)
    leg = material("Table Legs", (0.25, 0.17, 0.1))
    for x in (-0.72, 0.72):
        for y in (-0.38, 0.38):
            mesh_object(f"Leg {x:+.2f} {y:+.2f}", "cube", leg, location=(x, y, (top_z - 0.06) / 2),
                        scale=(0.03, 0.03, (top_z - 0.06) / 2), size=2.0)
    glass, _ = node_material("Glass", "ShaderNodeBsdfGlass", (0.9, 0.95, 1.0), IOR=1.45, Roughness=0.05)
    smooth(mesh_object("Glass Sphere", "uv_sphere", glass, location=(-0.38, 0.02, top_z + 0.12), radius=0.12,
                       segments=32, ring_count=16))
    brushed = material("Brushed Metal", (0.9, 0.9, 0.92), kind="principled", roughness=0.3, metallic=1.0)
    can = mesh_object("Brushed Can", "cylinder", brushed, location=(-0.05, 0.18, top_z + 0.11), radius=0.07,
                      depth=0.22, vertices=32)
    for p in can.data.polygons:  # the side smooth, the caps flat
        p.use_smooth = len(p.vertices) == 4
    polished, _ = node_material("Polished Gold", "ShaderNodeBsdfGlossy", (0.95, 0.8, 0.45),
                                Color=(0.95, 0.8, 0.45, 1), Roughness=0.1)
    smooth(mesh_object("Polished Ring", "torus", polished, location=(0.32, -0.08, top_z + 0.035),
                       major_radius=0.1, minor_radius=0.035, major_segments=32, minor_segments=12))
    ceramic, bsdf = node_material("Ceramic", "ShaderNodeBsdfPrincipled", (0.15, 0.35, 0.6),
                                  Base_Color=(0.15, 0.35, 0.6, 1), Roughness=0.5, Clearcoat=1.0,
                                  Clearcoat_Roughness=0.05)
    smooth(mesh_object("Ceramic Vase", "uv_sphere", ceramic, location=(0.2, 0.25, top_z + 0.14), radius=0.1,
                       scale=(1.0, 1.0, 1.4), segments=24, ring_count=12))
    # A box of lacquered paint: a Mix Shader of 70 % Diffuse and 30 % Glossy BSDF.
    lacquer = bpy.data.materials.new("Lacquer Mix")
    lacquer.use_nodes, lacquer.diffuse_color = True, (0.8, 0.3, 0.1, 1)
    nodes, links = lacquer.node_tree.nodes, lacquer.node_tree.links
    nodes.clear()
    out, mix = nodes.new("ShaderNodeOutputMaterial"), nodes.new("ShaderNodeMixShader")
    diffuse, glossy = nodes.new("ShaderNodeBsdfDiffuse"), nodes.new("ShaderNodeBsdfGlossy")
    diffuse.inputs["Color"].default_value = (0.8, 0.3, 0.1, 1)
    glossy.inputs["Roughness"].default_value = 0.2
    mix.inputs["Fac"].default_value = 0.3
    links.new(diffuse.outputs[0], mix.inputs[1])
    links.new(glossy.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], out.inputs["Surface"])
    mesh_object("Lacquer Box", "cube", lacquer, location=(-0.12, -0.2, top_z + 0.06), size=0.12,
                rotation=(0, 0, 0.5))
    target = (0.0, 0.05, top_z + 0.1)
    aim(area_light("Softbox", "RECTANGLE", size=0.9, size_y=0.6, power=60.0, location=(-1.1, -1.2, 1.8)), target)
    aim(area_light("Rim Disk", "DISK", size=0.3, power=20.0, location=(1.1, 0.9, 1.6)), target)
    camera((0.15, -1.55, 1.3), target, lens=45.0)
    save("14_still_life")


def volume_material(name, nodes_and_inputs):
    """A material with no Surface whose Volume is the sum (Add Shader) of volume nodes [(bl_idname, {input: value})]."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    shaders = []
    for idname, inputs in nodes_and_inputs:
        node = nodes.new(idname)
        for k, v in inputs.items():
            node.inputs[k].default_value = v
        shaders.append(node.outputs[0])
    while len(shaders) > 1:
        add = nodes.new("ShaderNodeAddShader")
        links.new(shaders.pop(), add.inputs[1])
        links.new(shaders.pop(), add.inputs[0])
        shaders.append(add.outputs[0])
    links.new(shaders[0], out.inputs["Volume"])
    return mat


def fog_stage():
    fresh_scene("fog_stage")
    mesh_object("Floor", "plane", material("Floor", (0.5, 0.5, 0.5)), size=14)
    mesh_object("Back Wall", "plane", material("Wall", (0.6, 0.55, 0.5)), location=(0, 3.2, 2.5),
                rotation=(math.pi / 2, 0, 0), size=8)
    mesh_object("Crate", "cube", material("Crate", (0.7, 0.4, 0.2)), location=(-1.2, 0.8, 0.4), size=0.8,
                rotation=(0, 0, 0.3))
    smooth(mesh_object("Ball", "uv_sphere", material("Ball", (0.2, 0.4, 0.7)), location=(1.0, 0.2, 0.5),
                       radius=0.5, segments=32, ring_count=16))
    # The street lamp: a pole, a point light in an emissive globe (the globe lights only what its emission does).
    # The pole ends below the lamp (a lamp inside it would light nothing), the globe above it.
    mesh_object("Pole", "cylinder", material("Pole", (0.1, 0.1, 0.1)), location=(2.4, 1.6, 1.0), radius=0.04,
                depth=2.0, vertices=12)
    smooth(mesh_object("Globe", "uv_sphere", emission_material("Globe", (1.0, 0.8, 0.5), 6.0),
                       location=(2.4, 1.6, 2.5), radius=0.12, segments=16, ring_count=8))
    other_light("Lamp", "POINT", 150.0, location=(2.4, 1.6, 2.2), color=(1.0, 0.85, 0.6))
    spot = other_light("Spot", "SPOT", 900.0, location=(-1.6, -0.6, 3.6), spot_size=math.radians(35),
                       spot_blend=0.15)
    aim(spot, (-0.6, 0.8, 0.0))
    area_light("Fill", "RECTANGLE", size=2.0, size_y=1.0, power=150.0, location=(0, -1.5, 3.9), visible=False)
    # The fog box over the stage (the camera outside it), its bottom 5 cm under the floor and its back 20 cm before the
    # wall: a face on a surface's plane
    # leaves Cycles 3.4 to find the floor or the face first, and where it takes the face it misses the floor
    # (docs/renderer.md, object volumes).
    mesh_object("Fog", "cube", volume_material("Fog", [
        ("ShaderNodeVolumeScatter", {"Density": 0.18, "Color": (0.9, 0.9, 0.95, 1), "Anisotropy": 0.4}),
        ("ShaderNodeVolumeAbsorption", {"Density": 0.05, "Color": (0.8, 0.7, 0.6, 1)})]),
        location=(0, 0.5, 1.975), scale=(3.5, 2.5, 2.025))
    camera((0.0, -6.5, 1.8), (0.0, 0.8, 1.2), lens=28.0)
    save("15_fog_stage")


def fog_room():
    fresh_scene("fog_room")
    room(material("Walls", (0.75, 0.75, 0.7)))
    mesh_object("Box", "cube", material("Orange", (0.8, 0.45, 0.15)), location=(1.0, 1.0, 0.6), size=1.2,
                rotation=(0, 0, 0.4))
    smooth(mesh_object("Sphere", "uv_sphere", material("Grey", (0.6, 0.6, 0.6)), location=(-1.1, 0.3, 0.7),
                       radius=0.7, segments=32, ring_count=16))
    area_light("Ceiling Light", "RECTANGLE", size=1.6, size_y=0.8, power=300.0, location=(0, 0.5, 2.98))
    area_light("Disk", "DISK", size=0.4, power=60.0, location=(-2.5, 2.0, 1.5), rotation=(0, math.pi / 2, 0),
               color=(1.0, 0.7, 0.4))
    camera((0.0, -2.8, 1.5), (0.0, 0.8, 0.9), lens=20.0)
    # A Principled Volume box a little larger than the room: it holds the camera and every light.
    mesh_object("Haze", "cube", volume_material("Haze", [
        ("ShaderNodeVolumePrincipled", {"Density": 0.25, "Color": (0.85, 0.85, 0.9, 1),
                                        "Absorption Color": (0.7, 0.7, 0.7, 1), "Anisotropy": 0.2})]),
        location=(0, 0, 1.5), scale=(3.2, 3.2, 1.7))
    save("16_fog_room")


def warehouse():
    fresh_scene("warehouse")
    rng = np.random.default_rng(17)
    room(material("Warehouse", (0.6, 0.6, 0.58)), size=(60, 60, 8))
    mesh_object("Floor", "plane", material("Sealed Concrete", (0.45, 0.45, 0.45), kind="principled",
                                           roughness=0.25), location=(0, 0, 0.001), size=59.9)
    rack, crate = material("Rack", (0.25, 0.3, 0.45)), material("Crate", (0.7, 0.5, 0.3), kind="principled",
                                                                  roughness=0.4)
    # 32 light datablocks (8 powers x 4 colours), shared by linked duplicates as in a real scene.
    colors = [(1.0, 0.85, 0.7), (1.0, 0.95, 0.9), (0.8, 0.9, 1.0), (1.0, 0.6, 0.4)]

    def light_data(kind, size, size_y, power_low, power_high):
        out = []
        for p in np.geomspace(power_low, power_high, 8):
            for c in colors:
                light = bpy.data.lights.new(f"{kind} {p:.3g} W", "AREA")
                light.shape, light.size, light.size_y = "RECTANGLE", size, size_y
                light.energy, light.color = float(p), c
                out.append(light)
        return out

    panels, strips = light_data("Panel", 0.5, 0.25, 1.0, 8.0), light_data("Strip", 0.25, 0.04, 0.02, 0.5)

    def place(name, data, location, rotation):
        obj = link(bpy.data.objects.new(name, data[rng.integers(len(data))]))
        obj.location, obj.rotation_euler = location, rotation

    # 3,600 ceiling panels, 1 m apart, 2 cm under the ceiling, facing down.
    for i in range(60):
        for j in range(60):
            place(f"Panel {i:02d} {j:02d}", panels, (j - 29.5, i - 29.5, 7.98), (0, 0, 0))
    # Eight racks, 50 m long, 4 m tall, 1.2 m deep, aisles 6 m wide; on each face two rows of 200 strips
    # (at 1.2 m and 2.6 m) facing the aisle: 6,400 strips.
    for r in range(8):
        x = -24.5 + 7.0 * r
        mesh_object(f"Rack {r}", "cube", rack, location=(x, 0.0, 2.0), scale=(0.6, 25.0, 2.0))
        for side in (-1, 1):
            for level, z in enumerate((1.2, 2.6)):
                for k in range(200):
                    place(f"Strip {r} {side:+d} {level} {k:03d}", strips, (x + side * 0.62, -24.875 + 0.25 * k, z),
                          (0, -side * math.pi / 2, 0))
    # Crates in the aisles.
    for k in range(24):
        x = -21.0 + 7.0 * int(rng.integers(7)) + float(rng.uniform(-1.5, 1.5))
        y, s = float(rng.uniform(-22, 22)), float(rng.uniform(0.5, 1.2))
        mesh_object(f"Crate {k:02d}", "cube", crate, location=(x, y, s / 2), size=s,
                    rotation=(0, 0, float(rng.uniform(0, math.pi))))
    camera((-27.0, -28.5, 5.5), (-4.0, -8.0, 0.5), lens=22.0)
    save("17_warehouse")


SCENES = {"01_paper": paper, "02_room": lambda: room_scene("02_room", fog=False), "03_glossy_floor": glossy_floor,
          "04_foggy_room": lambda: room_scene("04_foggy_room", fog=True), "05_hard_cases": hard_cases,
          "06_mixed_lights": mixed_lights, "07_studio": studio, "08_disk_room": disk_room,
          "09_hall": hall, "10_night_street": night_street, "11_paper_disk": paper_disk,
          "12_disk_ceiling": lambda: room_scene("12_disk_ceiling", fog=False, disk=True),
          "13_textured_room": textured_room, "14_still_life": still_life, "15_fog_stage": fog_stage,
          "16_fog_room": fog_room, "17_warehouse": warehouse}

if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    for name in argv or SCENES:
        SCENES[name]()
