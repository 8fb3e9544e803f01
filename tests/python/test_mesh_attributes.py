"""Mesh attributes and Object Info in node programs (render/svm/attribute_nodes.h): the 'attribute' op interpolates a
mesh's attribute with the hit's barycentrics as Cycles' Attribute / Color Attribute nodes read it, the Object Info and
Parametric globals, the radial tangent; camera rays and light samples read each mesh's own attributes (by name across
materials), the scene file keeps them and older files load without.  Deterministic: exact or float-precision checks."""
import dataclasses

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, save_as_older_version, top_camera

I = sphrect.NodeInstruction
OPS = sphrect.scene
ATTRIBUTE, COLOR_ATTRIBUTE = (OPS.NODE_ATTRIBUTE_NODES.index(n) for n in ("attribute", "color_attribute"))


def attribute_program(names, read=0, node=ATTRIBUTE, output=0):
    """The program reading attribute names[read]'s output `output` (0 colour, 1 fac, 2 alpha) as a colour."""
    code = [I(op="attribute", regs=[0, 1, 2], mode=node, data=read)]
    if output:
        code.append(I(op="convert", regs=[output, 3], mode=OPS.NODE_CONVERSIONS.index("float_to_vector")))
    return sphrect.NodeProgram(instructions=code, output=3 if output else 0, num_registers=4, attributes=list(names))


def evaluate(program, attributes=(), vertices=(0, 1, 2), barycentrics=(1.0, 0.0, 0.0), **kw):
    return np.array(sphrect._native._eval_node_program(dataclasses.asdict(program), (0, 0, 0), (0, 0, 0), (0, 0, 0),
                                                       attributes=list(attributes), vertices=vertices,
                                                       barycentrics=barycentrics, **kw))


VALUES = np.array([[1.0, 0.0, 0.0, 1.0], [0.0, 0.5, 0.0, 0.5], [0.0, 0.0, 0.25, 0.0], [9, 9, 9, 9]], np.float32)


def test_attribute_outputs_interpolate_with_the_barycentrics():
    """Colour, Fac (the mean; the first component for a two-component attribute) and Alpha at barycentrics b of the
    triangle's vertices: sum b_k value_k."""
    b = (0.2, 0.3, 0.5)
    expected = np.array(b) @ VALUES[:3].astype(np.float64)
    np.testing.assert_allclose(evaluate(attribute_program(["c"]), [(VALUES, False)], barycentrics=b), expected[:3],
                               atol=1e-7)
    fac = evaluate(attribute_program(["c"], output=1), [(VALUES, False)], barycentrics=b)
    np.testing.assert_allclose(fac, [expected[:3].mean()] * 3, atol=1e-7)
    fac_x = evaluate(attribute_program(["c"], output=1), [(VALUES, True)], barycentrics=b)
    np.testing.assert_allclose(fac_x, [expected[0]] * 3, atol=1e-7)
    alpha = evaluate(attribute_program(["c"], output=2), [(VALUES, False)], barycentrics=b)
    np.testing.assert_allclose(alpha, [expected[3]] * 3, atol=1e-7)
    # Other vertices of the array: the triangle's own.
    np.testing.assert_allclose(evaluate(attribute_program(["c"]), [(VALUES, False)], vertices=(3, 0, 1)),
                               VALUES[3, :3])


@pytest.mark.parametrize("node,alpha", [(ATTRIBUTE, 1.0), (COLOR_ATTRIBUTE, 0.0)])
def test_a_missing_attribute_reads_as_in_cycles(node, alpha):
    """A mesh without the attribute (none given, or an empty array): colour and fac 0; alpha 1 from the Attribute
    node (svm_node_attr's not-found type), 0 from Color Attribute (svm_node_vertex_color)."""
    for attributes in ([], [(np.zeros((0, 4), np.float32), False)]):
        for output, value in ((0, 0.0), (1, 0.0), (2, alpha)):
            if node == COLOR_ATTRIBUTE and output == 1:
                continue  # Color Attribute has no Fac
            got = evaluate(attribute_program(["x"], node=node, output=output), attributes)
            np.testing.assert_array_equal(got, [value] * 3)


def global_program(name):
    return sphrect.NodeProgram(instructions=[I(op="global", regs=[0], mode=OPS.NODE_GLOBALS.index(name))], output=0,
                               num_registers=1)


