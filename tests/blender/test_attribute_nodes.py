"""Nodes reading the mesh and its object (render/svm/attribute_nodes.h, exporter/geometry.corner_attributes): Attribute,
Color Attribute, Object Info, Geometry's Parametric / Tangent / Pointiness / Random Per Island and the Tangent node,
each output against Cycles 3.4's value.

Per case: one or more objects in a cell of a grid seen from above by an orthographic camera, an Emission whose Color
is the node's output, rendered by Cycles with 1 sample, filter width 0.01 px (rays through the pixel centres), max
bounces 0, Standard view, linear EXR.  Each pixel's ray is cast here against the exported triangles (the nearest one
under the pixel centre, its barycentrics) and the exported program evaluated there with the exported mesh's
attributes and Object Info (sphrect._native._eval_node_program): max abs difference <= 1e-3.  A pixel whose centre
lies within 1e-3 of an object's outline (of a triangle's edge, for Parametric) is left out (Cycles' ray may land on
either side).  Deterministic."""
import dataclasses

import bpy
import numpy as np
import pytest

from conftest import builders, export, render, set_resolution
from test_node_programs import render_cycles, sphrect_module
from test_texture_export import Tree

TOLERANCE = 1e-3
CELL = 16  # pixels per 2 m cell
COLUMNS = 6
PROBE = 1e-3  # m: pixels whose centre moved this far hits another object (or none) are left out
RNG = np.random.default_rng(7)


class Case:
    """`build(location)` makes the case's objects in the cell at `location` (returned), their material an Emission
    whose Color is the node output under test; `constant`: Cycles' value does not vary over the cell; `per_triangle`:
    it jumps across triangle edges (pixels on one are left out)."""

    def __init__(self, label, build, constant=False, per_triangle=False):
        self.label, self.build, self.constant, self.per_triangle = label, build, constant, per_triangle


