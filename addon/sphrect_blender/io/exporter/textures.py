"""Image Texture nodes -> sphrect.TextureLookup, and Blender images -> sphrect.Texture (one per image).

Pixels come from Blender's image data (packed, generated or on disk alike) with `foreach_get`, no per-pixel
Python: byte images as uint8 (Blender's bytes), float images as float32, Blender's row order (row 0 = bottom) and
channel count.  What Cycles 3.4 reads and how:

* colour space: a byte image's values are in its colour space ('sRGB' -> 'srgb', decoded after filtering as
  Cycles does; the data spaces -> 'linear'); a float image's buffer is already scene linear (Blender converts it
  on load; Cycles' BlenderImageLoader marks such builtin images raw), so float images are 'linear'.
* alpha: the colour is multiplied by the alpha as Cycles stores images, or not where the node's Alpha output is
  used (then Cycles divides it back): an image of partial alpha read both ways is two Textures (_apply_alpha_mode).
* a missing image (file not found, no image on the node) is Cycles' magenta (TEX_IMAGE_MISSING_*), warned.
* the Vector input: unlinked -> the active render UV map (Cycles' default); Texture Coordinate 'UV' /
  'Generated' or a UV Map node, through Mapping nodes (their affine maps composed into `transform`).
"""
import mathutils
import numpy as np

from ...native import load_sphrect
from .node_groups import CyclesNode, CyclesSocket, resolve, wrap_node

# Cycles' colour for an image it cannot read (kernel/svm/image.h TEX_IMAGE_MISSING_R/G/B/A).
MISSING_IMAGE_RGBA = (1.0, 0.0, 1.0, 1.0)
# Blender's colour spaces whose values are used as stored (the rest of the OCIO config is approximated as linear).
_LINEAR_COLORSPACES = {"Non-Color", "Linear", "Raw", "Linear Rec.709"}
_INTERPOLATIONS = {"Linear": "linear", "Closest": "closest"}  # Cubic and Smart: 'linear', warned
_IMAGE_NODE = "ShaderNodeTexImage"


def follow_reroutes(socket):
    """(node, output socket) feeding `socket` along the links Cycles follows (node_groups.py: through reroutes, muted
    nodes and node groups; both wrapped), or (None, None) when nothing does."""
    found = resolve(socket) if socket is not None else None
    if found is None:
        return None, None
    node, out, groups = found
    return CyclesNode(node, groups), CyclesSocket(out, groups)


def image_texture_source(socket, projected=False):
    """(Image Texture node, 'color' | 'alpha') when `socket` is linked from one (directly or through reroutes) that
    projects flat (a TextureLookup's); with `projected`, whatever its projection (read flat by a lookup, warned)."""
    node, output = follow_reroutes(socket)
    if node is None or node.bl_idname != _IMAGE_NODE or (node.projection != "FLAT" and not projected):
        return None
    return node, "alpha" if output.identifier == "Alpha" else "color"


def lookups_of(material):
    """Every TextureLookup a sphrect.Material reads (its inputs, normal map, layers and their mix factors)."""
    found = list(material.textures.values())
    if material.normal_map is not None:
        found.append(material.normal_map)
    for layer in material.layers:
        found.extend(f.lookup for f in layer.factors if f.lookup is not None)
        found.extend(lookups_of(layer.material))
    return found


def programs_of(material):
    """Every NodeProgram a sphrect.Material runs (its inputs', its normal's, its layers' and their mix factors')."""
    found = list(material.programs.values())
    if material.normal_program is not None:
        found.append(material.normal_program)
    for layer in material.layers:
        found.extend(f.program for f in layer.factors if f.program is not None)
        found.extend(programs_of(layer.material))
    return found


def has_normal_map(material):
    return material.normal_map is not None or any(has_normal_map(l.material) for l in material.layers)