def test_object_info_and_parametric_globals():
    """Object Info's location, colour, alpha, index, random from the hit's object (zeros without one); Parametric the
    weights of the triangle's first two vertices (Cycles' (1 - u - v, u, 0)), of Blender's corner order."""
    info = (1.0, 2.0, 3.0, 0.1, 0.2, 0.3, 0.4, 5.0, 0.625)
    expected = {"object_location": info[:3], "object_color": info[3:6], "object_alpha": (info[6], 0, 0),
                "object_index": (info[7], 0, 0), "object_random": (info[8], 0, 0)}
    for name, value in expected.items():
        np.testing.assert_allclose(evaluate(global_program(name), object_info=info), value, rtol=1e-7)
        np.testing.assert_array_equal(evaluate(global_program(name)), [0, 0, 0])
    np.testing.assert_allclose(evaluate(global_program("parametric"), barycentrics=(0.2, 0.3, 0.5)), (0.2, 0.3, 0))
    # A mesh whose triangles list Blender's corners reversed (a mirroring object's): Blender's first corner is the last.
    np.testing.assert_allclose(evaluate(global_program("parametric"), barycentrics=(0.2, 0.3, 0.5),
                                        corners_reversed=True), (0.5, 0.3, 0))


@pytest.mark.parametrize("axis,generated,expected", [
    (2, (0.8, 0.5, 0.1), (0.0, 1.0, 0.0)),   # about Z: (-(y - 1/2), x - 1/2, 0) = (0, 0.3, 0)
    (2, (0.5, 0.2, 0.9), (1.0, 0.0, 0.0)),   # (0.3, 0, 0)
    (1, (0.9, 0.1, 0.5), (0.0, 0.0, 0.0)),   # about Y: (0, 0, 0.4) is along the normal: undefined, zero
    (0, (0.5, 0.5, 0.5), (0.0, 0.0, 0.0))])  # on the axis
def test_radial_tangent(axis, generated, expected):
    """The Tangent node's radial tangent (Geometry's Tangent: about Z), made orthogonal to the normal (0, 0, 1)."""
    program = sphrect.NodeProgram(instructions=[I(op="constant", regs=[0], value=generated),
                                                I(op="radial_tangent", regs=[0, 1], mode=axis)],
                                  output=1, num_registers=2)
    np.testing.assert_allclose(evaluate(program), expected, atol=1e-7)


def quad(x0, name, attributes=None, material=0):
    """A unit square at x in [x0, x0 + 1], y in [-0.5, 0.5], facing up."""
    v = np.array([[x0, -0.5, 0], [x0 + 1, -0.5, 0], [x0 + 1, 0.5, 0], [x0, 0.5, 0]], np.float32)
    return sphrect.Mesh(vertices=v, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name=name,
                        material_ids=np.full(2, material, np.int32), attributes=attributes or {})


def constant_attribute(rgba, n=4):
    return np.tile(np.array(rgba, np.float32), (n, 1))


def glow(program):
    return sphrect.Material(base_color=(0.0, 0.0, 0.0), emission=(1.0, 1.0, 1.0), programs={"emission": program})


def test_camera_rays_read_each_meshes_attributes_by_name():
    """Three emissive quads seen from above: A (material 0 reads 'a') shows its 'a', B (material 1 lists ['b', 'a'],
    reads 'b') its 'b', C (material 0, no 'a') black: the renderer matches names across materials, a mesh lacking
    one reads 0."""
    a, b = (0.2, 0.4, 0.6, 1.0), (0.7, 0.1, 0.3, 1.0)
    scene = sphrect.Scene(
        camera=top_camera(width=30, height=10, half=1.5, height_above=1.0),
        materials=[glow(attribute_program(["a"])), glow(attribute_program(["b", "a"], read=0))],
        meshes=[quad(-1.5, "A", {"a": constant_attribute(a)}, 0),
                quad(-0.5, "B", {"b": constant_attribute(b), "a": constant_attribute(a)}, 1),
                quad(0.5, "C", {"z": constant_attribute(b)}, 0)])
    r = sphrect.Renderer(scene, techniques=["rectangle"], seed=1)
    assert r.render(1)
    img = r.image("rectangle")[..., :3]
    np.testing.assert_allclose(img[:, 1:9], np.broadcast_to(a[:3], img[:, 1:9].shape), rtol=1e-6)
    np.testing.assert_allclose(img[:, 11:19], np.broadcast_to(b[:3], img[:, 11:19].shape), rtol=1e-6)
    np.testing.assert_array_equal(img[:, 21:29], 0)


