"""Exporter numbers: lights (Cycles' power conventions), camera, materials, world, meshes, instances and
the scene-file round trip. No rendering here."""
import dataclasses
import importlib
import math

import bpy
import numpy as np
import pytest

import sphrect
from conftest import builders, export, lit_test_scene


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("shape", ["SQUARE", "RECTANGLE", "DISK", "ELLIPSE"])
@pytest.mark.parametrize("scale", [(2.0, 3.0, 1.0), (-1.5, 0.5, 2.0)])
def test_area_light_power_size_and_orientation(empty_scene, shape, scale):
    color = (1.0, 0.5, 0.25)
    obj = builders.area_light("L", shape, size=0.5, size_y=0.25, power=100.0, location=(1, 2, 3),
                              rotation=(0.3, 0.2, 0.1), scale=scale, color=color, two_sided=True, visible=False)
    scene, log = export()
    (light,) = scene.lights
    sx = 0.5 * abs(scale[0])
    sy = (0.5 if shape in {"SQUARE", "DISK"} else 0.25) * abs(scale[1])
    m = np.array(obj.matrix_world)
    emit = _unit(-m[:3, 2])  # local -Z, whatever the sign of the scale
    if shape in {"SQUARE", "RECTANGLE"}:
        assert isinstance(light, sphrect.RectLight)
        ex, ey = np.array(light.edge_x), np.array(light.edge_y)
        centre = np.array(light.corner) + 0.5 * (ex + ey)
        area = sx * sy
        assert sorted([np.linalg.norm(ex), np.linalg.norm(ey)]) == pytest.approx(sorted([sx, sy]), rel=1e-5)
    else:
        assert isinstance(light, sphrect.EllipseLight)
        ex, ey = np.array(light.axis_x), np.array(light.axis_y)
        centre = np.array(light.center)
        area = math.pi * sx * sy / 4.0
        assert sorted([np.linalg.norm(ex), np.linalg.norm(ey)]) == pytest.approx(sorted([sx / 2, sy / 2]), rel=1e-5)
    assert centre == pytest.approx([1, 2, 3], abs=1e-5)
    assert abs(np.dot(ex, ey)) < 1e-5
    assert _unit(np.cross(ex, ey)) == pytest.approx(emit, abs=1e-5)  # emits on the side of local -Z
    # Cycles: L = P * colour / (4 * area), area after the object's scale.
    assert light.radiance == pytest.approx([100.0 * c / (4.0 * area) for c in color], rel=1e-5)
    assert light.two_sided and not light.visible
    assert log.warning_text() == ""


@pytest.mark.parametrize("shape", ["RECTANGLE", "DISK"])
def test_area_light_spread_is_exported(empty_scene, shape):
    """Blender's Spread (radians) becomes the light's spread, without a warning; the default is pi: none."""
    obj = builders.area_light("L", shape, size=0.5, size_y=0.25, power=100.0, location=(0, 0, 2))
    scene, log = export()
    assert scene.lights[0].spread == pytest.approx(math.pi)
    obj.data.spread = math.radians(20)
    scene, log = export()
    assert scene.lights[0].spread == pytest.approx(math.radians(20), rel=1e-6)
    assert log.warning_text() == ""


