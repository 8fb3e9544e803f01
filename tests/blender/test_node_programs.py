"""Node programs (render/svm, exporter/node_program.py): each node's value against Cycles 3.4's, and the compiler.

Per node: a grid of planes facing an orthographic camera, each an Emission whose Color is one case's node output
(its inputs driven by the plane's Generated coordinates, so each pixel is another input), rendered by Cycles with 1
sample, filter width 0.01 px, max bounces 0, Standard view, linear EXR.  The exact point each pixel's ray hit is
read from a second render of the same grid and seed whose Emission is the Generated coordinates themselves (the same
rays: the render is deterministic); the exported program is evaluated there (sphrect._native._eval_node_program)
and compared: max abs difference <= 1e-3 relative to max(1, |value|) (values grow to ~10 in a few cases: exp, tan;
float32 precision).  Deterministic: no statistical tolerance."""
import dataclasses
import math

import bpy
import numpy as np
import pytest

from conftest import addon_module, builders, export, render, set_resolution
from test_texture_export import Tree, material_named, new_image

TOLERANCE = 1e-3
CELL = 16  # pixels per plane side
COLUMNS = 8


def sphrect_module():
    return addon_module("native").load_sphrect()


def render_cycles(scene, path):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.use_adaptive_sampling, c.use_denoising = "CPU", 1, False, False
    c.max_bounces, c.seed, c.filter_width = 0, 0, 0.01
    c.light_sampling_threshold, c.sample_clamp_direct, c.sample_clamp_indirect = 0.0, 0.0, 0.0
    scene.render.film_transparent = False
    scene.view_settings.view_transform, scene.view_settings.look = "Standard", "None"
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return addon_module("images").read_image_rgba(path)  # row 0 = top


