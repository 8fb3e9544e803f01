"""Smooth (singular) mirrors and glass as Cycles 3.4 shows them at max_bounces 0: it still traces a singular lobe's
one ray (its mirror direction, a glass's refracted one) and adds, with MIS skipped, the emission that ray finds --
area lights, emissive meshes, the world -- weighted by the closure (a glass: colour x F of the view, its refraction
colour x (1 - F)).  One scene per class, several spheres each, under a rectangle and a disk light, a soft point
light, an emissive panel above them and a grey world; compared as test_cycles_parity does (4x4 blocks, mean
relative difference over lit blocks), and per sphere: ours / Cycles summed over the blocks inside it (the
whole-image figure is mostly the ground; a sphere rendered black, as before singular lobes, gives well under 0.9).
Cycles renders are deterministic (fixed seed): the tests are."""
import bpy
import numpy as np
import pytest
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

from conftest import builders, export, render, set_resolution
from test_cycles_parity import render_cycles

pytestmark = pytest.mark.slow

WIDTH, HEIGHT, BLOCK = 160, 64, 4
CYCLES_SAMPLES, OUR_SAMPLES = 1024, 256
TOLERANCE = 0.01
SPHERE_TOLERANCE = 0.03  # per sphere (a few dozen blocks, so noisier)
RADIUS = 0.55
XS = (-2.6, -1.3, 0.0, 1.3, 2.6)


def glossy(name, distribution, color=(0.9, 0.75, 0.5)):
    mat, node = builders.node_material("ShaderNodeBsdfGlossy", "ShaderNodeBsdfGlossy", Color=(*color, 1.0),
                                       Roughness=0.0)
    node.distribution = distribution
    mat.name = name
    return mat


def glass(name, distribution, ior, color=(1.0, 1.0, 1.0)):
    mat, node = builders.node_material("ShaderNodeBsdfGlass", "ShaderNodeBsdfGlass", Color=(*color, 1.0),
                                       Roughness=0.0, IOR=ior)
    node.distribution = distribution
    mat.name = name
    return mat


def principled(name, color, **inputs):
    mat = builders.material(name, color, kind="principled", roughness=0.0)
    node = mat.node_tree.nodes["Principled BSDF"]
    for socket, value in inputs.items():
        node.inputs[socket].default_value = value
    return mat


def mirror_materials():
    return [glossy("Sharp", "SHARP"), glossy("GGX", "GGX", (0.6, 0.8, 0.9)), glossy("Beckmann", "BECKMANN"),
            glossy("Multiscatter", "MULTI_GGX", (0.8, 0.8, 0.8)),
            principled("Metal", (0.95, 0.64, 0.54), Metallic=1.0)]


def mixed_glass(name, fac):
    """Mix Shader of a Diffuse BSDF (weight 1 - fac) and a sharp Glass BSDF (fac)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out, mix = nodes.new("ShaderNodeOutputMaterial"), nodes.new("ShaderNodeMixShader")
    diffuse, sharp = nodes.new("ShaderNodeBsdfDiffuse"), nodes.new("ShaderNodeBsdfGlass")
    diffuse.inputs["Color"].default_value = (0.3, 0.6, 0.3, 1.0)
    sharp.distribution, sharp.inputs["Roughness"].default_value, sharp.inputs["IOR"].default_value = "GGX", 0.0, 1.45
    mix.inputs["Fac"].default_value = fac
    links.new(diffuse.outputs[0], mix.inputs[1])
    links.new(sharp.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], out.inputs["Surface"])
    return mat


def glass_materials():
    return [glass("Sharp glass", "SHARP", 1.45, (0.9, 0.8, 0.6)), glass("Beckmann glass", "BECKMANN", 2.4),
            glass("GGX glass", "GGX", 1.5, (0.7, 0.9, 0.8)),
            principled("Clear", (0.6, 0.8, 1.0), Transmission=1.0, IOR=1.5), mixed_glass("Half glass", 0.6)]


def lit_stage(scene, materials, inner_emitters=False):
    """A row of smooth spheres of `materials` over a grey ground, under a rectangle and a disk light (hidden from
    the camera), a soft point light, an emissive panel above the camera's view and a grey world; inner_emitters:
    a small emissive sphere inside each (what a glass's refracted ray finds)."""
    set_resolution(scene, WIDTH, HEIGHT)
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.06, 0.08, 1.0)
    cam = scene.camera
    cam.location, cam.data.lens = (0.0, -7.5, 1.6), 40.0
    cam.rotation_euler = (Vector((0.0, 0.0, 0.6)) - cam.location).to_track_quat("-Z", "Y").to_euler()
    builders.mesh_object("Ground", "plane", builders.material("Ground", (0.5, 0.5, 0.5)), size=20)
    for i, (x, mat) in enumerate(zip(XS, materials)):
        ball = builders.mesh_object(f"Ball{i}", "uv_sphere", mat, location=(x, 0.0, 0.6), radius=RADIUS,
                                    segments=48, ring_count=24)
        builders.smooth(ball)
        if inner_emitters:
            builders.mesh_object(f"Core{i}", "ico_sphere", builders.emission_material(f"Core{i}", (1.0, 0.5, 0.2),
                                 1.0), location=(x, 0.0, 0.6), radius=0.22, subdivisions=2)
    rect = builders.area_light("Rect", "RECTANGLE", size=2.0, size_y=1.0, power=300.0, location=(-2.0, -2.5, 3.5),
                               visible=False)
    builders.aim(rect, (0.0, 0.0, 0.6))
    disk = builders.area_light("Disk", "DISK", size=1.2, power=200.0, location=(2.5, -3.0, 2.5),
                               color=(0.8, 0.9, 1.0), visible=False)
    builders.aim(disk, (0.0, 0.0, 0.6))
    builders.other_light("Bulb", "POINT", 60.0, location=(0.8, -3.0, 1.2), shadow_soft_size=0.15)
    builders.mesh_object("Panel", "plane", builders.emission_material("Panel", (0.9, 0.9, 1.0), 3.0),
                         location=(0.0, -2.0, 3.0), rotation=(0.5, 0.0, 0.0), size=1.0, scale=(4.0, 0.4, 1.0))
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    return scene