def test_sheared_area_light_keeps_its_plane_and_power(empty_scene):
    """A rotated light under a non-uniformly scaled parent is a parallelogram in world space: exported as a
    rectangle of the same area (so the same power) in the same plane, emitting on the same side."""
    parent = bpy.data.objects.new("Parent", None)
    bpy.context.scene.collection.objects.link(parent)
    parent.scale = (1.0, 3.0, 1.0)
    obj = builders.area_light("L", "RECTANGLE", size=0.5, size_y=0.25, power=100.0, rotation=(0.4, 0.0, 0.6))
    obj.parent = parent
    bpy.context.view_layer.update()
    m = np.array(obj.matrix_world)
    u, v = m[:3, 0] * 0.5, m[:3, 1] * 0.25  # the world-space edges: not orthogonal
    assert abs(np.dot(_unit(u), _unit(v))) > 0.1
    area = np.linalg.norm(np.cross(u, v))
    scene, log = export()
    (light,) = scene.lights
    ex, ey = np.array(light.edge_x), np.array(light.edge_y)
    assert abs(np.dot(ex, ey)) < 1e-5 * np.linalg.norm(ex) * np.linalg.norm(ey)
    assert np.linalg.norm(np.cross(ex, ey)) == pytest.approx(area, rel=1e-5)
    assert light.radiance == pytest.approx([100.0 / (4.0 * area)] * 3, rel=1e-5)
    normal = _unit(np.cross(ex, ey))
    assert abs(np.dot(normal, _unit(np.cross(u, v)))) == pytest.approx(1.0, abs=1e-5)  # the same plane
    assert np.dot(normal, -m[:3, 2]) > 0  # emitting towards local -Z
    assert "sheared" in log.warning_text()


def test_point_spot_and_sun(empty_scene):
    builders.other_light("P", "POINT", 50.0, location=(1, 2, 3), color=(1, 0.5, 0))
    builders.other_light("S", "SPOT", 80.0, location=(0, 0, 4), rotation=(0.5, 0, 0), spot_size=0.7,
                         spot_blend=0.3)
    builders.other_light("Sun", "SUN", 3.0, rotation=(0.0, 0.4, 0.0))
    scene, log = export()
    kinds = {type(l).__name__: l for l in scene.lights}
    p, s, sun = kinds["PointLight"], kinds["SpotLight"], kinds["SunLight"]
    assert p.position == pytest.approx((1, 2, 3))
    assert p.intensity == pytest.approx([50 / (4 * math.pi), 25 / (4 * math.pi), 0], abs=1e-9)
    assert s.intensity == pytest.approx([80 / (4 * math.pi)] * 3)
    assert s.spot_size == pytest.approx(0.7) and s.spot_blend == pytest.approx(0.3)
    assert s.direction == pytest.approx([0, math.sin(0.5), -math.cos(0.5)], abs=1e-6)
    assert sun.irradiance == pytest.approx((3, 3, 3))
    assert sun.direction == pytest.approx([-math.sin(0.4), 0, -math.cos(0.4)], abs=1e-6)


def test_soft_lights_are_exported_without_warnings(empty_scene):
    """A point or spot light's radius (unscaled by the object, as Cycles 3.4 takes it) and a sun's angle are
    simulated: exported, not warned about; camera visibility goes with them."""
    for kind, radius in (("POINT", 0.3), ("SPOT", 0.2)):
        obj = builders.other_light(kind[0], kind, 50.0)
        obj.data.shadow_soft_size = radius
        obj.scale = (2, 2, 2)
    sun = builders.other_light("Sun", "SUN", 3.0)
    sun.data.angle = 0.2
    sun.visible_camera = False
    scene, log = export()
    by_type = {type(light).__name__: light for light in scene.lights}
    assert by_type["PointLight"].radius == pytest.approx(0.3)
    assert by_type["SpotLight"].radius == pytest.approx(0.2)
    assert by_type["SunLight"].angle == pytest.approx(0.2) and not by_type["SunLight"].visible
    assert "radius" not in log.warning_text() and "angle" not in log.warning_text()
    # Cycles' camera rays find a sun only with its Multiple Importance on.
    sun.visible_camera = True
    assert [light.visible for light in export()[0].lights if type(light).__name__ == "SunLight"] == [True]
    sun.data.cycles.use_multiple_importance_sampling = False
    sun.data.update_tag()  # an add-on's property: the depsgraph's copy follows only when tagged
    assert [light.visible for light in export()[0].lights if type(light).__name__ == "SunLight"] == [False]


