"""Blender materials and world -> sphrect.Material / sphrect.World.

Read from the node tree behind the active output: Diffuse BSDF and Principled BSDF (base colour, metallic,
specular, specular tint, roughness, sheen, sheen tint, clearcoat, clearcoat roughness: the renderer's
'principled' kind, Cycles 3.4's model), Glass and Refraction BSDF and a Principled BSDF of transmission 1 (kind
'glass': the dielectric reflection Cycles shows at zero bounces), Glossy BSDF and Anisotropic BSDF (kind
'glossy_bsdf', no Fresnel; their anisotropy and the Principled BSDF's along Cycles' default radial tangent) for
surfaces; Mix Shader and Add Shader trees of those (kind 'mix': each shader's
closures scaled by its weight, as svm_node_mix_closure does); volume-only materials (Volume linked, Surface not:
their volume is an object volume, volumes.py) and a white Transparent BSDF make a transparent surface, left out by
geometry.triangulate; Translucent BSDF (kind
'translucent'); Holdout (kind 'holdout': black, alpha 0); a coloured Transparent BSDF and a Principled BSDF's Alpha
(constant or an Image Texture's, expanded into a Mix Shader with a white Transparent BSDF as Cycles does) as kind
'transparent'; emission with Cycles 3.4's conventions -- an Emission shader emits
radiance colour x strength (svm_node_emission_weight), the Principled BSDF's Emission x Emission Strength adds to
its BSDF, a mix scales each side's closures by its weight, mesh emission is two-sided (emissive_pdf:
|Ng . wi| > 0); Background for the world colour, any other world Surface (a Sky Texture, gradients, mixes...)
baked by Cycles into an environment image (world_bake.py); the volume shaders on the World output
(volume_shaders.py) for a homogeneous medium.  Image Texture nodes (textures.py) drive Principled's Base Color,
Roughness, Metallic and Specular, the Color of Diffuse, Glossy, Glass and Translucent BSDFs and the Roughness of
Glossy and Glass, Mix Shader factors, and a Normal input through a tangent-space Normal Map node; a graph of the
nodes node_program.py compiles (Math, Mix, ColorRamp, Texture Coordinate, ...) drives the same inputs, the emission's
Color and Strength and Mix Shader factors as a NodeProgram the renderer runs per hit (a graph of constants folds to
its value); every other linked input and every other node is logged as unsupported, its own value used.  Links are
read as Cycles follows them (node_groups.py: muted and invalid links left out, muted nodes passing their internal
links, groups inlined), and a Mix / Add Shader graph is walked once per node, whatever the number of paths across it
(_closures)."""
import dataclasses

import mathutils
import numpy as np

from . import world_bake
from .node_groups import MAX_GROUP_DEPTH, own_value, read_links_anew, too_deep_groups, wrap_node
from .node_program import (ProgramCompiler, compile_product, compile_socket, emission_sum, emission_under_factors,
                           is_shading_normal, program_mean)
from .textures import TextureExport, follow_reroutes, image_texture_source
from .visibility import world_invisible_to
from .volume_shaders import read_volume


def _active_output(tree, node_type):
    """The output node Cycles uses (wrapped: node_groups.py), None when there is none or it is muted (Cycles then
    links nothing to its output: a black surface, no volume).  Each export of a tree starts here: its links are read
    anew."""
    read_links_anew()
    outputs = [n for n in tree.nodes if n.bl_idname == node_type]
    active = next((n for n in outputs if getattr(n, "is_active_output", False)
                   and getattr(n, "target", "ALL") in {"ALL", "CYCLES"}), outputs[0] if outputs else None)
    return wrap_node(active) if active is not None and not active.mute else None


def _warn_of_deep_groups(tree, log, owner):
    if too_deep_groups(tree):
        log.unsupported_feature(f"node groups nested more than {MAX_GROUP_DEPTH} deep (the links through the deeper "
                                "ones left out)", owner)


def _linked_node(socket):
    return follow_reroutes(socket)[0]


class ImplicitEmission:
    """A colour or a value linked straight into a shader input (a Material Output's Surface, a Mix or Add Shader's
    shader): Cycles inserts an Emission there (ShaderGraph::connect), of that colour (a value: its Strength) and
    strength 1.  `socket` is the shader input; the leaf _shader gives the emission of."""
    bl_idname = "implicit Emission"

    def __init__(self, socket, node, output):
        self.socket = socket
        self.key = ("implicit emission", node.key, output.identifier)  # what emits: the same wherever it is linked


def _linked_shader(socket):
    """The node feeding shader input `socket`: a node, an ImplicitEmission (an output that is not a shader), None."""
    node, output = follow_reroutes(socket)
    if node is not None and output is not None and output.type != "SHADER":
        return ImplicitEmission(socket, node, output)
    return node


def _value(node, name, log, owner):
    """An input's own value; a linked input is logged (its link is not followed)."""
    socket = node.inputs.get(name)
    if socket is None:
        return None
    if socket.is_linked:
        source = socket.links[0].from_node
        log.unsupported_feature(f"linked '{name}' input ({source.bl_label or source.bl_idname})", owner)
    return own_value(socket)


# The material inputs (sphrect.scene.TEXTURED_INPUTS) an Image Texture can drive on each shader node; the socket
# of a field is its title-cased name ('Base Color', 'Roughness', ...), 'Color' for the base colour of the BSDFs
# other than Principled's.
_TEXTURABLE = {"ShaderNodeBsdfPrincipled": {"base_color", "roughness", "metallic", "specular"},
               "ShaderNodeBsdfDiffuse": {"base_color"},
               "ShaderNodeBsdfGlossy": {"base_color", "roughness"},
               "ShaderNodeBsdfAnisotropic": {"base_color", "roughness"},
               "ShaderNodeBsdfGlass": {"base_color", "roughness"},
               "ShaderNodeBsdfTranslucent": {"base_color"},
               "ShaderNodeBsdfTransparent": {"base_color"}}


def _socket_name(node, field):
    if field == "base_color" and node.bl_idname != "ShaderNodeBsdfPrincipled":
        return "Color"
    return field.replace("_", " ").title()


class _Inputs:
    """A shader node's inputs as a sphrect.Material reads them: read(field) is the input's own value, and an input
    an Image Texture node drives is recorded in `textures` (field -> TextureLookup) instead of warned."""

    def __init__(self, sphrect, node, textures, log, owner):
        self.node, self.log, self.owner = node, log, owner
        allowed = _TEXTURABLE.get(node.bl_idname, set())
        self.textured_fields = [f for f in sphrect.scene.TEXTURED_INPUTS if f in allowed]
        self.tex_export = textures
        self.textures = {}  # field -> TextureLookup, or NodeProgram (moved to Material.programs: _split_programs)
        self.folded = {}  # field -> the constant a graph of known nodes folds to

    def textured(self, field):
        """Whether `field`'s input is linked from an Image Texture node, or from a graph the renderer evaluates per
        hit (node_program.py; recorded on the first call)."""
        if field in self.textures:
            return True
        if field not in self.textured_fields or field in self.folded:
            return False
        socket = self.node.inputs.get(_socket_name(self.node, field))
        source = image_texture_source(socket)
        if source is not None:
            self.textures[field] = self.tex_export.lookup(*source, self.owner)
            return True
        program, constant = compile_socket(self.tex_export.sphrect, self.tex_export, self.log, self.owner, socket)
        if program is not None:
            self.textures[field] = program
            return True
        if constant is not None:
            self.folded[field] = constant
        return False

    def read(self, field):
        if self.textured(field):
            return own_value(self.node.inputs[_socket_name(self.node, field)])
        if field in self.folded:
            return self.folded[field]
        return _value(self.node, _socket_name(self.node, field), self.log, self.owner)

    def value(self, name):
        """An input that no texture drives, by socket name (a linked one warned)."""
        return _value(self.node, name, self.log, self.owner)

    def unwarned(self, name):
        """An input's own value, unwarned (for tests of which model applies; the value read later warns)."""
        socket = self.node.inputs.get(name)
        return own_value(socket) if socket is not None else None


