"""Image worlds (issue 28): the exporter's Background from an equirectangular Environment Texture ->
sphrect.Environment (the image a Texture, the Mapping / Vector Rotate / Texture Coordinate rotation its to_world,
Strength and a constant Multiply its strength), the worlds it cannot take as they are baked by Cycles
(_world_not_representable), and Cycles parity of a scene lit by an HDR-like float image (a bright blob and a sky
gradient) and of Blender's own HDR photographs (its studio-light worlds): mean relative difference over lit
4x4-pixel blocks, as test_cycles_parity.py measures (Cycles 2048 spp, SPHRECT 512 spp).  Fixed seeds:
deterministic."""
import os

import bpy
import mathutils
import numpy as np
import pytest

from conftest import builders, export, set_resolution
from test_cycles_parity import HEIGHT, WIDTH, difference_to_cycles


def hdr_pixels(height=32, width=64, sun=(0.3, 0.72), sun_value=60.0, sun_radius=0.05):
    """Float RGBA [H, W, 4], row 0 the bottom: a sky gradient (blue above, warm below, dim) and a bright blob at
    (u, v) = sun (v = 0.72: ~40 degrees above the horizon)."""
    v, u = np.meshgrid((np.arange(height) + 0.5) / height, (np.arange(width) + 0.5) / width, indexing="ij")
    pixels = np.ones((height, width, 4), np.float32)
    up = np.clip(2 * v - 1, 0, 1)
    pixels[..., 0] = 0.25 + 0.3 * (1 - up) + 0.1 * np.sin(2 * np.pi * u)
    pixels[..., 1] = 0.3 + 0.15 * (1 - up)
    pixels[..., 2] = 0.35 + 0.5 * up
    d2 = (np.minimum(np.abs(u - sun[0]), 1 - np.abs(u - sun[0])) * 2) ** 2 + (v - sun[1]) ** 2
    blob = sun_value * np.exp(-d2 / (2 * sun_radius ** 2))
    pixels[..., :3] += blob[..., None] * np.array([1.0, 0.9, 0.75])
    return pixels


def image_world(pixels, strength=1.0, rotation_z=None, name="HDR"):
    """A world whose Background Color is an Environment Texture of a packed float image of `pixels`, behind a
    Point Mapping rotating about Z by `rotation_z` (radians) from a Texture Coordinate's Generated, if given."""
    height, width = pixels.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=True, float_buffer=True)
    image.pixels.foreach_set(np.ascontiguousarray(pixels, np.float32).ravel())
    image.pack()
    world = bpy.data.worlds.new(name)
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    env = nodes.new("ShaderNodeTexEnvironment")
    env.image = image
    background = nodes["Background"]
    background.inputs["Strength"].default_value = strength
    links.new(env.outputs["Color"], background.inputs["Color"])
    if rotation_z is not None:
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, rotation_z)
        coords = nodes.new("ShaderNodeTexCoord")
        links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    bpy.context.scene.world = world
    return world, env


def ground():
    builders.mesh_object("Ground", "plane", builders.material("Ground", (0.8, 0.8, 0.8)), size=8)


def test_environment_texture_world_is_an_environment(empty_scene):
    pixels = hdr_pixels(8, 16)
    world, env = image_world(pixels, strength=2.5, rotation_z=0.6)
    ground()
    scene, log = export()
    e = scene.world.environment
    assert e is not None and scene.world.background == (0.0, 0.0, 0.0)
    texture = scene.textures[e.texture]
    assert texture.colorspace == "linear"
    np.testing.assert_allclose(texture.pixels[..., :3], pixels[..., :3], rtol=1e-6)
    assert e.strength == pytest.approx((2.5, 2.5, 2.5))
    assert e.interpolation == "linear"
    # Cycles looks the direction w up at R w (R the Mapping's rotation): to_world = R^T.
    expected = np.array(mathutils.Euler((0, 0, 0.6), "XYZ").to_matrix()).T
    np.testing.assert_allclose(np.array(e.to_world), expected, atol=1e-6)
    assert "mean colour" not in log.warning_text()
    assert "no lights" not in log.warning_text()


def test_scaled_mapping_and_multiply_are_an_environment(empty_scene):
    """A uniform scale does not change the direction (Cycles normalises it); a Multiply by a constant colour (Mix
    node, factor 0.5) is a factor of the strength: 1 - f + f c."""
    world, env = image_world(hdr_pixels(4, 8), strength=2.0, rotation_z=0.3)
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes["Mapping"].inputs["Scale"].default_value = (3.0, 3.0, 3.0)
    mix = nodes.new("ShaderNodeMixRGB")
    mix.blend_type = "MULTIPLY"
    mix.inputs["Fac"].default_value = 0.5
    mix.inputs["Color2"].default_value = (0.2, 0.4, 1.0, 1.0)
    links.new(env.outputs["Color"], mix.inputs["Color1"])
    links.new(mix.outputs["Color"], nodes["Background"].inputs["Color"])
    ground()
    e = export()[0].world.environment
    assert e is not None
    assert e.strength == pytest.approx(tuple(2.0 * (0.5 + 0.5 * np.array([0.2, 0.4, 1.0]))))
    expected = np.array(mathutils.Euler((0, 0, 0.3), "XYZ").to_matrix()).T
    np.testing.assert_allclose(np.array(e.to_world), expected, atol=1e-6)