def test_camera_lens_sensor_shift_and_dof(empty_scene):
    cam = empty_scene.camera
    cam.data.lens, cam.data.sensor_width, cam.data.sensor_height = 35.0, 32.0, 18.0
    cam.data.sensor_fit = "VERTICAL"
    cam.data.shift_x, cam.data.shift_y = 0.1, -0.05
    cam.data.dof.use_dof = True
    cam.data.dof.aperture_fstop = 2.8
    target = bpy.data.objects.new("Focus", None)
    empty_scene.collection.objects.link(target)
    view = -np.array(cam.matrix_world)[:3, 2]
    side = np.array(cam.matrix_world)[:3, 0]
    target.location = np.array(cam.location) + 4.0 * view + 1.5 * side  # 4 m along the view axis
    cam.data.dof.focus_object = target
    bpy.context.view_layer.update()
    c = export()[0].camera
    assert (c.width, c.height, c.type) == (32, 24, "perspective")
    assert (c.lens, c.sensor_width, c.sensor_height) == pytest.approx((35.0, 32.0, 18.0))
    assert c.sensor_fit == "VERTICAL"
    assert (c.shift_x, c.shift_y) == pytest.approx((0.1, -0.05))
    assert c.focus_distance == pytest.approx(4.0, rel=1e-5)
    assert c.aperture_radius == pytest.approx(0.035 / (2 * 2.8))
    assert np.array(c.to_world) == pytest.approx(np.array(cam.matrix_world), abs=1e-6)
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = 5.0
    c = export()[0].camera
    assert c.type == "orthographic" and c.ortho_scale == pytest.approx(5.0)


def _principled_material(name, **inputs):
    mat = builders.material(name, kind="principled")
    node = mat.node_tree.nodes["Principled BSDF"]
    for k, v in inputs.items():
        node.inputs[k].default_value = v
    return mat


def test_materials_and_slots(empty_scene):
    diffuse = builders.material("Matte", (0.2, 0.4, 0.6))
    glossy = _principled_material("Metal", **{"Base Color": (0.9, 0.8, 0.1, 1), "Metallic": 0.7,
                                              "Roughness": 0.25, "Specular": 0.4})
    obj = builders.mesh_object("Cube", "cube", diffuse)
    obj.data.materials.append(glossy)
    obj.data.polygons[0].material_index = 1
    scene, log = export()
    mats = {m.name: m for m in scene.materials}
    assert mats["Matte"].kind == "diffuse" and mats["Matte"].base_color == pytest.approx((0.2, 0.4, 0.6))
    metal = mats["Metal"]
    assert metal.kind == "principled"
    assert (metal.metallic, metal.roughness, metal.specular) == pytest.approx((0.7, 0.25, 0.4))
    assert metal.base_color == pytest.approx((0.9, 0.8, 0.1))
    (mesh,) = scene.meshes
    ids = np.asarray(mesh.material_ids)
    names = [scene.materials[i].name for i in ids]
    assert names.count("Metal") == 2 and names.count("Matte") == 10  # one quad face = two triangles
    assert log.unsupported == {}


