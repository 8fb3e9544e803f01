"""A material input's shader node graph -> sphrect.NodeProgram, as Cycles 3.4 compiles a graph into SVM code
(scene/svm.cpp, each node's compile in scene/shader_nodes.cpp) for the renderer to run per hit (render/svm/).

The compiler walks the graph behind one input along the links Cycles follows (node_groups.py: reroutes, muted nodes,
groups, invalid links left out), depth first from the input, and emits each node's instructions once, after those
of the nodes it reads -- however many paths reach it (a shared sub-graph is one set of instructions; a graph of n
nodes compiles in O(n)).  Every node output gets a register (three floats); a link between sockets of different
types converts as Cycles' svm_node_convert does (a colour to a float by its luminance, a vector by its mean, a float
to a colour or vector by repeating it).  An unlinked input is a constant instruction of its own value.

A node the compiler does not know is warned, naming it and the value used instead: the input it feeds reads its
own value, as before programs existed.  Adding a node: an entry in _NODE_COMPILERS (bl_idname -> a function of the
compiler and the node returning its outputs' registers), emitting the op that render/svm/program.h defines for it
(a new op there: its NodeOp, kNodeOpNames entry and evaluate.cpp case).  Node families other helpers add
(procedural textures, shading inputs, colour nodes) go in the marked place at the end of this file."""
import dataclasses

import numpy as np

from .node_groups import own_value
from .textures import follow_reroutes

# The renderer's value types: 'float' (a register's x), 'color' and 'vector' (its three floats).
_SOCKET_TYPES = {"VALUE": "float", "INT": "float", "BOOLEAN": "float", "RGBA": "color", "VECTOR": "vector"}
# Names in NodeProgram.attributes besides a mesh's own attributes (the exporter's geometry.corner_attributes): those
# Cycles computes from the mesh (its standard ones, which an Attribute node of the name reads too), the one a Color
# Attribute node without a name reads (the mesh's render colour attribute), an Attribute node of type Object's.
POINTINESS, RANDOM_PER_ISLAND, RENDER_COLOR = "pointiness", "random_per_island", ""
OBJECT_ATTRIBUTE_PREFIX = "object:"  # + the name of the object's custom property
UV_TANGENT_PREFIX = "tangent:"  # + a UV map's name ('': the render one): its tangents, in object space
# Cycles' RAMP_TABLE_SIZE: a ColorRamp is baked into this many evenly spaced colours (blender/shader.cpp).
RAMP_TABLE_SIZE = 256


class NotCompiled(Exception):
    """A node output the compiler cannot give (the message names it and why)."""


def socket_type(socket):
    return _SOCKET_TYPES.get(socket.type, "float")