def is_anisotropic(material):
    """Whether a lobe of the material is stretched along the mesh's tangent: Cycles' default one, radial about the
    object's Z axis from the Generated coordinates, in the object's space."""
    return material.anisotropic != 0 or any(is_anisotropic(l.material) for l in material.layers)


def _coordinates_read(program):
    """The mesh coordinates ('uv', 'generated') a NodeProgram reads."""
    names = load_sphrect().scene.NODE_GLOBALS
    return {names[i.mode] for i in program.instructions if i.op == "global"} & {"uv", "generated"}


def coordinates_needed(material):
    """The mesh coordinates ('uv', 'generated') a material reads; a normal map needs the UVs (its tangents), an
    anisotropic lobe the Generated coordinates (its radial tangent)."""
    needed = {lookup.coordinates for lookup in lookups_of(material)}
    for program in programs_of(material):
        needed |= _coordinates_read(program)
    if has_normal_map(material):
        needed.add("uv")
    if is_anisotropic(material):
        needed.add("generated")
    return needed


def _apply_alpha_mode(image, pixels, unassociated):
    """Turns Blender's pixels (float [H, W, C], in place) into the colour Cycles 3.4's Image Texture node gives:
    Cycles stores colour x alpha (a byte image of straight alpha is multiplied on load, in its encoded bytes;
    Blender's float buffers and 'Premultiplied' bytes already are), and divides the filtered colour by the alpha
    when the node's Alpha output is used (here per pixel: the same for Closest, close for Linear); neither for
    data colour spaces or 'Channel Packed' images; 'None' ignores the alpha (1).  Returns whether the two
    colours differ for this image (a byte image's unassociated colour is then no longer bytes)."""
    if pixels.shape[2] < 4:
        return False
    mode = image.alpha_mode
    if mode == "NONE":
        pixels[..., 3] = 1.0
        return False
    alpha = pixels[..., 3:4]
    if mode == "CHANNEL_PACKED" or image.colorspace_settings.is_data or not (alpha < 1).any():
        return False
    color = pixels[..., :3]
    if mode == "STRAIGHT" and not image.is_float:  # BlenderImageLoader's integer premultiply: c a / 255, truncated
        as_bytes = np.round(pixels * 255.0).astype(np.int32)
        color[...] = (as_bytes[..., :3] * as_bytes[..., 3:4] // 255) / 255.0
    if unassociated:
        partial = (alpha > 0) & (alpha < 1)
        np.divide(color, alpha, out=color, where=np.broadcast_to(partial, color.shape))
    return True


class TextureExport:
    """Scene.textures as the materials' Image Texture nodes fill it (one Texture per Blender image)."""

    def __init__(self, sphrect, log):
        self.sphrect, self.log = sphrect, log
        self.list = []
        self.index = {}
        self.uv_maps_named = {}  # material name -> UV map names its nodes ask for (checked per object)
        self._reached = {}  # material node tree -> the outputs its Material Output reaches (_reached_outputs)
        self._means = {}  # (texture, output) -> its scalar's mean (factor_mean)
        # The Material Output's Displacement input of the material being exported, where Cycles bumps with it
        # (materials.export_material): every program of that material reads its displaced normal.
        self.displacement = None

    def lookup(self, node, output, owner, light_coordinates=None):
        """The TextureLookup of Image Texture `node`'s output ('color' / 'alpha') read by material `owner`, or by a
        light's node tree (light_coordinates: _light_source's maps from the light's own coordinates)."""
        node = wrap_node(node)
        interpolation = _INTERPOLATIONS.get(node.interpolation)
        if interpolation is None:
            self.log.unsupported_feature(f"Image Texture interpolation '{node.interpolation}' (Linear used)", owner)
            interpolation = "linear"
        if node.projection != "FLAT":
            self.log.unsupported_feature(f"Image Texture projection '{node.projection}' (Flat used)", owner)
        coordinates, transform = self._vector(node.inputs["Vector"], owner, light_coordinates)
        # Cycles divides the colour by the alpha when the node's Alpha output is used (NODE_IMAGE_ALPHA_UNASSOCIATE)
        # by a node its graph keeps: one the material's output reaches.
        tree = node.groups[0].id_data if node.groups else node.id_data
        alpha_used = (node.key, "Alpha") in self._reached_outputs(tree)
        texture = self.texture_of(node.image, owner, unassociated=alpha_used)
        return self.sphrect.TextureLookup(texture=texture, output=output,
                                          coordinates=coordinates, transform=transform[:3].tolist(),
                                          interpolation=interpolation, extension=node.extension.lower())

    def _reached_outputs(self, tree):
        """(node key, output identifier) of each node output the active Material Output of material tree `tree`
        reaches along the links Cycles follows (Cycles drops the rest of the graph); each node visited once."""
        key = tree.as_pointer()  # an embedded tree's name is its kind's ('Shader Nodetree')
        if key not in self._reached:
            outputs = [n for n in tree.nodes if n.bl_idname in {"ShaderNodeOutputMaterial", "ShaderNodeOutputLight"}]
            active = [n for n in outputs if getattr(n, "is_active_output", False)] or outputs[:1]
            reached, stack = set(), [wrap_node(n) for n in active if not n.mute]
            visited = {n.key for n in stack}
            while stack:
                for socket in stack.pop().inputs:
                    source, output = follow_reroutes(socket)
                    if source is None:
                        continue
                    reached.add((source.key, output.identifier))
                    if source.key not in visited:
                        visited.add(source.key)
                        stack.append(source)
            self._reached[key] = reached
        return self._reached[key]

    def factor_mean(self, factors):
        """The product of MixFactors' means over their images: the constant weight of shaders whose factor the
        renderer cannot vary (an emission, a second Principled BSDF in a mix)."""
        result = 1.0
        for f in factors:
            if f.program is not None:  # over the UV square (one reading images: 1/2)
                from .node_program import program_mean
                value = program_mean(self.sphrect, f.program)
                mean = min(max(value[0], 0.0), 1.0) if value is not None else 0.5
                result *= 1.0 - mean if f.complement else mean
                continue
            mean = self._scalar_mean(f.lookup.texture, f.lookup.output)
            result *= 1.0 - mean if f.complement else mean
        return result

    def color_mean(self, lookup):
        """Mean over its image of what a lookup reads, as an RGB colour (the alpha as grey), decoded by the
        renderer's own texel decoding (texture.h ImageColorMean): the constant colour of an emitter whose Color an
        image drives."""
        if lookup.output == "alpha":
            return (self._scalar_mean(lookup.texture, "alpha"),) * 3
        texture = self.list[lookup.texture]
        if texture is None or texture.pixels is None:
            return (0.5, 0.5, 0.5)
        key = (lookup.texture, "rgb")
        if key not in self._means:
            self._means[key] = tuple(self.sphrect.texture_color_mean(texture.pixels, texture.colorspace == "srgb"))
        return self._means[key]

    def _scalar_mean(self, index, output):
        """Mean of a texture's scalar (its alpha, or its colour's luminance, decoded, clamped to [0, 1] as a Mix
        factor is) over its pixels."""
        key = (index, output)
        texture = self.list[index]
        if texture is None or texture.pixels is None:  # not read (the material panel's notes): no mean to take
            return 0.5
        if key not in self._means:  # the renderer's own texel decoding and scalar (texture.h ImageScalarMean)
            self._means[key] = self.sphrect.texture_scalar_mean(texture.pixels, texture.colorspace == "srgb",
                                                                output == "alpha")
        return self._means[key]

    def name_uv_map(self, uv_map, owner):
        """A UV Map or Normal Map node of material `owner` names `uv_map` ('' = the active render one)."""
        if uv_map:
            self.uv_maps_named.setdefault(owner, set()).add(uv_map)

    def texture_of(self, image, owner, unassociated=False):
        """Index into Scene.textures of `image` (None: the node has no image), added on first use: its colour
        associated with (multiplied by) its alpha, as Cycles stores images, or `unassociated` (two Textures only
        for an image whose alpha makes them differ)."""
        key = (image.name_full if image is not None else None, unassociated)
        if key not in self.index:
            texture, alpha_matters = self._texture(image, owner, unassociated)
            self.index[key] = len(self.list)
            self.list.append(texture)
            if not alpha_matters:
                self.index[(key[0], not unassociated)] = self.index[key]
        return self.index[key]

    def _texture(self, image, owner, unassociated):
        """(Texture, whether its associated and unassociated colours differ)."""
        if image is None:
            self.log.problem(f"an Image Texture node of material '{owner}' has no image: magenta, as Cycles "
                             "shows it")
            return self._missing("(no image)"), False
        if image.source in {"SEQUENCE", "MOVIE", "TILED"}:
            self.log.unsupported_feature(f"image source '{image.source}' (its current pixels used)", image.name)
        count = len(image.pixels)  # reading the pixels loads the image (packed or from its file)
        width, height = image.size
        if not image.has_data or count == 0 or width * height == 0:
            self.log.problem(f"image '{image.name}' could not be read ({image.filepath or 'no file'}): magenta, "
                             "as Cycles shows it")
            return self._missing(image.name), False
        channels = count // (width * height)
        if 4 * count > self.sphrect.default_memory_limit():  # Blender's float copy alone would not fit
            self.log.problem(f"image '{image.name}' ({width} x {height}) needs {4 * count / 2**30:.1f} GiB to export, "
                             "more than half the memory: magenta")
            return self._missing(image.name), False
        pixels = np.empty(count, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        pixels = pixels.reshape(height, width, channels)
        alpha_matters = _apply_alpha_mode(image, pixels, unassociated)
        if image.is_float:
            colorspace = "linear"  # Blender's float buffers are scene linear whatever the file's colour space
        elif unassociated and alpha_matters:  # colour / alpha: between bytes, kept as float32 (still encoded)
            colorspace = self._colorspace(image)
        else:
            pixels *= 255.0  # back to Blender's bytes (a quarter of the memory): k / 255 -> k, rounded
            pixels += 0.5
            pixels = pixels.astype(np.uint8)
            colorspace = self._colorspace(image)
        name = image.name + (" (unassociated alpha)" if unassociated and alpha_matters else "")
        pixels.flags.writeable = False  # so that every renderer of the scene (compare mode's) shares, not copies, it
        return self.sphrect.Texture(name=name, pixels=pixels, colorspace=colorspace), alpha_matters

    def _colorspace(self, image):
        name = image.colorspace_settings.name
        if name == "sRGB":
            return "srgb"
        if name not in _LINEAR_COLORSPACES:
            self.log.unsupported_feature(f"image colour space '{name}' (read as linear)", image.name)
        return "linear"

    def _missing(self, name):
        pixels = np.array(MISSING_IMAGE_RGBA, dtype=np.float32).reshape(1, 1, 4)
        return self.sphrect.Texture(name=name, pixels=pixels, colorspace="linear")

    def _vector(self, socket, owner, light_coordinates=None):
        """(coordinates, 4x4 transform) of an Image Texture's Vector input: the coordinates it reads and the
        Mapping nodes' affine maps between them and the node (composed, the one nearest the image last).  For a
        light's own texture ('uv' -- the light's coordinates -- and the map from them through the source)."""
        fallback = ("uv", np.eye(4) if light_coordinates is None else light_coordinates["uv"])
        transform = np.eye(4)
        node, output = follow_reroutes(socket)
        while node is not None and node.bl_idname == "ShaderNodeMapping":
            mapping = self._mapping(node, owner)
            if mapping is None:
                return fallback
            transform = transform @ mapping
            node, output = follow_reroutes(node.inputs["Vector"])
            if node is None:
                self.log.unsupported_feature("Mapping node with an unlinked Vector input (UV used)", owner)
                return fallback
        if light_coordinates is not None:
            source = self._light_source(node, output, owner, light_coordinates)
            return ("uv", transform @ source) if source is not None else fallback
        if node is None:
            return "uv", transform  # Cycles' default for an unlinked Image Texture vector: the UV map
        if node.bl_idname == "ShaderNodeTexCoord" and output.identifier in {"UV", "Generated"}:
            if node.from_instancer:
                self.log.unsupported_feature("Texture Coordinate 'From Instancer' (the object's own used)", owner)
            return output.identifier.lower(), transform
        if node.bl_idname == "ShaderNodeUVMap":
            if node.from_instancer:
                self.log.unsupported_feature("UV Map 'From Instancer' (the object's own used)", owner)
            self.name_uv_map(node.uv_map, owner)
            return "uv", transform
        label = output.name if node.bl_idname == "ShaderNodeTexCoord" else node.bl_label or node.bl_idname
        self.log.unsupported_feature(f"Image Texture vector from '{label}' (UV used)", owner)
        return "uv", np.eye(4)

    def _light_source(self, node, output, owner, maps):
        """The 4x4 map from a light's own coordinates to what the node feeding its Image Texture's vector gives,
        as Cycles 3.4 shades a light (no object, svm_node_tex_coord and svm_node_attr): Geometry > Parametric its
        coordinates along its axes (maps['parametric']); Texture Coordinate > Object and Generated the point in world
        space (maps['position']; an Object node's object: in that object's space); UV, a UV Map node or nothing the
        UV attribute a light lacks, (0, 0, 0) (maps['uv']).  None (warned) for any other source."""
        if node is None or node.bl_idname == "ShaderNodeUVMap":
            return maps["uv"]
        if node.bl_idname == "ShaderNodeNewGeometry" and output.identifier == "Parametric":
            return maps["parametric"]
        if node.bl_idname == "ShaderNodeTexCoord":
            if output.identifier == "UV":
                return maps["uv"]
            if output.identifier == "Generated" or (output.identifier == "Object" and node.object is None):
                return maps["position"]
            if output.identifier == "Object":
                return np.linalg.pinv(np.array(node.object.matrix_world, dtype=np.float64)) @ maps["position"]
        label = output.name if node.bl_idname in {"ShaderNodeTexCoord", "ShaderNodeNewGeometry"} else \
            node.bl_label or node.bl_idname
        self.log.unsupported_feature(f"Image Texture vector of a light from '{label}' (UV used)", owner)
        return None

    def _mapping(self, node, owner):
        """4x4 matrix of a Mapping node (svm_mapping: Point T R S, Texture its inverse S^-1 R^T (v - T), Vector
        R S); None (warned) for a Normal mapping."""
        values = {}
        for name in ("Location", "Rotation", "Scale"):
            socket = node.inputs[name]
            if socket.is_linked:
                self.log.unsupported_feature(f"linked '{name}' input of a Mapping node (its value used)", owner)
            values[name] = np.array(socket.default_value, dtype=np.float64)
        rotation = np.array(mathutils.Euler(values["Rotation"], "XYZ").to_matrix(), dtype=np.float64)
        scale, location = values["Scale"], values["Location"]
        m = np.eye(4)
        if node.vector_type in {"POINT", "VECTOR"}:
            m[:3, :3] = rotation * scale  # R S: column j scaled by scale[j]
            if node.vector_type == "POINT":
                m[:3, 3] = location
        elif node.vector_type == "TEXTURE":
            inverse_scale = np.divide(1.0, scale, out=np.zeros(3), where=scale != 0)  # Cycles' safe_divide
            m[:3, :3] = inverse_scale[:, None] * rotation.T
            m[:3, 3] = -m[:3, :3] @ location
        else:
            self.log.unsupported_feature(f"Mapping node of type '{node.vector_type}' (ignored)", owner)
            return None
        return m