def test_unsupported_nodes_are_listed_once(empty_scene):
    textured = _principled_material("Textured")
    tex = textured.node_tree.nodes.new("ShaderNodeTexSky")  # not read: Image Textures and node programs are
    textured.node_tree.links.new(tex.outputs["Color"], textured.node_tree.nodes["Principled BSDF"].inputs[0])
    toon = bpy.data.materials.new("Toon")
    toon.use_nodes = True
    tree = toon.node_tree
    tree.nodes.remove(tree.nodes["Principled BSDF"])
    g = tree.nodes.new("ShaderNodeBsdfToon")
    tree.links.new(g.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    lamp = bpy.data.materials.new("Lamp")
    lamp.use_nodes = True
    tree = lamp.node_tree
    e = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(e.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    for i, mat in enumerate((textured, toon, lamp)):
        builders.mesh_object(f"Obj{i}", "cube", mat, location=(3 * i, 0, 0))
    hairy = bpy.data.objects["Obj0"]
    hairy.modifiers.new("Hair", "PARTICLE_SYSTEM").particle_system.settings.type = "HAIR"
    builders.mesh_object("Copy", "cube", textured, location=(0, 3, 0))
    scene, log = export()
    text = log.warning_text()
    assert "linked 'Base Color' input (Sky Texture) (Textured)" in text
    assert "'Toon BSDF' shader node" in text and "(Toon)" in text
    # The Emission shader is read since issue 11 (was: logged as "emission on meshes (Lamp)").
    assert "Lamp" not in text
    assert [m.emission for m in scene.materials if m.name == "Lamp"] == [pytest.approx((1.0, 1.0, 1.0))]
    assert text.count("Textured") == 1  # listed once, however many objects use it
    assert "hair particles (Obj0)" in text
    assert len(scene.meshes) == 4  # nothing dropped: unsupported materials fall back to diffuse


def test_a_particle_emitter_hidden_from_render_is_left_out(empty_scene):
    """Its Instancing > Render off (show_instancer_for_render): Cycles 3.4 skips the emitter's own geometry (the
    depsgraph instance's show_self); so does the exporter (mpett/tornado.blend's smoke sources were drawn before)."""
    builders.mesh_object("Emitter", "cube", builders.material("Grey"))
    emitter = bpy.data.objects["Emitter"]
    settings = emitter.modifiers.new("Particles", "PARTICLE_SYSTEM").particle_system.settings
    settings.count = 0
    scene, _ = export()
    assert [m.name for m in scene.meshes] == ["Emitter"]
    # (export() reads the viewport's depsgraph, which takes the viewport's flag; a render's takes the render's.)
    emitter.show_instancer_for_render = emitter.show_instancer_for_viewport = False
    bpy.context.view_layer.update()
    scene, _ = export()
    assert scene.meshes == []


def test_world_colour_and_volume(empty_scene):
    tree = empty_scene.world.node_tree
    bg = tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.1, 0.2, 0.3, 1)
    bg.inputs["Strength"].default_value = 2.0
    scatter = tree.nodes.new("ShaderNodeVolumeScatter")
    scatter.inputs["Density"].default_value = 0.5
    scatter.inputs["Color"].default_value = (0.8, 0.6, 0.4, 1)
    scatter.inputs["Anisotropy"].default_value = 0.25
    tree.links.new(scatter.outputs[0], tree.nodes["World Output"].inputs["Volume"])
    world = export()[0].world
    assert world.background == pytest.approx((0.2, 0.4, 0.6))
    assert world.medium.sigma_s == pytest.approx((0.4, 0.3, 0.2))
    assert world.medium.sigma_a == pytest.approx((0, 0, 0))
    assert world.medium.g == pytest.approx(0.25)
    tree.nodes.remove(scatter)
    pv = tree.nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Density"].default_value = 2.0
    pv.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
    tree.links.new(pv.outputs[0], tree.nodes["World Output"].inputs["Volume"])
    medium = export()[0].world.medium
    assert medium.sigma_s == pytest.approx((1.0, 1.0, 1.0))
    assert medium.sigma_a == pytest.approx((1.0, 1.0, 1.0))  # density * (1 - colour), black absorption colour


def test_world_filtered_out_of_the_view_layer_is_not_exported(empty_scene):
    """Cycles renders no world (none seen, none lighting, no volume) when the view layer's Filter > Environment is
    off (use_sky; its background shader is then the empty one): the black world, without the world's warnings.
    Back on, the world is exported again. (A third-party file, natronics/kaleidospace, lit only by its sky with the
    filter off, rendered lit here and black in Cycles.)"""
    tree = empty_scene.world.node_tree
    bg = tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.1, 0.2, 0.3, 1)
    bg.inputs["Strength"].default_value = 2.0
    scatter = tree.nodes.new("ShaderNodeVolumeScatter")
    tree.links.new(scatter.outputs[0], tree.nodes["World Output"].inputs["Volume"])
    empty_scene.world.cycles_visibility.diffuse = False
    empty_scene.world.update_tag()
    bpy.context.view_layer.use_sky = False
    scene, log = export()
    assert scene.world == sphrect.World()
    assert "world hidden from diffuse" not in log.warning_text()
    bpy.context.view_layer.use_sky = True
    scene, log = export()
    assert scene.world.background == pytest.approx((0.2, 0.4, 0.6)) and scene.world.medium is not None
    assert scene.world.invisible_to == ("diffuse",) and "world hidden from diffuse" in log.warning_text()