class ProgramCompiler:
    """Compiles inputs of one material's node graph (compile); the images its Image Texture nodes read go to
    `textures` (a TextureExport); `log` and `owner` for warnings."""

    def __init__(self, sphrect, textures, log, owner):
        self.sphrect, self.textures, self.log, self.owner = sphrect, textures, log, owner
        self.names = sphrect.scene

    def compile(self, socket, want=None):
        """The NodeProgram of input `socket` (wrapped), its result of type `want` (default: the socket's own), or
        None past MAX_NODE_REGISTERS (warned); unknown nodes on the way are warned, their inputs' own values used."""
        def body():
            reg, kind = self.input(socket)
            return self._convert(reg, kind, want or socket_type(socket))
        return self._program(body, f"'{socket.name}'")

    def compile_displaced_normal(self):
        """The program of the shading normal the material's displacement bumps (displaced_normal), or None past
        MAX_NODE_REGISTERS (warned)."""
        return self._program(self.displaced_normal, "a displacement")

    def compile_product(self, color_socket, strength_socket):
        """The program of colour x strength (an emission's), or None past MAX_NODE_REGISTERS (warned)."""
        def body():
            color, strength = self.input(color_socket, "color")[0], self.input(strength_socket, "float")[0]
            return self.emit("scale", [color, strength], 1)[0]
        return self._program(body, "an emission")

    def _program(self, body, what):
        """The NodeProgram whose instructions body() emits, returning its result's register."""
        self._code, self._data, self._outputs, self._constants, self._visiting = [], [], {}, {}, set()
        self._registers, self._attributes = 0, []
        # A Bump node's Height is compiled three times (Cycles' refine_bump_nodes copies its sub-graph): _shift 0 at
        # the point, 1 and 2 with the position-dependent globals read at P + dx and P + dy.  An instruction of a copy
        # equal to one before it (inputs, settings, table: it reads nothing that moved) is that one (_emitted), so
        # what does not depend on the position stays one copy.
        self._shift, self._emitted, self._tables, self._copies = 0, {}, {}, {}
        self._displacing = False
        try:
            output = body()
        except _TooManyRegisters:
            self.log.unsupported_feature(f"a node graph needing more than {self.names.MAX_NODE_REGISTERS} values on "
                                         f"{what} (its own value used)", self.owner)
            return None
        return self.sphrect.NodeProgram(instructions=self._without_unread_copies(output), output=output,
                                        num_registers=self._registers, data=self._data, attributes=self._attributes)

    def _without_unread_copies(self, output):
        """The code less the Height copies' instructions whose results nothing reads (a copied Geometry node's
        other outputs)."""
        if not self._copies:
            return self._code
        read, kept = {output}, []
        for k in range(len(self._code) - 1, -1, -1):
            i = self._code[k]
            if k in self._copies and not any(r in read for r in i.regs[len(i.regs) - self._copies[k]:]):
                continue
            read.update(i.regs)  # its inputs (and its own outputs: harmless)
            kept.append(i)
        return kept[::-1]

    # -- building blocks ------------------------------------------------------------------------------------------

    def register(self):
        if self._registers >= self.names.MAX_NODE_REGISTERS:
            raise _TooManyRegisters()
        self._registers += 1
        return self._registers - 1

    def emit(self, op, inputs, outputs, mode=0, flags=0, data=0, size=0, value=(0.0, 0.0, 0.0)):
        """Appends an instruction; `outputs` registers are allocated here (a count), returned as a list."""
        key = (op, tuple(inputs), outputs, int(mode), int(flags), int(data), int(size), tuple(map(float, value)))
        if self._shift and key in self._emitted:
            return self._emitted[key]
        out = [self.register() for _ in range(outputs)]
        self._emitted[key] = out
        if self._shift:
            self._copies[len(self._code)] = outputs
        self._code.append(self.sphrect.NodeInstruction(op=op, regs=list(inputs) + out, mode=int(mode),
                                                       flags=int(flags), data=int(data), size=int(size),
                                                       value=tuple(float(v) for v in value)))
        return out

    def constant(self, value, kind):
        """A register holding `value` (a float, or three floats), shared by equal constants."""
        v = (float(value),) * 3 if np.ndim(value) == 0 else tuple(float(x) for x in list(value)[:3])
        if kind == "float":
            v = (v[0], 0.0, 0.0)
        if v not in self._constants:
            self._constants[v] = self.emit("constant", [], 1, value=v)[0]
        return self._constants[v]

    def global_input(self, name):
        """A register holding the hit's input `name` (one of NODE_GLOBALS), read once per program; the shading normal
        bumped by the material's displacement where it has one (displaced_normal)."""
        if name == "normal" and self.textures.displacement is not None and not self._displacing:
            return self.displaced_normal()
        shift = self._shift if name in self.sphrect._native.node_shifted_globals else 0
        key = ("global", name, shift)
        if key not in self._outputs:
            self._outputs[key] = self.emit("global", [], 1, mode=self.names.NODE_GLOBALS.index(name), flags=shift)[0]
        return self._outputs[key]

    def displaced_normal(self):
        """Cycles' automatic bump of a material's Displacement ('Bump Only', 3.4's default: ShaderGraph::
        bump_from_displacement): a Bump of distance and strength 1 on the shading normal whose heights are the
        displacement vector's component along that normal at P, P + dx and P + dy; it replaces the shading normal
        of every closure and of every graph reading it (SetNormal)."""
        key = ("displaced normal",)
        if key not in self._outputs:
            socket = self.textures.displacement
            saved, self._displacing = self._displacing, True
            try:
                normal = self.global_input("normal")
                one = self.constant(1.0, "float")
                dot = list(self.sphrect._native.node_vector_math_ops).index("DOT_PRODUCT")
                heights = [self.emit("vector_math", [self.shifted_input(socket, shift, "vector"), normal, normal, one],
                                     2, mode=dot)[1] for shift in (0, 1, 2)]
                self._outputs[key] = self.emit("bump", heights + [one, one, normal], 1)[0]
            finally:
                self._displacing = saved
        return self._outputs[key]

    def shifted_input(self, socket, shift, want=None):
        """The register of input(socket, want) with the hit's position moved as copy `shift` of a Bump's Height."""
        saved, self._shift = self._shift, shift
        try:
            return self.input(socket, want)[0]
        finally:
            self._shift = saved

    def attribute(self, name, node="attribute"):
        """{'color', 'fac', 'alpha'}: registers of the hit mesh's attribute `name` (sphrect.Mesh.attributes) as
        Cycles' Attribute node (`node` 'attribute') or Color Attribute node ('color_attribute') reads it, once per
        program."""
        key = ("attribute", name, node)
        if key not in self._outputs:
            if name not in self._attributes:
                self._attributes.append(name)
            regs = self.emit("attribute", [], 3, mode=self.names.NODE_ATTRIBUTE_NODES.index(node),
                             data=self._attributes.index(name))
            self._outputs[key] = dict(zip(("color", "fac", "alpha"), regs))
        return self._outputs[key]

    def table(self, values):
        """Offset of `values` in the program's data (appended, or where equal values already are)."""
        values = tuple(float(v) for v in values)
        if values not in self._tables:
            self._tables[values] = len(self._data)
            self._data.extend(values)
        return self._tables[values]

    def _convert(self, reg, kind, want):
        if kind == want or {kind, want} == {"color", "vector"}:
            return reg
        if want == "float":
            mode = "color_to_float" if kind == "color" else "vector_to_float"
        else:
            mode = "float_to_vector"
        return self.emit("convert", [reg], 1, mode=self.names.NODE_CONVERSIONS.index(mode))[0]

    # -- the graph ------------------------------------------------------------------------------------------------

    def input(self, socket, want=None):
        """(register, type) of node input `socket` (wrapped): what feeds it, converted to the socket's type as the
        link does, or its own value; then as `want` (default: the socket's type)."""
        own = socket_type(socket)
        explicit, want = want, want or own
        node, output = follow_reroutes(socket)
        if node is not None:
            try:
                reg, kind = self.output(node, output)
                if socket.type == "SHADER":  # a colour or value Cycles turns into an Emission (ImplicitEmission)
                    return self._convert(reg, kind, explicit or kind), explicit or kind
                # The link converts to the input's type (svm_node_convert), the node then reads it as `want`.
                return self._convert(self._convert(reg, kind, own), own, want), want
            except NotCompiled as e:
                self.log.unsupported_feature(f"{e} on '{socket.name}' (its own value used)", self.owner)
        return self.constant(own_value(socket), want), want

    def input_named(self, node, identifier, want=None):
        socket = next((s for s in node.inputs if s.identifier == identifier), None)
        if socket is None:
            raise NotCompiled(f"'{node.bl_label or node.bl_idname}' node without an input '{identifier}'")
        return self.input(socket, want)[0]

    def output(self, node, output):
        """(register, type) of `output` of `node` (both wrapped), its node compiled on first use."""
        key = (node.key, output.identifier, self._shift)
        if key not in self._outputs:
            if node.key in self._visiting:  # Blender marks a cycle's closing link invalid: not reached normally
                raise NotCompiled(f"a cycle through '{node.name}'")
            compile_node = _NODE_COMPILERS.get(node.bl_idname)
            if compile_node is None:
                raise NotCompiled(f"'{node.bl_label or node.bl_idname}' node")
            self._visiting.add(node.key)
            try:
                outputs = compile_node(self, node)
            finally:
                self._visiting.discard(node.key)
            for identifier, value in outputs.items():
                self._outputs[(node.key, identifier, self._shift)] = value
            if key not in self._outputs:
                raise NotCompiled(f"'{node.bl_label or node.bl_idname}' node's output '{output.name}'")
        return self._outputs[key]


class _TooManyRegisters(Exception):
    pass


def _index(names, value, what, node):
    if value not in names:
        raise NotCompiled(f"'{node.bl_label}' node's {what} '{value}'")
    return names.index(value)


# -- node compilers: (compiler, node) -> {output identifier: (register, type)} ----------------------------------------

def _value(c, node):
    return {"Value": (c.constant(node.outputs[0].default_value, "float"), "float")}


def _rgb(c, node):
    return {"Color": (c.constant(node.outputs[0].default_value, "color"), "color")}


def _texture_coordinate(c, node):
    if node.from_instancer:
        c.log.unsupported_feature("Texture Coordinate 'From Instancer' (the object's own used)", c.owner)
    outputs = {"Generated": (c.global_input("generated"), "vector"), "UV": (c.global_input("uv"), "vector"),
               "Normal": (c.global_input("object_normal"), "vector"),
               "Reflection": (c.global_input("reflection"), "vector")}
    if node.object is None:
        outputs["Object"] = (c.global_input("object"), "vector")
    else:  # another object's space: its inverse transform of the position, a constant map
        inverse = np.linalg.pinv(np.array(node.object.matrix_world, dtype=np.float64))
        reg = c.emit("transform", [c.global_input("position")], 1, data=c.table(inverse[:3].ravel()))[0]
        outputs["Object"] = (reg, "vector")
    camera = _scene_camera()
    if camera is not None:  # Cycles' camera space: Blender's camera matrix with z flipped (+z ahead)
        world_to_camera = np.diag([1.0, 1.0, -1.0, 1.0]) @ np.linalg.inv(np.array(camera.matrix_world, np.float64))
        reg = c.emit("transform", [c.global_input("position")], 1, data=c.table(world_to_camera[:3].ravel()))[0]
        outputs["Camera"] = (reg, "vector")
        reg = c.emit("project", [c.global_input("position")], 1, data=c.table(_world_to_window(camera).ravel()))[0]
        outputs["Window"] = (reg, "vector")
    return outputs


