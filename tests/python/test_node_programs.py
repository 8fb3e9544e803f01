"""Node programs (Material.programs, MixFactor.program: render/svm) in the renderer: a program-driven input renders as
the same value or image given directly does, a program-driven emitter lights a plane as the closed form says, the
scene file keeps programs (older files load without), bad programs are refused.

Statistical tests use fixed seeds; the per-pixel t-tests (render_testing.pixel_t_test) fail falsely with probability
FAMILY_ALPHA = 1e-4 over all their pixels and configurations."""
import dataclasses

import numpy as np
import pytest

import sphrect
from render_testing import (expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance, replicate_images,
                            save_as_older_version, top_camera)
from sphrect.render import build_native_scene

FAMILY_ALPHA = 1e-4
I = sphrect.NodeInstruction
OPS = sphrect.scene


def constant_program(value):
    return sphrect.NodeProgram(instructions=[I(op="constant", regs=[0], value=value)], output=0, num_registers=1)


def image_program(texture, interpolation="closest"):
    """The image at the hit's UVs (an Image Texture node on the UVs)."""
    return sphrect.NodeProgram(instructions=[
        I(op="global", regs=[0], mode=OPS.NODE_GLOBALS.index("uv")),
        I(op="image", regs=[0, 1, 2], data=texture, mode=OPS.TEXTURE_INTERPOLATIONS.index(interpolation))],
        output=1, num_registers=3)


def scalar_image_program(texture):
    """image_program's colour as a float input reads it (its luminance, as Cycles converts the link)."""
    program = image_program(texture)
    program.instructions.append(I(op="convert", regs=[1, 3], mode=OPS.NODE_CONVERSIONS.index("color_to_float")))
    program.output, program.num_registers = 3, 4
    return program


def two_tone_program(split=0.5, low=0.25):
    """1 where the UV's u < split, `low` elsewhere: low + (1 - low) (u < split), as a colour."""
    return sphrect.NodeProgram(instructions=[
        I(op="global", regs=[0], mode=OPS.NODE_GLOBALS.index("uv")),
        I(op="separate", regs=[0, 1, -1, -1]),
        I(op="constant", regs=[2], value=(split, 0, 0)),
        I(op="constant", regs=[3], value=(1 - low, 0, 0)),
        I(op="constant", regs=[4], value=(low, 0, 0)),
        I(op="math", regs=[1, 2, 2, 5], mode=OPS.NODE_MATH_OPS.index("LESS_THAN")),
        I(op="math", regs=[5, 3, 4, 6], mode=OPS.NODE_MATH_OPS.index("MULTIPLY_ADD")),
        I(op="convert", regs=[6, 7], mode=OPS.NODE_CONVERSIONS.index("float_to_vector"))],
        output=7, num_registers=8)


def lit_plane(material, textures=()):
    ground = plane_mesh(size=2.0)
    ground.material_ids = np.zeros(2, np.int32)
    ground.uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    light = sphrect.RectLight(corner=(-0.5, -0.4, 1.0), edge_x=(0.0, 0.9, 0.0), edge_y=(1.1, 0.0, 0.0),
                              radiance=(2.0,) * 3)
    return sphrect.Scene(camera=top_camera(height_above=0.5), meshes=[ground], lights=[light], materials=[material],
                         textures=list(textures))


def images(scene, samples=4):
    r = sphrect.Renderer(scene, techniques=["rectangle"], seed=3)
    assert r.render(samples)
    return r.image("rectangle")


CHECKER = sphrect.Texture(name="checker", colorspace="linear",
                          pixels=np.array([[[0.9, 0.2, 0.1], [0.1, 0.5, 0.9]], [[0.3, 0.8, 0.2], [0.7, 0.7, 0.1]]],
                                          np.float32))