def _rgb(v):
    return tuple(float(x) for x in v[:3])


def _nonzero_input(node, name, log, owner, what):
    v = _value(node, name, log, owner)
    if v is not None and np.any(np.asarray(v, dtype=float) > 0):
        log.unsupported_feature(what, owner)


def volume_socket(mat):
    """The Volume input of material `mat`'s active output when a shader is linked there (its medium:
    volume_shaders.read_volume), else None."""
    if mat is None or not mat.use_nodes or mat.node_tree is None:
        return None
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    return out.inputs["Volume"] if out is not None and _linked_node(out.inputs["Volume"]) is not None else None


def is_volume_only(mat):
    """A node material whose active output has a Volume link and no Surface link: Cycles makes its surface
    transparent (it neither shades nor occludes), so the exporter leaves those triangles out."""
    if mat is None or not mat.use_nodes or mat.node_tree is None:
        return False
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    return out is not None and out.inputs["Volume"].is_linked and _linked_node(out.inputs["Surface"]) is None


def left_out_surface(mat):
    """Whether the material's surface is left out of the meshes (geometry.triangulate): volume-only (its volume is
    an object volume: volumes.py) or transparent_surface."""
    return is_volume_only(mat) or transparent_surface(mat) is not None


def transparent_surface(mat):
    """Why a material's surface that is not volume-only is left out (geometry.triangulate), as the warning names it,
    or None: a white Transparent BSDF alone on the Surface (it lets camera and shadow rays through unchanged in
    Cycles, transparent bounces being counted apart from max_bounces: leaving it out is exact and costs nothing; a
    coloured one is kind 'transparent')."""
    if mat is None or not mat.use_nodes or mat.node_tree is None:
        return None
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    node = _linked_node(out.inputs["Surface"]) if out is not None else None
    if node is None or node.bl_idname != "ShaderNodeBsdfTransparent":
        return None
    color = node.inputs["Color"]
    if not color.is_linked and all(float(v) >= 1 for v in color.default_value[:3]):
        return "Transparent BSDF surfaces (left out: transparent)"
    return None  # a coloured one filters the rays through it: kind 'transparent'


def export_material(sphrect, mat, log, textures=None):
    """sphrect.Material of a Blender material; the images its Image Texture nodes read go to `textures`
    (a TextureExport, the scene's list)."""
    textures = textures if textures is not None else TextureExport(sphrect, log)
    if mat is None:
        return sphrect.Material(name="default")
    name = mat.name
    if not mat.use_nodes or mat.node_tree is None:
        return sphrect.Material(name=name, kind="diffuse", base_color=_rgb(mat.diffuse_color))
    _warn_of_deep_groups(mat.node_tree, log, name)
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    if left_out_surface(mat):  # its triangles are left out (geometry.triangulate), which warns per object
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.0, 0.0, 0.0))
    # A Volume link is the object volume's (volumes.py), read per object.
    node = _linked_shader(out.inputs["Surface"]) if out is not None else None
    if node is None:
        log.unsupported_feature("materials without a surface shader (black)", name)
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.0, 0.0, 0.0))
    textures.displacement = _displacement_socket(mat, out, log)
    try:
        material = _shader(sphrect, node, textures, log, name)
        if textures.displacement is not None and material.normal_program is None and material.normal_map is None:
            program = ProgramCompiler(sphrect, textures, log, name).compile_displaced_normal()
            if program is not None and not is_shading_normal(sphrect, program):
                material = dataclasses.replace(material, normal_program=program)
    finally:
        textures.displacement = None
    return _split_programs(sphrect, material)


def _displacement_socket(mat, out, log):
    """The Material Output's Displacement input when Cycles bumps the shading normal with it (ProgramCompiler.
    displaced_normal: 3.4's default method, Bump Only), else None; what is not drawn is said."""
    socket = out.inputs["Displacement"]
    if not socket.is_linked:
        return None
    method = getattr(getattr(mat, "cycles", None), "displacement_method", "BUMP")
    if method == "DISPLACEMENT":
        log.unsupported_feature("true displacement (the surface drawn undisplaced)", mat.name)
        return None
    if method == "BOTH":
        log.unsupported_feature("displacement 'Displacement and Bump' (the surface undisplaced, its bump in world "
                                "space)", mat.name)
    return socket


def _split_programs(sphrect, material):
    """The material with the NodePrograms its inputs' `textures` hold (_Inputs) moved to `programs`, its layers'
    too."""
    programs = {k: v for k, v in material.textures.items() if isinstance(v, sphrect.NodeProgram)}
    layers = [dataclasses.replace(l, material=_split_programs(sphrect, l.material)) for l in material.layers]
    if not programs and not any(l.material is not k.material for l, k in zip(layers, material.layers)):
        return material
    return dataclasses.replace(material, layers=layers, programs={**material.programs, **programs},
                               textures={k: v for k, v in material.textures.items() if k not in programs})


def _emission_term(node, color_input, strength_input, weight, log, owner, textures=None, light_coordinates=None):
    """(weight x colour x strength, None) -- Cycles' emission closure weight -- or, for a colour an Image Texture
    drives, (weight x strength, its TextureLookup): the renderer multiplies the emission by the image's colour at each
    point of the emitter (Material.textures["emission"], or a light's texture: light_coordinates as
    TextureExport.lookup's).  A negative strength is logged and read as 0 (Cycles 3.4 does not clamp it: its emission
    would be negative)."""
    socket = node.inputs.get(color_input)
    source = image_texture_source(socket) if textures is not None and socket is not None and socket.is_linked else None
    strength_socket = node.inputs.get(strength_input)
    if textures is not None and light_coordinates is None and socket is not None and strength_socket is not None \
            and (source is None or strength_socket.is_linked) and (socket.is_linked or strength_socket.is_linked):
        # A graph the renderer evaluates per hit: its colour x strength multiplies weight (the emitter's constant).
        program, _ = compile_product(textures.sphrect, textures, log, owner, socket, strength_socket)
        if program is not None:
            return _rgb(np.full(3, weight)), program
    lookup = textures.lookup(*source, owner, light_coordinates) if source is not None else None
    color = np.ones(3) if lookup is not None else np.asarray(_value(node, color_input, log, owner)[:3], dtype=float)
    strength = _value(node, strength_input, log, owner)
    if strength < 0:
        log.unsupported_feature("negative emission strength (0 used)", owner)
        strength = 0.0
    return _rgb(np.clip(color, 0, None) * strength * weight), lookup


def _emission(node, color_input, strength_input, weight, log, owner, textures=None):
    """_emission_term's emission as one constant: an image's colour taken as its mean, warned (where the renderer
    cannot vary it: under a texture-driven Mix Shader factor)."""
    emission, lookup = _emission_term(node, color_input, strength_input, weight, log, owner, textures)
    if lookup is None:
        return emission
    source = "a node graph" if isinstance(lookup, textures.sphrect.NodeProgram) else "an Image Texture"
    mean = "its mean colour over the UV square" if source == "a node graph" else "the image's mean colour"
    log.unsupported_feature(f"'{color_input}' of an emitter from {source} under a texture-driven Mix Shader "
                            f"factor ({mean} used)", owner)
    return _rgb(np.asarray(emission) * np.asarray(_color_mean(textures, lookup)))