def _scene_camera():
    """The scene's camera (Camera and Window coordinates are the render camera's), or None."""
    try:
        import bpy
        return bpy.context.scene.camera
    except (ImportError, AttributeError):
        return None


def _world_to_window(camera):
    """The 4x4 map from the world to Window coordinates (Cycles' camera_world_to_ndc: the frame [0, 1]^2 from its
    bottom left, z 0) after the division by its last row: Blender's view and projection of the render's frame."""
    import bpy
    scene = bpy.context.scene
    render = scene.render
    width, height = render.resolution_x * render.resolution_percentage / 100, \
        render.resolution_y * render.resolution_percentage / 100
    projection = np.array(camera.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=int(width),
                                                    y=int(height), scale_x=render.pixel_aspect_x,
                                                    scale_y=render.pixel_aspect_y), np.float64)
    clip = projection @ np.linalg.inv(np.array(camera.matrix_world, np.float64))
    window = np.zeros((4, 4))
    window[0] = 0.5 * (clip[0] + clip[3])  # x in [-1, 1] -> [0, 1]
    window[1] = 0.5 * (clip[1] + clip[3])
    window[3] = clip[3]
    return window


def _uv_map(c, node):
    """The render UV map, or the one the node names (read as an attribute: (u, v, 0), 0 where the mesh lacks it)."""
    if node.from_instancer:
        c.log.unsupported_feature("UV Map 'From Instancer' (the object's own used)", c.owner)
    if node.uv_map:
        return {"UV": (c.attribute(node.uv_map)["color"], "vector")}
    return {"UV": (c.global_input("uv"), "vector")}


def _geometry(c, node):
    return {"Position": (c.global_input("position"), "vector"), "Normal": (c.global_input("normal"), "vector"),
            "True Normal": (c.global_input("true_normal"), "vector"),
            "Incoming": (c.global_input("incoming"), "vector"),
            "Backfacing": (c.global_input("backfacing"), "float"),
            **_geometry_mesh_outputs(c, node)}


def _math(c, node):
    a, b, d = (c.input(s, "float")[0] for s in list(node.inputs)[:3])
    mode = _index(c.names.NODE_MATH_OPS, node.operation, "operation", node)
    return {"Value": (c.emit("math", [a, b, d], 1, mode=mode, flags=node.use_clamp)[0], "float")}


def _mix_rgb(c, node):
    """The legacy Mix RGB node (Cycles' MixNode): its factor always clamped, the result when use_clamp."""
    fac, a, b = c.input(node.inputs["Fac"], "float")[0], c.input(node.inputs["Color1"])[0], \
        c.input(node.inputs["Color2"])[0]
    mode = _index(c.names.NODE_MIX_BLENDS, node.blend_type, "blend type", node)
    reg = c.emit("mix_color", [fac, a, b], 1, mode=mode, flags=1 | (2 if node.use_clamp else 0))[0]
    return {"Color": (reg, "color")}


def _mix(c, node):
    """The Mix node (Cycles' MixColorNode, MixFloatNode, MixVectorNode, MixVectorNonUniformNode)."""
    clamp = 1 if node.clamp_factor else 0
    if node.data_type == "RGBA":
        fac = c.input_named(node, "Factor_Float", "float")
        a, b = c.input_named(node, "A_Color", "color"), c.input_named(node, "B_Color", "color")
        mode = _index(c.names.NODE_MIX_BLENDS, node.blend_type, "blend type", node)
        reg = c.emit("mix_color", [fac, a, b], 1, mode=mode, flags=clamp | (2 if node.clamp_result else 0))[0]
        return {"Result_Color": (reg, "color")}
    if node.data_type == "FLOAT":
        fac = c.input_named(node, "Factor_Float", "float")
        a, b = c.input_named(node, "A_Float", "float"), c.input_named(node, "B_Float", "float")
        return {"Result_Float": (c.emit("mix_float", [fac, a, b], 1, flags=clamp)[0], "float")}
    if node.data_type == "VECTOR":
        uniform = node.factor_mode == "UNIFORM"
        fac = c.input_named(node, "Factor_Float", "float") if uniform else \
            c.input_named(node, "Factor_Vector", "vector")
        a, b = c.input_named(node, "A_Vector", "vector"), c.input_named(node, "B_Vector", "vector")
        reg = c.emit("mix_vector", [fac, a, b], 1, mode=0 if uniform else 1, flags=clamp)[0]
        return {"Result_Vector": (reg, "vector")}
    raise NotCompiled(f"Mix node of type '{node.data_type}'")


def _color_ramp(c, node):
    """Baked into RAMP_TABLE_SIZE colours at i / (size - 1) by Blender's own evaluation, as Cycles' sync does
    (colorramp_to_array): every interpolation and colour mode; linear interpolation between the entries unless
    Constant."""
    ramp = node.color_ramp
    rows = [ramp.evaluate(i / (RAMP_TABLE_SIZE - 1)) for i in range(RAMP_TABLE_SIZE)]
    offset = c.table(np.asarray(rows, dtype=np.float64).ravel())
    fac = c.input(node.inputs["Fac"], "float")[0]
    color, alpha = c.emit("color_ramp", [fac], 2, flags=ramp.interpolation != "CONSTANT", data=offset,
                          size=RAMP_TABLE_SIZE)
    return {"Color": (color, "color"), "Alpha": (alpha, "float")}


def _invert(c, node):
    fac, color = c.input(node.inputs["Fac"], "float")[0], c.input(node.inputs["Color"], "color")[0]
    return {"Color": (c.emit("invert", [fac, color], 1)[0], "color")}


def _clamp(c, node):
    value, lo, hi = (c.input(node.inputs[n], "float")[0] for n in ("Value", "Min", "Max"))
    mode = _index(c.names.NODE_CLAMP_TYPES, node.clamp_type, "type", node)
    return {"Result": (c.emit("clamp", [value, lo, hi], 1, mode=mode)[0], "float")}


def _map_range(c, node):
    """Map Range on a float (its sockets' plain identifiers) or per vector component (their _FLOAT3 twins)."""
    mode = _index(c.names.NODE_MAP_RANGE_TYPES, node.interpolation_type, "interpolation", node)
    if node.data_type == "FLOAT_VECTOR":
        names = ("Vector", "From_Min_FLOAT3", "From_Max_FLOAT3", "To_Min_FLOAT3", "To_Max_FLOAT3", "Steps_FLOAT3")
        regs = [c.input_named(node, n, "vector") for n in names]
        return {"Vector": (c.emit("map_range", regs, 1, mode=mode, flags=node.clamp | 2)[0], "vector")}
    regs = [c.input_named(node, n, "float") for n in ("Value", "From Min", "From Max", "To Min", "To Max", "Steps")]
    return {"Result": (c.emit("map_range", regs, 1, mode=mode, flags=node.clamp)[0], "float")}


def _separate(model, input_name, output_names, input_type):
    def compile_node(c, node):
        mode = model if model is not None else node.mode
        reg = c.input(node.inputs[input_name], input_type)[0]
        outs = c.emit("separate", [reg], 3, mode=_index(c.names.NODE_COLOR_MODELS, mode, "mode", node))
        return {name: (r, "float") for name, r in zip(output_names, outs)}
    return compile_node