@pytest.mark.parametrize("kind", ["diffuse", "principled", "glossy_bsdf"])
def test_a_program_input_renders_as_the_image_given_directly(kind):
    """Base colour and roughness from a program reading an image equal the same image as a TextureLookup, bit for
    bit (the same Bsdf per hit); a constant program equals a 1-texel image of that value."""
    lookup = sphrect.TextureLookup(texture=0, interpolation="closest")
    fields = ["base_color"] + (["roughness"] if kind != "diffuse" else [])
    direct = sphrect.Material(kind=kind, textures={f: lookup for f in fields})
    programmed = sphrect.Material(kind=kind, programs={f: image_program(0) if f == "base_color" else
                                                       scalar_image_program(0) for f in fields})
    a, b = images(lit_plane(direct, [CHECKER])), images(lit_plane(programmed, [CHECKER]))
    assert a[..., :3].max() > 0
    np.testing.assert_array_equal(a, b)
    one_texel = sphrect.Texture(name="c", colorspace="linear", pixels=np.full((1, 1, 3), 0.3, np.float32))
    direct = sphrect.Material(kind=kind, textures={f: lookup for f in fields})
    constant = sphrect.Material(kind=kind, programs={f: constant_program((0.3, 0.3, 0.3)) for f in fields})
    np.testing.assert_array_equal(images(lit_plane(direct, [one_texel])), images(lit_plane(constant, [one_texel])))


def test_a_program_mix_factor_renders_as_the_image_factor():
    """A Mix Shader factor from a program reading an image equals the image's MixFactor."""
    def mix(factor):
        red = sphrect.Material(kind="diffuse", base_color=(0.8, 0.1, 0.1))
        glossy = sphrect.Material(kind="glossy_bsdf", base_color=(0.9, 0.9, 0.9), roughness=0.3)
        return sphrect.Material(kind="mix", layers=[
            sphrect.MaterialLayer(weight=1.0, material=red, factors=[dataclasses.replace(factor, complement=True)]),
            sphrect.MaterialLayer(weight=1.0, material=glossy, factors=[factor])])
    lookup = sphrect.TextureLookup(texture=0, interpolation="closest")
    a = images(lit_plane(mix(sphrect.MixFactor(lookup=lookup)), [CHECKER]))
    b = images(lit_plane(mix(sphrect.MixFactor(program=scalar_image_program(0))), [CHECKER]))
    np.testing.assert_array_equal(a, b)


# An emissive quad 1 above the ground, facing down, u along x: its part u < 1/2 (x < 0.05) of radiance RADIANCE, the
# rest a quarter of it (two_tone_program), lighting a Lambertian ground.
RADIANCE, ALBEDO = 2.0, 0.5
QUAD = np.array([[-0.5, -0.4, 1.0], [0.6, -0.4, 1.0], [0.6, 0.5, 1.0], [-0.5, 0.5, 1.0]])
FIRST = [[-0.5, -0.4, 1], [0.05, -0.4, 1], [0.05, 0.5, 1], [-0.5, 0.5, 1]]
SECOND = [[0.05, -0.4, 1], [0.6, -0.4, 1], [0.6, 0.5, 1], [0.05, 0.5, 1]]


def emitter_scene():
    ground = plane_mesh()
    ground.material_ids = np.zeros(2, np.int32)
    quad = sphrect.Mesh(vertices=QUAD.astype(np.float32), triangles=np.array([[0, 2, 1], [0, 3, 2]], np.int32),
                        uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32),
                        material_ids=np.ones(2, np.int32), name="emitter")
    emitter = sphrect.Material(name="emitter", base_color=(0.0, 0.0, 0.0), emission=(RADIANCE,) * 3,
                               programs={"emission": two_tone_program()})
    return sphrect.Scene(camera=top_camera(height_above=0.5), meshes=[ground, quad], lights=[],
                         materials=[sphrect.Material(name="ground", base_color=(ALBEDO,) * 3), emitter])


def facing_program():
    """A Layer Weight's Facing (blend 1/2: 1 - |N.I|) as a colour: 0 seen face-on, 1 edge-on."""
    return sphrect.NodeProgram(instructions=[
        I(op="constant", regs=[0], value=(0.5, 0, 0)),
        I(op="global", regs=[1], mode=OPS.NODE_GLOBALS.index("normal")),
        I(op="layer_weight", regs=[0, 1, 2, 3]),
        I(op="convert", regs=[3, 4], mode=OPS.NODE_CONVERSIONS.index("float_to_vector"))],
        output=4, num_registers=5)