def _color_mean(textures, lookup):
    """The mean colour of an emission's TextureLookup or NodeProgram (a program's over the UV square; one that reads
    images: grey 1/2)."""
    if isinstance(lookup, textures.sphrect.NodeProgram):
        mean = program_mean(textures.sphrect, lookup)
        return mean if mean is not None else (0.5, 0.5, 0.5)
    return textures.color_mean(lookup)


def _textured_emission(material):
    """(emission, its lookup or None) of a material from _bsdf, and the material without its emission."""
    lookup = material.textures.get("emission")  # a TextureLookup or a NodeProgram (_emission_term)
    plain = dataclasses.replace(material, emission=(0.0, 0.0, 0.0),
                                textures={k: v for k, v in material.textures.items() if k != "emission"})
    return material.emission, lookup, plain


def _with_emission(material, constant, textured, textures, log, name):
    """The material with the summed emission: constant (RGB) plus the textured terms [(scale, TextureLookup or
    NodeProgram)].  One alone is the material's emission texture or program; several, or one beside a constant
    emission, are summed into one program (node_program.emission_sum)."""
    constant = np.asarray(constant, dtype=float)
    if len(textured) == 1 and not np.any(constant > 0):
        scale, lookup = textured[0]
        return dataclasses.replace(material, emission=_rgb(scale), textures={**material.textures, "emission": lookup})
    if textured:  # their sum as one program (the renderer's emitter is one program times a constant)
        program = emission_sum(textures.sphrect, _rgb(constant), [(_rgb(scale), lookup) for scale, lookup in textured])
        if program is not None:
            return dataclasses.replace(material, emission=(1.0, 1.0, 1.0),
                                       textures={**material.textures, "emission": program})
        log.unsupported_feature("emission from several Image Textures, or from one beside a constant emission (the "
                                "images' mean colours used)", name)
        for scale, lookup in textured:
            constant = constant + np.asarray(scale) * np.asarray(_color_mean(textures, lookup))
    return dataclasses.replace(material, emission=_rgb(constant))


# Distinct lists of texture-driven Mix Shader factors a material's shaders may sit under (_closures): past it,
# the graph's texture-driven mixes are not modelled.
MAX_FACTOR_LISTS = 1024


def _closure_sources(sphrect, node, textures, name):
    """Where the closures of shader node `node` come from: [(node or WHITE_TRANSPARENT, weight, MixFactor or None,
    whether it is a shader of its own)] (svm_node_mix_closure: the factor clamped to [0, 1], (1 - fac) to the
    first input, fac to the second, a side of weight 0 skipped as Cycles does; Add: 1 to each; a Principled BSDF
    whose Alpha is below 1 or an image's: Cycles' PrincipledBsdfNode::expand, a Mix Shader of Fac = Alpha, a white
    Transparent BSDF first); [(node, 1, None, True)] for any other shader; None for a Mix factor linked from
    anything but an Image Texture (not modelled)."""
    if node.bl_idname == "ShaderNodeMixShader":
        fac_socket = node.inputs[0]
        first, second = _linked_shader(node.inputs[1]), _linked_shader(node.inputs[2])
        if not fac_socket.is_linked:
            fac = min(max(float(fac_socket.default_value), 0.0), 1.0)
            return [(n, w, None, False) for n, w in ((first, 1 - fac), (second, fac)) if n is not None and w > 0]
        source = image_texture_source(fac_socket)
        program = None
        if source is None:
            program, constant = compile_socket(sphrect, textures, textures.log, name, fac_socket, "float")
            if program is None and constant is None:
                return None
            if program is None:  # a graph of known nodes folding to a constant
                fac = min(max(float(constant), 0.0), 1.0)
                return [(n, w, None, False) for n, w in ((first, 1 - fac), (second, fac)) if n is not None and w > 0]
        if first is not None and first == second:  # (1 - fac) + fac of the same closures: exactly those
            return [(first, 1.0, None, False)]
        if program is not None:
            return [(n, 1.0, sphrect.MixFactor(program=program, complement=n is first), False)
                    for n in (first, second) if n is not None]
        lookup = textures.lookup(*source, name)
        return [(n, 1.0, sphrect.MixFactor(lookup=lookup, complement=n is first), False)
                for n in (first, second) if n is not None]
    if node.bl_idname == "ShaderNodeAddShader":
        return [(n, 1.0, None, False) for n in map(_linked_shader, node.inputs) if n is not None]
    if node.bl_idname == "ShaderNodeBsdfPrincipled" and _has_alpha(node):
        alpha_socket = node.inputs["Alpha"]
        source = image_texture_source(alpha_socket, projected=True) if alpha_socket.is_linked else None
        if source is not None:
            lookup = textures.lookup(*source, name)
            return [(WHITE_TRANSPARENT, 1.0, sphrect.MixFactor(lookup=lookup, complement=True), True),
                    (node, 1.0, sphrect.MixFactor(lookup=lookup), True)]
        alpha = min(max(float(alpha_socket.default_value), 0.0), 1.0)
        return [(WHITE_TRANSPARENT, 1 - alpha, None, True), (node, alpha, None, True)]
    return [(node, 1.0, None, True)]


def _factor_key(factor):
    if factor.program is not None:
        return ("program", repr(factor.program), factor.complement)
    lookup = factor.lookup
    return (lookup.texture, lookup.output, lookup.coordinates, repr(lookup.transform), lookup.interpolation,
            lookup.extension, factor.complement)


def _closures(sphrect, node, textures, log, name):
    """[(weight, shader node, mix factors)] of the shaders a tree of Mix and Add Shader nodes from `node` reaches
    (_closure_sources), in the order a depth-first walk first reaches them, or None (warned) when the Mix factors
    are not modelled.  Each shader comes once per list of texture-driven factors above it, its weights summed over the
    paths to it: the graph is walked once per node (and factor list), as Cycles compiles each node once, not once
    per path (paths may be exponentially many).  A texture-driven factor is a MixFactor of each shader below it (its
    complement for the first input)."""
    root = (("node", node.key), ())
    states = {root: (node, [])}  # (node key, factor keys) -> (node, MixFactors): a node under a list of factors
    edges, shaders, finished, done, factor_lists = {}, [], [], set(), set()
    stack = [root]
    while stack:  # depth first, without recursion: a graph may be deeper than Python's stack
        state = stack[-1]
        if state in edges:
            stack.pop()
            if state not in done:
                done.add(state)
                finished.append(state)
            continue
        edges[state] = _state_edges(sphrect, state, states, shaders, textures, name)
        if edges[state] is None:
            log.unsupported_feature("linked Mix Shader factor (grey diffuse used)", name)
            return None
        if any(child in edges and child not in done for child, _ in edges[state]):  # not with valid links
            log.unsupported_feature("a cycle of shader nodes (the link closing it left out)", name)
            edges[state] = [(child, w) for child, w in edges[state] if child not in edges or child in done]
        factor_lists.update(factors for _, factors in edges[state])
        if len(factor_lists) > MAX_FACTOR_LISTS:
            log.unsupported_feature(f"more than {MAX_FACTOR_LISTS} combinations of texture-driven Mix Shader "
                                    "factors (grey diffuse used)", name)
            return None
        stack.extend(reversed([child for child, _ in edges[state] if child not in edges]))
    weights = dict.fromkeys(states, 0.0)
    weights[root] = 1.0
    for state in reversed(finished):  # parents before children: a state's weight is complete when it is read
        for child, weight in edges[state]:
            weights[child] += weights[state] * weight
    return [(weights[state], *states[state]) for state in shaders]