def _combine(model, input_names, output_name, output_type):
    def compile_node(c, node):
        mode = model if model is not None else node.mode
        regs = [c.input(node.inputs[n], "float")[0] for n in input_names]
        reg = c.emit("combine", regs, 1, mode=_index(c.names.NODE_COLOR_MODELS, mode, "mode", node))[0]
        return {output_name: (reg, output_type)}
    return compile_node


def _rgb_to_bw(c, node):
    return {"Val": (c.input(node.inputs["Color"], "float")[0], "float")}  # the colour's luminance


def _mapping(c, node):
    regs = [c.input(node.inputs[n], "vector")[0] for n in ("Vector", "Location", "Rotation", "Scale")]
    mode = _index(c.names.NODE_MAPPING_TYPES, node.vector_type, "type", node)
    return {"Vector": (c.emit("mapping", regs, 1, mode=mode)[0], "vector")}


_IMAGE_INTERPOLATIONS = {"Linear": "linear", "Closest": "closest"}  # Cubic and Smart: 'linear', warned


def _image_texture(c, node):
    """An Image Texture node (Cycles' svm_node_tex_image, flat projection): its image as TextureExport.lookup keeps it
    (the colour unassociated from its alpha where Cycles does so), read at its Vector input (unlinked: the UVs)."""
    interpolation = _IMAGE_INTERPOLATIONS.get(node.interpolation)
    if interpolation is None:
        c.log.unsupported_feature(f"Image Texture interpolation '{node.interpolation}' (Linear used)", c.owner)
        interpolation = "linear"
    vector = node.inputs["Vector"]
    coords = c.input(vector, "vector")[0] if follow_reroutes(vector)[0] is not None else c.global_input("uv")
    tree = node.groups[0].id_data if node.groups else node.id_data
    alpha_used = (node.key, "Alpha") in c.textures._reached_outputs(tree)
    texture = c.textures.texture_of(node.image, c.owner, unassociated=alpha_used)
    projection = _index(c.names.NODE_IMAGE_PROJECTIONS, node.projection, "projection", node)
    flags = c.names.TEXTURE_EXTENSIONS.index(node.extension.lower()) + 4 * projection
    color, alpha = c.emit("image", [coords], 2, mode=c.names.TEXTURE_INTERPOLATIONS.index(interpolation),
                          flags=flags, data=texture, value=(float(node.projection_blend), 0.0, 0.0))
    return {"Color": (color, "color"), "Alpha": (alpha, "float")}


# -- procedural textures (render/svm/procedural_textures.h; settings read by procedural_params.py) --------------------

def _texture_vector(c, node):
    """The register of a texture node's point: its Vector input (unlinked: the Generated coordinates, as Cycles'
    LINK_TEXTURE_GENERATED), through the node's Texture Mapping as Cycles' TextureMapping::compile_begin applies it
    (skipped when it is the identity; Blender's sync gives it no min/max)."""
    vector = node.inputs["Vector"]
    reg = c.input(vector, "vector")[0] if follow_reroutes(vector)[0] is not None else c.global_input("generated")
    matrix = _texture_mapping_matrix(node)
    if matrix is not None:
        reg = c.emit("transform", [reg], 1, data=c.table(matrix[:3].ravel()))[0]
        if node.texture_mapping.vector_type == "NORMAL":  # then normalised, as Cycles' mapping of normals
            zero = c.constant(0.0, "float")
            reg = c.emit("vector_math", [reg, reg, reg, zero], 2,
                         mode=c.sphrect._native.node_vector_math_ops.index("NORMALIZE"))[0]
    return reg


def _texture_mapping_matrix(node):
    """The 4x4 map of a node's Texture Mapping (TextureMapping::compute_transform), or None when Cycles skips it."""
    m = getattr(node, "texture_mapping", None)
    if m is None:
        return None
    axes = {"NONE": None, "X": 0, "Y": 1, "Z": 2}
    mapping = (m.mapping_x, m.mapping_y, m.mapping_z)
    translation, rotation, scale = (np.array(v, np.float64) for v in (m.translation, m.rotation, m.scale))
    if not translation.any() and not rotation.any() and (scale == 1).all() and mapping == ("X", "Y", "Z"):
        return None
    project = np.zeros((4, 4))
    project[3, 3] = 1
    for row, axis in enumerate(mapping):
        if axes[axis] is not None:
            project[row, axes[axis]] = 1
    if m.vector_type in ("TEXTURE", "NORMAL"):  # kept invertible
        scale = np.where(np.abs(scale) < 1e-5, np.where(scale < 0, -1e-5, np.where(scale > 0, 1e-5, 0.0)), scale)
    rx, ry, rz = (np.eye(4) for _ in range(3))
    (cx, cy, cz), (sx, sy, sz) = np.cos(rotation), np.sin(rotation)
    rx[1:3, 1:3] = [[cx, -sx], [sx, cx]]
    ry[0, 0], ry[0, 2], ry[2, 0], ry[2, 2] = cy, sy, -sy, cy
    rz[0:2, 0:2] = [[cz, -sz], [sz, cz]]
    rot, scl, tra = rz @ ry @ rx, np.diag([*scale, 1.0]), np.eye(4)
    tra[:3, 3] = translation
    if m.vector_type == "TEXTURE":
        mat = np.linalg.inv(tra @ rot @ scl)
    elif m.vector_type == "POINT":
        mat = tra @ rot @ scl
    elif m.vector_type == "VECTOR":
        mat = rot @ scl
    else:  # NORMAL: the inverse transpose, no translation
        mat = np.linalg.inv(rot @ scl).T
    return mat @ project


def _packed(c, node, names):
    """One register holding up to three float inputs of `node` (x, y, z): a constant when none is linked."""
    sockets = [node.inputs[n] for n in names]
    if all(follow_reroutes(s)[0] is None for s in sockets):
        values = [float(s.default_value) for s in sockets] + [0.0] * (3 - len(sockets))
        return c.constant(values, "vector")
    regs = [c.input(s, "float")[0] for s in sockets]
    regs += [c.constant(0.0, "float")] * (3 - len(regs))
    return c.emit("combine", regs, 1, mode=c.names.NODE_COLOR_MODELS.index("RGB"))[0]


def _w(c, node):
    return c.input(node.inputs["W"], "float")[0]


def _dimensions(value):
    return int(value[0]) - 1  # '1D'..'4D'


def _noise_texture(c, node):
    regs = [_texture_vector(c, node), _w(c, node), _packed(c, node, ("Scale", "Detail", "Roughness")),
            _packed(c, node, ("Distortion",))]
    fac, color = c.emit("noise_texture", regs, 2, mode=_dimensions(node.noise_dimensions))
    return {"Fac": (fac, "float"), "Color": (color, "color")}


def _voronoi_texture(c, node):
    n = c.sphrect._native
    mode = _dimensions(node.voronoi_dimensions) + 4 * (
        _index(n.node_voronoi_metrics, node.distance.lower(), "distance metric", node)
        + 4 * _index(n.node_voronoi_features, node.feature.lower(), "feature", node))
    regs = [_texture_vector(c, node), _w(c, node), _packed(c, node, ("Scale", "Smoothness", "Exponent")),
            _packed(c, node, ("Randomness",))]
    distance, color, position = c.emit("voronoi_texture", regs, 3, mode=mode)
    outputs = {"Distance": (distance, "float"), "Radius": (distance, "float"), "Color": (color, "color"),
               "Position": (position, "vector")}
    if node.voronoi_dimensions in ("1D", "4D"):
        outputs["W"] = (c.emit("voronoi_texture", regs, 1, mode=mode, flags=1)[0], "float")
    return outputs