def test_a_view_dependent_emitter_is_chosen_by_its_power():
    """Light selection weighs a program's emitter by its mean over the directions it is seen from, cosine-weighted
    (its power): a glow only seen at grazing angles is not taken for black, which made its rare samples fireflies.
    1 - |cos| over the cosine-weighted hemisphere averages 1/3 (16 directions here: within 10%)."""
    emitter = sphrect.Material(name="emitter", base_color=(0.0, 0.0, 0.0), emission=(RADIANCE,) * 3,
                               programs={"emission": facing_program()})
    scene = dataclasses.replace(emitter_scene(), materials=[emitter_scene().materials[0], emitter])
    scene.meshes[1].vertices[2, 0] += 0.05  # no longer a rectangle: two triangle lights
    native, _ = build_native_scene(scene)
    radiance = np.array(native.area_light_radiance)
    assert radiance.shape == (2, 3)
    np.testing.assert_allclose(radiance, RADIANCE / 3, rtol=0.1)


def two_tone_irradiance(P):
    return RADIANCE * (polygon_irradiance(P, (0, 0, 1), FIRST) + 0.25 * polygon_irradiance(P, (0, 0, 1), SECOND))


@pytest.mark.parametrize("technique", ["rectangle", "area"])
def test_a_program_driven_emitter_lights_the_plane_as_the_closed_form(technique):
    """Light samples (by blocks, for the rectangle the two triangles form) and BSDF rays read the program at their
    point of the emitter: the ground's image is the two halves' irradiance (Lambert's polygon formula)."""
    cam = top_camera(height_above=0.5)
    expected = expected_plane_image(cam, ALBEDO, two_tone_irradiance)
    reps = replicate_images(emitter_scene(), [technique], 12, 16, mis="balance", bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps[technique], expected, FAMILY_ALPHA / 2)
    assert ok, f"{technique}: worst p = {p_min:.3g} < {alpha:.3g}"


def test_camera_rays_see_the_program_emission():
    """The emitter seen from above through the ground... from below: a camera under it sees RADIANCE and a quarter."""
    scene = emitter_scene()
    scene.meshes = scene.meshes[1:]
    scene.meshes[0].material_ids = np.zeros(2, np.int32)
    scene.materials = scene.materials[1:]
    scene.camera = sphrect.Camera(width=22, height=18, type="orthographic", ortho_scale=1.1,
                                  to_world=[[1, 0, 0, 0.05], [0, -1, 0, 0.05], [0, 0, -1, 0.0], [0, 0, 0, 1]])
    img = images(scene, samples=1)[..., 0]
    assert img[:, :10].min() == pytest.approx(RADIANCE, rel=1e-6)
    assert img[:, 12:].max() == pytest.approx(0.25 * RADIANCE, rel=1e-6)


def test_programs_are_saved_and_older_files_load(tmp_path):
    scene = lit_plane(sphrect.Material(kind="principled", programs={"base_color": image_program(0),
                                                                    "roughness": two_tone_program()}), [CHECKER])
    path = tmp_path / "p.sphrect.npz"
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert loaded.materials[0].programs == scene.materials[0].programs
    np.testing.assert_array_equal(images(scene), images(loaded))
    old = tmp_path / "old.sphrect.npz"
    save_as_older_version(path, old, 17, lambda meta: [m.pop("programs") for m in meta["materials"]])
    assert sphrect.load_scene(old).materials[0].programs == {}