def emission_of(name, out):
    """A material `name` whose Emission Color is out(tree) (an output socket)."""
    t = Tree(name)
    emission = t.node("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    t.link(out(t), emission.inputs["Color"])
    return t.surface(emission)


def half_plus_half(t, socket):
    """0.5 v + 0.5: a vector in [-1, 1] as a non-negative colour."""
    m = t.node("ShaderNodeVectorMath", operation="MULTIPLY_ADD")
    t.link(socket, m.inputs[0])
    m.inputs[1].default_value, m.inputs[2].default_value = (0.5, 0.5, 0.5), (0.5, 0.5, 0.5)
    return m.outputs[0]


def grid(location, material, name="Grid", subdivisions=4):
    """A 1.8 m grid of subdivisions^2 faces (their edges away from the pixel centres)."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=subdivisions, y_subdivisions=subdivisions, size=1.8,
                                    location=location)
    obj = bpy.context.active_object
    obj.name = name
    obj.data.materials.append(material)
    return obj


def random_attribute(mesh, name, data_type, domain, low=0.0, high=1.0):
    """Adds attribute `name` of random values; returns it."""
    if data_type in ("BYTE_COLOR", "FLOAT_COLOR"):
        attribute = mesh.color_attributes.new(name, data_type, domain)
    else:
        attribute = mesh.attributes.new(name, data_type, domain)
    key, width = {"FLOAT": ("value", 1), "FLOAT_VECTOR": ("vector", 3), "BYTE_COLOR": ("color", 4),
                  "FLOAT_COLOR": ("color", 4)}[data_type]
    values = RNG.uniform(low, high, len(attribute.data) * width).astype(np.float32)
    attribute.data.foreach_set(key, values)
    return attribute


def node_output(node_type, output, **props):
    def out(t):
        node = t.node(node_type, **props)
        return node.outputs[output]
    return out


def attribute_case(label, name, data_type, domain, node_type, output, constant=False, **props):
    def build(location):
        obj = grid(location, emission_of(label, node_output(node_type, output, **props)), label)
        if data_type is not None:
            random_attribute(obj.data, name, data_type, domain)
        return [obj]
    return Case(label, build, constant)


def render_color_case():
    """Color Attribute without a name: the mesh's render colour attribute (a point-domain float one, beside a corner
    byte one)."""
    def build(location):
        obj = grid(location, emission_of("Render Color", node_output("ShaderNodeVertexColor", "Color")), "Render")
        random_attribute(obj.data, "Other", "BYTE_COLOR", "CORNER")
        random_attribute(obj.data, "Shown", "FLOAT_COLOR", "POINT")
        names = [a.name for a in obj.data.color_attributes]
        obj.data.color_attributes.render_color_index = names.index("Shown")
        assert obj.data.color_attributes[obj.data.color_attributes.render_color_index].name == "Shown"
        return [obj]
    return Case("Render Color", build)


def named_uv_map_case():
    """A UV Map node naming a map that is not the render one."""
    def build(location):
        obj = grid(location, emission_of("UV Map named", node_output("ShaderNodeUVMap", "UV", uv_map="Second")),
                   "Second UVs")
        layer = obj.data.uv_layers.new(name="Second")
        assert not layer.active_render
        uvs = RNG.uniform(0.0, 1.0, 2 * len(layer.data)).astype(np.float32)
        layer.data.foreach_set("uv", uvs)
        return [obj]
    return Case("UV Map named", build)


def object_property_case():
    def build(location):
        obj = grid(location, emission_of("Object Property", node_output("ShaderNodeAttribute", "Color",
                                                                         attribute_type="OBJECT",
                                                                         attribute_name="tint")), "Tinted")
        obj["tint"] = (0.2, 0.5, 0.9)
        return [obj]
    return Case("Object Property", build, constant=True)


def object_info_case(label, output, transform=None, constant=True):
    """Object Info's `output` on four 0.8 m planes (other names, colours, pass indices) in the cell."""
    def out(t):
        socket = t.node("ShaderNodeObjectInfo").outputs[output]
        return transform(t, socket) if transform else socket
    material = []

    def build(location):
        if not material:
            material.append(emission_of(label, out))
            material[0].pass_index = 7
        objects = []
        for k, (dx, dy) in enumerate(((-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5))):
            bpy.ops.mesh.primitive_plane_add(size=0.8, location=(location[0] + dx, location[1] + dy, 0.0))
            obj = bpy.context.active_object
            obj.name = f"{label} {k}"
            obj.color = tuple(RNG.uniform(0.0, 1.0, 4))
            obj.pass_index = 3 * k + 1
            obj.data.materials.append(material[0])
            objects.append(obj)
        return objects
    return Case(label, build, constant)


def location_scaled(t, socket):
    m = t.node("ShaderNodeVectorMath", operation="MULTIPLY_ADD")
    t.link(socket, m.inputs[0])
    m.inputs[1].default_value, m.inputs[2].default_value = (0.05, 0.05, 0.05), (0.5, 0.5, 0.5)
    return m.outputs[0]


def instance_random_case():
    """Object Info Random of a collection's plane instanced twice (the instances' random_id)."""
    def build(location):
        material = emission_of("Instance Random", node_output("ShaderNodeObjectInfo", "Random"))
        collection = bpy.data.collections.new("Instanced")
        bpy.ops.mesh.primitive_plane_add(size=0.8, location=(100.0, 100.0, 0.0))  # the source, out of view
        source = bpy.context.active_object
        source.data.materials.append(material)
        for c in source.users_collection:
            c.objects.unlink(source)
        collection.objects.link(source)
        collection.instance_offset = (100.0, 100.0, 0.0)
        empties = []
        for k, dx in enumerate((-0.5, 0.5)):
            empty = bpy.data.objects.new(f"Instancer {k}", None)
            empty.instance_type, empty.instance_collection = "COLLECTION", collection
            empty.location = (location[0] + dx, location[1], 0.0)
            bpy.context.scene.collection.objects.link(empty)
            empties.append(empty)
        return empties
    return Case("Instance Random", build, constant=True)