def _musgrave_texture(c, node):
    mode = _dimensions(node.musgrave_dimensions) + 4 * _index(c.sphrect._native.node_musgrave_types,
                                                              node.musgrave_type.lower(), "type", node)
    regs = [_texture_vector(c, node), _w(c, node), _packed(c, node, ("Scale", "Detail", "Dimension")),
            _packed(c, node, ("Lacunarity", "Offset", "Gain"))]
    return {"Fac": (c.emit("musgrave_texture", regs, 1, mode=mode)[0], "float")}


def _white_noise_texture(c, node):
    value, color = c.emit("white_noise_texture", [_texture_vector(c, node), _w(c, node)], 2,
                          mode=_dimensions(node.noise_dimensions))
    return {"Value": (value, "float"), "Color": (color, "color")}


def _gradient_texture(c, node):
    mode = _index(c.sphrect._native.node_gradient_types, node.gradient_type.lower(), "type", node)
    fac = c.emit("gradient_texture", [_texture_vector(c, node)], 1, mode=mode)[0]
    return {"Fac": (fac, "float"), "Color": (c._convert(fac, "float", "color"), "color")}


def _checker_texture(c, node):
    regs = [_texture_vector(c, node), c.input(node.inputs["Color1"], "color")[0],
            c.input(node.inputs["Color2"], "color")[0], c.input(node.inputs["Scale"], "float")[0]]
    color, fac = c.emit("checker_texture", regs, 2)
    return {"Color": (color, "color"), "Fac": (fac, "float")}


def _wave_texture(c, node):
    n = c.sphrect._native
    wave_type = _index(n.node_wave_types, node.wave_type.lower(), "type", node)
    direction = _index(n.node_wave_bands_directions, node.bands_direction.lower(), "direction", node) \
        if node.wave_type == "BANDS" else \
        _index(n.node_wave_rings_directions, node.rings_direction.lower(), "direction", node)
    profile = _index(n.node_wave_profiles, node.wave_profile.lower(), "profile", node)
    regs = [_texture_vector(c, node), _packed(c, node, ("Scale", "Distortion", "Detail")),
            _packed(c, node, ("Detail Scale", "Detail Roughness", "Phase Offset"))]
    fac = c.emit("wave_texture", regs, 1, mode=wave_type + 2 * (direction + 4 * profile))[0]
    return {"Fac": (fac, "float"), "Color": (c._convert(fac, "float", "color"), "color")}


def _magic_texture(c, node):
    regs = [_texture_vector(c, node), _packed(c, node, ("Scale", "Distortion"))]
    color, fac = c.emit("magic_texture", regs, 2, mode=min(int(node.turbulence_depth), 10))
    return {"Color": (color, "color"), "Fac": (fac, "float")}


def _brick_texture(c, node):
    regs = [_texture_vector(c, node)] + [c.input(node.inputs[n], "color")[0] for n in ("Color1", "Color2", "Mortar")]
    regs += [_packed(c, node, ("Scale", "Mortar Size", "Mortar Smooth")),
             _packed(c, node, ("Bias", "Brick Width", "Row Height"))]
    data = c.table([node.offset, node.offset_frequency, node.squash, node.squash_frequency])
    color = c.emit("brick_texture", regs, 1, data=data)[0]
    fac = c.emit("brick_texture", regs, 1, data=data, flags=1)[0]
    return {"Color": (color, "color"), "Fac": (fac, "float")}


# -- shading inputs (render/svm/shading_nodes.h) and colour nodes (color_nodes.h; settings: color_node_params.py) ---

def _normal_input(c, node):
    """A node's Normal input: its link, else the shading normal (Cycles' LINK_NORMAL)."""
    socket = node.inputs["Normal"]
    return c.input(socket, "vector")[0] if follow_reroutes(socket)[0] is not None else c.global_input("normal")


def _layer_weight(c, node):
    fresnel, facing = c.emit("layer_weight", [c.input(node.inputs["Blend"], "float")[0], _normal_input(c, node)], 2)
    return {"Fresnel": (fresnel, "float"), "Facing": (facing, "float")}


def _fresnel(c, node):
    return {"Fac": (c.emit("fresnel", [c.input(node.inputs["IOR"], "float")[0], _normal_input(c, node)], 1)[0],
                    "float")}


def _light_falloff(c, node):
    regs = [c.input(node.inputs[n], "float")[0] for n in ("Strength", "Smooth")]
    quadratic, linear, constant = c.emit("light_falloff", regs, 3)
    return {"Quadratic": (quadratic, "float"), "Linear": (linear, "float"), "Constant": (constant, "float")}


def _blackbody(c, node):
    return {"Color": (c.emit("blackbody", [c.input(node.inputs["Temperature"], "float")[0]], 1)[0], "color")}


def _wavelength(c, node):
    return {"Color": (c.emit("wavelength", [c.input(node.inputs["Wavelength"], "float")[0]], 1)[0], "color")}


def _hue_saturation(c, node):
    regs = [c.input(node.inputs[n], "float")[0] for n in ("Hue", "Saturation", "Value", "Fac")]
    regs.append(c.input(node.inputs["Color"], "color")[0])
    return {"Color": (c.emit("hue_saturation", regs, 1)[0], "color")}


def _bright_contrast(c, node):
    regs = [c.input(node.inputs["Color"], "color")[0], c.input(node.inputs["Bright"], "float")[0],
            c.input(node.inputs["Contrast"], "float")[0]]
    return {"Color": (c.emit("bright_contrast", regs, 1)[0], "color")}


def _gamma(c, node):
    regs = [c.input(node.inputs["Color"], "color")[0], c.input(node.inputs["Gamma"], "float")[0]]
    return {"Color": (c.emit("gamma", regs, 1)[0], "color")}


def _vector_math(c, node):
    sockets = {s.identifier: s for s in node.inputs}
    regs = [c.input(sockets[n], "vector")[0] for n in ("Vector", "Vector_001", "Vector_002")]
    regs.append(c.input(sockets["Scale"], "float")[0])
    mode = _index(c.sphrect._native.node_vector_math_ops, node.operation, "operation", node)
    vector, value = c.emit("vector_math", regs, 2, mode=mode)
    return {"Vector": (vector, "vector"), "Value": (value, "float")}


def _vector_rotate(c, node):
    regs = [c.input(node.inputs[n], "vector")[0] for n in ("Vector", "Center", "Axis")]
    regs += [c.input(node.inputs["Angle"], "float")[0], c.input(node.inputs["Rotation"], "vector")[0]]
    mode = _index(c.sphrect._native.node_vector_rotate_types, node.rotation_type, "type", node)
    return {"Vector": (c.emit("vector_rotate", regs, 1, mode=mode, flags=node.invert)[0], "vector")}