def _state_edges(sphrect, state, states, shaders, textures, name):
    """The states state's closures come from, with their weights (a shader of its own has none)."""
    (kind, _), factor_keys = state
    node, factors = states[state]
    if kind == "shader":
        shaders.append(state)
        return []
    sources = _closure_sources(sphrect, node, textures, name)
    if sources is None:
        return None
    edges = []
    for source, weight, factor, own in sources:
        key = (("shader" if own else "node", source if source is WHITE_TRANSPARENT else source.key),
               factor_keys + ((_factor_key(factor),) if factor is not None else ()))
        states.setdefault(key, (source, factors + ([factor] if factor is not None else [])))
        edges.append((key, weight))
    return edges


# The white Transparent BSDF Cycles mixes under a Principled BSDF whose Alpha is below 1 (_closures).
WHITE_TRANSPARENT = "white Transparent BSDF of a Principled Alpha"


def _has_alpha(node):
    """Whether a Principled BSDF's Alpha makes it partly transparent: below 1, or linked (an Image Texture: per hit;
    anything else is not modelled, Alpha 1 used and warned by _principled)."""
    socket = node.inputs.get("Alpha")
    if socket is None:
        return False
    if socket.is_linked:
        return image_texture_source(socket, projected=True) is not None
    return float(socket.default_value) < 1


def _transparent(sphrect, leaf, textures, log, name):
    """kind 'transparent' of a Transparent BSDF node (its Color, or an Image Texture's) or of WHITE_TRANSPARENT."""
    if leaf is WHITE_TRANSPARENT:
        return sphrect.Material(name=name, kind="transparent", base_color=(1.0, 1.0, 1.0))
    inputs = _Inputs(sphrect, leaf, textures, log, name)
    return sphrect.Material(name=name, kind="transparent", base_color=_rgb(inputs.read("base_color")),
                            textures=inputs.textures)


def _is_textured(layer):
    """Whether a layer reads a texture (its material's inputs, normal map or its mix factors): such layers are
    evaluated per hit by the renderer and never merged with others here."""
    m = layer.material
    return bool(layer.factors or m.textures or m.normal_map is not None or m.normal_program is not None)


def _shader(sphrect, node, textures, log, name):
    """The surface shader behind the output: one BSDF, or the weighted sum of the shaders a tree of Mix and Add
    Shader nodes reaches (kind 'mix'), emission summed."""
    leaves = _closures(sphrect, node, textures, log, name)
    if leaves is None:  # warned
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.8, 0.8, 0.8))
    emission = np.zeros(3)
    textured_emission = []  # [(scale, TextureLookup)]: emission an image drives (_with_emission)
    layers = []
    # An emitter's emission is one image times a constant (Material.textures["emission"]): under a texture-driven
    # factor it takes the factor's mean over its image.
    constant_emission = "emission under a texture-driven Mix Shader factor (the factor's image mean used)"
    for weight, leaf, factors in leaves:
        if isinstance(leaf, ImplicitEmission):
            program, value = compile_socket(sphrect, textures, log, name, leaf.socket, "color")
            if program is None and value is None:
                log.unsupported_feature(f"'{follow_reroutes(leaf.socket)[0].bl_label}' node on a shader input (no "
                                        "emission)", name)
                continue
            term = weight * (np.ones(3) if program is not None else np.clip(np.asarray(value[:3], float), 0, None))
            if factors:  # the factors' weights multiply it per point, as an Emission's
                combined = emission_under_factors(sphrect, program, factors)
                if combined is not None:
                    textured_emission.append((term, combined))
                else:
                    log.unsupported_feature(constant_emission, name)
                    emission += term * textures.factor_mean(factors)
            elif program is None:
                emission += term
            else:
                textured_emission.append((term, program))
        elif leaf is WHITE_TRANSPARENT or leaf.bl_idname == "ShaderNodeBsdfTransparent":
            transparent = _transparent(sphrect, leaf, textures, log, name)
            layers.append(sphrect.MaterialLayer(weight=weight, material=transparent, factors=factors))
        elif leaf.bl_idname == "ShaderNodeEmission":
            if factors:  # the factors' weights multiply the emission per point (a program)
                term, lookup = _emission_term(leaf, "Color", "Strength", weight, log, name, textures)
                program = emission_under_factors(sphrect, lookup, factors)
                if program is not None:
                    textured_emission.append((term, program))
                else:
                    log.unsupported_feature(constant_emission, name)
                    emission += _emission(leaf, "Color", "Strength", weight * textures.factor_mean(factors), log,
                                          name, textures)
            else:
                term, lookup = _emission_term(leaf, "Color", "Strength", weight, log, name, textures)
                if lookup is None:
                    emission += term
                else:
                    textured_emission.append((term, lookup))
        elif leaf.bl_idname == "ShaderNodeHoldout":  # black, and a hole in the film's alpha (1 - its weight)
            if factors:  # the film's alpha is made at the camera hit from the material's constant holdout
                log.unsupported_feature("Holdout under a texture-driven Mix Shader factor (the factor's image mean "
                                        "used)", name)
            layers.append(sphrect.MaterialLayer(weight=weight * textures.factor_mean(factors),
                                                material=sphrect.Material(name=name, kind="holdout")))
        else:
            own, lookup, plain = _textured_emission(_bsdf(sphrect, leaf, textures, log, name))
            program = emission_under_factors(sphrect, lookup, factors) if factors and any(c > 0 for c in own) \
                else None
            if program is not None:
                textured_emission.append((weight * np.asarray(own), program))
            elif factors and any(c > 0 for c in own):
                log.unsupported_feature(constant_emission, name)
                if lookup is not None:
                    log.unsupported_feature("an emission Image Texture under a texture-driven Mix Shader factor (the "
                                            "image's mean colour used)", name)
                    own = np.asarray(own) * np.asarray(_color_mean(textures, lookup))
                emission += weight * textures.factor_mean(factors) * np.asarray(own)
            elif lookup is not None:
                textured_emission.append((weight * np.asarray(own), lookup))
            else:
                emission += weight * np.asarray(own)
            layers.append(sphrect.MaterialLayer(weight=weight, material=plain, factors=factors))
    layers = _fit_mix(sphrect, layers, textures, log, name)
    with_emission = lambda m: _with_emission(m, emission, textured_emission, textures, log, name)  # noqa: E731
    if not layers:
        return with_emission(sphrect.Material(name=name, kind="diffuse", base_color=(0.0, 0.0, 0.0)))
    if all(l.material.kind == "diffuse" and l.material.diffuse_roughness == 0 and not _is_textured(l) for l in layers):
        # Lambert is linear in its colour: one diffuse, exactly
        color = sum(l.weight * np.asarray(l.material.base_color) for l in layers)
        return with_emission(sphrect.Material(name=name, kind="diffuse", base_color=_rgb(color)))
    if len(layers) == 1 and layers[0].weight == 1 and not layers[0].factors:
        return with_emission(layers[0].material)
    normal_map = _mix_normal_map(layers, log, name)
    return with_emission(sphrect.Material(name=name, kind="mix", layers=layers, **normal_map))


def _mix_normal_map(layers, log, name):
    """The mix's normal map (a mix's layers have none of their own): the one every layer has, else the first
    one (warned); taken off the layers."""
    maps = [(l.material.normal_map, l.material.normal_map_strength, l.material.normal_program) for l in layers]
    used = [m for m in maps if m[0] is not None or m[2] is not None]
    if not used:
        return {}
    if len(used) < len(maps) or any(m != used[0] for m in used[1:]):
        log.unsupported_feature("shaders of a mix with different normal maps or Bump nodes (the first one used for "
                                "all)", name)
    for l in layers:
        l.material = dataclasses.replace(l.material, normal_map=None, normal_map_strength=1.0, normal_program=None)
    return {"normal_map": used[0][0], "normal_map_strength": used[0][1], "normal_program": used[0][2]}