def geometry_case(label, output, transform=None, mesh="grid", per_triangle=False):
    def out(t):
        socket = t.node("ShaderNodeNewGeometry").outputs[output]
        return transform(t, socket) if transform else socket

    def build(location):
        material = emission_of(label, out)
        if mesh in ("grid", "mirrored grid"):
            obj = grid(location, material, label)
            if mesh == "mirrored grid":  # negative scale: the exporter reverses its triangles' corners
                obj.scale = (-1.0, 1.0, 1.0)
            return [obj]
        if mesh == "islands":  # four separate quads of one mesh
            verts, faces = [], []
            for k, (dx, dy) in enumerate(((-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5))):
                verts += [(dx - 0.4, dy - 0.4, 0), (dx + 0.4, dy - 0.4, 0), (dx + 0.4, dy + 0.4, 0),
                          (dx - 0.4, dy + 0.4, 0)]
                faces.append((4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3))
            me = bpy.data.meshes.new(label)
            me.from_pydata(verts, [], faces)
            obj = bpy.data.objects.new(label, me)
            obj.location = location
            bpy.context.scene.collection.objects.link(obj)
        elif mesh == "ico":
            bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.9, location=location)
            obj = bpy.context.active_object
        elif mesh == "split sphere":  # every edge split: each vertex a few co-located ones
            bpy.ops.mesh.primitive_uv_sphere_add(segments=12, ring_count=8, radius=0.9, location=location,
                                                 rotation=(0.4, 0.2, 0.0))
            obj = bpy.context.active_object
            obj.modifiers.new("Split", "EDGE_SPLIT").split_angle = 0.01
        else:  # a turned cube, subdivided (rounded)
            bpy.ops.mesh.primitive_cube_add(size=1.1, location=location, rotation=(0.5, 0.3, 0.2))
            obj = bpy.context.active_object
            subdivide = obj.modifiers.new("Subdivide", "SUBSURF")
            subdivide.levels = subdivide.render_levels = 2
        obj.name = label
        obj.data.materials.append(material)
        return [obj]
    return Case(label, build, per_triangle=per_triangle)


def tangent_case(axis, uv_map=None):
    """The Tangent node, radial about `axis`, or along a UV map (uv_map: its name, '' the render one) of an ico sphere,
    or of a grid's second UV map, the first turned and scaled (on quads whose UVs are not affine Blender's MikkTSpace,
    splitting each quad itself, may differ from Cycles' on the loop triangles)."""
    label = f"Tangent {axis}" if uv_map is None else f"Tangent UV '{uv_map}'"

    def out(t):
        if uv_map is None:
            node = t.node("ShaderNodeTangent", direction_type="RADIAL", axis=axis)
        else:
            node = t.node("ShaderNodeTangent", direction_type="UV_MAP", uv_map=uv_map)
        return half_plus_half(t, node.outputs["Tangent"])

    def build(location):  # a sphere: on a plane facing an axis the radial tangent about it is undefined
        if uv_map:
            obj = grid(location, emission_of(label, out), label)
            layer = obj.data.uv_layers.new(name=uv_map)
            uv = np.empty(2 * len(layer.data), np.float32)
            layer.data.foreach_get("uv", uv)
            turned = uv.reshape(-1, 2) @ np.array([[0.8, 0.6], [-0.6, 0.8]], np.float32).T * 2.0
            layer.data.foreach_set("uv", turned.ravel())
            return [obj]
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.9, location=location)
        obj = bpy.context.active_object
        obj.data.materials.append(emission_of(label, out))
        return [obj]
    return Case(label, build, constant=uv_map == "Second")