def _normal(c, node):
    """The Normal node: its direction normalised (a constant), Dot that with the Normal input normalised
    (NormalNodeDot), through Vector Math's Normalize and Dot Product."""
    direction = np.asarray(node.outputs["Normal"].default_value, np.float32)
    length = np.sqrt(np.float32(np.dot(direction, direction)))
    unit = c.constant(tuple(direction / length) if length > 0 else (0.0, 0.0, 0.0), "vector")
    ops, zero = c.sphrect._native.node_vector_math_ops, c.constant(0.0, "float")
    normal = c.input(node.inputs["Normal"], "vector")[0]
    normal = c.emit("vector_math", [normal, normal, normal, zero], 2, mode=ops.index("NORMALIZE"))[0]
    dot = c.emit("vector_math", [unit, normal, normal, zero], 2, mode=ops.index("DOT_PRODUCT"))[1]
    return {"Normal": (unit, "vector"), "Dot": (dot, "float")}


def _bump(c, node):
    """The Bump node (Cycles' svm_node_set_bump, world space): its Height at the point and at P + dx, P + dy (the
    compact ray differential along the true normal's orthonormals), Strength, Distance, Invert, and its Normal input
    (unlinked: the shading normal).  An unlinked Height passes the normal through, as Cycles' constant folding."""
    if c._shift:
        raise NotCompiled("Bump node inside another Bump node's Height")
    socket = node.inputs["Normal"]
    source = follow_reroutes(socket)[0]
    if source is not None and source.bl_idname not in _NODE_COMPILERS:
        c.log.unsupported_feature(f"'{source.bl_label or source.bl_idname}' node on a Bump node's Normal input (the "
                                  "shading normal used)", c.owner)
        source = None
    normal = c.input(socket, "vector")[0] if source is not None else c.global_input("normal")
    height = node.inputs["Height"]
    if follow_reroutes(height)[0] is None:
        return {"Normal": (normal, "vector")}
    heights = [c.shifted_input(height, shift, "float") for shift in (0, 1, 2)]
    strength, distance = c.input(node.inputs["Strength"], "float")[0], c.input(node.inputs["Distance"], "float")[0]
    return {"Normal": (c.emit("bump", heights + [strength, distance, normal], 1, flags=int(node.invert))[0],
                       "vector")}


def _displacement(c, node):
    """The Displacement node (svm_node_displacement): its Normal (unlinked: the shading normal before any bump) times
    (Height - Midlevel) x Scale, in the world, or in Object space through the object's transform (the normal taken
    into the object, scaled there, the offset taken back out: an object's scale scales it)."""
    socket = node.inputs["Normal"]
    normal = c.input(socket, "vector")[0] if follow_reroutes(socket)[0] is not None else c.global_input("normal")
    height, midlevel, scale = (c.input(node.inputs[n], "float")[0] for n in ("Height", "Midlevel", "Scale"))
    amount = c.emit("math", [height, midlevel, midlevel], 1, mode=c.names.NODE_MATH_OPS.index("SUBTRACT"))[0]
    amount = c.emit("math", [amount, scale, scale], 1, mode=c.names.NODE_MATH_OPS.index("MULTIPLY"))[0]
    scale_op = list(c.sphrect._native.node_vector_math_ops).index("SCALE")
    if node.space == "OBJECT":
        inside = c.emit("object_space", [normal], 1, mode=0)[0]
        offset = c.emit("vector_math", [inside, inside, inside, amount], 2, mode=scale_op)[0]
        return {"Displacement": (c.emit("object_space", [offset], 1, mode=1)[0], "vector")}
    return {"Displacement": (c.emit("vector_math", [normal, normal, normal, amount], 2, mode=scale_op)[0], "vector")}


def _curves(kind, value_name, output_name, value_type):
    def compile_node(c, node):
        from .color_node_params import curve_table
        table = curve_table(node.mapping, kind)
        data = c.table([table["min_x"], table["max_x"], float(table["extrapolate"])] +
                       [float(v) for v in np.asarray(table["table"]).ravel()])
        regs = [c.input(node.inputs[0], "float")[0], c.input(node.inputs[value_name], value_type)[0]]  # Fac, Factor
        reg = c.emit("curves", regs, 1, mode=0 if kind != "float" else 1, data=data, size=len(table["table"]))[0]
        return {output_name: (reg, value_type)}
    return compile_node


# -- mesh attributes and the object (render/svm/attribute_nodes.h; the exporter's geometry.corner_attributes) -------

def _geometry_mesh_outputs(c, node):
    """Geometry's outputs from the mesh: Parametric (Cycles' (1 - u - v, u, 0): the weights of the triangle's first two
    corners), Tangent (radial about Z), Pointiness and Random Per Island (attributes Cycles computes)."""
    return {"Parametric": (c.global_input("parametric"), "vector"),
            "Tangent": (_radial_tangent(c, "Z"), "vector"),
            "Pointiness": (c.attribute(POINTINESS)["fac"], "float"),
            "Random Per Island": (c.attribute(RANDOM_PER_ISLAND)["fac"], "float")}


def _radial_tangent(c, axis):
    return c.emit("radial_tangent", [c.global_input("generated")], 1, mode="XYZ".index(axis))[0]


def _tangent(c, node):
    """Radial about an axis, or along a UV map (its MikkTSpace tangents, an attribute; the render map's without a
    name; 0 where the mesh lacks the map)."""
    if node.direction_type == "RADIAL":
        return {"Tangent": (_radial_tangent(c, node.axis), "vector")}
    tangent = c.attribute(UV_TANGENT_PREFIX + node.uv_map)["color"]
    return {"Tangent": (c.emit("radial_tangent", [tangent], 1, mode=3)[0], "vector")}


def _material_pass_index(owner):
    """Object Info > Material Index: the pass index of material `owner` (0 for a light's node tree, as Cycles)."""
    try:
        import bpy
        material = bpy.data.materials.get(owner)
    except ImportError:
        return 0
    return material.pass_index if material is not None else 0


def _object_info(c, node):
    return {"Location": (c.global_input("object_location"), "vector"),
            "Color": (c.global_input("object_color"), "color"),
            "Alpha": (c.global_input("object_alpha"), "float"),
            "Object Index": (c.global_input("object_index"), "float"),
            "Material Index": (c.constant(_material_pass_index(c.owner), "float"), "float"),
            "Random": (c.global_input("object_random"), "float")}


def _attribute_outputs(regs):
    return {"Color": (regs["color"], "color"), "Vector": (regs["color"], "vector"), "Fac": (regs["fac"], "float"),
            "Alpha": (regs["alpha"], "float")}


# Attribute names Cycles reads as its standard attributes (Attribute::name_standard) that programs have as globals.
_STANDARD_GLOBALS = {"generated": "generated", "uv": "uv"}