def _average_principled(sphrect, principled, weights=None):
    """One layer for several Principled BSDF layers: their total weight, weight-averaged inputs and colour
    (`weights`: the layers' own by default)."""
    weights = [l.weight for l in principled] if weights is None else weights
    total = sum(weights)
    fields = ("roughness", "metallic", "specular", "specular_tint", "sheen", "sheen_tint", "clearcoat",
              "clearcoat_roughness")
    average = lambda values: sum(w * np.asarray(v, dtype=float) for w, v in zip(weights, values)) / total
    averaged = {f: float(average([getattr(l.material, f) for l in principled])) for f in fields}
    merged = dataclasses.replace(principled[0].material, base_color=_rgb(average([l.material.base_color for l in
                                                                                principled])),
                                 emission=_rgb(average([l.material.emission for l in principled])), **averaged)
    return sphrect.MaterialLayer(total, merged)


def _fit_mix(sphrect, layers, textures, log, name):
    """The layers as the renderer's mix can hold them: several untextured Principled BSDFs of equal inputs but for
    the base colour merge exactly (weights summed, colours weight-averaged) where no tint makes the closures
    non-linear in it; other untextured ones are replaced by one of their weight-averaged inputs and total weight;
    textured layers (textures.py: evaluated per hit) stay apart, but for Principled BSDFs (the renderer's mix holds
    one): several with a textured one are averaged too, each mix factor read as its image's mean, the heaviest
    textured one's textures kept; glossy / glass lobes beyond sphrect.MAX_MIX_GLOSSY_LOBES distinct ones are
    dropped, lightest first; all warned."""
    plain = [l for l in layers if l.material.kind == "principled" and not _is_textured(l)]
    if len(plain) > 1:
        # Cycles' closures are linear in the base colour when neither tint divides it by its luminance.
        inputs = [dataclasses.replace(l.material, name="", emission=(0.0, 0.0, 0.0), base_color=(0.0, 0.0, 0.0))
                  for l in plain]
        m0 = plain[0].material
        linear_in_color = m0.specular_tint == 0 and (m0.sheen == 0 or m0.sheen_tint == 0)
        if any(m != inputs[0] for m in inputs[1:]) or not linear_in_color:
            log.unsupported_feature(f"a mix of {len(plain)} different Principled BSDFs (one of their "
                                    "weight-averaged inputs used)", name)
        layers = [l for l in layers if not any(l is p for p in plain)] + [_average_principled(sphrect, plain)]
    principled = [l for l in layers if l.material.kind == "principled"]
    if len(principled) > 1:
        log.unsupported_feature(f"a mix of {len(principled)} Principled BSDFs, textured ones among them (one of "
                                "their averaged inputs used, mix factors read as their images' means)", name)
        weights = [l.weight * textures.factor_mean(l.factors) for l in principled]
        merged = _average_principled(sphrect, principled, weights)
        textured = max((l for l in principled if l.material.textures or l.material.normal_map is not None
                        or l.material.normal_program is not None), key=lambda l: l.weight, default=None)
        if textured is not None:
            merged.material = dataclasses.replace(merged.material, textures=textured.material.textures,
                                                  normal_map=textured.material.normal_map,
                                                  normal_map_strength=textured.material.normal_map_strength,
                                                  normal_program=textured.material.normal_program)
        layers = [l for l in layers if l.material.kind != "principled"] + [merged]
    # The renderer says which glossy / glass layers share a lobe; a textured roughness keeps a layer's lobe apart
    # (at a hit its roughness is the image's).
    glossy = [l for l in layers if l.material.kind in ("glass", "glossy_bsdf")]
    keys = {id(l): (slot, repr(l.material.textures.get("roughness")))
            for l, slot in zip(glossy, sphrect.mix_lobe_slots([l.material for l in glossy]))}
    lobes = {}
    for l in glossy:
        lobes[keys[id(l)]] = lobes.get(keys[id(l)], 0.0) + l.weight
    if len(lobes) > sphrect.MAX_MIX_GLOSSY_LOBES:
        kept = set(sorted(lobes, key=lobes.get, reverse=True)[:sphrect.MAX_MIX_GLOSSY_LOBES])
        log.unsupported_feature(f"a mix of {len(lobes)} glossy / glass shaders of different roughness or IOR "
                                f"(the {sphrect.MAX_MIX_GLOSSY_LOBES} heaviest kept)", name)
        layers = [l for l in layers if id(l) not in keys or keys[id(l)] in kept]
    return layers


def _bsdf(sphrect, node, textures, log, name):
    """A Diffuse, Principled, Glossy, Anisotropic, Glass or Refraction BSDF node (the Principled one's own emission
    included)."""
    inputs = _Inputs(sphrect, node, textures, log, name)
    if node.bl_idname == "ShaderNodeBsdfDiffuse":
        color = _rgb(inputs.read("base_color"))
        roughness = float(inputs.value("Roughness"))  # Cycles' Oren-Nayar where not 0 (Material.diffuse_roughness)
        return sphrect.Material(name=name, kind="diffuse", base_color=color, diffuse_roughness=roughness,
                                textures=inputs.textures, **_normal_map(node, textures, log, name))
    if node.bl_idname == "ShaderNodeBsdfPrincipled":
        return _principled(sphrect, node, inputs, textures, log, name)
    if node.bl_idname in {"ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction"}:
        return _glass(sphrect, node, inputs, textures, log, name)
    if node.bl_idname in {"ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic"}:
        return _glossy(sphrect, node, inputs, textures, log, name)
    if node.bl_idname == "ShaderNodeBsdfTranslucent":  # Lambertian transmission: lit through the surface
        return sphrect.Material(name=name, kind="translucent", base_color=_rgb(inputs.read("base_color")),
                                textures=inputs.textures, **_normal_map(node, textures, log, name))
    log.unsupported_feature(f"'{node.bl_label or node.bl_idname}' shader node (grey diffuse used)", name)
    return sphrect.Material(name=name, kind="diffuse", base_color=(0.8, 0.8, 0.8))


def _glossy(sphrect, node, inputs, textures, log, name):
    """Glossy BSDF and Blender 3.4's Anisotropic BSDF as Cycles 3.4 evaluates them: Color x GGX or Beckmann
    reflection of alpha = Roughness^2, no Fresnel (kind 'glossy_bsdf'), the Anisotropic BSDF's GGX stretched along
    Cycles' default tangent by its Anisotropy and turned by its Rotation; Sharp (or roughness ~0) is a delta lobe whose
    mirror ray the renderer traces, as Cycles does at zero bounces."""
    distribution = getattr(node, "distribution", "GGX")
    roughness = 0.0 if distribution == "SHARP" else float(inputs.read("roughness"))
    rough = roughness > 0 or "roughness" in inputs.textures
    if distribution == "ASHIKHMIN_SHIRLEY" and rough:
        log.unsupported_feature(f"{node.bl_label} distribution 'Ashikhmin-Shirley' (GGX used)", name)
    anisotropy = {}
    if node.bl_idname == "ShaderNodeBsdfAnisotropic":
        anisotropy = _anisotropy(node, inputs, "Anisotropy", "Rotation", log, name)
        if anisotropy and distribution == "BECKMANN":
            log.unsupported_feature("anisotropy of a Beckmann Anisotropic BSDF (isotropic used)", name)
            anisotropy = {}
    color = _rgb(inputs.read("base_color"))
    return sphrect.Material(name=name, kind="glossy_bsdf", base_color=color, roughness=roughness,
                            distribution=_GLOSSY_DISTRIBUTIONS.get(distribution, "ggx"),
                            textures=inputs.textures, **anisotropy, **_normal_map(node, textures, log, name))


# Blender's Glossy / Anisotropic BSDF distributions -> Material.distribution (Sharp, Ashikhmin-Shirley: GGX).
_GLOSSY_DISTRIBUTIONS = {"BECKMANN": "beckmann", "MULTI_GGX": "multiscatter_ggx"}


