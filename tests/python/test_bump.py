"""Bump node programs (op 'bump', Material.normal_program): the op against its closed form, and a bump-driven
shading normal rendering as the normal map of the same normal does (both replace the shading normal, with Cycles'
bump shadowing of the diffuse lobes).  The Cycles comparisons are tests/blender/test_bump.py."""
import dataclasses

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, save_as_older_version, top_camera
from sphrect.render import build_native_scene

I = sphrect.NodeInstruction
OPS = sphrect.scene
# Cycles' make_orthonormals(+z): the directions of a Bump's dx and dy copies on a plane facing +z.
DX, DY = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0), np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)


def slope_program(slope, strength=1.0, distance=1.0, invert=False):
    """A Bump of height slope * (Geometry Position x), the shading normal its Normal."""
    position, normal = OPS.NODE_GLOBALS.index("position"), OPS.NODE_GLOBALS.index("normal")
    code = [I(op="global", regs=[k], mode=position, flags=k) for k in range(3)]
    code += [I(op="separate", regs=[k, 3 + k, -1, -1]) for k in range(3)]
    code += [I(op="constant", regs=[6], value=(slope, 0, 0)), I(op="constant", regs=[7], value=(0, 0, 0))]
    multiply = OPS.NODE_MATH_OPS.index("MULTIPLY")
    code += [I(op="math", regs=[3 + k, 6, 7, 8 + k], mode=multiply) for k in range(3)]
    code += [I(op="constant", regs=[11], value=(strength, 0, 0)), I(op="constant", regs=[12], value=(distance, 0, 0)),
             I(op="global", regs=[13], mode=normal), I(op="bump", regs=[8, 9, 10, 11, 12, 13, 14], flags=int(invert))]
    return sphrect.NodeProgram(instructions=code, output=14, num_registers=15)


def evaluate(program, p=(0.2, -0.1, 0.0), dP=0.01):
    p = np.array(p)
    shifts = [tuple(tuple(v) for v in (p + o, (p + o) * [1, 1, 0], p + o, p + o)) for o in (dP * DX, dP * DY)]
    return np.array(sphrect._native._eval_node_program(dataclasses.asdict(program), tuple(p), tuple(p), tuple(p),
                                                       dP=dP, shifts=shifts))


def test_the_bump_op_tilts_the_normal_against_the_height_gradient():
    """A height rising along x by `slope` gives normalize(-distance slope, 0, 1) whatever dP (a linear height's
    differences scale with it), its reverse inverted; strength blends with the normal; without a ray differential
    (dP = 0: light samples' hits) the normal is kept, as Cycles does."""
    tilted = np.array([-0.3, 0.0, 1.0]) / np.hypot(0.3, 1.0)
    np.testing.assert_allclose(evaluate(slope_program(0.6, distance=0.5)), tilted, atol=2e-4)
    np.testing.assert_allclose(evaluate(slope_program(0.6, distance=0.5), dP=1e-3), tilted, atol=2e-3)
    np.testing.assert_allclose(evaluate(slope_program(0.6, distance=0.5, invert=True)), tilted * [-1, 1, 1],
                               atol=2e-4)
    half = 0.5 * tilted + 0.5 * np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(evaluate(slope_program(0.6, strength=0.5, distance=0.5)), half / np.linalg.norm(half),
                               atol=2e-4)
    np.testing.assert_allclose(evaluate(slope_program(0.6, distance=0.5), dP=0.0), [0.0, 0.0, 1.0], atol=1e-7)


def lit_plane(**material):
    ground = plane_mesh(size=2.0)
    ground.uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    light = sphrect.RectLight(corner=(-0.5, -0.4, 1.0), edge_x=(0.0, 0.9, 0.0), edge_y=(1.1, 0.0, 0.0),
                              radiance=(2.0,) * 3)
    pixel = np.array([[[0.365, 0.5, 0.95]]], np.float32)  # 2 c - 1 = 0.9 (-0.3, 0, 1): normalize(-0.3, 0, 1)
    return sphrect.Scene(camera=top_camera(width=16, height=16, height_above=0.5), meshes=[ground], lights=[light],
                         materials=[sphrect.Material(**material)],
                         textures=[sphrect.Texture(name="n", colorspace="linear", pixels=pixel)])


def images(scene, samples=4):
    r = sphrect.Renderer(scene, techniques=["rectangle"], seed=3)
    assert r.render(samples)
    return r.image("rectangle")


@pytest.mark.parametrize("kind", ["diffuse", "principled"])
def test_a_bumped_plane_renders_as_the_normal_map_of_its_normal(kind):
    """The slope bump's constant normal normalize(-0.3, 0, 1) and a one-pixel tangent-space normal map of the same
    normal give the same image (same samples: both replace the shading normal before anything is sampled), unlike
    the flat plane's."""
    inputs = dict(kind=kind, base_color=(0.7, 0.6, 0.5), roughness=0.4)
    bumped = images(lit_plane(**inputs, normal_program=slope_program(0.6, distance=0.5)))
    mapped = images(lit_plane(**inputs, normal_map=sphrect.TextureLookup(texture=0)))
    flat = images(lit_plane(**inputs))
    np.testing.assert_allclose(bumped, mapped, rtol=2e-3, atol=1e-6)
    assert np.abs(flat - mapped)[..., :3].max() > 0.1 * mapped[..., :3].max()


def test_normal_programs_are_saved_and_older_files_load(tmp_path):
    scene = lit_plane(kind="diffuse", normal_program=slope_program(0.6))
    path = tmp_path / "b.sphrect.npz"
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert loaded.materials[0].normal_program == scene.materials[0].normal_program
    np.testing.assert_array_equal(images(scene), images(loaded))
    old = tmp_path / "old.sphrect.npz"
    save_as_older_version(path, old, 18, lambda meta: [m.pop("normal_program") for m in meta["materials"]])
    assert sphrect.load_scene(old).materials[0].normal_program is None


def test_bad_normal_programs_are_refused():
    def refused(match, **material):
        with pytest.raises(ValueError, match=match):
            build_native_scene(lit_plane(kind="diffuse", **material))
    refused("normal map or a normal program", normal_program=slope_program(1.0),
            normal_map=sphrect.TextureLookup(texture=0))
    program = slope_program(1.0)
    program.instructions[1] = dataclasses.replace(program.instructions[1], flags=3)
    refused("flags out of range", normal_program=program)
    mix = sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(
        weight=1.0, material=sphrect.Material(kind="diffuse", normal_program=slope_program(1.0)))])
    with pytest.raises(ValueError, match="normal map of its own"):
        build_native_scene(dataclasses.replace(lit_plane(kind="diffuse"), materials=[mix]))


def test_programs_read_the_normal_before_the_bump():
    """Geometry Normal (Cycles' sd->N) is the shading normal before a Bump replaced it for the closures: an emission
    of the normal on a bumped plane seen from above shows (0, 0, 1), not the tilted normal."""
    normal = sphrect.NodeProgram(instructions=[I(op="global", regs=[0], mode=OPS.NODE_GLOBALS.index("normal"))],
                                 output=0, num_registers=1)
    scene = lit_plane(kind="diffuse", base_color=(0.0, 0.0, 0.0), emission=(1.0, 1.0, 1.0),
                      programs={"emission": normal}, normal_program=slope_program(0.6, distance=0.5))
    scene.lights = []
    np.testing.assert_allclose(images(scene, samples=1)[..., :3], np.broadcast_to([0.0, 0.0, 1.0], (16, 16, 3)),
                               atol=1e-6)
