"""The Light Path node's outputs (render/svm/program.h RayContext) in each context a program is evaluated under direct
lighting, as Cycles 3.4 gives them (kernel/svm/light_path.h from the path_flag each evaluation passes and the path
state's counters), and the renderer's use of them: a camera-invisible emitter still lights the ground, a surface
that is transparent to shadow rays alone casts no shadow.

Statistical tests use fixed seeds; the per-pixel t-tests (render_testing.pixel_t_test) fail falsely with probability
FAMILY_ALPHA = 1e-4 over all their pixels and configurations."""
import dataclasses

import numpy as np
import pytest

import sphrect
from render_testing import expected_plane_image, pixel_t_test, plane_mesh, polygon_irradiance, replicate_images, \
    top_camera
from test_node_programs import images, lit_plane

FAMILY_ALPHA = 1e-4
I = sphrect.NodeInstruction
GLOBALS = sphrect.scene.NODE_GLOBALS
OUTPUTS = ("is_camera_ray", "is_shadow_ray", "is_diffuse_ray", "is_glossy_ray", "is_singular_ray",
           "is_reflection_ray", "is_transmission_ray", "is_volume_scatter_ray", "ray_depth", "diffuse_depth",
           "glossy_depth", "transparent_depth", "transmission_depth")


def global_program(name):
    return sphrect.NodeProgram(instructions=[I(op="global", regs=[0], mode=GLOBALS.index(name))], output=0,
                               num_registers=1)


def light_path(ray, transparent_depth=0):
    """{output: value} of every Light Path output for a hit found by `ray` (_eval_node_program's names)."""
    return {name: sphrect._native._eval_node_program(dataclasses.asdict(global_program(name)), (0, 0, 0), (0, 0, 0),
                                                     (0, 0, 0), ray=ray, transparent_depth=transparent_depth)[0]
            for name in OUTPUTS}


def expect(flags=(), depth=0, diffuse=0, glossy=0, transparent=0, transmission=0):
    values = {f"is_{f}_ray": 1.0 for f in flags}
    values.update(ray_depth=depth, diffuse_depth=diffuse, glossy_depth=glossy, transparent_depth=transparent,
                  transmission_depth=transmission)
    return {name: float(values.get(name, 0.0)) for name in OUTPUTS}


# Cycles 3.4 under direct lighting (max_bounces 0 or 1):
#  - a camera ray's hit: path_state_init's PATH_RAY_CAMERA, every counter 0 but the transparent surfaces passed;
#  - a light sample's point of an emitter: light_sample_shader_eval passes PATH_RAY_EMISSION alone (so not a camera
#    ray, whatever the shading point), and svm_node_light_path adds 1 to Ray Depth for it;
#  - a surface a shadow ray crosses: PATH_RAY_SHADOW alone, Ray Depth + 1, the shadow path's transparent count;
#  - what a BSDF or phase ray finds: path_state_next of the lobe's label (bounce 1, its class's counter 1).
CONTEXTS = {
    ("camera", 0): expect(["camera"]),
    ("camera", 2): expect(["camera"], transparent=2),
    ("light_sample", 0): expect(depth=1),
    ("shadow", 0): expect(["shadow"], depth=1),
    ("shadow", 3): expect(["shadow"], depth=1, transparent=3),
    ("diffuse", 0): expect(["diffuse", "reflection"], depth=1, diffuse=1),
    ("glossy", 1): expect(["glossy", "reflection"], depth=1, glossy=1, transparent=1),
    ("diffuse+transmission", 0): expect(["diffuse", "transmission"], depth=1, transmission=1),
    ("glossy+transmission", 0): expect(["glossy", "transmission"], depth=1, transmission=1),
    ("volume_scatter", 0): expect(["volume_scatter"], depth=1),
}


@pytest.mark.parametrize("ray, transparent", list(CONTEXTS))
def test_each_context_gives_cycles_flags_and_depths(ray, transparent):
    assert light_path(ray, transparent) == CONTEXTS[(ray, transparent)]


def test_the_outputs_are_the_renderer_globals_and_bad_rays_are_refused():
    assert set(OUTPUTS) <= set(GLOBALS)
    for bad in ("camera+diffuse", "sideways", "shadow+glossy"):
        with pytest.raises(ValueError):
            light_path(bad)
    with pytest.raises(ValueError):
        light_path("camera", 99)


# An emissive quad 1 above the ground, facing down, radiance RADIANCE for every ray but the camera's: a mix of an
# emission (its factor 1 - Is Camera Ray) and a transparent layer (factor Is Camera Ray), as the exporter makes of
# Mix Shader(Is Camera Ray, Emission, Transparent).
RADIANCE, ALBEDO = 2.0, 0.5
QUAD = np.array([[-0.5, -0.4, 1.0], [0.6, -0.4, 1.0], [0.6, 0.5, 1.0], [-0.5, 0.5, 1.0]])