@pytest.mark.parametrize("location", [(0.0, 0.0, 0.0), (0.0, 2.0, 0.0)])
def test_object_coordinates_of_a_rotated_empty(empty_scene, location):
    """A Texture Coordinate's Object output of an object: Cycles looks the direction up at the object's inverse
    matrix, a rotation for an empty at the origin (to_world its rotation), not one where it is moved (baked)."""
    world, env = image_world(hdr_pixels(4, 8))
    empty = builders.link(bpy.data.objects.new("Frame", None))
    empty.rotation_euler = (0.2, 0.0, 0.9)
    empty.location = location
    nodes, links = world.node_tree.nodes, world.node_tree.links
    coords = nodes.new("ShaderNodeTexCoord")
    coords.object = empty
    links.new(coords.outputs["Object"], env.inputs["Vector"])
    ground()
    bpy.context.view_layer.update()
    with stand_in_bake() as baked:
        e = export()[0].world.environment
    if location == (0.0, 0.0, 0.0):
        assert baked == []
        np.testing.assert_allclose(np.array(e.to_world), np.array(empty.matrix_world.to_3x3()), atol=1e-6)
    else:  # baked
        assert baked == [world.name] and e.to_world == np.eye(3).tolist()


@pytest.mark.parametrize("invert", [False, True])
def test_vector_rotate_is_the_environment_rotation(empty_scene, invert):
    """A Vector Rotate node (axis and angle, about the origin) between the Mapping and the image: Cycles looks w up
    at R_rotate R_mapping w."""
    world, env = image_world(hdr_pixels(4, 8), rotation_z=0.3)
    nodes, links = world.node_tree.nodes, world.node_tree.links
    rotate = nodes.new("ShaderNodeVectorRotate")
    rotate.rotation_type = "AXIS_ANGLE"
    rotate.invert = invert
    rotate.inputs["Axis"].default_value = (1.0, 1.0, 0.0)
    rotate.inputs["Angle"].default_value = 0.7
    links.new(nodes["Mapping"].outputs["Vector"], rotate.inputs["Vector"])
    links.new(rotate.outputs["Vector"], env.inputs["Vector"])
    ground()
    e = export()[0].world.environment
    assert e is not None
    turn = np.array(mathutils.Matrix.Rotation(-0.7 if invert else 0.7, 3, mathutils.Vector((1, 1, 0)).normalized()))
    mapping = np.array(mathutils.Euler((0, 0, 0.3), "XYZ").to_matrix())
    np.testing.assert_allclose(np.array(e.to_world), (turn @ mapping).T, atol=1e-6)
    rotate.inputs["Center"].default_value = (0.0, 0.0, 1.0)  # a rotation about a point off the origin: not one
    with stand_in_bake() as baked:
        e = export()[0].world.environment
    assert baked == [world.name] and e.to_world == np.eye(3).tolist()


class stand_in_bake:
    """world_bake.bake_world replaced by a 2 x 4 image of its own while exporting (the bake itself is
    test_world_bake.py's): the worlds it is asked to bake, by name, and the image it gave."""
    PIXELS = np.arange(24, dtype=np.float32).reshape(2, 4, 3) / 24

    def __enter__(self):
        from sphrect_blender.io.exporter import world_bake
        self.module, self.original, self.names = world_bake, world_bake.bake_world, []
        world_bake.bake_world = lambda world, *a, **kw: self.names.append(world.name) or self.PIXELS.copy()
        return self.names

    def __exit__(self, *exc):
        self.module.bake_world = self.original