def test_headless_export_is_what_a_render_evaluates(empty_scene, tmp_path):
    """The headless export (the study's and side_by_side_cycles.py's) takes the depsgraph a render evaluates, as F12
    and Cycles do: a collection disabled in renders but shown in the viewport is left out, and a Subdivision
    modifier exports at its render level. (BlenderKit's model_thumbnailer.blend keeps four backdrops in collections
    disabled in renders: exported from the viewport's depsgraph they hid the world Cycles shows, 18% apart.)"""
    lit_test_scene(empty_scene)
    hidden = bpy.data.collections.new("Hidden")
    empty_scene.collection.children.link(hidden)
    hidden.hide_render = True
    bpy.ops.mesh.primitive_cube_add(location=(3, 3, 1))
    cube = bpy.context.active_object
    cube.name = "InHidden"
    for c in cube.users_collection:
        c.objects.unlink(cube)
    hidden.objects.link(cube)
    bpy.ops.mesh.primitive_cube_add(location=(-3, 3, 1))
    subdivided = bpy.context.active_object
    subdivided.name = "Subdivided"
    modifier = subdivided.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels, modifier.render_levels = 0, 1
    bpy.context.view_layer.update()
    viewport = {m.name: len(m.triangles) for m in export()[0].meshes}
    assert "InHidden" in viewport and viewport["Subdivided"] == 12  # the viewport's depsgraph
    out = str(tmp_path / "scene.sphrect.npz")
    headless = importlib.import_module("sphrect_blender.headless")
    headless.run("export", {"out": out, "warnings": str(tmp_path / "warnings.json")})
    meshes = {m.name: len(m.triangles) for m in sphrect.load_scene(out).meshes}
    assert "InHidden" not in meshes and meshes["Subdivided"] == 48
    assert empty_scene.render.engine == "SPHRECT"  # the engine the export borrowed is given back


def _outward_fraction(vertices, triangles, centre):
    v = np.asarray(vertices, dtype=np.float64)[np.asarray(triangles)]
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    return np.mean(np.einsum("ij,ij->i", n, v.mean(axis=1) - centre) > 0)


def test_modifiers_instances_and_transforms(empty_scene):
    box = builders.mesh_object("Box", "cube", location=(0, 0, 1), size=1.0)
    arr = box.modifiers.new("Array", "ARRAY")
    arr.count = 3
    builders.mesh_object("Mirrored", "cube", location=(5, 0, 0), scale=(-1, 1, 1))
    coll = bpy.data.collections.new("Inst")
    piece = builders.mesh_object("Piece", "cube", size=0.5)
    empty_scene.collection.objects.unlink(piece)
    coll.objects.link(piece)
    for i in range(2):
        e = bpy.data.objects.new(f"Instance{i}", None)
        e.instance_type, e.instance_collection = "COLLECTION", coll
        e.location = (0, 10 + 3 * i, 0)
        empty_scene.collection.objects.link(e)
    scene, log = export()
    meshes = {m.name: m for m in scene.meshes}
    assert len(meshes["Box"].triangles) == 36  # the array modifier is applied
    assert np.asarray(meshes["Box"].vertices)[:, 0].max() == pytest.approx(2.5, abs=1e-5)
    instances = [m for name, m in meshes.items() if "/Piece" in name]
    assert len(instances) == 2
    centres = sorted(float(np.asarray(m.vertices)[:, 1].mean()) for m in instances)
    assert centres == pytest.approx([10.0, 13.0], abs=1e-5)
    # Mirroring (negative scale) keeps the triangles facing outward.
    m = meshes["Mirrored"]
    assert _outward_fraction(m.vertices, m.triangles, np.array([5, 0, 0])) == 1.0
    # An instance hides from what its instancing object or itself hides from (Cycles' sync_object).
    bpy.data.objects["Instance0"].visible_shadow = False
    piece.visible_glossy = False
    hidden = sorted(m.invisible_to for m in export()[0].meshes if "/Piece" in m.name)
    assert hidden == [("glossy",), ("shadow", "glossy")]