def cases():
    a = attribute_case
    return [
        a("Color Attribute bytes", "Col", "BYTE_COLOR", "CORNER", "ShaderNodeVertexColor", "Color", layer_name="Col"),
        a("Color Attribute alpha", "Col", "BYTE_COLOR", "CORNER", "ShaderNodeVertexColor", "Alpha", layer_name="Col"),
        a("Color Attribute point", "Col", "FLOAT_COLOR", "POINT", "ShaderNodeVertexColor", "Color", layer_name="Col"),
        render_color_case(),
        a("Color Attribute missing", None, None, None, "ShaderNodeVertexColor", "Alpha", constant=True,
          layer_name="Nothing"),
        a("Attribute float point", "h", "FLOAT", "POINT", "ShaderNodeAttribute", "Color", attribute_name="h"),
        a("Attribute float face", "h", "FLOAT", "FACE", "ShaderNodeAttribute", "Fac", attribute_name="h"),
        a("Attribute vector face", "v", "FLOAT_VECTOR", "FACE", "ShaderNodeAttribute", "Vector", attribute_name="v"),
        a("Attribute vector Fac", "v", "FLOAT_VECTOR", "POINT", "ShaderNodeAttribute", "Fac", attribute_name="v"),
        a("Attribute colour corner", "c", "BYTE_COLOR", "CORNER", "ShaderNodeAttribute", "Color", attribute_name="c"),
        a("Attribute colour Fac", "c", "FLOAT_COLOR", "CORNER", "ShaderNodeAttribute", "Fac", attribute_name="c"),
        a("Attribute colour Alpha", "c", "BYTE_COLOR", "CORNER", "ShaderNodeAttribute", "Alpha", attribute_name="c"),
        a("Attribute UV Vector", None, None, None, "ShaderNodeAttribute", "Vector", attribute_name="UVMap"),
        a("Attribute UV Fac", None, None, None, "ShaderNodeAttribute", "Fac", attribute_name="UVMap"),
        a("Attribute generated", None, None, None, "ShaderNodeAttribute", "Color", attribute_name="generated"),
        a("Attribute uv Fac", None, None, None, "ShaderNodeAttribute", "Fac", attribute_name="uv"),
        a("Attribute missing Alpha", None, None, None, "ShaderNodeAttribute", "Alpha", constant=True,
          attribute_name="Nothing"),
        a("Attribute missing Color", None, None, None, "ShaderNodeAttribute", "Color", constant=True,
          attribute_name="Nothing"),
        object_property_case(),
        named_uv_map_case(),
        object_info_case("Object Random", "Random"),
        object_info_case("Object Color", "Color"),
        object_info_case("Object Alpha", "Alpha"),
        object_info_case("Object Index", "Object Index", lambda t, s: _scaled(t, s, 0.1)),
        object_info_case("Material Index", "Material Index", lambda t, s: _scaled(t, s, 0.1)),
        object_info_case("Object Location", "Location", location_scaled),
        instance_random_case(),
        geometry_case("Parametric", "Parametric", per_triangle=True),
        geometry_case("Parametric mirrored", "Parametric", mesh="mirrored grid", per_triangle=True),
        geometry_case("Geometry Tangent", "Tangent", half_plus_half),
        tangent_case("X"),
        tangent_case("Y"),
        tangent_case(None, uv_map=""),
        tangent_case(None, uv_map="Second"),
        geometry_case("Random Per Island", "Random Per Island", mesh="islands"),
        geometry_case("Pointiness ico sphere", "Pointiness", mesh="ico"),
        geometry_case("Pointiness split sphere", "Pointiness", mesh="split sphere"),
        geometry_case("Pointiness subdivided cube", "Pointiness", mesh="cube"),
    ]


def _scaled(t, socket, factor):
    m = t.node("ShaderNodeMath", operation="MULTIPLY")
    t.link(socket, m.inputs[0])
    m.inputs[1].default_value = factor
    return m.outputs[0]