def test_bad_programs_are_refused():
    def refused(program, match):
        with pytest.raises(ValueError, match=match):
            build_native_scene(lit_plane(sphrect.Material(programs={"base_color": program}), [CHECKER]))
    program = constant_program((1, 1, 1))
    program.output = 3
    refused(program, "output")
    refused(sphrect.NodeProgram(instructions=[I(op="math", regs=[0, 0, 0, 1])], output=1, num_registers=2),
            "nothing wrote before")
    refused(sphrect.NodeProgram(instructions=[I(op="bogus", regs=[0])], output=0, num_registers=1), "op")
    refused(sphrect.NodeProgram(instructions=[I(op="image", regs=[-1, 0, -1], data=0)], output=0, num_registers=1),
            "input has no register")
    bad_image = image_program(5)
    refused(bad_image, "image index")
    with pytest.raises(ValueError, match="both a texture and a node program"):
        build_native_scene(lit_plane(sphrect.Material(programs={"base_color": image_program(0)},
                                                      textures={"base_color": sphrect.TextureLookup(texture=0)}),
                                     [CHECKER]))


def _eval(program, generated):
    return np.array(sphrect._native._eval_node_program(dataclasses.asdict(program), (0, 0, 0), (0, 0, 0), generated))


def test_texture_ops_give_the_pure_functions_values():
    """A noise_texture / voronoi_texture instruction (settings packed three to a register, mode the dimensions,
    metric and feature) at Generated points gives what sphrect._native.procedural_texture does there."""
    points = np.random.default_rng(7).uniform(-3, 3, (20, 3)).astype(np.float32)
    noise = sphrect.NodeProgram(instructions=[
        I(op="global", regs=[0], mode=OPS.NODE_GLOBALS.index("generated")),
        I(op="constant", regs=[1], value=(0.3, 0, 0)),             # w
        I(op="constant", regs=[2], value=(2.5, 3.0, 0.6)),         # scale, detail, roughness
        I(op="constant", regs=[3], value=(0.4, 0, 0)),             # distortion
        I(op="noise_texture", regs=[0, 1, 2, 3, 4, 5], mode=2)],   # 3D
        output=5, num_registers=6)
    want = sphrect._native.procedural_texture("noise", points, dimensions=3, scale=2.5, detail=3.0, roughness=0.6,
                                              distortion=0.4)
    got = np.array([_eval(noise, tuple(map(float, p))) for p in points])
    assert np.array_equal(got.astype(np.float32), np.asarray(want["color"], np.float32).reshape(got.shape))
    features, metrics = sphrect._native.node_voronoi_features, sphrect._native.node_voronoi_metrics
    mode = 1 + 4 * (metrics.index("manhattan") + 4 * features.index("f2"))  # 2D
    voronoi = sphrect.NodeProgram(instructions=noise.instructions[:4] + [
        I(op="voronoi_texture", regs=[0, 1, 2, 3, 4, 5, 6], mode=mode)], output=4, num_registers=7)
    want = sphrect._native.procedural_texture("voronoi", points, dimensions=2, feature="f2", metric="manhattan",
                                              scale=2.5, smoothness=3.0, exponent=0.6, randomness=0.4)
    got = np.array([_eval(voronoi, tuple(map(float, p)))[0] for p in points])
    assert np.array_equal(got.astype(np.float32), np.asarray(want["distance"], np.float32).ravel())
    assert np.ptp(got) > 0


def test_bad_texture_and_curve_instructions_are_refused():
    def refused(instructions, registers, match, data=()):
        program = sphrect.NodeProgram(instructions=[I(op="constant", regs=[0])] + instructions, output=registers - 1,
                                      num_registers=registers, data=list(data))
        with pytest.raises(ValueError, match=match):
            build_native_scene(lit_plane(sphrect.Material(programs={"base_color": program})))
    refused([I(op="voronoi_texture", regs=[0, 0, 0, 0, 1, -1, -1], mode=80)], 2, "mode out of range")
    refused([I(op="brick_texture", regs=[0, 0, 0, 0, 0, 0, 1], data=0)], 2, "brick settings", data=[0.5, 2, 1])
    refused([I(op="curves", regs=[0, 0, 1], data=0, size=4)], 2, "curve table", data=[0, 1, 1] + [0.0] * 11)
    refused([I(op="noise_texture", regs=[0, 0, 0, -1, 1, 2])], 3, "input has no register")