def test_curves_text_surfaces_and_metaballs_are_exported_once(empty_scene):
    """The depsgraph gives each such object's triangles as an instance of its own (a Mesh) besides the object
    (Curve / MetaBall data): Cycles renders the mesh once (object_is_geometry), and so must the export -- twice
    doubled a neon sign's light (a third-party file)."""
    red = builders.material("Red", (0.8, 0.1, 0.1))
    bpy.ops.curve.primitive_bezier_circle_add(location=(0, 0, 0))
    curve = bpy.context.object
    curve.data.bevel_depth = 0.1
    curve.data.materials.append(red)
    curve.visible_glossy = False
    bpy.ops.object.text_add(location=(3, 0, 0))
    bpy.ops.object.metaball_add(location=(-3, 0, 0))
    bpy.ops.surface.primitive_nurbs_surface_sphere_add(location=(0, 3, 0))
    depsgraph = bpy.context.evaluated_depsgraph_get()
    expected = {}
    for name in ("BezierCircle", "Text", "Mball", "SurfSphere"):
        mesh = bpy.data.objects[name].evaluated_get(depsgraph).to_mesh()
        mesh.calc_loop_triangles()
        expected[name] = len(mesh.loop_triangles)
        bpy.data.objects[name].evaluated_get(depsgraph).to_mesh_clear()
    scene, log = export()
    for name, count in expected.items():
        mine = [m for m in scene.meshes if m.name.split("/")[0] == name]
        assert len(mine) == 1 and len(mine[0].triangles) == count > 0, name
    (ring,) = [m for m in scene.meshes if m.name.startswith("BezierCircle")]
    assert scene.materials[int(ring.material_ids[0])].name == "Red"
    assert ring.invisible_to == ("glossy",)


def test_smooth_meshes_get_unit_normals(empty_scene):
    sphere = builders.mesh_object("Sphere", "uv_sphere", location=(1, 1, 1), radius=0.5, segments=16,
                                  ring_count=8)
    builders.smooth(sphere)
    builders.mesh_object("Flat", "cube", location=(4, 0, 0))
    meshes = {m.name: m for m in export()[0].meshes}
    assert meshes["Flat"].normals is None
    n = np.asarray(meshes["Sphere"].normals)
    v = np.asarray(meshes["Sphere"].vertices)
    assert n.shape == v.shape
    assert np.linalg.norm(n, axis=1) == pytest.approx(1.0, abs=1e-5)
    radial = (v - [1, 1, 1]) / np.linalg.norm(v - [1, 1, 1], axis=1, keepdims=True)
    assert np.min(np.einsum("ij,ij->i", n, radial)) > 0.99  # smooth normals of a sphere are radial


def _same(a, b):
    """Dataclasses equal field by field (JSON turns tuples into lists)."""
    da, db = dataclasses.asdict(a), dataclasses.asdict(b)
    if da.keys() != db.keys():
        return False
    for k in da:
        if isinstance(da[k], (str, bool, dict)) or da[k] is None:
            if da[k] != db[k]:
                return False
        elif not np.allclose(np.asarray(da[k], dtype=float), np.asarray(db[k], dtype=float)):
            return False
    return True