def _anisotropy(node, inputs, amount, rotation, log, name):
    """Material.anisotropic / anisotropic_rotation of a shader's anisotropy inputs ({} when isotropic), along
    Cycles' default tangent (a linked Tangent is not modelled: warned)."""
    value = float(inputs.value(amount))
    if value == 0:
        return {}
    tangent = node.inputs.get("Tangent")
    if tangent is not None and tangent.is_linked:
        log.unsupported_feature("linked 'Tangent' input (the default radial tangent used)", name)
    return {"anisotropic": value, "anisotropic_rotation": float(inputs.value(rotation))}


def _glass(sphrect, node, inputs, textures, log, name):
    """Glass or Refraction BSDF as Cycles 3.4 shows it at zero bounces: the Glass BSDF's GGX / Beckmann reflection
    of the lights, weighted by the dielectric Fresnel of the view (kind 'glass'); the refracted part of a rough one,
    the whole of a Refraction BSDF, is black (it needs a bounce, or a light seen through an open surface: not
    modelled).  A sharp glass's reflected and refracted rays are traced (the emitters they find)."""
    distribution = getattr(node, "distribution", "GGX")
    roughness = 0.0 if distribution == "SHARP" else float(inputs.read("roughness"))
    if distribution == "MULTI_GGX" and (roughness > 0 or "roughness" in inputs.textures):
        log.unsupported_feature(f"{node.bl_label} distribution 'Multiscatter GGX' (GGX used)", name)
    normal_map = _normal_map(node, textures, log, name)
    if node.bl_idname == "ShaderNodeBsdfRefraction" or not _singular(sphrect, roughness, inputs):
        _warn_rough_refraction(log, name)
    color = _rgb(inputs.read("base_color"))
    if node.bl_idname == "ShaderNodeBsdfRefraction":
        color = (0.0, 0.0, 0.0)
    return sphrect.Material(name=name, kind="glass", base_color=color, roughness=roughness,
                            ior=float(inputs.value("IOR")),
                            distribution="beckmann" if distribution == "BECKMANN" else "ggx",
                            textures=inputs.textures, **normal_map)


def _singular(sphrect, roughness, inputs):
    """Whether an untextured roughness makes Cycles' closure singular: a sharp mirror or glass, whose mirror and
    refracted rays the renderer traces (what Cycles shows of them at zero bounces)."""
    return "roughness" not in inputs.textures and sphrect.is_singular_roughness(roughness)


def _warn_rough_refraction(log, name):
    log.unsupported_feature("refraction of lights seen through a surface (black where rough, as Cycles at zero "
                            "bounces except behind open surfaces)", name)


# Principled BSDF inputs read into sphrect.Material (kind 'principled'), by the Material field they fill.
_PRINCIPLED_INPUTS = {"metallic": "Metallic", "specular": "Specular", "specular_tint": "Specular Tint",
                      "roughness": "Roughness", "sheen": "Sheen", "sheen_tint": "Sheen Tint",
                      "clearcoat": "Clearcoat", "clearcoat_roughness": "Clearcoat Roughness"}
# Above Cycles' closure cutoff these change the image and are not modelled.
_PRINCIPLED_UNSUPPORTED = (("Subsurface", "subsurface scattering (Burley diffuse used)"),)


def _principled(sphrect, node, inputs, textures, log, name):
    """Cycles 3.4's Principled BSDF (svm_node_closure_bsdf), GGX or Multiscatter GGX."""
    if (inputs.value("Transmission") >= 1 and not inputs.textured("metallic")
            and inputs.unwarned("Metallic") <= 0):
        glass = _principled_glass(sphrect, node, inputs, textures, log, name)
        if glass is not None:
            return glass
    color = _rgb(inputs.read("base_color"))
    values = {field: float(inputs.read(field) if field in inputs.textured_fields else inputs.value(socket))
              for field, socket in _PRINCIPLED_INPUTS.items()}
    for socket, what in _PRINCIPLED_UNSUPPORTED:
        _nonzero_input(node, socket, log, name, what)
    # Multiscatter GGX: Cycles' random walk above roughness 0.075 (the renderer's switch, as Cycles' closure setup).
    if getattr(node, "distribution", "GGX") == "MULTI_GGX":
        values["distribution"] = "multiscatter_ggx"
    values.update(_principled_transmission(sphrect, node, inputs, values, log, name))
    clearcoat_normal = node.inputs.get("Clearcoat Normal")
    if values["clearcoat"] > 0 and clearcoat_normal is not None and clearcoat_normal.is_linked:
        log.unsupported_feature("linked 'Clearcoat Normal' input", name)
    values.update(_anisotropy(node, inputs, "Anisotropic", "Anisotropic Rotation", log, name))
    emission, lookup = _emission_term(node, "Emission", "Emission Strength", 1.0, log, name, textures)
    _unmodelled_alpha(node, log, name)
    return sphrect.Material(name=name, kind="principled", base_color=color, emission=emission,
                            textures={**inputs.textures, **({"emission": lookup} if lookup else {})},
                            **_normal_map(node, textures, log, name), **values)


def _principled_transmission(sphrect, node, inputs, values, log, name):
    """Material.transmission / ior of a Principled BSDF whose Transmission is above 0 ({} otherwise): its glass part
    reflects the lights as a Glass BSDF does at zero bounces (Cycles' closure weight t (1 - metallic), the Fresnel of
    the view), the refracted part black when rough (a sharp one's refracted ray is traced)."""
    transmission = float(inputs.value("Transmission"))
    if transmission <= 0:
        return {}
    if not _singular(sphrect, values["roughness"], inputs):
        _warn_rough_refraction(log, name)
    if values["specular_tint"] > 0:
        log.unsupported_feature("Specular Tint of the transmission's reflection (untinted)", name)
    if values.get("distribution") == "multiscatter_ggx" and values["roughness"] > 0.05:
        log.unsupported_feature("Multiscatter GGX of the transmission's reflection (GGX used)", name)
    return {"transmission": transmission, "ior": float(inputs.value("IOR"))}


def _unmodelled_alpha(node, log, name):
    """Warns of a Principled Alpha linked from something other than an Image Texture (Alpha 1 used); the rest is
    _closures' mix with a Transparent BSDF."""
    socket = node.inputs.get("Alpha")
    if socket is not None and socket.is_linked and image_texture_source(socket, projected=True) is None:
        log.unsupported_feature("Principled Alpha linked from a node other than an Image Texture (1 used)", name)


def _principled_glass(sphrect, node, inputs, textures, log, name):
    """A Principled BSDF of transmission 1, metallic 0: Cycles' closures are then only its glass (no diffuse,
    sheen or other specular), whose reflection is a white Glass BSDF's at the same roughness and IOR when the
    specular tint is 0 (cspec0 white) -- kind 'glass' (a Roughness texture kept).  None when a tint or clearcoat
    needs more."""
    if inputs.value("Specular Tint") > 0 or inputs.value("Clearcoat") > 0:
        return None
    roughness = float(inputs.read("roughness"))
    if _singular(sphrect, roughness, inputs) and tuple(_rgb(inputs.read("base_color"))) != (1.0, 1.0, 1.0):
        return None  # a sharp glass's refraction (traced) takes the base colour: kind 'principled' keeps it
    if getattr(node, "distribution", "GGX") == "MULTI_GGX" and (roughness > 0.05 or "roughness" in inputs.textures):
        log.unsupported_feature("Principled BSDF distribution 'Multiscatter GGX' (GGX used)", name)
    normal_map = _normal_map(node, textures, log, name)
    if not _singular(sphrect, roughness, inputs):
        _warn_rough_refraction(log, name)
    _unmodelled_alpha(node, log, name)
    emission, lookup = _emission_term(node, "Emission", "Emission Strength", 1.0, log, name, textures)
    return sphrect.Material(name=name, kind="glass", base_color=(1.0, 1.0, 1.0), roughness=roughness,
                            ior=float(inputs.value("IOR")), emission=emission,
                            textures={**{k: v for k, v in inputs.textures.items() if k == "roughness"},
                                      **({"emission": lookup} if lookup else {})}, **normal_map)