@pytest.mark.parametrize("change", ["mirror_ball", "translation", "unequal_scale", "sky"])
def test_worlds_not_representable_are_baked(empty_scene, change):
    """A mirror-ball projection, a Mapping with a translation or an unequal scale, a Sky Texture: not mapped
    directly but baked by Cycles (world_bake.py) into an Environment of identity to_world and strength 1, its
    background the bake's mean over the sphere; no warning of a mean colour."""
    world, env = image_world(hdr_pixels(4, 8), strength=2.0, rotation_z=0.3)
    nodes = world.node_tree.nodes
    if change == "mirror_ball":
        env.projection = "MIRROR_BALL"
    elif change == "translation":
        nodes["Mapping"].inputs["Location"].default_value = (0.0, 0.5, 0.0)
    elif change == "unequal_scale":
        nodes["Mapping"].inputs["Scale"].default_value = (1.0, 2.0, 1.0)
    else:
        sky = nodes.new("ShaderNodeTexSky")
        world.node_tree.links.new(sky.outputs["Color"], nodes["Background"].inputs["Color"])
    ground()
    with stand_in_bake() as baked:
        scene, log = export()
    assert baked == [world.name]
    e = scene.world.environment
    assert e.to_world == np.eye(3).tolist() and tuple(e.strength) == (1.0, 1.0, 1.0)
    texture = scene.textures[e.texture]
    assert texture.colorspace == "linear"
    np.testing.assert_array_equal(texture.pixels, stand_in_bake.PIXELS)
    from sphrect_blender.io.exporter import world_bake
    assert scene.world.background == pytest.approx(tuple(world_bake.sphere_mean(stand_in_bake.PIXELS)), rel=1e-6)
    assert "mean colour" not in log.warning_text()


def test_missing_environment_image_is_magenta(empty_scene):
    world, env = image_world(hdr_pixels(4, 8))
    env.image = None
    ground()
    scene, log = export()
    texture = scene.textures[scene.world.environment.texture]
    np.testing.assert_array_equal(texture.pixels.reshape(-1)[:3], [1.0, 0.0, 1.0])


def floor_box_and_ball(scene):
    """The parity tests' scene under the world: the ground, a box and a smooth ball, at the parity resolution."""
    ground()
    builders.mesh_object("Box", "cube", builders.material("Box", (0.7, 0.4, 0.2)), location=(0.6, 0.5, 0.5),
                         size=1.0, rotation=(0, 0, 0.4))
    sphere = builders.mesh_object("Ball", "uv_sphere", builders.material("Ball", (0.3, 0.6, 0.8)),
                                  location=(-0.9, -0.2, 0.6), radius=0.6)
    builders.smooth(sphere)
    set_resolution(scene, WIDTH, HEIGHT)
    bpy.context.view_layer.update()


@pytest.mark.slow
def test_environment_lit_scene_matches_cycles(empty_scene, tmp_path):
    """A floor, a box and a sphere lit only by an HDR-like image world rotated by a Mapping (a sun-like blob 60x
    the sky, ~40 degrees up), the camera seeing the sky above the horizon."""
    image_world(hdr_pixels(), strength=1.5, rotation_z=0.8)
    floor_box_and_ball(empty_scene)
    difference, ours, cycles = difference_to_cycles(empty_scene, "image world", tmp_path, light_samples=2)
    assert difference <= 0.01
    # The comparison can fail: the world unrotated is caught.
    empty_scene.world.node_tree.nodes["Mapping"].inputs["Rotation"].default_value = (0.0, 0.0, 0.0)
    unrotated, _, _ = difference_to_cycles(empty_scene, "image world, unrotated", tmp_path, cycles=cycles)
    assert unrotated > 0.03


@pytest.mark.slow
@pytest.mark.parametrize("name", ["sunrise.exr", "courtyard.exr", "night.exr"])
def test_blenders_own_hdris_match_cycles(empty_scene, name, tmp_path):
    """Real HDR photographs: the equirectangular studio-light worlds Blender ships (Poly Haven's, CC0), as a world
    image on the floor, box and sphere scene (rotated 2 rad about Z)."""
    path = os.path.join(bpy.utils.system_resource("DATAFILES", path="studiolights/world"), name)
    world, env = image_world(hdr_pixels(2, 4), rotation_z=2.0, name=name)
    env.image = bpy.data.images.load(path)
    floor_box_and_ball(empty_scene)
    scene, _ = export()
    assert scene.world.environment is not None
    difference, _, _ = difference_to_cycles(empty_scene, f"Blender's {name}", tmp_path, light_samples=2)
    assert difference <= 0.01


@pytest.mark.slow
def test_object_coordinates_world_matches_cycles(empty_scene, tmp_path):
    """The HDR-like world looked up in the frame of an empty rotated about X and Z (Texture Coordinate Object)."""
    world, env = image_world(hdr_pixels(), strength=1.5)
    empty = builders.link(bpy.data.objects.new("Frame", None))
    empty.rotation_euler = (0.5, 0.0, 2.2)
    coords = world.node_tree.nodes.new("ShaderNodeTexCoord")
    coords.object = empty
    world.node_tree.links.new(coords.outputs["Object"], env.inputs["Vector"])
    ground()
    builders.mesh_object("Box", "cube", builders.material("Box", (0.7, 0.4, 0.2)), location=(0.6, 0.5, 0.5),
                         size=1.0, rotation=(0, 0, 0.4))
    set_resolution(empty_scene, WIDTH, HEIGHT)
    bpy.context.view_layer.update()
    assert export()[0].world.environment is not None
    difference, _, _ = difference_to_cycles(empty_scene, "image world in an object's frame", tmp_path)
    assert difference <= 0.01