def _attribute(c, node):
    """Cycles' Attribute node: a mesh attribute or UV map by name (Geometry), an object's custom property (Object;
    Instancer reads the object's own, warned); a name the mesh lacks reads 0 (alpha 1)."""
    kind, name = node.attribute_type, node.attribute_name
    if kind == "INSTANCER":
        c.log.unsupported_feature("Attribute node of type Instancer (the object's own property read)", c.owner)
    if kind in ("OBJECT", "INSTANCER"):
        name = OBJECT_ATTRIBUTE_PREFIX + name
    elif kind != "GEOMETRY":
        raise NotCompiled(f"'Attribute' node of type {kind.replace('_', ' ').title()}")
    if kind == "GEOMETRY" and name in _STANDARD_GLOBALS:  # Cycles' standard attributes the hit has
        reg = c.global_input(_STANDARD_GLOBALS[name])
        if name == "uv":  # a float2: Fac is u
            fac = c.emit("separate", [reg], 3, mode=c.names.NODE_COLOR_MODELS.index("RGB"))[0]
        else:
            fac = c.emit("convert", [reg], 1, mode=c.names.NODE_CONVERSIONS.index("vector_to_float"))[0]
        return {"Color": (reg, "color"), "Vector": (reg, "vector"), "Fac": (fac, "float"),
                "Alpha": (c.constant(1.0, "float"), "float")}
    if not node.attribute_name:  # no attribute: what Cycles reads of a missing one
        return {"Color": (c.constant(0.0, "color"), "color"), "Vector": (c.constant(0.0, "vector"), "vector"),
                "Fac": (c.constant(0.0, "float"), "float"), "Alpha": (c.constant(1.0, "float"), "float")}
    return _attribute_outputs(c.attribute(name))


def _color_attribute(c, node):
    """Cycles' Color Attribute node: the named colour attribute, or the mesh's render one; missing: 0, alpha 0."""
    regs = c.attribute(node.layer_name or RENDER_COLOR, "color_attribute")
    return {"Color": (regs["color"], "color"), "Alpha": (regs["alpha"], "float")}


# -- the Light Path node (render/svm/program.h RayContext: what each ray that evaluates a program passes) -------------

# Its outputs and the hit's inputs they read (Blender 3.4's node has no Is Volume Scatter Ray).
_LIGHT_PATH_GLOBALS = {"Is Camera Ray": "is_camera_ray", "Is Shadow Ray": "is_shadow_ray",
                       "Is Diffuse Ray": "is_diffuse_ray", "Is Glossy Ray": "is_glossy_ray",
                       "Is Singular Ray": "is_singular_ray", "Is Reflection Ray": "is_reflection_ray",
                       "Is Transmission Ray": "is_transmission_ray", "Ray Length": "ray_length",
                       "Ray Depth": "ray_depth", "Diffuse Depth": "diffuse_depth", "Glossy Depth": "glossy_depth",
                       "Transparent Depth": "transparent_depth", "Transmission Depth": "transmission_depth"}


def _light_path(c, node):
    """The outputs something reads (Cycles' LightPathNode::compile emits only those), each a global of the hit."""
    return {s.identifier: (c.global_input(_LIGHT_PATH_GLOBALS[s.identifier]), "float") for s in node.outputs
            if s.identifier in _LIGHT_PATH_GLOBALS and s.is_linked}


_NODE_COMPILERS = {
    "ShaderNodeValue": _value,
    "ShaderNodeDisplacement": _displacement,
    "ShaderNodeRGB": _rgb,
    "ShaderNodeTexCoord": _texture_coordinate,
    "ShaderNodeUVMap": _uv_map,
    "ShaderNodeNewGeometry": _geometry,
    "ShaderNodeMath": _math,
    "ShaderNodeMixRGB": _mix_rgb,
    "ShaderNodeMix": _mix,
    "ShaderNodeValToRGB": _color_ramp,
    "ShaderNodeInvert": _invert,
    "ShaderNodeClamp": _clamp,
    "ShaderNodeMapRange": _map_range,
    "ShaderNodeSeparateRGB": _separate("RGB", "Image", ("R", "G", "B"), "color"),
    "ShaderNodeSeparateXYZ": _separate("RGB", "Vector", ("X", "Y", "Z"), "vector"),
    "ShaderNodeSeparateHSV": _separate("HSV", "Color", ("H", "S", "V"), "color"),
    "ShaderNodeSeparateColor": _separate(None, "Color", ("Red", "Green", "Blue"), "color"),
    "ShaderNodeCombineRGB": _combine("RGB", ("R", "G", "B"), "Image", "color"),
    "ShaderNodeCombineXYZ": _combine("RGB", ("X", "Y", "Z"), "Vector", "vector"),
    "ShaderNodeCombineHSV": _combine("HSV", ("H", "S", "V"), "Color", "color"),
    "ShaderNodeCombineColor": _combine(None, ("Red", "Green", "Blue"), "Color", "color"),
    "ShaderNodeRGBToBW": _rgb_to_bw,
    "ShaderNodeMapping": _mapping,
    "ShaderNodeTexImage": _image_texture,
    "ShaderNodeTexNoise": _noise_texture,
    "ShaderNodeTexVoronoi": _voronoi_texture,
    "ShaderNodeTexMusgrave": _musgrave_texture,
    "ShaderNodeTexWhiteNoise": _white_noise_texture,
    "ShaderNodeTexGradient": _gradient_texture,
    "ShaderNodeTexChecker": _checker_texture,
    "ShaderNodeTexWave": _wave_texture,
    "ShaderNodeTexMagic": _magic_texture,
    "ShaderNodeTexBrick": _brick_texture,
    "ShaderNodeLayerWeight": _layer_weight,
    "ShaderNodeFresnel": _fresnel,
    "ShaderNodeLightFalloff": _light_falloff,
    "ShaderNodeBlackbody": _blackbody,
    "ShaderNodeWavelength": _wavelength,
    "ShaderNodeHueSaturation": _hue_saturation,
    "ShaderNodeBrightContrast": _bright_contrast,
    "ShaderNodeGamma": _gamma,
    "ShaderNodeVectorMath": _vector_math,
    "ShaderNodeVectorRotate": _vector_rotate,
    "ShaderNodeNormal": _normal,
    "ShaderNodeRGBCurve": _curves("rgb", "Color", "Color", "color"),
    "ShaderNodeVectorCurve": _curves("vector", "Vector", "Vector", "vector"),
    "ShaderNodeFloatCurve": _curves("float", "Value", "Value", "float"),
    "ShaderNodeBump": _bump,
    # mesh attributes and the object (render/svm/attribute_nodes.h)
    "ShaderNodeObjectInfo": _object_info,
    "ShaderNodeAttribute": _attribute,
    "ShaderNodeVertexColor": _color_attribute,
    "ShaderNodeTangent": _tangent,
    "ShaderNodeLightPath": _light_path,
}


def compilable(socket):
    """Whether a node the compiler knows feeds input `socket` (wrapped)."""
    node, _ = follow_reroutes(socket)
    return node is not None and node.bl_idname in _NODE_COMPILERS


def program_globals(sphrect, program):
    """The NODE_GLOBALS a program reads (the exporter gives meshes the coordinates and object transform they need)."""
    names = sphrect.scene.NODE_GLOBALS
    return {names[i.mode] for i in program.instructions if i.op == "global"}


def is_shading_normal(sphrect, program):
    """Whether a program's result is the hit's shading normal as it is (a Bump of unlinked Height)."""
    code = program.instructions
    return len(code) == 1 and code[0].op == "global" and code[0].mode == sphrect.scene.NODE_GLOBALS.index("normal")