# Blender's Normal Map node Color when nothing is linked to it: the unperturbed normal.
_FLAT_NORMAL_COLOR = (0.5, 0.5, 1.0)


def _normal_map(node, textures, log, owner):
    """Material.normal_map / normal_map_strength of a shader's Normal input: a tangent-space Normal Map node whose
    Color an Image Texture drives ({} and a warning for other nodes, spaces or colours)."""
    socket = node.inputs.get("Normal")
    source = _linked_node(socket)
    if source is None:
        return {}
    if source.bl_idname == "ShaderNodeBump":
        return _bump_normal(socket, textures, log, owner)
    if source.bl_idname != "ShaderNodeNormalMap":
        log.unsupported_feature(f"'{source.bl_label or source.bl_idname}' node on a Normal input (ignored)", owner)
        return {}
    if source.space != "TANGENT":
        log.unsupported_feature(f"Normal Map space '{source.space}' (ignored)", owner)
        return {}
    strength = source.inputs["Strength"]
    if strength.is_linked:
        log.unsupported_feature("linked 'Strength' input of a Normal Map node (its value used)", owner)
    color = source.inputs["Color"]
    image = image_texture_source(color, projected=True)
    if image is None:
        if color.is_linked:
            feeding = _linked_node(color)
            label = (feeding.bl_label or feeding.bl_idname) if feeding is not None else "a reroute"
            log.unsupported_feature(f"Normal Map colour from '{label}' (ignored)", owner)
        elif any(abs(float(c) - f) > 1e-6 for c, f in zip(color.default_value, _FLAT_NORMAL_COLOR)):
            log.unsupported_feature("Normal Map node of an unlinked colour (ignored)", owner)
        return {}
    textures.name_uv_map(source.uv_map, owner)
    return {"normal_map": textures.lookup(*image, owner), "normal_map_strength": float(strength.default_value)}


def _bump_normal(socket, textures, log, owner):
    """Material.normal_program of a shader's Normal input a Bump node feeds (node_program.py compiles its Height
    three times), or {} when it leaves the shading normal as it is (an unlinked Height)."""
    sphrect = textures.sphrect
    program = ProgramCompiler(sphrect, textures, log, owner).compile(socket, "vector")
    if program is None or is_shading_normal(sphrect, program):
        return {}
    return {"normal_program": program}


def export_world(sphrect, world, log, textures=None):
    """sphrect.World of a Blender world: a constant Background, or an image world (sphrect.Environment, its image
    added to `textures`, a TextureExport: Scene.textures) where Cycles evaluates the Background's Color as an
    equirectangular Environment Texture (_direct_world); every other world surface baked by
    Cycles through _world_not_representable (world_bake.py); its Ray Visibility as World.invisible_to."""
    if world is None:
        return sphrect.World()
    hidden = world_invisible_to(world, sphrect.scene.WORLD_RAY_KINDS)
    if "diffuse" in hidden:  # measured: docs/renderer.md, Ray visibility
        log.unsupported_feature("world hidden from diffuse rays (the visible lobes lit exactly, where Cycles' glossy "
                                "rays also carry some diffuse reflection: docs/renderer.md)", world.name)
    return dataclasses.replace(_world_shading(sphrect, world, log, textures), invisible_to=hidden)


def _world_shading(sphrect, world, log, textures):
    if not world.use_nodes or world.node_tree is None:
        return sphrect.World(background=_rgb(world.color))
    _warn_of_deep_groups(world.node_tree, log, world.name)
    out = _active_output(world.node_tree, "ShaderNodeOutputWorld")
    if out is None:
        return sphrect.World()
    background, environment, camera_environment = (0.0, 0.0, 0.0), None, None
    surface = _linked_node(out.inputs["Surface"])
    if surface is not None:
        if textures is None:
            textures = TextureExport(sphrect, log)
        direct = _direct_world(sphrect, surface, textures, log, world.name)
        if direct is not None:
            background, environment = direct
        else:
            background, environment, camera_environment = _world_not_representable(sphrect, world, surface,
                                                                                   textures, log)
    medium = read_volume(sphrect, out.inputs["Volume"], world.name, log)[0]
    return sphrect.World(background=background, medium=medium, environment=environment,
                         camera_environment=camera_environment)


def _world_not_representable(sphrect, world, surface, textures, log):
    """(background, environment, camera_environment) of a world surface the renderer cannot take as it is
    (_direct_world), baked by Cycles (world_bake.py): the image as a linear float texture added to `textures`,
    strength 1 (the Background's Strength is in the image), identity to_world; background the image's mean radiance
    over the sphere (what a renderer without environments shows).  A world whose Light Path node's Is Camera Ray
    shows the camera something else is baked twice: its light (Is Camera Ray 0, as Cycles' light samples and BSDF
    rays see it) and what the camera sees (camera_environment).  A failed bake: a black world, said.  A bake of one
    colour (an RGB or Value node, a Mix of constants...) is that constant Background, as if typed in: no image to
    sample.  A Rendered viewport's export does not wait for a bake (world_bake.in_background): a stand-in
    meanwhile, the world's last bake it showed or else _stand_in_constant (the camera then sees the light)."""
    used = _light_path_outputs(world.node_tree, set())
    if used - {"Is Camera Ray"}:
        log.unsupported_feature(f"Light Path {', '.join(sorted(used - {'Is Camera Ray'}))} in a world (baked as "
                                "light samples see it, for every ray)", world.name)
    split = "Is Camera Ray" in used
    pixels = _baked_world(world, log, camera_rays=not split)
    if pixels is None:
        return (0.0, 0.0, 0.0), None, None
    if isinstance(pixels, world_bake.BakeNotReady):
        if pixels.stand_in is None:
            return _stand_in_constant(surface), None, None
        pixels = pixels.stand_in
    camera = _baked_world(world, log, camera_rays=True) if split else None
    camera_environment = None
    if camera is not None and not isinstance(camera, world_bake.BakeNotReady) and \
            not (camera.shape == pixels.shape and np.array_equal(camera, pixels)):
        if np.all(camera == camera[0, 0]):
            camera = camera[:1, :1]  # one colour: a 1 x 1 image
        camera_environment = _baked_environment(sphrect, textures, f"{world.name} (baked world, camera)", camera)
    if np.all(pixels == pixels[0, 0]):
        return _rgb(pixels[0, 0]), None, camera_environment
    environment = _baked_environment(sphrect, textures, f"{world.name} (baked world)", pixels)
    return _rgb(world_bake.sphere_mean(pixels)), environment, camera_environment


def _baked_environment(sphrect, textures, name, pixels):
    """An Environment (strength 1, identity) over a bake's linear radiance `pixels`, added to the scene's textures."""
    textures.list.append(sphrect.Texture(name=name, pixels=pixels, colorspace="linear"))
    return sphrect.Environment(texture=len(textures.list) - 1)


def _baked_world(world, log, camera_rays):
    """world_bake.bake_world's pixels; its BakeNotReady (a Rendered viewport's: the problem said if it failed); None
    when the bake failed (said)."""
    try:
        return world_bake.bake_world(world, camera_rays=camera_rays)
    except world_bake.BakeNotReady as not_ready:
        if not_ready.error is not None:
            log.problem(f"world '{world.name}' could not be baked by Cycles (a stand-in used): {not_ready.error}")
        return not_ready
    except world_bake.BakeError as e:
        log.problem(f"world '{world.name}' could not be baked by Cycles (black used): {e}")
        return None