def camera_mix(first, second, emission=None, name="is_camera_ray"):
    """A mix of `first` (weight 1 - the output `name`) and `second` (weight `name`); `emission`: the first's
    emission as a program of RADIANCE (1 - name)."""
    factor = sphrect.MixFactor(program=global_program(name))
    layers = [sphrect.MaterialLayer(weight=1.0, material=first, factors=[sphrect.MixFactor(
        program=global_program(name), complement=True)]),
        sphrect.MaterialLayer(weight=1.0, material=second, factors=[factor])]
    programs = {}
    if emission is not None:
        programs["emission"] = sphrect.NodeProgram(instructions=[
            I(op="global", regs=[0], mode=GLOBALS.index(name)),
            I(op="constant", regs=[1], value=(1.0, 0, 0)),
            I(op="math", regs=[1, 0, 0, 2], mode=sphrect.scene.NODE_MATH_OPS.index("SUBTRACT")),
            I(op="convert", regs=[2, 3], mode=sphrect.scene.NODE_CONVERSIONS.index("float_to_vector"))],
            output=3, num_registers=4)
    return sphrect.Material(kind="mix", layers=layers, emission=emission or (0.0, 0.0, 0.0), programs=programs)


def hidden_emitter_scene():
    ground = plane_mesh()
    ground.material_ids = np.zeros(2, np.int32)
    quad = sphrect.Mesh(vertices=QUAD.astype(np.float32), triangles=np.array([[0, 2, 1], [0, 3, 2]], np.int32),
                        uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32),
                        material_ids=np.ones(2, np.int32), name="emitter")
    glow = sphrect.Material(kind="diffuse", base_color=(0.0, 0.0, 0.0))
    clear = sphrect.Material(kind="transparent", base_color=(1.0, 1.0, 1.0))
    emitter = camera_mix(glow, clear, emission=(RADIANCE,) * 3)
    return sphrect.Scene(camera=top_camera(height_above=0.5), meshes=[ground, quad], lights=[],
                         materials=[sphrect.Material(name="ground", base_color=(ALBEDO,) * 3), emitter])


@pytest.mark.parametrize("technique", ["rectangle", "area"])
def test_a_camera_invisible_emitter_lights_the_ground(technique):
    """Light samples and BSDF rays see RADIANCE: the ground's image is the quad's irradiance (Lambert's polygon
    formula) -- the camera looks at the ground from below the quad, through nothing."""
    cam = top_camera(height_above=0.5)
    expected = expected_plane_image(cam, ALBEDO, lambda P: RADIANCE * polygon_irradiance(P, (0, 0, 1), QUAD))
    reps = replicate_images(hidden_emitter_scene(), [technique], 12, 16, mis="balance")
    ok, p_min, alpha = pixel_t_test(reps[technique], expected, FAMILY_ALPHA / 4)
    assert ok, f"{technique}: worst p = {p_min:.3g} < {alpha:.3g}"


def test_the_camera_sees_through_a_camera_invisible_emitter():
    """A camera above the quad looks through it (transparent for camera rays, no emission) at the lit ground; a
    camera ray's emission program reads 0, so the quad adds nothing where it covers the ground."""
    scene = hidden_emitter_scene()
    scene.camera = top_camera(height_above=2.0)
    with_quad = images(scene, samples=8)
    scene.materials[1] = sphrect.Material(kind="transparent", base_color=(1.0, 1.0, 1.0))
    assert with_quad[..., :3].max() > 0
    # Without the emission the ground is black: with it, the ground is lit and nothing of the quad itself is seen
    # (the brightest pixel stays far below RADIANCE, what a visible quad would show).
    assert images(scene, samples=8)[..., :3].max() == 0
    assert with_quad[..., :3].max() < 0.5 * RADIANCE


def test_a_surface_transparent_to_shadow_rays_casts_no_shadow():
    """A diffuse plate between the light and the ground, transparent for shadow rays alone: the ground under it is
    lit as without the plate by the light samples (the BSDF rays, diffuse, are stopped by it as in Cycles): with
    MIS off (light samples alone), the image equals the plate-less one where the camera does not see the plate."""
    plate = sphrect.Mesh(vertices=np.array([[-0.3, -0.3, 0.5], [0.3, -0.3, 0.5], [0.3, 0.3, 0.5], [-0.3, 0.3, 0.5]],
                                           np.float32), triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32),
                         material_ids=np.ones(2, np.int32), name="plate")
    gray = sphrect.Material(kind="diffuse", base_color=(0.5, 0.5, 0.5))
    clear = sphrect.Material(kind="transparent", base_color=(1.0, 1.0, 1.0))

    def render(material):
        scene = lit_plane(sphrect.Material(kind="diffuse", base_color=(0.7, 0.7, 0.7)))
        scene.meshes.append(plate)
        scene.materials.append(material)
        scene.camera = top_camera(height_above=0.2)  # under the plate: it is not seen
        r = sphrect.Renderer(scene, techniques=["rectangle"], seed=3, mis="none")
        assert r.render(4)
        return r.image("rectangle")

    shadowless = render(camera_mix(gray, clear, name="is_shadow_ray"))
    np.testing.assert_array_equal(shadowless, render(clear))
    assert render(gray)[..., :3].mean() < 0.9 * shadowless[..., :3].mean()  # an opaque plate does cast one