class Case:
    """A material whose Emission Color is out(tree, a, b, gx, gy) -- a, b floats in [-1.5, 1.5] from the plane's
    Generated x and y, gx, gy those coordinates -- an output socket."""

    def __init__(self, label, out):
        self.label, self.out = label, out

    def material(self):
        t = Tree(self.label)
        coords = t.node("ShaderNodeTexCoord")
        sep = t.node("ShaderNodeSeparateXYZ")
        t.link(coords.outputs["Generated"], sep.inputs[0])
        a = affine(t, sep.outputs["X"], 3.0, -1.5)
        b = affine(t, sep.outputs["Y"], 3.0, -1.5)
        emission = t.node("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 1.0
        t.link(self.out(t, a, b, sep.outputs["X"], sep.outputs["Y"]), emission.inputs["Color"])
        return t.surface(emission)


def affine(t, socket, scale, offset):
    m = t.node("ShaderNodeMath", operation="MULTIPLY_ADD")
    t.link(socket, m.inputs[0])
    m.inputs[1].default_value, m.inputs[2].default_value = scale, offset
    return m.outputs[0]


def coordinates_material():
    t = Tree("Coordinates")
    emission = t.node("ShaderNodeEmission")
    t.link(t.node("ShaderNodeTexCoord").outputs["Generated"], emission.inputs["Color"])
    return t.surface(emission)


def grid_scene(scene, count):
    """count planes (2 x 2, at the cells of a COLUMNS-wide grid) under an orthographic camera looking down."""
    rows = (count + COLUMNS - 1) // COLUMNS
    planes = []
    for k in range(count):
        bpy.ops.mesh.primitive_plane_add(size=2.0, location=(2.0 * (k % COLUMNS), -2.0 * (k // COLUMNS), 0.0))
        planes.append(bpy.context.active_object)
    cam = bpy.data.objects.new("Top", bpy.data.cameras.new("Top"))
    bpy.context.scene.collection.objects.link(cam)
    cam.data.type, cam.data.ortho_scale, cam.data.sensor_fit = "ORTHO", 2.0 * COLUMNS, "HORIZONTAL"
    cam.location = (COLUMNS - 1.0, -(rows - 1.0), 5.0)
    scene.camera = cam
    set_resolution(scene, CELL * COLUMNS, CELL * rows)
    return planes, rows


def cycles_grid(scene, cases, tmp_path, name="nodes"):
    """The grid of `cases` rendered by Cycles twice with the same rays: (planes, rows, the Generated coordinates each
    pixel's ray hit, the cases' values there); the scene left set for SPHRECT."""
    planes, rows = grid_scene(scene, len(cases))
    coords_material = coordinates_material()
    for p in planes:
        p.data.materials.clear()
        p.data.materials.append(coords_material)
    bpy.context.view_layer.update()
    coordinates = render_cycles(scene, str(tmp_path / "coordinates.exr"))
    for p, case in zip(planes, cases):
        p.data.materials.clear()
        p.data.materials.append(case.material())
    bpy.context.view_layer.update()
    theirs = render_cycles(scene, str(tmp_path / f"{name}.exr"))
    scene.render.engine = "SPHRECT"
    return planes, rows, coordinates, theirs


def cell_hits(k, coordinates):
    """(y, x, Generated g, the plane's local point, its world point) of each pixel of case k's cell, from the
    Generated coordinates each pixel's ray hit (cycles_grid)."""
    row, col = k // COLUMNS, k % COLUMNS
    for j in range(CELL):
        for i in range(CELL):
            y, x = row * CELL + j, col * CELL + i
            g = coordinates[y, x, :3].astype(np.float64)
            local = np.array([2 * g[0] - 1, 2 * g[1] - 1, 0.0])
            yield y, x, g, local, local + np.array([2.0 * col, -2.0 * row, 0.0])


def node_values_against_cycles(scene, cases, tmp_path):
    """Max over cases and pixels of |ours - Cycles| / max(1, |Cycles|) per case label; and the worst."""
    sphrect = sphrect_module()
    planes, rows, coordinates, theirs = cycles_grid(scene, cases, tmp_path)
    exported, log = export()
    images = [(t.pixels, t.colorspace == "srgb") for t in exported.textures]
    # Cycles' camera rays start on the near clipping plane: an orthographic ray's length to the planes (z = 0).
    ray_length = scene.camera.location.z - scene.camera.data.clip_start
    errors = {}
    for k, case in enumerate(cases):
        material = material_named(exported, case.label)
        program = material.programs["emission"]
        fields = dataclasses.asdict(program)
        row, col = k // COLUMNS, k % COLUMNS
        worst = 0.0
        for y, x, g, local, world in cell_hits(k, coordinates):
            ours = np.array(sphrect._native._eval_node_program(fields, tuple(world), (g[0], g[1], 0.0), tuple(g),
                                                               tuple(local), images, ray_length))
            cycles = theirs[y, x, :3].astype(np.float64)
            worst = max(worst, float(np.max(np.abs(ours - cycles) / np.maximum(1.0, np.abs(cycles)))))
        errors[case.label] = worst
        cell = theirs[row * CELL:(row + 1) * CELL, col * CELL:(col + 1) * CELL, :3]
        constant = ("Geometry Normal", "Geometry True Normal", "Geometry Incoming", "Geometry Backfacing",
                    "Texture Coordinate Normal", "Texture Coordinate Reflection",  # on a plane seen orthographically
                    "Normal Normal")  # a constant direction
        assert np.ptp(cell) > 0 or case.label in constant, f"{case.label}: Cycles' image does not vary"
    return errors


def check(errors):
    for label, e in sorted(errors.items(), key=lambda kv: -kv[1]):
        print(f"{label}: {e:.2e}")
    bad = {k: v for k, v in errors.items() if not v <= TOLERANCE}
    assert not bad


def math_case(op):
    def out(t, a, b, gx, gy):
        m = t.node("ShaderNodeMath", operation=op)
        t.link(a, m.inputs[0])
        t.link(b, m.inputs[1])
        m.inputs[2].default_value = 0.3
        return m.outputs[0]
    return Case("Math " + op, out)


MATH_OPS = [item.identifier for item in bpy.types.ShaderNodeMath.bl_rna.properties["operation"].enum_items]
BLENDS = [item.identifier for item in bpy.types.ShaderNodeMixRGB.bl_rna.properties["blend_type"].enum_items]


@pytest.mark.slow
def test_math_matches_cycles(empty_scene, tmp_path):
    check(node_values_against_cycles(empty_scene, [math_case(op) for op in MATH_OPS], tmp_path))


def combine(t, r, g, b=None):
    c = t.node("ShaderNodeCombineXYZ")
    t.link(r, c.inputs[0])
    t.link(g, c.inputs[1])
    if b is not None:
        t.link(b, c.inputs[2])
    else:
        c.inputs[2].default_value = 0.4
    return c.outputs[0]


def mix_rgb_case(blend, clamp):
    def out(t, a, b, gx, gy):
        m = t.node("ShaderNodeMixRGB", blend_type=blend, use_clamp=clamp)
        t.link(affine(t, gx, 1.4, -0.2), m.inputs["Fac"])
        t.link(combine(t, gx, gy), m.inputs["Color1"])
        t.link(combine(t, gy, affine(t, gx, -1.0, 1.0), gx), m.inputs["Color2"])
        return m.outputs[0]
    return Case(f"MixRGB {blend}{' clamp' if clamp else ''}", out)


def mix_case(data_type, blend="MIX", clamp_factor=True, clamp_result=False, factor_mode="UNIFORM"):
    def out(t, a, b, gx, gy):
        m = t.node("ShaderNodeMix", data_type=data_type, blend_type=blend, clamp_factor=clamp_factor,
                   clamp_result=clamp_result)
        if data_type == "VECTOR":
            m.factor_mode = factor_mode
        fac = affine(t, gx, 1.4, -0.2)
        sockets = {s.identifier: s for s in m.inputs}
        if data_type == "VECTOR" and factor_mode == "NON_UNIFORM":
            t.link(combine(t, fac, gy), sockets["Factor_Vector"])
        else:
            t.link(fac, sockets["Factor_Float"])
        suffix = {"RGBA": "Color", "FLOAT": "Float", "VECTOR": "Vector"}[data_type]
        if data_type == "FLOAT":
            t.link(gy, sockets["A_Float"])
            t.link(a, sockets["B_Float"])
        else:
            t.link(combine(t, gx, gy), sockets["A_" + suffix])
            t.link(combine(t, gy, affine(t, gx, -1.0, 1.0), gx), sockets["B_" + suffix])
        return next(s for s in m.outputs if s.identifier == "Result_" + suffix)
    return Case(f"Mix {data_type} {blend} {clamp_factor} {clamp_result} {factor_mode}", out)


@pytest.mark.slow
def test_mix_matches_cycles(empty_scene, tmp_path):
    cases = [mix_rgb_case(b, False) for b in BLENDS] + [mix_rgb_case(b, True) for b in ("ADD", "LINEAR_LIGHT")]
    cases += [mix_case("RGBA", b, clamp_factor=False, clamp_result=b in ("ADD", "DODGE")) for b in BLENDS]
    cases += [mix_case("FLOAT", clamp_factor=c) for c in (True, False)]
    cases += [mix_case("VECTOR", factor_mode=m) for m in ("UNIFORM", "NON_UNIFORM")]
    check(node_values_against_cycles(empty_scene, cases, tmp_path))


def ramp_case(interpolation, color_mode="RGB", hue="NEAR"):
    def out(t, a, b, gx, gy):
        r = t.node("ShaderNodeValToRGB")
        ramp = r.color_ramp
        ramp.interpolation, ramp.color_mode, ramp.hue_interpolation = interpolation, color_mode, hue
        ramp.elements[0].position, ramp.elements[0].color = 0.2, (0.9, 0.1, 0.05, 1.0)
        ramp.elements[1].position, ramp.elements[1].color = 0.85, (0.1, 0.3, 1.0, 0.5)
        mid = ramp.elements.new(0.5)
        mid.color = (0.2, 0.9, 0.3, 0.8)
        t.link(affine(t, gx, 1.2, -0.1), r.inputs["Fac"])
        if interpolation == "LINEAR" and color_mode == "RGB":  # the Alpha output too, through a combine
            return combine(t, r.outputs["Alpha"], gy)
        return r.outputs["Color"]
    return Case(f"ColorRamp {interpolation} {color_mode} {hue}", out)


def converter_cases():
    def invert(t, a, b, gx, gy):
        n = t.node("ShaderNodeInvert")
        t.link(affine(t, gy, 1.5, -0.2), n.inputs["Fac"])
        t.link(combine(t, gx, a), n.inputs["Color"])
        return n.outputs[0]

    def clamp(kind):
        def out(t, a, b, gx, gy):
            n = t.node("ShaderNodeClamp", clamp_type=kind)
            t.link(a, n.inputs["Value"])
            n.inputs["Min"].default_value, n.inputs["Max"].default_value = (-0.4, 0.6) if kind == "MINMAX" else \
                (0.6, -0.4)
            if kind == "RANGE":  # the bounds reversed where b < 0.6
                t.link(b, n.inputs["Max"])
            return n.outputs[0]
        return out

    def map_range(kind, clamp_on):
        def out(t, a, b, gx, gy):
            n = t.node("ShaderNodeMapRange", interpolation_type=kind, clamp=clamp_on)
            t.link(a, n.inputs["Value"])
            n.inputs["From Min"].default_value, n.inputs["From Max"].default_value = -0.8, 1.1
            n.inputs["To Min"].default_value, n.inputs["To Max"].default_value = 0.2, 2.5
            n.inputs["Steps"].default_value = 4.0
            return n.outputs["Result"]
        return out

    def vector_map_range(kind, clamp_on):
        def out(t, a, b, gx, gy):
            n = t.node("ShaderNodeMapRange", data_type="FLOAT_VECTOR", interpolation_type=kind, clamp=clamp_on)
            sockets = {s.identifier: s for s in n.inputs}
            t.link(combine(t, a, b, gx), sockets["Vector"])
            sockets["From_Min_FLOAT3"].default_value = (-0.8, 0.9, 0.3)  # y reversed, z a zero range
            sockets["From_Max_FLOAT3"].default_value = (1.1, -0.7, 0.3)
            sockets["To_Min_FLOAT3"].default_value = (0.2, 1.5, 0.1)
            sockets["To_Max_FLOAT3"].default_value = (2.5, 0.3, 0.9)
            sockets["Steps_FLOAT3"].default_value = (4.0, 3.0, 0.0)
            return n.outputs["Vector"]
        return out

    def separate_combine(sep, comb, model=None):
        def out(t, a, b, gx, gy):
            s = t.node(sep)
            c = t.node(comb)
            if model:
                s.mode = c.mode = model
            t.link(combine(t, gx, gy, affine(t, gx, -0.5, 0.8)), s.inputs[0])
            t.link(s.outputs[2], c.inputs[0])
            t.link(s.outputs[0], c.inputs[1])
            t.link(s.outputs[1], c.inputs[2])
            return c.outputs[0]
        return out

    def rgb_to_bw(t, a, b, gx, gy):
        n = t.node("ShaderNodeRGBToBW")
        t.link(combine(t, gx, gy, affine(t, gx, -0.5, 0.8)), n.inputs[0])
        return n.outputs[0]

    def mapping(kind):
        def out(t, a, b, gx, gy):
            n = t.node("ShaderNodeMapping", vector_type=kind)
            t.link(combine(t, a, b), n.inputs["Vector"])
            n.inputs["Location"].default_value = (0.3, -0.2, 0.1)
            n.inputs["Rotation"].default_value = (0.4, -0.7, 1.1)
            n.inputs["Scale"].default_value = (1.5, 0.5, -2.0)
            return n.outputs[0]
        return out

    def value_rgb(t, a, b, gx, gy):
        v = t.node("ShaderNodeValue")
        v.outputs[0].default_value = 0.37
        c = t.node("ShaderNodeRGB")
        c.outputs[0].default_value = (0.1, 0.6, 0.9, 1.0)
        m = t.node("ShaderNodeMixRGB", blend_type="MULTIPLY")
        t.link(v.outputs[0], m.inputs["Fac"])
        t.link(c.outputs[0], m.inputs["Color1"])
        t.link(combine(t, gx, gy), m.inputs["Color2"])
        return m.outputs[0]

    def coordinate(output):
        def out(t, a, b, gx, gy):
            return t.node("ShaderNodeTexCoord").outputs[output]
        return out

    def geometry(output):
        def out(t, a, b, gx, gy):
            return t.node("ShaderNodeNewGeometry").outputs[output]
        return out

    def uv_map(t, a, b, gx, gy):
        return t.node("ShaderNodeUVMap").outputs[0]

    cases = [Case("Invert", invert), Case("RGB to BW", rgb_to_bw), Case("Value RGB", value_rgb),
             Case("UV Map", uv_map)]
    cases += [Case(f"Clamp {k}", clamp(k)) for k in ("MINMAX", "RANGE")]
    cases += [Case(f"Map Range {k} {c}", map_range(k, c)) for k in ("LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP")
              for c in (True, False)]
    cases += [Case(f"Vector Map Range {k} {c}", vector_map_range(k, c))
              for k in ("LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP") for c in (True, False)]
    cases += [Case("Separate Combine RGB", separate_combine("ShaderNodeSeparateRGB", "ShaderNodeCombineRGB")),
              Case("Separate Combine XYZ", separate_combine("ShaderNodeSeparateXYZ", "ShaderNodeCombineXYZ"))]
    cases += [Case(f"Separate Combine Color {m}", separate_combine("ShaderNodeSeparateColor",
                                                                     "ShaderNodeCombineColor", m))
              for m in ("RGB", "HSV", "HSL")]
    cases += [Case(f"Mapping {k}", mapping(k)) for k in ("POINT", "TEXTURE", "VECTOR", "NORMAL")]
    cases += [Case(f"Texture Coordinate {o}", coordinate(o)) for o in ("Generated", "UV", "Object", "Normal",
                                                                       "Reflection", "Camera", "Window")]
    cases += [Case(f"Geometry {o}", geometry(o)) for o in ("Position", "Normal", "True Normal", "Incoming",
                                                            "Backfacing")]
    return cases


def image_case(interpolation, extension, colorspace, output="Color", projection="FLAT"):
    """An Image Texture of a 5 x 3 image (sRGB bytes, or Non-Color) at Generated mapped to [-0.6, 1.6] (outside the
    image: its extension), through the node's `projection` (Box: the plane's Z face, the camera facing it)."""
    def out(t, a, b, gx, gy):
        name = f"Pixels {colorspace}"
        image = bpy.data.images.get(name)
        if image is None:
            pixels = np.random.default_rng(5).random((3, 5, 4)).astype(np.float32)
            pixels[..., 3] = np.linspace(0.2, 1.0, 15).reshape(3, 5)
            image = new_image(name, pixels, colorspace=colorspace)
        node = t.image(image, interpolation=interpolation, extension=extension, projection=projection,
                       projection_blend=0.3)
        mapping = t.node("ShaderNodeMapping", vector_type="POINT")
        mapping.inputs["Scale"].default_value = (2.2, 2.2, 1.0)
        mapping.inputs["Location"].default_value = (-0.6, -0.6, 0.0)
        t.link(t.nodes["Texture Coordinate"].outputs["Generated"], mapping.inputs["Vector"])
        t.link(mapping.outputs[0], node.inputs["Vector"])
        keep = t.node("ShaderNodeMixRGB", blend_type="MIX")  # factor 0: the image as is, through a program (an image
        keep.inputs["Fac"].default_value = 0.0                 # alone on the emission is a TextureLookup)
        t.link(node.outputs[output], keep.inputs["Color1"])
        return keep.outputs[0]
    return Case(f"Image {interpolation} {extension} {colorspace} {output} {projection}", out)


@pytest.mark.slow
def test_image_texture_matches_cycles(empty_scene, tmp_path):
    cases = [image_case(i, e, c) for i in ("Linear", "Closest") for e in ("REPEAT", "EXTEND", "CLIP")
             for c in ("sRGB", "Non-Color")]
    cases += [image_case("Linear", "REPEAT", "sRGB", "Alpha"), image_case("Cubic", "EXTEND", "Non-Color")]
    cases += [image_case("Linear", "REPEAT", "sRGB", "Color", p) for p in ("SPHERE", "TUBE", "BOX")]
    errors = node_values_against_cycles(empty_scene, cases, tmp_path)
    errors.pop("Image Cubic EXTEND Non-Color Color FLAT")  # Cubic is read as Linear (warned): not compared
    check(errors)


@pytest.mark.slow
def test_color_ramp_and_converters_match_cycles(empty_scene, tmp_path):
    cases = [ramp_case(i) for i in ("LINEAR", "CONSTANT", "EASE", "CARDINAL", "B_SPLINE")]
    cases += [ramp_case("LINEAR", "HSV", h) for h in ("NEAR", "FAR", "CW", "CCW")] + [ramp_case("LINEAR", "HSL")]
    check(node_values_against_cycles(empty_scene, cases + converter_cases(), tmp_path))


# -- procedural textures, shading inputs, colour nodes --------------------------------------------------------------

def texture_case(label, node_type, output, props=None, inputs=None, vector=True, w=True, mapping=None):
    """A texture node at Vector (a, b, a b / 2) (or, vector False, its default: Generated), W from b when it has
    one; `inputs` its input values (a float, or 'a' / 'b' for a link), `mapping` its Texture Mapping settings."""
    def out(t, a, b, gx, gy):
        n = t.node(node_type, **(props or {}))
        if vector:
            ab = t.node("ShaderNodeMath", operation="MULTIPLY")
            t.link(a, ab.inputs[0])
            t.link(b, ab.inputs[1])
            t.link(combine(t, a, b, affine(t, ab.outputs[0], 0.5, 0.0)), n.inputs["Vector"])
        if w and "W" in n.inputs:
            t.link(b, n.inputs["W"])
        for name, value in (inputs or {}).items():
            if value in ("a", "b"):
                t.link(affine(t, {"a": a, "b": b}[value], 0.2, 1.0), n.inputs[name])
            else:
                n.inputs[name].default_value = value
        for key, value in (mapping or {}).items():
            setattr(n.texture_mapping, key, value)
        return n.outputs[output]
    return Case(label, out)


def noise_cases():
    cases = []
    for dims in ("1D", "2D", "3D", "4D"):
        for output in ("Fac", "Color"):
            cases.append(texture_case(f"Noise {dims} {output}", "ShaderNodeTexNoise", output,
                                      {"noise_dimensions": dims}, {"Detail": 3.5, "Distortion": 0.4}))
    cases.append(texture_case("Noise linked settings", "ShaderNodeTexNoise", "Color", None,
                              {"Scale": "a", "Detail": "b", "Roughness": 0.6}))
    cases.append(texture_case("Noise Generated", "ShaderNodeTexNoise", "Fac", vector=False))
    cases.append(texture_case("Noise mapped point", "ShaderNodeTexNoise", "Fac", vector=False,
                              mapping={"translation": (0.3, -0.2, 0.1), "rotation": (0.4, 0.2, 1.1),
                                       "scale": (1.5, 0.7, 2.0)}))
    cases.append(texture_case("Noise mapped texture", "ShaderNodeTexNoise", "Fac", vector=False,
                              mapping={"vector_type": "TEXTURE", "translation": (0.3, -0.2, 0.1),
                                       "rotation": (0.4, 0.2, 1.1), "scale": (1.5, 0.7, 2.0),
                                       "mapping_x": "Y", "mapping_y": "X", "mapping_z": "NONE"}))
    # Vector type: no translation; min / max set: Blender's sync does not pass them on, so Cycles ignores them.
    cases.append(texture_case("Noise mapped vector min max", "ShaderNodeTexNoise", "Fac", vector=False,
                              mapping={"vector_type": "VECTOR", "translation": (0.3, -0.2, 0.1),
                                       "rotation": (0.4, 0.2, 1.1), "scale": (1.5, 0.7, 2.0), "use_min": True,
                                       "use_max": True, "min": (0.5, 0.5, 0.5), "max": (0.6, 0.6, 0.6)}))
    cases.append(texture_case("Noise mapped normal", "ShaderNodeTexNoise", "Fac", vector=False,
                              mapping={"vector_type": "NORMAL", "rotation": (0.4, 0.2, 1.1),
                                       "scale": (1.5, 0.7, 2.0)}))
    return cases


def voronoi_cases():
    cases = []
    for feature in ("F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"):
        for metric in ("EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI"):
            if feature in ("DISTANCE_TO_EDGE", "N_SPHERE_RADIUS") and metric != "EUCLIDEAN":
                continue  # they use the Euclidean distance only
            for dims in ("2D", "3D"):
                outputs = ("Distance", "Color", "Position") if feature in ("F1", "F2", "SMOOTH_F1") else \
                    ("Radius",) if feature == "N_SPHERE_RADIUS" else ("Distance",)
                for output in outputs:
                    cases.append(texture_case(f"Voronoi {dims} {feature} {metric} {output}", "ShaderNodeTexVoronoi",
                                              output, {"voronoi_dimensions": dims, "feature": feature,
                                                       "distance": metric},
                                              {"Scale": 2.5, "Exponent": 1.5, "Randomness": 0.8}))
    for dims in ("1D", "4D"):
        for output in ("Distance", "Color", "W"):
            cases.append(texture_case(f"Voronoi {dims} F1 {output}", "ShaderNodeTexVoronoi", output,
                                      {"voronoi_dimensions": dims}, {"Scale": 2.5}))
    return cases


def musgrave_cases():
    cases = []
    for kind in ("MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HYBRID_MULTIFRACTAL", "FBM", "HETERO_TERRAIN"):
        for dims in ("1D", "2D", "3D", "4D"):
            cases.append(texture_case(f"Musgrave {dims} {kind}", "ShaderNodeTexMusgrave", "Fac",
                                      {"musgrave_dimensions": dims, "musgrave_type": kind},
                                      {"Scale": 2.0, "Detail": 3.5, "Offset": 0.7, "Gain": 1.3}))
    return cases


def other_texture_cases():
    cases = []
    for dims in ("1D", "2D", "3D", "4D"):
        for output in ("Value", "Color"):
            cases.append(texture_case(f"White Noise {dims} {output}", "ShaderNodeTexWhiteNoise", output,
                                      {"noise_dimensions": dims}))
    for kind in ("LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL"):
        cases.append(texture_case(f"Gradient {kind}", "ShaderNodeTexGradient", "Fac", {"gradient_type": kind}))
    cases += [texture_case(f"Checker {o}", "ShaderNodeTexChecker", o, None, {"Scale": 3.0}) for o in ("Color", "Fac")]
    for kind, direction in (("BANDS", "X"), ("BANDS", "DIAGONAL"), ("RINGS", "SPHERICAL"), ("RINGS", "Z")):
        for profile in ("SIN", "SAW", "TRI"):
            props = {"wave_type": kind, "wave_profile": profile,
                     ("bands_direction" if kind == "BANDS" else "rings_direction"): direction}
            cases.append(texture_case(f"Wave {kind} {direction} {profile}", "ShaderNodeTexWave", "Fac", props,
                                      {"Distortion": 2.0, "Detail": 3.0, "Phase Offset": 0.4}))
    for depth in (0, 2, 5):
        cases += [texture_case(f"Magic {depth} {o}", "ShaderNodeTexMagic", o, {"turbulence_depth": depth})
                  for o in ("Color", "Fac")]
    cases += [texture_case(f"Brick {o}", "ShaderNodeTexBrick", o, {"offset": 0.3, "squash": 1.4,
                                                                  "squash_frequency": 3},
                           {"Scale": 2.0, "Mortar Smooth": 0.4, "Bias": 0.2}) for o in ("Color", "Fac")]
    return cases


def node_case(label, node_type, output, props=None, inputs=None):
    """A node whose inputs are `inputs`: name -> a float or tuple, or a function (t, a, b, gx, gy) -> socket."""
    def out(t, a, b, gx, gy):
        n = t.node(node_type, **(props or {}))
        for name, value in (inputs or {}).items():
            socket = next(s for s in n.inputs if s.identifier == name or s.name == name)
            if callable(value):
                t.link(value(t, a, b, gx, gy), socket)
            else:
                socket.default_value = value
        return next(s for s in n.outputs if s.identifier == output or s.name == output)
    return Case(label, out)


def color_of(t, a, b, gx, gy):
    return combine(t, gx, gy, affine(t, gx, -0.6, 0.9))


def tilted_normal(t, a, b, gx, gy):
    n = t.node("ShaderNodeVectorMath", operation="NORMALIZE")
    t.link(combine(t, affine(t, gx, 1.2, -0.6), affine(t, gy, 0.8, -0.4), affine(t, gx, 0.0, 1.0)), n.inputs[0])
    return n.outputs[0]


def curve_case(node_type, value_input, output):
    def out(t, a, b, gx, gy):
        n = t.node(node_type)
        curves = n.mapping.curves
        for curve in list(curves)[:len(curves)]:
            curve.points.new(0.3, 0.7)
        n.mapping.update()
        t.link(affine(t, gx, 1.2, 0.0), n.inputs[0])
        value = color_of(t, a, b, gx, gy) if value_input != "Value" else affine(t, gy, 1.4, -0.2)
        t.link(value, n.inputs[value_input])
        return n.outputs[output]
    return Case(f"Curves {node_type}", out)


def shading_color_cases():
    lin = lambda scale, offset, which="gx": lambda t, a, b, gx, gy: affine(t, {"gx": gx, "gy": gy}[which],  # noqa
                                                                          scale, offset)
    cases = [node_case("Layer Weight Fresnel", "ShaderNodeLayerWeight", "Fresnel", None,
                       {"Blend": lin(1.0, 0.0, "gy"), "Normal": tilted_normal}),
             node_case("Layer Weight Facing", "ShaderNodeLayerWeight", "Facing", None,
                       {"Blend": lin(1.0, 0.0, "gy"), "Normal": tilted_normal}),
             node_case("Fresnel", "ShaderNodeFresnel", "Fac", None,
                       {"IOR": lin(2.0, 1.0, "gy"), "Normal": tilted_normal}),
             node_case("Light Falloff Quadratic", "ShaderNodeLightFalloff", "Quadratic", None,
                       {"Strength": lin(100.0, 1.0), "Smooth": lin(30.0, 0.0, "gy")}),
             node_case("Light Falloff Linear", "ShaderNodeLightFalloff", "Linear", None,
                       {"Strength": lin(1.0, 0.1), "Smooth": lin(30.0, 0.0, "gy")}),
             node_case("Light Falloff Constant", "ShaderNodeLightFalloff", "Constant", None,
                       {"Strength": lin(0.2, 0.01), "Smooth": lin(30.0, 0.0, "gy")}),
             node_case("Blackbody", "ShaderNodeBlackbody", "Color", None, {"Temperature": lin(9000.0, 800.0)}),
             node_case("Wavelength", "ShaderNodeWavelength", "Color", None, {"Wavelength": lin(420.0, 360.0)}),
             node_case("Hue Saturation Value", "ShaderNodeHueSaturation", "Color", None,
                       {"Hue": lin(1.0, 0.0), "Saturation": lin(2.0, 0.0, "gy"), "Value": lin(0.8, 0.6),
                        "Fac": 0.8, "Color": color_of}),
             node_case("Bright Contrast", "ShaderNodeBrightContrast", "Color", None,
                       {"Color": color_of, "Bright": lin(0.6, -0.3, "gy"), "Contrast": lin(1.5, -0.5)}),
             node_case("Gamma", "ShaderNodeGamma", "Color", None, {"Color": color_of, "Gamma": lin(2.5, 0.2, "gy")}),
             curve_case("ShaderNodeRGBCurve", "Color", "Color"),
             curve_case("ShaderNodeVectorCurve", "Vector", "Vector"),
             curve_case("ShaderNodeFloatCurve", "Value", "Value")]

    def normal_node(output):
        def out(t, a, b, gx, gy):
            n = t.node("ShaderNodeNormal")
            n.outputs["Normal"].default_value = (0.3, -0.5, 0.8)
            t.link(tilted_normal(t, a, b, gx, gy) if output == "Dot" else combine(t, a, b), n.inputs["Normal"])
            return n.outputs[output]
        return Case(f"Normal {output}", out)
    cases += [normal_node("Dot"), normal_node("Normal")]
    value_ops = ("DOT_PRODUCT", "DISTANCE", "LENGTH")
    for op in [i.identifier for i in bpy.types.ShaderNodeVectorMath.bl_rna.properties["operation"].enum_items]:
        cases.append(node_case(f"Vector Math {op}", "ShaderNodeVectorMath", "Value" if op in value_ops else "Vector",
                               {"operation": op},
                               {"Vector": lambda t, a, b, gx, gy: combine(t, a, b),
                                "Vector_001": lambda t, a, b, gx, gy: combine(t, b, affine(t, gx, 1.0, 0.3), a),
                                "Vector_002": (0.2, -0.4, 0.7), "Scale": lin(2.0, 0.5, "gy")}))
    for kind in ("AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ"):
        for invert in (False, True):
            cases.append(node_case(f"Vector Rotate {kind} {invert}", "ShaderNodeVectorRotate", "Vector",
                                   {"rotation_type": kind, "invert": invert},
                                   {"Vector": lambda t, a, b, gx, gy: combine(t, a, b), "Center": (0.1, 0.2, -0.3),
                                    "Axis": (0.3, 0.5, 1.0), "Angle": lin(3.0, -1.0, "gy"),
                                    "Rotation": (0.3, -0.6, 1.2)}))
    return cases


@pytest.mark.slow
def test_noise_and_musgrave_textures_match_cycles(empty_scene, tmp_path):
    check(node_values_against_cycles(empty_scene, noise_cases() + musgrave_cases(), tmp_path))


@pytest.mark.slow
def test_voronoi_texture_matches_cycles(empty_scene, tmp_path):
    check(node_values_against_cycles(empty_scene, voronoi_cases(), tmp_path))


@pytest.mark.slow
def test_other_procedural_textures_match_cycles(empty_scene, tmp_path):
    check(node_values_against_cycles(empty_scene, other_texture_cases(), tmp_path))


@pytest.mark.slow
def test_shading_input_and_colour_nodes_match_cycles(empty_scene, tmp_path):
    check(node_values_against_cycles(empty_scene, shading_color_cases(), tmp_path))


# -- the compiler ------------------------------------------------------------------------------------------------

def emission_program(material):
    return material.programs["emission"]


def test_a_shared_sub_graph_is_compiled_once(empty_scene):
    """A Math node read by two paths (both Mix inputs) and a chain of 30 nodes each read twice: each node's
    instructions appear once (paths are 2^30)."""
    t = Tree("Shared")
    coords = t.node("ShaderNodeTexCoord")
    sep = t.node("ShaderNodeSeparateXYZ")
    t.link(coords.outputs["Generated"], sep.inputs[0])
    value = sep.outputs["X"]
    for _ in range(30):
        m = t.node("ShaderNodeMath", operation="ADD")
        t.link(value, m.inputs[0])
        t.link(value, m.inputs[1])
        value = m.outputs[0]
    emission = t.node("ShaderNodeEmission")
    t.link(value, emission.inputs["Color"])
    bpy.ops.mesh.primitive_plane_add()
    bpy.context.active_object.data.materials.append(t.surface(emission))
    exported, log = export()
    program = emission_program(material_named(exported, "Shared"))
    assert sum(i.op == "math" for i in program.instructions) == 30
    assert sum(i.op == "separate" for i in program.instructions) == 1
    # The program doubles Generated x 30 times.
    sphrect = sphrect_module()
    value = sphrect._native._eval_node_program(dataclasses.asdict(program), (0, 0, 0), (0, 0, 0), (1e-8, 0, 0))
    assert value[0] == pytest.approx(1e-8 * 2**30, rel=1e-5)


def test_a_cycle_groups_in_groups_muted_nodes_and_an_unknown_node(empty_scene):
    """A link closing a cycle (Blender marks it invalid: left out), a Math node inside a group inside a group, a
    muted Math node (its first input passed on) and an unknown node (warned, naming it and the value used)."""
    inner = bpy.data.node_groups.new("Inner", "ShaderNodeTree")
    inner.inputs.new("NodeSocketFloat", "x")
    inner.outputs.new("NodeSocketFloat", "y")
    gi, go = inner.nodes.new("NodeGroupInput"), inner.nodes.new("NodeGroupOutput")
    m = inner.nodes.new("ShaderNodeMath")
    m.operation = "MULTIPLY"
    m.inputs[1].default_value = 3.0
    inner.links.new(gi.outputs[0], m.inputs[0])
    inner.links.new(m.outputs[0], go.inputs[0])
    outer = bpy.data.node_groups.new("Outer", "ShaderNodeTree")
    outer.inputs.new("NodeSocketFloat", "x")
    outer.outputs.new("NodeSocketFloat", "y")
    gi, go = outer.nodes.new("NodeGroupInput"), outer.nodes.new("NodeGroupOutput")
    g = outer.nodes.new("ShaderNodeGroup")
    g.node_tree = inner
    outer.links.new(gi.outputs[0], g.inputs[0])
    outer.links.new(g.outputs[0], go.inputs[0])

    t = Tree("Graph")
    coords = t.node("ShaderNodeTexCoord")
    sep = t.node("ShaderNodeSeparateXYZ")
    t.link(coords.outputs["Generated"], sep.inputs[0])
    group = t.node("ShaderNodeGroup")
    group.node_tree = outer
    t.link(sep.outputs["X"], group.inputs[0])
    muted = t.node("ShaderNodeMath", operation="SINE", mute=True)
    t.link(group.outputs[0], muted.inputs[0])
    add = t.node("ShaderNodeMath", operation="ADD")
    t.link(muted.outputs[0], add.inputs[0])
    t.link(add.outputs[0], add.inputs[1])  # closes a cycle: invalid
    unknown = t.node("ShaderNodeTexSky")  # not compiled (yet): its input reads its own value
    bright = t.node("ShaderNodeMath", operation="ADD")
    bright.inputs[0].default_value = 0.25
    t.link(unknown.outputs["Color"], bright.inputs[0])
    t.link(add.outputs[0], bright.inputs[1])
    emission = t.node("ShaderNodeEmission")
    t.link(bright.outputs[0], emission.inputs["Color"])
    bpy.ops.mesh.primitive_plane_add()
    bpy.context.active_object.data.materials.append(t.surface(emission))
    bpy.context.view_layer.update()
    assert not t.mat.node_tree.links[-3].is_valid or not [lk for lk in t.mat.node_tree.links if
                                                         lk.to_node == add and lk.from_node == add][0].is_valid
    exported, log = export()
    program = emission_program(material_named(exported, "Graph"))
    assert [k for k in log.unsupported if "Sky Texture" in k and "own value" in k]
    sphrect = sphrect_module()
    value = sphrect._native._eval_node_program(dataclasses.asdict(program), (0, 0, 0), (0, 0, 0), (0.2, 0, 0))
    # x 3 (the groups), the muted sine passes it on, + 0 (the cycle's input reads its own 0.5), + 0.25 (own value)
    assert value[0] == pytest.approx(3 * 0.2 + 0.5 + 0.25, abs=1e-6)


def test_program_driven_inputs_are_exported_unwarned(empty_scene):
    """Math / ColorRamp / Mix RGB on a Principled BSDF's Base Color, Roughness and Emission: programs, no warning
    about those inputs; a graph of constants folds to the input's constant."""
    t = parity_material(t_name="Driven")
    bpy.ops.mesh.primitive_plane_add()
    bpy.context.active_object.data.materials.append(t)
    exported, log = export()
    m = material_named(exported, "Driven")
    assert set(m.programs) == {"base_color", "roughness", "emission"}
    assert not m.textures
    assert not [k for k in log.unsupported if "linked" in k]


def parity_material(t_name="Lava"):
    """A Principled BSDF whose base colour (Mix RGB of two colours by a ColorRamp of Generated x), roughness (Math of
    Generated y) and emission (ColorRamp) vary over the surface."""
    t = Tree(t_name)
    p = t.node("ShaderNodeBsdfPrincipled")
    coords = t.node("ShaderNodeTexCoord")
    sep = t.node("ShaderNodeSeparateXYZ")
    t.link(coords.outputs["Generated"], sep.inputs[0])
    ramp = t.node("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].position, ramp.color_ramp.elements[0].color = 0.3, (0, 0, 0, 1)
    ramp.color_ramp.elements[1].position, ramp.color_ramp.elements[1].color = 0.7, (1, 1, 1, 1)
    t.link(sep.outputs["X"], ramp.inputs["Fac"])
    mix = t.node("ShaderNodeMixRGB", blend_type="MIX")
    mix.inputs["Color1"].default_value = (0.8, 0.2, 0.05, 1)
    mix.inputs["Color2"].default_value = (0.1, 0.4, 0.8, 1)
    t.link(ramp.outputs["Color"], mix.inputs["Fac"])
    t.link(mix.outputs[0], p.inputs["Base Color"])
    rough = t.node("ShaderNodeMath", operation="MULTIPLY_ADD")
    t.link(sep.outputs["Y"], rough.inputs[0])
    rough.inputs[1].default_value, rough.inputs[2].default_value = 0.8, 0.1
    t.link(rough.outputs[0], p.inputs["Roughness"])
    glow = t.node("ShaderNodeValToRGB")
    glow.color_ramp.elements[0].position, glow.color_ramp.elements[0].color = 0.45, (0, 0, 0, 1)
    glow.color_ramp.elements[1].position, glow.color_ramp.elements[1].color = 0.55, (1.0, 0.35, 0.05, 1)
    t.link(sep.outputs["Y"], glow.inputs["Fac"])
    t.link(glow.outputs["Color"], p.inputs["Emission"])
    p.inputs["Emission Strength"].default_value = 3.0
    return t.surface(p)


def parity_view(scene, light, target=(0.0, 0.0, 0.0)):
    """The parity renders' set-up: a 1 m square light 2 m up (if `light`), the camera looking at `target`, the
    parity tests' resolution, the rectangle technique."""
    from test_cycles_parity import HEIGHT, WIDTH
    if light:
        builders.area_light("Light", "RECTANGLE", size=1.0, size_y=1.0, power=150.0, location=(0.5, 0.0, 2.0),
                            rotation=(0.3, 0.0, 0.0))
    builders.camera((0.0, -3.5, 3.0), target, lens=30.0)
    set_resolution(scene, WIDTH, HEIGHT)
    scene.sphrect.technique = "RECTANGLE"
    bpy.context.view_layer.update()


@pytest.mark.slow
def test_program_material_matches_cycles(empty_scene, tmp_path):
    """A floor of parity_material (base colour, roughness and a glowing stripe from Math / ColorRamp / Mix RGB)
    under a rectangle light: mean relative difference to Cycles (test_cycles_parity's measure) <= 1%."""
    from test_cycles_parity import difference_to_cycles
    scene = empty_scene
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    bpy.context.active_object.data.materials.append(parity_material())
    addon_module("native")
    parity_view(scene, light=True)
    difference, ours, cycles = difference_to_cycles(scene, "node program material", tmp_path)
    assert difference <= 0.01


def textured_glow_material():
    """A Principled floor whose Base Color is a Voronoi cell colour and Roughness a Noise Fac, beside an Emission
    panel whose colour is a Musgrave through a ColorRamp and whose Strength a Light Falloff (Linear): the camera sees
    the glow scaled by its rays' length, from the near clipping plane as in Cycles."""
    t = Tree("Procedural")
    p = t.node("ShaderNodeBsdfPrincipled")
    cells = t.node("ShaderNodeTexVoronoi")
    cells.inputs["Scale"].default_value = 4.0
    t.link(cells.outputs["Color"], p.inputs["Base Color"])
    noise = t.node("ShaderNodeTexNoise")
    t.link(noise.outputs["Fac"], p.inputs["Roughness"])
    floor = t.surface(p)
    g = Tree("Glow")
    emission = g.node("ShaderNodeEmission")
    musgrave = g.node("ShaderNodeTexMusgrave")
    ramp = g.node("ShaderNodeValToRGB")
    ramp.color_ramp.elements[1].color = (1.0, 0.5, 0.1, 1)
    g.link(musgrave.outputs["Fac"], ramp.inputs["Fac"])
    g.link(ramp.outputs["Color"], emission.inputs["Color"])
    falloff = g.node("ShaderNodeLightFalloff")
    falloff.inputs["Strength"].default_value = 1.5
    g.link(falloff.outputs["Linear"], emission.inputs["Strength"])
    return floor, g.surface(emission)


@pytest.mark.slow
def test_procedural_textures_and_light_falloff_render_as_in_cycles(empty_scene, tmp_path):
    """textured_glow_material's floor under a rectangle light, its glowing panel seen by the camera: mean relative
    difference to Cycles (test_cycles_parity's measure) <= 1%, and nothing warned."""
    from test_cycles_parity import difference_to_cycles
    scene = empty_scene
    floor, glow = textured_glow_material()
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    bpy.context.active_object.data.materials.append(floor)
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(0.0, 1.0, 0.6), rotation=(1.2, 0.0, 0.0))
    bpy.context.active_object.data.materials.append(glow)
    parity_view(scene, light=True)
    exported, log = export()
    assert "Procedural" not in log.warning_text() and "Glow" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "procedural textures and light falloff", tmp_path)
    assert difference <= 0.01


def lava_material():
    """Lava cracks: a Mix Shader of a dark Principled BSDF and an orange Emission whose factor is a ColorRamp (Constant
    interpolation: sharp cracks) of a Math wave of Generated x and y; both the factor and the glow's colour vary."""
    t = Tree("Lava")
    coords = t.node("ShaderNodeTexCoord")
    sep = t.node("ShaderNodeSeparateXYZ")
    t.link(coords.outputs["Generated"], sep.inputs[0])
    wave = t.node("ShaderNodeMath", operation="SINE")
    t.link(affine(t, sep.outputs["X"], 9.0, 0.0), wave.inputs[0])
    ripple = t.node("ShaderNodeMath", operation="MULTIPLY_ADD")
    t.link(wave.outputs[0], ripple.inputs[0])
    ripple.inputs[1].default_value = 0.3
    t.link(sep.outputs["Y"], ripple.inputs[2])
    cracks = t.node("ShaderNodeValToRGB")
    ramp = cracks.color_ramp
    ramp.interpolation = "CONSTANT"
    ramp.elements[0].position, ramp.elements[0].color = 0.0, (0, 0, 0, 1)
    ramp.elements[1].position, ramp.elements[1].color = 0.45, (1, 1, 1, 1)
    ramp.elements.new(0.6).color = (0, 0, 0, 1)
    t.link(ripple.outputs[0], cracks.inputs["Fac"])
    rock = t.node("ShaderNodeBsdfPrincipled")
    rock.inputs["Base Color"].default_value = (0.05, 0.04, 0.04, 1)
    rock.inputs["Roughness"].default_value = 0.6
    glow = t.node("ShaderNodeEmission")
    glow.inputs["Strength"].default_value = 8.0
    heat = t.node("ShaderNodeMixRGB", blend_type="MIX")
    heat.inputs["Color1"].default_value = (1.0, 0.15, 0.0, 1)
    heat.inputs["Color2"].default_value = (1.0, 0.6, 0.1, 1)
    t.link(sep.outputs["X"], heat.inputs["Fac"])
    t.link(heat.outputs[0], glow.inputs["Color"])
    mix = t.node("ShaderNodeMixShader")
    t.link(cracks.outputs["Color"], mix.inputs[0])
    t.link(rock.outputs[0], mix.inputs[1])
    t.link(glow.outputs[0], mix.inputs[2])
    return t.surface(mix)


def add_faint_glow(mat):
    """lava_material plus an Add Shader of a second Emission whose Strength a Math node of Generated y drives: two
    varying emissions, summed into one program."""
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    out = nodes["Material Output"]
    mix = out.inputs["Surface"].links[0].from_node
    add, glow = nodes.new("ShaderNodeAddShader"), nodes.new("ShaderNodeEmission")
    glow.inputs["Color"].default_value = (0.2, 0.4, 1.0, 1)
    strength = nodes.new("ShaderNodeMath")
    strength.operation = "MULTIPLY"
    strength.inputs[1].default_value = 1.5
    links.new(nodes["Separate XYZ"].outputs["Y"], strength.inputs[0])
    links.new(strength.outputs[0], glow.inputs["Strength"])
    links.new(mix.outputs[0], add.inputs[0])
    links.new(glow.outputs[0], add.inputs[1])
    links.new(add.outputs[0], out.inputs["Surface"])
    return mat


@pytest.mark.slow
@pytest.mark.parametrize("two_glows", [False, True])
def test_lava_cracks_glow_as_in_cycles(empty_scene, tmp_path, two_glows):
    """The issue's lava: a graph-driven Mix Shader factor keeps the Principled lobe and the emission (a program of the
    glow's colour times the factor), which lights a white floor beside it and is seen by the camera: mean relative
    difference to Cycles <= 1%, no warning; with a second, graph-driven glow added, both summed in one program."""
    from test_cycles_parity import mean_relative_difference
    from test_cycles_parity import render_cycles as parity_cycles
    scene = empty_scene
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0.0, 0.0, 0.6), rotation=(math.radians(60), 0.0, 0.0))
    bpy.context.active_object.data.materials.append(add_faint_glow(lava_material()) if two_glows else lava_material())
    builders.mesh_object("Floor", "plane", builders.material("Floor", (0.8, 0.8, 0.8)), size=6.0)
    parity_view(scene, light=False, target=(0.0, 0.0, 0.3))
    exported, log = export()
    lava = material_named(exported, "Lava")
    assert lava.kind == "mix" and "emission" in lava.programs
    assert all(f.program is not None for layer in lava.layers for f in layer.factors)
    assert "Lava" not in log.warning_text()
    # test_cycles_parity's measure, SPHRECT at 2048 samples: at 512 the emitter's noise alone is 1.6% (two Cycles
    # seeds of 2048 samples differ by 0.49%).
    cycles = parity_cycles(scene, str(tmp_path / "cycles.exr"), samples=2048)
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = 2048, 1, 2
    ours = render()["images"]["rectangle"]
    difference = mean_relative_difference(ours, cycles)
    print(f"lava cracks{' and a second glow' if two_glows else ''}: mean relative difference to Cycles (4x4 "
          f"blocks): {difference:.4f}")
    assert difference <= 0.01


@pytest.mark.slow
def test_a_smooth_emitter_s_graph_reads_its_smooth_normal(empty_scene, tmp_path):
    """A coarse smooth-shaded sphere glowing by Layer Weight Facing (a neon tube's rim) over a floor: Cycles sets up
    the points light samples and BSDF rays find on it with the interpolated normal (shader_setup_from_sample), and
    so does SPHRECT: mean relative difference to Cycles <= 1% (with the flat triangle normal: 3.9%)."""
    from test_cycles_parity import mean_relative_difference
    from test_cycles_parity import render_cycles as parity_cycles
    scene = empty_scene
    t = Tree("Rim")
    emission = t.node("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 12.0
    facing = t.node("ShaderNodeLayerWeight")
    t.link(facing.outputs["Facing"], emission.inputs["Color"])
    bpy.ops.mesh.primitive_uv_sphere_add(segments=8, ring_count=5, radius=0.5, location=(0.0, 0.3, 0.7))
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(t.surface(emission))
    builders.mesh_object("Floor", "plane", builders.material("Floor", (0.8, 0.8, 0.8)), size=6.0)
    parity_view(scene, light=False, target=(0.0, 0.0, 0.3))
    cycles = parity_cycles(scene, str(tmp_path / "cycles.exr"), samples=2048)
    scene.render.engine = "SPHRECT"  # 2048 samples as Cycles': at 512 the small emitter's noise alone is ~0.9%
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = 2048, 1, 2
    difference = mean_relative_difference(render()["images"]["rectangle"], cycles)
    print(f"smooth rim emitter: mean relative difference to Cycles (4x4 blocks): {difference:.4f}")
    assert difference <= 0.01


def gradient_glow():
    """A ColorRamp of a Gradient linked straight into the Material Output's Surface: Cycles' implicit Emission of
    that colour (ShaderGraph::connect inserts it, strength 1)."""
    t = Tree("Implicit")
    ramp = t.node("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.2, 0.05, 0.0, 1)
    ramp.color_ramp.elements[1].color = (4.0, 2.0, 0.5, 1)
    gradient = t.node("ShaderNodeTexGradient")
    t.link(gradient.outputs["Fac"], ramp.inputs["Fac"])
    return t.surface(ramp)


def test_a_colour_or_value_linked_into_a_shader_input_is_an_emission(empty_scene):
    """Cycles inserts an Emission of strength 1 where a colour (its Color) or a value (its Strength, white) meets a
    shader input: a varying colour on the Surface is an emission program, a constant RGB the emission itself, a Value
    under a Mix Shader half of it; nothing warned."""
    glow = gradient_glow()
    t = Tree("RGB")
    rgb = t.node("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.5, 0.25, 2.0, 1.0)
    plain = t.surface(rgb)
    t = Tree("Half")
    mix = t.node("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.5
    value = t.node("ShaderNodeValue")
    value.outputs[0].default_value = 3.0
    t.link(t.node("ShaderNodeBsdfDiffuse").outputs[0], mix.inputs[1])
    t.link(value.outputs[0], mix.inputs[2])
    half = t.surface(mix)
    for i, mat in enumerate((glow, plain, half)):
        builders.mesh_object(f"P{i}", "plane", mat, location=(3 * i, 0, 0))
    exported, log = export()
    assert not any(name in log.warning_text() for name in ("Implicit", "RGB", "Half")), log.warning_text()
    assert "emission" in material_named(exported, "Implicit").programs
    assert np.allclose(material_named(exported, "RGB").emission, (0.5, 0.25, 2.0))
    assert np.allclose(material_named(exported, "Half").emission, (1.5, 1.5, 1.5))


@pytest.mark.slow
def test_an_implicit_emission_glows_as_in_cycles(empty_scene, tmp_path):
    """gradient_glow on a panel lighting a white floor and seen by the camera: mean relative difference to Cycles
    <= 1% (a third-party grass file drew it as a grey diffuse before)."""
    from test_cycles_parity import mean_relative_difference
    from test_cycles_parity import render_cycles as parity_cycles
    scene = empty_scene
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0.0, 0.0, 0.6), rotation=(math.radians(60), 0.0, 0.0))
    bpy.context.active_object.data.materials.append(gradient_glow())
    builders.mesh_object("Floor", "plane", builders.material("Floor", (0.8, 0.8, 0.8)), size=6.0)
    parity_view(scene, light=False, target=(0.0, 0.0, 0.3))
    cycles = parity_cycles(scene, str(tmp_path / "cycles.exr"), samples=2048)
    scene.render.engine = "SPHRECT"
    scene.sphrect.samples, scene.sphrect.passes, scene.sphrect.light_samples = 2048, 1, 2
    difference = mean_relative_difference(render()["images"]["rectangle"], cycles)
    print(f"implicit emission: mean relative difference to Cycles (4x4 blocks): {difference:.4f}")
    assert difference <= 0.01


@pytest.mark.slow
def test_box_and_sphere_projected_images_render_as_in_cycles(empty_scene, tmp_path):
    """A rotated smooth sphere whose Base Color is an image box-projected (blend 0.25: one, two and three faces'
    images blended over its surface) at its Object coordinates, beside a cube whose image is sphere-projected, under
    a rectangle light: mean relative difference to Cycles <= 1%; both drawn flat (the projection ignored) are far."""
    from test_cycles_parity import difference_to_cycles, mean_relative_difference
    pixels = np.random.default_rng(3).random((6, 8, 4)).astype(np.float32)
    pixels[..., 3] = 1.0
    image = new_image("Projected", pixels, colorspace="sRGB")

    def projected(name, projection):
        t = Tree(name)
        bsdf = t.node("ShaderNodeBsdfPrincipled")
        node = t.image(image, interpolation="Closest", projection=projection, projection_blend=0.25)
        t.link(t.node("ShaderNodeTexCoord").outputs["Object"], node.inputs["Vector"])
        t.link(node.outputs["Color"], bsdf.inputs["Base Color"])
        return t.surface(bsdf)
    scene = empty_scene
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(-0.7, 0.0, 0.6), rotation=(0.4, 0.3, 0.2))
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(projected("Box", "BOX"))
    bpy.ops.mesh.primitive_cube_add(size=0.9, location=(0.8, 0.2, 0.45), rotation=(0.0, 0.0, 0.5))
    bpy.context.active_object.data.materials.append(projected("Sphere", "SPHERE"))
    builders.mesh_object("Floor", "plane", builders.material("Floor", (0.8, 0.8, 0.8)), size=6.0)
    parity_view(scene, light=True)
    exported, log = export()
    assert "projection" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "box and sphere projections", tmp_path)
    assert difference <= 0.01
    for name in ("Box", "Sphere"):
        bpy.data.materials[name].node_tree.nodes["Image Texture"].projection = "FLAT"
    scene.render.engine = "SPHRECT"
    assert mean_relative_difference(render()["images"]["rectangle"], cycles) > 0.03


def test_math_helpers_are_the_renderer_names():
    sphrect = sphrect_module()
    assert set(MATH_OPS) == set(sphrect.scene.NODE_MATH_OPS)
    assert set(BLENDS) == set(sphrect.scene.NODE_MIX_BLENDS)
    assert math.isfinite(TOLERANCE)