def test_scene_file_round_trip(empty_scene, tmp_path):
    import sphrect_blender
    from conftest import lit_test_scene
    lit_test_scene(empty_scene)
    builders.other_light("Spot", "SPOT", 30.0, location=(0, -2, 3))
    path = str(tmp_path / "scene.sphrect.npz")
    log = sphrect_blender.export_scene(bpy.context.evaluated_depsgraph_get(), path)
    assert log.warning_text() == ""
    original, _ = export()
    loaded = sphrect.load_scene(path)
    assert _same(loaded.camera, original.camera)
    assert [type(l) for l in loaded.lights] == [type(l) for l in original.lights]
    assert all(_same(a, b) for a, b in zip(loaded.lights, original.lights))
    assert all(_same(a, b) for a, b in zip(loaded.materials, original.materials))
    for a, b in zip(loaded.meshes, original.meshes):
        assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.triangles, b.triangles)
        assert np.array_equal(a.material_ids, b.material_ids)
    # A bpy Scene works as well as a depsgraph.
    scene_path = str(tmp_path / "from_scene.sphrect.npz")
    sphrect_blender.export_scene(empty_scene, scene_path)
    assert len(sphrect.load_scene(scene_path).meshes) == len(original.meshes)
    # The operator writes the same file format.
    op_path = str(tmp_path / "op.sphrect.npz")
    assert bpy.ops.export_scene.sphrect(filepath=op_path) == {"FINISHED"}
    assert len(sphrect.load_scene(op_path).meshes) == len(original.meshes)


def test_ray_visibility_is_exported(empty_scene):
    """Object > Visibility > Ray Visibility of meshes and lights, a light's Cast Shadow and Multiple Importance:
    exported as the scene's invisible_to / cast_shadow / use_mis (simulated, so not warned about); everything
    visible exports as before."""
    lit_test_scene(empty_scene)
    scene, log = export()
    assert all(m.invisible_to == () for m in scene.meshes)
    assert [(l.invisible_to, l.cast_shadow, l.use_mis) for l in scene.lights] == [((), True, True)]
    box, light = bpy.data.objects["Box"], bpy.data.objects["Light"]
    box.visible_camera = box.visible_shadow = box.visible_volume_scatter = False
    light.visible_diffuse = light.visible_transmission = False
    light.data.cycles.cast_shadow = False
    light.data.cycles.use_multiple_importance_sampling = False
    light.data.update_tag()  # an add-on's property: the depsgraph's copy follows only when tagged
    scene, log = export()
    by_name = {m.name: m for m in scene.meshes}
    assert by_name["Box"].invisible_to == ("camera", "shadow", "volume_scatter")
    assert by_name["Ground"].invisible_to == ()
    (exported,) = scene.lights
    assert exported.invisible_to == ("diffuse", "transmission")
    assert not exported.cast_shadow and not exported.use_mis
    assert "visibility" not in log.warning_text()
    for kind, data in (("POINT", {}), ("SUN", {"angle": 0.1})):
        obj = builders.other_light(kind, kind, 10.0)
        obj.visible_glossy = False
        for key, value in data.items():
            setattr(obj.data, key, value)
    scene, _ = export()
    by_type = {type(l).__name__: l for l in scene.lights}
    assert by_type["PointLight"].invisible_to == ("glossy",) and by_type["SunLight"].invisible_to == ("glossy",)


def test_visibility_settings_not_simulated_are_warned(empty_scene):
    """An emissive material's Multiple Importance off is not simulated: warned, naming it; at its default, not.  The
    world's Ray Visibility is exported (World.invisible_to, 'scatter' as 'volume_scatter'), unwarned."""
    lit_test_scene(empty_scene)
    mat = builders.material("Glow", (0.1, 0.1, 0.1))
    mat.node_tree.nodes.clear()
    out = mat.node_tree.nodes.new("ShaderNodeOutputMaterial")
    emission = mat.node_tree.nodes.new("ShaderNodeEmission")
    mat.node_tree.links.new(emission.outputs[0], out.inputs["Surface"])
    builders.mesh_object("Panel", "plane", mat, location=(0, 0, 3), size=0.5)
    text = export()[1].warning_text()
    assert "ray visibility" not in text and "Multiple Importance" not in text
    empty_scene.world.cycles_visibility.diffuse = False
    mat.cycles.sample_as_light = False
    empty_scene.world.update_tag()  # the depsgraph's copies follow only when tagged
    mat.update_tag()
    empty_scene.world.cycles_visibility.scatter = False
    scene, log = export()
    text = log.warning_text()
    assert "Multiple Importance off" in text and "Glow" in text and "ray visibility" not in text
    assert scene.world.invisible_to == ("diffuse", "volume_scatter")