def varies(program):
    """Whether a program's result depends on the hit (it reads the hit or an image): else it is a constant."""
    return any(i.op in {"global", "image", "attribute"} for i in program.instructions)


def constant_of(sphrect, program):
    """The value of a program that does not vary (varies() false), as a float 3-tuple."""
    return tuple(sphrect._native._eval_node_program(dataclasses.asdict(program), (0, 0, 0), (0, 0, 0),
                                                    (0, 0, 0)))


def compile_socket(sphrect, textures, log, owner, socket, want=None):
    """(NodeProgram, None) for input `socket` (wrapped) when its graph varies over the surface, (None, value) when it
    folds to a constant (a float, or an RGB tuple), (None, None) when nothing the compiler knows feeds it."""
    if socket is None or not compilable(socket):
        return None, None
    program = ProgramCompiler(sphrect, textures, log, owner).compile(socket, want)
    if program is None:
        return None, None
    if varies(program):
        return program, None
    value = constant_of(sphrect, program)
    return None, value[0] if (want or socket_type(socket)) == "float" else value


def compile_product(sphrect, textures, log, owner, color_socket, strength_socket):
    """(NodeProgram of colour x strength, None), or (None, None) when neither varies: an emission's radiance."""
    if not compilable(color_socket) and not compilable(strength_socket):
        return None, None  # nothing known feeds them (the caller warns of what does)
    compiler = ProgramCompiler(sphrect, textures, log, owner)
    program = compiler.compile_product(color_socket, strength_socket)
    return (program, None) if program is not None and varies(program) else (None, None)


def program_mean(sphrect, program, samples=8):
    """A program's mean colour over the UV and Generated square (samples^2 points), where it must stand for a
    constant; None for a program that reads images or mesh attributes (not evaluated here)."""
    if any(i.op in ("image", "attribute") for i in program.instructions):
        return None
    fields = dataclasses.asdict(program)
    total = np.zeros(3)
    for j in range(samples):
        for i in range(samples):
            uv = ((i + 0.5) / samples, (j + 0.5) / samples, 0.0)
            total += sphrect._native._eval_node_program(fields, uv, uv, uv)
    return tuple(float(x) for x in total / samples**2)


_DATA_OPS = {"color_ramp", "transform", "project", "brick_texture", "curves"}  # ops whose `data` is an offset


class _Composer:
    """Programs joined into one (their registers and tables moved past the ones before), and instructions on their
    results: an emission under Mix Shader factors (emission_under_factors)."""

    def __init__(self, sphrect):
        self.sphrect, self.names = sphrect, sphrect.scene
        self.code, self.data, self.registers, self.attributes = [], [], 0, []

    def append(self, program):
        """The register of `program`'s result once appended."""
        base, data_base = self.registers, len(self.data)
        for name in program.attributes:
            if name not in self.attributes:
                self.attributes.append(name)
        for i in program.instructions:
            regs = [r + base if r >= 0 else -1 for r in i.regs]
            data = i.data + data_base if i.op in _DATA_OPS else i.data
            if i.op == "attribute":
                data = self.attributes.index(program.attributes[i.data])
            self.code.append(dataclasses.replace(i, regs=regs, data=data))
        self.data.extend(program.data)
        self.registers += program.num_registers
        return program.output + base

    def emit(self, op, inputs, outputs=1, mode=0, flags=0, data=0, value=(0.0, 0.0, 0.0)):
        out = list(range(self.registers, self.registers + outputs))
        self.registers += outputs
        self.code.append(self.sphrect.NodeInstruction(op=op, regs=list(inputs) + out, mode=mode, flags=flags,
                                                      data=data, value=tuple(float(v) for v in value)))
        return out[0] if outputs == 1 else out

    def lookup(self, lookup):
        """(colour register, alpha register) of a TextureLookup at its coordinates through its transform."""
        coords = self.emit("global", [], mode=self.names.NODE_GLOBALS.index(lookup.coordinates))
        offset = len(self.data)
        self.data.extend(float(v) for row in lookup.transform for v in row)
        mapped = self.emit("transform", [coords], data=offset)
        return self.emit("image", [mapped], 2, mode=self.names.TEXTURE_INTERPOLATIONS.index(lookup.interpolation),
                         flags=self.names.TEXTURE_EXTENSIONS.index(lookup.extension), data=lookup.texture)

    def color(self, source):
        """The register of a TextureLookup's colour (its alpha as grey) or a NodeProgram's result."""
        if isinstance(source, self.sphrect.NodeProgram):
            return self.append(source)
        color, alpha = self.lookup(source)
        if source.output != "alpha":
            return color
        return self.emit("convert", [alpha], mode=self.names.NODE_CONVERSIONS.index("float_to_vector"))

    def factor(self, factor):
        """The register of a MixFactor's weight: its scalar clamped to [0, 1] (svm_node_mix_closure), or 1 minus."""
        if factor.program is not None:
            value = self.append(factor.program)
        else:
            color, alpha = self.lookup(factor.lookup)
            value = alpha if factor.lookup.output == "alpha" else \
                self.emit("convert", [color], mode=self.names.NODE_CONVERSIONS.index("color_to_float"))
        zero, one = self.emit("constant", [], value=(0, 0, 0)), self.emit("constant", [], value=(1, 0, 0))
        value = self.emit("clamp", [value, zero, one], mode=self.names.NODE_CLAMP_TYPES.index("MINMAX"))
        if factor.complement:
            value = self.emit("math", [one, value, zero], mode=self.names.NODE_MATH_OPS.index("SUBTRACT"))
        return value

    def program(self, output):
        if self.registers > self.names.MAX_NODE_REGISTERS:
            return None
        return self.sphrect.NodeProgram(instructions=self.code, output=output, num_registers=self.registers,
                                        data=self.data, attributes=self.attributes)


def emission_sum(sphrect, constant, terms):
    """The NodeProgram of a constant emission (RGB) plus terms [(RGB scale, TextureLookup or NodeProgram)]: several
    textured or graph-driven emissions of one material as one (the renderer's emitter is one program times a
    constant).  None past MAX_NODE_REGISTERS."""
    c = _Composer(sphrect)
    blends = sphrect.scene.NODE_MIX_BLENDS
    one = c.emit("constant", [], value=(1, 0, 0))
    total = c.emit("constant", [], value=constant)
    for scale, source in terms:
        color = c.color(source)
        scaled = c.emit("mix_color", [one, color, c.emit("constant", [], value=scale)], mode=blends.index("MULTIPLY"))
        total = c.emit("mix_color", [one, total, scaled], mode=blends.index("ADD"))  # a + b at factor 1
    return c.program(total)


def emission_under_factors(sphrect, emission, factors):
    """The NodeProgram of an emission (None: white; a TextureLookup's colour, its alpha as grey; a NodeProgram's
    colour) times the weights of the texture- or graph-driven Mix Shader factors above it: the renderer varies it
    per point, so an emitter under such a mix keeps its light (the factors' lobes keep theirs: MixFactor).  None
    past MAX_NODE_REGISTERS."""
    c = _Composer(sphrect)
    color = c.emit("constant", [], value=(1, 1, 1)) if emission is None else c.color(emission)
    for f in factors:
        color = c.emit("scale", [color, c.factor(f)])
    return c.program(color)