def top_view(scene, count):
    rows = (count + COLUMNS - 1) // COLUMNS
    cam = bpy.data.objects.new("Top", bpy.data.cameras.new("Top"))
    scene.collection.objects.link(cam)
    cam.data.type, cam.data.ortho_scale, cam.data.sensor_fit = "ORTHO", 2.0 * COLUMNS, "HORIZONTAL"
    cam.location = (COLUMNS - 1.0, -(rows - 1.0), 10.0)
    scene.camera = cam
    set_resolution(scene, CELL * COLUMNS, CELL * rows)
    return rows


def pixel_centres(scene):
    """(x, y) world coordinates [H, W, 2] of the pixel centres (row 0 at the top)."""
    cam = scene.camera
    w, h = scene.render.resolution_x, scene.render.resolution_y
    size = cam.data.ortho_scale / w
    i, j = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    return np.stack([cam.location.x + (i - w / 2) * size, cam.location.y + (h / 2 - j) * size], axis=-1)


def cast(meshes, x, y):
    """(mesh, triangle, barycentrics (3,), hit point) of the highest triangle under (x, y) (what a ray from above
    finds first), or None."""
    best = None
    for mesh in meshes:
        v = np.asarray(mesh.vertices, np.float64)
        t = np.asarray(mesh.triangles)
        a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
        e1, e2 = b[:, :2] - a[:, :2], c[:, :2] - a[:, :2]
        d = np.array([x, y]) - a[:, :2]
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            b1 = (d[:, 0] * e2[:, 1] - d[:, 1] * e2[:, 0]) / det
            b2 = (e1[:, 0] * d[:, 1] - e1[:, 1] * d[:, 0]) / det
        inside = (det != 0) & (b1 >= 0) & (b2 >= 0) & (b1 + b2 <= 1)
        for k in np.flatnonzero(inside):
            z = a[k, 2] + b1[k] * (b[k, 2] - a[k, 2]) + b2[k] * (c[k, 2] - a[k, 2])
            if best is None or z > best[3][2]:
                best = (mesh, int(k), np.array([1 - b1[k] - b2[k], b1[k], b2[k]]), np.array([x, y, z]))
    return best


def evaluate(sphrect, scene, hit):
    """Our value of the hit's material program (its emission) at hit."""
    mesh, k, bary, p = hit
    tri = [int(i) for i in np.asarray(mesh.triangles)[k]]
    material = scene.materials[int(np.asarray(mesh.material_ids)[k]) if mesh.material_ids is not None else 0]
    program = material.programs["emission"]

    def interpolate(values, width):
        if values is None:
            return (0.0, 0.0, 0.0)
        v = np.asarray(values, np.float64)[tri]
        out = bary @ v
        return tuple(out) + (0.0,) * (3 - width)
    uv, generated = interpolate(mesh.uvs, 2), interpolate(mesh.generated, 3)
    translation = np.array(mesh.object_translation or (0.0, 0.0, 0.0))
    linear = np.array(mesh.object_linear) if mesh.object_linear is not None else np.eye(3)
    local = tuple(np.linalg.solve(linear, p - translation))
    corners = np.asarray(mesh.vertices, np.float64)[tri]
    normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])  # flat shading: the winding's side,
    normal *= np.sign(normal[2]) / np.linalg.norm(normal)                 # facing the camera above
    empty = np.zeros((0, 4), np.float32)
    attributes = [(mesh.attributes.get(name, empty), name in mesh.attributes_fac_x) for name in program.attributes]
    info = (*translation, *mesh.object_color[:3], mesh.object_color[3], float(mesh.object_index),
            float(mesh.object_random))
    return np.array(sphrect._native._eval_node_program(dataclasses.asdict(program), tuple(p), uv, generated, local,
                                                       attributes=attributes, vertices=tri,
                                                       barycentrics=tuple(bary), object_info=info,
                                                       normal=tuple(normal),
                                                       corners_reversed=mesh.corners_reversed))