def test_light_samples_read_the_emitters_attributes():
    """An emissive quad above the ground whose program reads its constant attribute lights the ground as the program
    of that constant does, to float rounding (the interpolated constant; light samples and BSDF rays read the emitter's
    attributes, the same samples)."""
    value = (0.6, 0.3, 0.9, 1.0)

    def scene(program):
        ground = plane_mesh(size=2.0)
        ground.material_ids = np.zeros(2, np.int32)
        lamp = quad(-0.5, "lamp", {"a": constant_attribute(value)}, 1)
        lamp.vertices[:, 2] = 1.0
        lamp.triangles = lamp.triangles[:, ::-1].copy()  # facing down
        return sphrect.Scene(camera=top_camera(height_above=0.5), meshes=[ground, lamp],
                             materials=[sphrect.Material(base_color=(0.5, 0.5, 0.5)), glow(program)])
    constant = sphrect.NodeProgram(instructions=[I(op="constant", regs=[0], value=value[:3])], output=0,
                                   num_registers=1)

    def image(s):
        r = sphrect.Renderer(s, techniques=["rectangle", "area"], seed=5, mis="balance")
        assert r.render(4)
        return r.image("rectangle"), r.image("area")
    for ours, reference in zip(image(scene(attribute_program(["a"]))), image(scene(constant))):
        assert ours[..., :3].max() > 0
        np.testing.assert_allclose(ours, reference, rtol=1e-5)


def test_attributes_and_object_info_are_saved_and_older_files_load(tmp_path):
    scene = sphrect.Scene(camera=top_camera(), materials=[glow(attribute_program(["a"]))],
                          meshes=[quad(0.0, "A", {"a": constant_attribute((0.1, 0.2, 0.3, 0.4)),
                                                  "uv": constant_attribute((0.5, 0.6, 0.0, 1.0))})])
    mesh = scene.meshes[0]
    mesh.attributes_fac_x = ("uv",)
    mesh.object_color, mesh.object_index, mesh.object_random = (0.3, 0.2, 0.1, 0.5), 4, 0.25
    mesh.corners_reversed = True
    path = tmp_path / "a.sphrect.npz"
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    m = loaded.meshes[0]
    assert sorted(m.attributes) == ["a", "uv"] and m.attributes_fac_x == ("uv",)
    for name in m.attributes:
        np.testing.assert_array_equal(m.attributes[name], mesh.attributes[name])
    assert (m.object_color, m.object_index, m.object_random) == ((0.3, 0.2, 0.1, 0.5), 4, 0.25)
    assert m.corners_reversed
    assert loaded.materials[0].programs == scene.materials[0].programs
    old = tmp_path / "old.sphrect.npz"

    def strip(meta):
        for m in meta["meshes"]:
            m.pop("attributes"), m.pop("attributes_fac_x"), m.pop("object_info"), m.pop("corners_reversed")
        for mat in meta["materials"]:
            mat["programs"]["emission"].pop("attributes")
    save_as_older_version(path, old, 18, strip)
    m = sphrect.load_scene(old).meshes[0]
    assert m.attributes == {} and m.object_color == (1.0, 1.0, 1.0, 1.0) and m.object_random == 0.0
    assert not m.corners_reversed


def test_bad_attributes_are_refused():
    scene = sphrect.Scene(camera=top_camera(), materials=[glow(attribute_program(["a"]))],
                          meshes=[quad(0.0, "A", {"a": np.zeros((3, 4), np.float32)})])
    with pytest.raises(ValueError, match="attribute 'a'"):
        sphrect.Renderer(scene)
    scene.meshes[0].attributes = {"a": np.full((4, 4), np.nan, np.float32)}
    with pytest.raises(ValueError, match="attribute 'a'"):
        sphrect.Renderer(scene)
    scene.meshes[0].attributes = {}
    scene.materials[0].programs["emission"].attributes = []
    with pytest.raises(ValueError, match="names none of the program's attributes"):
        sphrect.Renderer(scene)