def _stand_in_constant(surface):
    """The constant radiance a world shows while its first bake runs: a Background's or Emission's own Color x
    Strength (its node's values, whatever is linked to them), else black."""
    if surface.bl_idname not in {"ShaderNodeBackground", "ShaderNodeEmission"}:
        return (0.0, 0.0, 0.0)
    return _rgb(np.array(own_value(surface.inputs["Color"])[:3]) * float(own_value(surface.inputs["Strength"])))


def _light_path_outputs(tree, seen):
    """The names of the Light Path outputs a node tree (or a group inside it) links to something."""
    seen.add(tree.name_full)
    used = {link.from_socket.name for link in tree.links if link.from_node.bl_idname == "ShaderNodeLightPath"}
    for node in tree.nodes:
        group = getattr(node, "node_tree", None)
        if group is not None and group.name_full not in seen:
            used |= _light_path_outputs(group, seen)
    return used


def _direct_world(sphrect, surface, textures, log, owner):
    """(background, environment) of a Background the renderer takes as Cycles evaluates it, or None: a constant
    Color, or an Environment Texture (equirectangular) behind optional Mapping / Vector Rotate nodes and a Texture
    Coordinate (Generated, or Object: the ray's direction in a world) whose affine map is a rotation times a positive
    uniform scale without translation, its Color times a constant colour (a MixRGB Multiply) and the Strength."""
    if surface.bl_idname != "ShaderNodeBackground" or surface.inputs["Strength"].is_linked:
        return None
    strength = float(own_value(surface.inputs["Strength"]))
    color_socket = surface.inputs["Color"]
    if not color_socket.is_linked:
        return _rgb(np.array(own_value(color_socket)[:3]) * strength), None
    source, output = follow_reroutes(color_socket)
    factor = np.ones(3)
    if source is not None and source.bl_idname in {"ShaderNodeMixRGB", "ShaderNodeMix"}:
        source, output, factor = _constant_multiply(source)
    if source is None or source.bl_idname != "ShaderNodeTexEnvironment" or output.identifier != "Color" \
            or source.projection != "EQUIRECTANGULAR":
        return None
    rotation = _environment_rotation(source, textures, owner)
    if rotation is None:
        return None
    interpolation = _ENVIRONMENT_INTERPOLATIONS.get(source.interpolation)
    if interpolation is None:
        log.unsupported_feature(f"Environment Texture interpolation '{source.interpolation}' (Linear used)", owner)
        interpolation = "linear"
    environment = sphrect.Environment(texture=textures.texture_of(source.image, owner),
                                      strength=_rgb(factor * strength), to_world=rotation.T.tolist(),
                                      interpolation=interpolation)
    return (0.0, 0.0, 0.0), environment


_ENVIRONMENT_INTERPOLATIONS = {"Linear": "linear", "Closest": "closest"}  # Cubic and Smart: 'linear', warned


def _mix_color_sockets(mix):
    """(factor, A, B, blend type, clamped) of a legacy MixRGB node or a 3.4 Mix node of colours, else None."""
    if mix.bl_idname == "ShaderNodeMixRGB":
        return mix.inputs["Fac"], mix.inputs["Color1"], mix.inputs["Color2"], mix.blend_type, mix.use_clamp
    if mix.bl_idname == "ShaderNodeMix" and mix.data_type == "RGBA" and mix.factor_mode == "UNIFORM":
        by_id = {socket.identifier: socket for socket in mix.inputs}
        return by_id["Factor_Float"], by_id["A_Color"], by_id["B_Color"], mix.blend_type, mix.clamp_result
    return None


def _constant_multiply(mix):
    """(source node, its output, the constant colour factor) of a Multiply mix of a linked A by an unlinked B,
    mix(a, a b, fac) = a (1 - fac + fac b), or of an unlinked A by a linked B at factor 1 (a b); (None, None, None)
    for any other mix (clamped, a linked factor, another blend)."""
    none = (None, None, None)
    sockets = _mix_color_sockets(mix)
    if sockets is None:
        return none
    fac, a, b, blend, clamp = sockets
    if blend != "MULTIPLY" or clamp or fac.is_linked or a.is_linked == b.is_linked:
        return none
    f = min(max(float(own_value(fac)), 0.0), 1.0)
    if a.is_linked:
        source, output = follow_reroutes(a)
        return source, output, 1.0 - f + f * np.array(own_value(b)[:3])
    if f != 1.0:
        return none
    source, output = follow_reroutes(b)
    return source, output, np.array(own_value(a)[:3])


def _vector_rotate(node):
    """4x4 matrix of a Vector Rotate node (Cycles' svm_node_vector_rotate: about its Center, by Angle about Axis or
    X / Y / Z, or by an XYZ Euler rotation; Invert the inverse rotation), None where an input is linked."""
    if any(socket.is_linked for socket in node.inputs if socket.identifier != "Vector"):
        return None
    values = {socket.identifier: own_value(socket) for socket in node.inputs if socket.identifier != "Vector"}
    kind = node.rotation_type
    if kind == "EULER_XYZ":
        rotation = np.array(mathutils.Euler(values["Rotation"], "XYZ").to_matrix(), dtype=np.float64)
        if node.invert:
            rotation = rotation.T
    else:
        axis = {"X_AXIS": (1.0, 0.0, 0.0), "Y_AXIS": (0.0, 1.0, 0.0), "Z_AXIS": (0.0, 0.0, 1.0)}.get(kind)
        axis = mathutils.Vector(axis if axis is not None else values["Axis"])
        if axis.length == 0:
            return np.eye(4)  # Cycles leaves the vector as it is
        angle = -values["Angle"] if node.invert else values["Angle"]
        rotation = np.array(mathutils.Matrix.Rotation(angle, 3, axis.normalized()), dtype=np.float64)
    center = np.array(values["Center"], dtype=np.float64)
    m = np.eye(4)
    m[:3, :3] = rotation
    m[:3, 3] = center - rotation @ center
    return m


def _environment_rotation(node, textures, owner):
    """The rotation Q (3x3) under which Environment Texture `node` looks the ray direction w up at Q w (Cycles
    normalises its vector), or None: its Vector through Mapping and Vector Rotate nodes from nothing (the
    direction), a Texture Coordinate's Generated or Object output (in a world both the direction; Object of an
    object: its inverse matrix) must be an affine map s Q with s > 0 and no translation."""
    transform = np.eye(4)
    source, output = follow_reroutes(node.inputs["Vector"])
    while source is not None and source.bl_idname in {"ShaderNodeMapping", "ShaderNodeVectorRotate"}:
        mapping = textures._mapping(source, owner) if source.bl_idname == "ShaderNodeMapping" else \
            _vector_rotate(source)
        if mapping is None:
            return None
        transform = transform @ mapping
        source, output = follow_reroutes(source.inputs["Vector"])
        if source is None:
            return None  # an unlinked Vector is its own constant value
    if source is not None:
        if source.bl_idname != "ShaderNodeTexCoord" or output.identifier not in {"Generated", "Object"}:
            return None
        if output.identifier == "Object" and source.object is not None:
            transform = transform @ np.array(source.object.matrix_world.inverted(), dtype=np.float64)
    linear, translation = transform[:3, :3], transform[:3, 3]
    scale = abs(np.linalg.det(linear)) ** (1 / 3)
    if not scale > 1e-12 or np.linalg.det(linear) <= 0 or np.any(np.abs(translation) > 1e-6 * scale):
        return None
    q = linear / scale
    if not np.allclose(q @ q.T, np.eye(3), atol=1e-5):
        return None
    return q