def blocks(image):
    rgb = image[..., :3].astype(np.float64)
    return rgb.reshape(HEIGHT // BLOCK, BLOCK, WIDTH // BLOCK, BLOCK, 3).mean(axis=(1, 3))


def sphere_blocks(scene, index):
    """The blocks wholly inside sphere `index`'s outline (row 0 = top)."""
    cam = scene.camera
    centre = world_to_camera_view(scene, cam, Vector((XS[index], 0.0, 0.6)))
    right = cam.matrix_world.to_3x3() @ Vector((1.0, 0.0, 0.0))
    edge = world_to_camera_view(scene, cam, Vector((XS[index], 0.0, 0.6)) + right * RADIUS)
    cx, cy, r = centre.x * WIDTH, (1 - centre.y) * HEIGHT, (edge - centre).length * WIDTH * 0.9
    ys, xs = np.mgrid[0:HEIGHT // BLOCK, 0:WIDTH // BLOCK]
    corners = [((xs + dx) * BLOCK - cx) ** 2 + ((ys + dy) * BLOCK - cy) ** 2 for dx in (0, 1) for dy in (0, 1)]
    return np.all([c < r * r for c in corners], axis=0)


def blocks_of_both(scene, tmp_path):
    """Our and Cycles' images of the scene in blocks, and their mean relative difference over the lit blocks."""
    cycles = render_cycles(scene, str(tmp_path / "cycles.exr"), samples=CYCLES_SAMPLES)
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = OUR_SAMPLES, 1, 2
    ours = render()["images"]["rectangle"]
    a, b = blocks(ours), blocks(cycles)
    lit = b > 0.02 * b.max()
    return a, b, float(np.mean(np.abs(a[lit] - b[lit]) / b[lit]))


def compare(scene, label, tmp_path, n):
    a, b, difference = blocks_of_both(scene, tmp_path)
    ratios = []
    for i in range(n):
        inside = sphere_blocks(scene, i)
        assert inside.sum() >= 6
        ratios.append(float(a[inside].sum() / b[inside].sum()))
    print(f"{label}: mean relative difference to Cycles (4x4 blocks) {difference:.4f}; per sphere ours / Cycles "
          + ", ".join(f"{r:.4f}" for r in ratios))
    return difference, ratios, a, b


def test_smooth_mirrors_match_cycles(empty_scene, tmp_path):
    """Glossy BSDF Sharp, GGX, Beckmann and Multiscatter GGX at roughness 0, a Principled metal of roughness 0."""
    materials = mirror_materials()
    scene = lit_stage(empty_scene, materials)
    exported, _ = export()
    assert all(m.roughness == 0 for m in exported.materials if m.name in {mat.name for mat in materials})
    difference, ratios, _, _ = compare(scene, "smooth mirrors", tmp_path, len(materials))
    assert difference <= TOLERANCE
    assert all(abs(r - 1) <= SPHERE_TOLERANCE for r in ratios)


def test_smooth_glass_matches_cycles(empty_scene, tmp_path):
    """Glass BSDF Sharp, Beckmann (IOR 2.4, the issue's) and GGX at roughness 0, Principled transmission 1 at
    roughness 0 (its refraction tinted by the base colour), a Mix Shader of a Diffuse and a sharp Glass BSDF, each
    with an emitter inside."""
    materials = glass_materials()
    scene = lit_stage(empty_scene, materials, inner_emitters=True)
    difference, ratios, _, _ = compare(scene, "smooth glass", tmp_path, len(materials))
    assert difference <= TOLERANCE
    assert all(abs(r - 1) <= SPHERE_TOLERANCE for r in ratios)


def test_emitter_inside_sharp_glass_cube_matches_cycles(empty_scene, tmp_path):
    """thirdparty_blends/mpett/glowing_cube.blend's case: an emissive object inside a sharp glass cube (flat faces,
    so the refracted rays keep parallel), bright in Cycles through the glass, black before singular lobes were
    traced; the refracted rays that miss it end on the cube's inner faces (surfaces: nothing more at zero
    bounces)."""
    scene = empty_scene
    set_resolution(scene, WIDTH, HEIGHT)
    scene.camera.location = (1.6, -5.5, 2.6)
    scene.camera.rotation_euler = (Vector((0.0, 0.0, 0.7)) - scene.camera.location).to_track_quat("-Z", "Y").to_euler()
    builders.mesh_object("Ground", "plane", builders.material("Ground", (0.5, 0.5, 0.5)), size=20)
    builders.mesh_object("Cube", "cube", glass("Cube glass", "SHARP", 1.5), location=(0.0, 0.0, 0.75), size=1.5,
                         rotation=(0.0, 0.0, 0.5))
    builders.mesh_object("Glow", "torus", builders.emission_material("Glow", (0.3, 1.0, 0.4), 2.0),
                         location=(0.0, 0.0, 0.75), rotation=(1.0, 0.3, 0.0), major_radius=0.45, minor_radius=0.08)
    lamp = builders.area_light("Rect", "RECTANGLE", size=2.0, size_y=1.0, power=300.0, location=(-2.0, -2.5, 3.5),
                               visible=False)
    builders.aim(lamp, (0.0, 0.0, 0.6))
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()
    a, b, difference = blocks_of_both(scene, tmp_path)
    # The cube's blocks: where the cube is seen (Cycles' image greenish: the torus seen through the glass).
    green = (b[..., 1] > 1.5 * b[..., 0]) & (b[..., 1] > 0.05)
    ratio = float(a[green].sum() / b[green].sum())
    print(f"emitter in a sharp glass cube: mean relative difference to Cycles {difference:.4f}; the torus seen "
          f"through the glass ({int(green.sum())} blocks) ours / Cycles {ratio:.4f}")
    assert green.sum() >= 10
    assert difference <= TOLERANCE
    assert abs(ratio - 1) <= SPHERE_TOLERANCE


def test_sharp_glass_and_tinted_principled_glass_export(empty_scene):
    """A sharp glass is not warned of black refraction (its refracted ray is traced; a rough one still is); a
    Principled of Transmission 1 at roughness 0 and a tinted base colour stays 'principled' (its refraction takes the
    base colour), a white one is a white 'glass'."""
    lit_stage(empty_scene, [glass("Sharp glass", "SHARP", 1.45), glass("Rough glass", "GGX", 1.45),
                            principled("Tinted", (0.6, 0.8, 1.0), Transmission=1.0),
                            principled("White", (1.0, 1.0, 1.0), Transmission=1.0)])
    bpy.data.materials["Rough glass"].node_tree.nodes["Glass BSDF"].inputs["Roughness"].default_value = 0.2
    exported, log = export()
    kinds = {m.name: m.kind for m in exported.materials}
    assert (kinds["Sharp glass"], kinds["Tinted"], kinds["White"]) == ("glass", "principled", "glass")
    warned = log.warning_text()
    assert "refraction of lights" in warned and "Rough glass" in warned
    assert "Sharp glass" not in warned and "Tinted" not in warned and "White" not in warned


def test_emitter_found_by_a_singular_ray_reads_is_singular_ray(empty_scene, tmp_path):
    """A panel whose Emission Strength is Light Path's Is Singular Ray: seen in a sharp mirror, not in a rough one
    nor by the camera, as in Cycles (its PATH_RAY_SINGULAR)."""
    materials = [glossy("Sharp", "SHARP"), glossy("Rough", "GGX")]
    scene = lit_stage(empty_scene, materials)
    bpy.data.materials["Rough"].node_tree.nodes["Glossy BSDF"].inputs["Roughness"].default_value = 0.3
    panel = bpy.data.materials["Panel"]
    nodes, links = panel.node_tree.nodes, panel.node_tree.links
    links.new(nodes.new("ShaderNodeLightPath").outputs["Is Singular Ray"], nodes["Emission"].inputs["Strength"])
    for name in ("Rect", "Disk", "Bulb"):
        bpy.data.objects.remove(bpy.data.objects[name])
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    _, ratios, ours, cycles = compare(scene, "Is Singular Ray", tmp_path, 1)  # in blocks
    rough = sphere_blocks(scene, 1)
    assert ours[sphere_blocks(scene, 0)].sum() > 0.1
    assert ours[rough].sum() == 0 and cycles[rough].sum() == 0
    assert abs(ratios[0] - 1) <= SPHERE_TOLERANCE
