"""Procedural texture nodes' settings as the renderer's params (native/render/svm/procedural_textures.h).

One function per node, reading the node's enums and its inputs' values into the dict that
`sphrect._native.procedural_texture(name, points, w, **params)` and the node-program compiler take.  Input values are
the sockets' own (`default_value`): for a linked input that is the value Cycles would use unlinked, which the
compiler replaces by the link's.  Enum values are Blender's identifiers in lower case (the C++ name lists').
The Vector input is the point, not a setting; so is W, and the Texture Mapping the compiler applies.

    name, params = procedural_params(node)   # ('voronoi', {'dimensions': 3, 'feature': 'f1', ...}) or None
"""


def _value(node, socket_name):
    return float(node.inputs[socket_name].default_value)


def _color(node, socket_name):
    return tuple(float(c) for c in node.inputs[socket_name].default_value[:3])


def _dimensions(identifier):
    return int(identifier[0])  # '1D' .. '4D'


def noise_params(node):
    return {"dimensions": _dimensions(node.noise_dimensions), "scale": _value(node, "Scale"),
            "detail": _value(node, "Detail"), "roughness": _value(node, "Roughness"),
            "distortion": _value(node, "Distortion")}


def musgrave_params(node):
    return {"dimensions": _dimensions(node.musgrave_dimensions), "type": node.musgrave_type.lower(),
            "scale": _value(node, "Scale"), "detail": _value(node, "Detail"), "dimension": _value(node, "Dimension"),
            "lacunarity": _value(node, "Lacunarity"), "offset": _value(node, "Offset"), "gain": _value(node, "Gain")}


def voronoi_params(node):
    return {"dimensions": _dimensions(node.voronoi_dimensions), "feature": node.feature.lower(),
            "metric": node.distance.lower(), "scale": _value(node, "Scale"),
            "smoothness": _value(node, "Smoothness"), "exponent": _value(node, "Exponent"),
            "randomness": _value(node, "Randomness")}


def white_noise_params(node):
    return {"dimensions": _dimensions(node.noise_dimensions)}


def gradient_params(node):
    return {"type": node.gradient_type.lower()}


def checker_params(node):
    return {"color1": _color(node, "Color1"), "color2": _color(node, "Color2"), "scale": _value(node, "Scale")}


def wave_params(node):
    return {"type": node.wave_type.lower(), "bands_direction": node.bands_direction.lower(),
            "rings_direction": node.rings_direction.lower(), "profile": node.wave_profile.lower(),
            "scale": _value(node, "Scale"), "distortion": _value(node, "Distortion"), "detail": _value(node, "Detail"),
            "detail_scale": _value(node, "Detail Scale"), "detail_roughness": _value(node, "Detail Roughness"),
            "phase_offset": _value(node, "Phase Offset")}


def magic_params(node):
    return {"depth": int(node.turbulence_depth), "scale": _value(node, "Scale"),
            "distortion": _value(node, "Distortion")}


def brick_params(node):
    return {"offset": float(node.offset), "offset_frequency": int(node.offset_frequency),
            "squash": float(node.squash), "squash_frequency": int(node.squash_frequency),
            "color1": _color(node, "Color1"), "color2": _color(node, "Color2"), "mortar": _color(node, "Mortar"),
            "scale": _value(node, "Scale"), "mortar_size": _value(node, "Mortar Size"),
            "mortar_smooth": _value(node, "Mortar Smooth"), "bias": _value(node, "Bias"),
            "brick_width": _value(node, "Brick Width"), "row_height": _value(node, "Row Height")}


# bl_idname -> (the renderer's node name, the function reading its params); names as sphrect._native's
# procedural_textures.
PROCEDURAL_NODES = {
    "ShaderNodeTexNoise": ("noise", noise_params),
    "ShaderNodeTexMusgrave": ("musgrave", musgrave_params),
    "ShaderNodeTexVoronoi": ("voronoi", voronoi_params),
    "ShaderNodeTexWhiteNoise": ("white_noise", white_noise_params),
    "ShaderNodeTexGradient": ("gradient", gradient_params),
    "ShaderNodeTexChecker": ("checker", checker_params),
    "ShaderNodeTexWave": ("wave", wave_params),
    "ShaderNodeTexMagic": ("magic", magic_params),
    "ShaderNodeTexBrick": ("brick", brick_params),
}


def procedural_params(node):
    """(node name, params dict) of a procedural texture node, or None for any other node."""
    entry = PROCEDURAL_NODES.get(node.bl_idname)
    return None if entry is None else (entry[0], entry[1](node))