def values_against_cycles(scene, case_list, tmp_path):
    """Per case label: max abs difference between ours and Cycles' over the cell's pixels."""
    top_view(scene, len(case_list))
    for k, case in enumerate(case_list):
        case.build((2.0 * (k % COLUMNS), -2.0 * (k // COLUMNS), 0.0))
    bpy.context.view_layer.update()
    theirs = render_cycles(scene, str(tmp_path / "nodes.exr"))
    scene.render.engine = "SPHRECT"
    exported, log = export()
    sphrect = sphrect_module()
    centres = pixel_centres(scene)
    errors, skipped = {}, 0
    for k, case in enumerate(case_list):
        row, col = k // COLUMNS, k % COLUMNS
        cx, cy = 2.0 * col, -2.0 * row
        meshes = [m for m in exported.meshes if np.all(np.abs(np.asarray(m.vertices)[:, :2].mean(axis=0)
                                                              - (cx, cy)) < 1.0)]
        worst = 0.0
        for j in range(row * CELL, (row + 1) * CELL):
            for i in range(col * CELL, (col + 1) * CELL):
                x, y = centres[j, i]
                hit = cast(meshes, x, y)
                probes = [cast(meshes, x + dx, y + dy)
                          for dx, dy in ((PROBE, 0), (-PROBE, 0), (0, PROBE), (0, -PROBE))]
                if any((h is None) != (hit is None) or (h is not None and h[0] is not hit[0]) or
                       (case.per_triangle and h is not None and h[1] != hit[1]) for h in probes):
                    skipped += 1
                    continue
                ours = np.zeros(3) if hit is None else evaluate(sphrect, exported, hit)
                worst = max(worst, float(np.max(np.abs(ours - theirs[j, i, :3]))))
        errors[case.label] = worst
        cell = theirs[row * CELL:(row + 1) * CELL, col * CELL:(col + 1) * CELL, :3]
        if not case.constant:
            inner = cell[4:-4, 4:-4]
            assert np.ptp(inner) > 1e-4, f"{case.label}: Cycles' image does not vary"
    assert skipped < 0.05 * centres.shape[0] * centres.shape[1]
    return errors, log, theirs


def test_attribute_and_object_nodes_match_cycles(empty_scene, tmp_path):
    """Every case's max abs difference to Cycles <= 1e-3; no warning about the nodes (a missing attribute is
    warned, as the value it reads)."""
    errors, log, _ = values_against_cycles(empty_scene, cases(), tmp_path)
    for label, e in sorted(errors.items(), key=lambda kv: -kv[1]):
        print(f"{label}: {e:.2e}")
    assert not {k: v for k, v in errors.items() if not v <= TOLERANCE}
    text = log.warning_text()
    assert "Object Info" not in text and "Attribute' node" not in text and "Tangent" not in text


def random_tint_material():
    """A Principled BSDF whose Base Color multiplies the mesh's colour attribute 'Paint' by a ColorRamp of Object Info
    > Random (each object another hue)."""
    t = Tree("Random Tint")
    p = t.node("ShaderNodeBsdfPrincipled")
    ramp = t.node("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.9, 0.2, 0.1, 1)
    ramp.color_ramp.elements[1].color = (0.1, 0.4, 0.9, 1)
    t.link(t.node("ShaderNodeObjectInfo").outputs["Random"], ramp.inputs["Fac"])
    mix = t.node("ShaderNodeMixRGB", blend_type="MULTIPLY")
    mix.inputs["Fac"].default_value = 1.0
    t.link(ramp.outputs["Color"], mix.inputs["Color1"])
    t.link(t.node("ShaderNodeVertexColor", layer_name="Paint").outputs["Color"], mix.inputs["Color2"])
    t.link(mix.outputs["Color"], p.inputs["Base Color"])
    return t.surface(p), t


@pytest.mark.slow
def test_object_random_and_colour_attribute_render_as_in_cycles(empty_scene, tmp_path):
    """Six tiles on a dark floor, one material (Object Info Random through a ColorRamp times a corner colour attribute
    on the Principled Base Color) under a rectangle light: mean relative difference to Cycles (test_cycles_parity's
    measure) <= 1%; the same material with both nodes unlinked (their inputs' own values, what the exporter used
    before) is clearly further (> 5%)."""
    from test_cycles_parity import difference_to_cycles, mean_relative_difference
    from test_node_programs import parity_view
    scene = empty_scene
    material, tree = random_tint_material()
    bpy.ops.mesh.primitive_plane_add(size=4.0, location=(0.0, 0.0, -0.01))
    bpy.context.active_object.data.materials.append(builders.material("Floor", (0.05, 0.05, 0.05)))
    for k in range(6):
        bpy.ops.mesh.primitive_grid_add(x_subdivisions=3, y_subdivisions=3, size=0.9,
                                        location=(-1.0 + (k % 3), -0.5 + (k // 3), 0.0))
        obj = bpy.context.active_object
        obj.name = f"Tile {k}"
        random_attribute(obj.data, "Paint", "BYTE_COLOR", "CORNER", low=0.3, high=1.0)
        obj.data.materials.append(material)
    parity_view(scene, light=True)
    exported, log = export()
    assert "Random Tint" not in log.warning_text()
    difference, ours, cycles = difference_to_cycles(scene, "object random and colour attribute", tmp_path)
    assert difference <= 0.01
    for link in list(tree.links):
        if link.from_node.bl_idname in ("ShaderNodeObjectInfo", "ShaderNodeVertexColor"):
            tree.links.remove(link)
    scene.render.engine = "SPHRECT"
    without = render()["images"]["rectangle"]
    further = mean_relative_difference(without, cycles)
    print(f"without the nodes: {further:.4f}")
    assert further > 0.05


def test_only_what_programs_read_is_exported(empty_scene):
    """A mesh gets the attributes its materials' programs read (per corner: unwelded), a mesh whose material reads
    none keeps its welded vertices and no attributes; Object Info fields only where a program reads them (random
    from the object's name); a missing attribute and an Attribute node of type View Layer are warned."""
    def reads(name, out):
        return emission_of(name, out)
    attribute = reads("Reads a", node_output("ShaderNodeAttribute", "Color", attribute_name="a"))
    plain = builders.material("Plain", (0.5, 0.5, 0.5))
    info = reads("Reads random", node_output("ShaderNodeObjectInfo", "Random"))
    missing = reads("Reads missing", node_output("ShaderNodeAttribute", "Fac", attribute_name="missing"))
    view_layer = reads("View layer", node_output("ShaderNodeAttribute", "Fac", attribute_type="VIEW_LAYER",
                                                 attribute_name="x"))
    objects = {}
    for k, (name, material) in enumerate((("P", attribute), ("Q", plain), ("R", info), ("S", missing),
                                          ("T", view_layer))):
        obj = grid((3.0 * k, 0.0, 0.0), material, name)
        random_attribute(obj.data, "a", "FLOAT", "POINT")
        random_attribute(obj.data, "b", "BYTE_COLOR", "CORNER")
        obj.color = (0.1, 0.2, 0.3, 0.4)
        objects[name] = obj
    exported, log = export()
    meshes = {m.name: m for m in exported.meshes}
    assert set(meshes["P"].attributes) == {"a"}
    assert len(meshes["P"].vertices) == 3 * len(meshes["P"].triangles)  # per corner
    assert meshes["Q"].attributes == {} and len(meshes["Q"].vertices) == len(objects["Q"].data.vertices)
    assert meshes["P"].object_random == 0.0 and meshes["P"].object_color == (1.0, 1.0, 1.0, 1.0)
    r = meshes["R"]
    assert r.object_random == pytest.approx(sphrect_module()._native._object_random("R"), abs=0)
    assert 0 < r.object_random < 1 and r.object_color == pytest.approx((0.1, 0.2, 0.3, 0.4))
    text = log.warning_text()
    assert "attribute 'missing' a node reads, which the mesh lacks" in text
    assert "'Attribute' node of type View Layer" in text
    assert "Reads a" not in text and "Reads random" not in text
