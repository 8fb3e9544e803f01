"""Blender materials and world -> sphrect.Material / sphrect.World.

Read from the node tree behind the active output: Diffuse BSDF and Principled BSDF (base colour, metallic,
specular, specular tint, roughness, sheen, sheen tint, clearcoat, clearcoat roughness: the renderer's
'principled' kind, Cycles 3.4's model), Glass and Refraction BSDF and a Principled BSDF of transmission 1 (kind
'glass': the dielectric reflection Cycles shows at zero bounces), Glossy BSDF and Anisotropic BSDF (kind
'glossy_bsdf', no Fresnel) for surfaces; Mix Shader and Add Shader trees of those with unlinked factors (kind
'mix': each shader's closures scaled by its weight, as svm_node_mix_closure does); volume-only materials (Volume
linked, Surface not) and a white Transparent BSDF make a transparent surface, left out by geometry.triangulate;
Holdout and Translucent BSDF are black (warned); emission with Cycles 3.4's conventions -- an Emission shader
emits radiance colour x strength (svm_node_emission_weight), the Principled BSDF's Emission x Emission Strength
adds to its BSDF, a mix scales each side's closures by its weight, mesh emission is two-sided (emissive_pdf:
|Ng . wi| > 0); Background for the world colour; Volume Scatter, Volume Absorption or Principled Volume on the
World output for a homogeneous medium.  Only unlinked input values are read: every linked input and every other
node is logged as unsupported."""
import dataclasses

import numpy as np


def _active_output(tree, node_type):
    outputs = [n for n in tree.nodes if n.bl_idname == node_type]
    for n in outputs:
        if getattr(n, "is_active_output", False) and getattr(n, "target", "ALL") in {"ALL", "CYCLES"}:
            return n
    return outputs[0] if outputs else None


def _linked_node(socket):
    if socket is None or not socket.is_linked:
        return None
    node = socket.links[0].from_node
    while node.bl_idname == "NodeReroute":
        if not node.inputs[0].is_linked:
            return None
        node = node.inputs[0].links[0].from_node
    return node


def _value(node, name, log, owner):
    """An input's own value; a linked input is logged (its link is not followed)."""
    socket = node.inputs.get(name)
    if socket is None:
        return None
    if socket.is_linked:
        source = socket.links[0].from_node
        log.unsupported_feature(f"linked '{name}' input ({source.bl_label or source.bl_idname})", owner)
    value = socket.default_value
    try:
        return tuple(float(v) for v in value)
    except TypeError:
        return float(value)


def _rgb(v):
    return tuple(float(x) for x in v[:3])


def _nonzero_input(node, name, log, owner, what):
    v = _value(node, name, log, owner)
    if v is not None and np.any(np.asarray(v, dtype=float) > 0):
        log.unsupported_feature(what, owner)


def is_volume_only(mat):
    """A node material whose active output has a Volume link and no Surface link: Cycles makes its surface
    transparent (it neither shades nor occludes), so the exporter leaves those triangles out."""
    if mat is None or not mat.use_nodes or mat.node_tree is None:
        return False
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    return out is not None and out.inputs["Volume"].is_linked and _linked_node(out.inputs["Surface"]) is None


def transparent_surface(mat):
    """Why the material's surface is left out (geometry.triangulate), as the warning names it, or None:
    volume-only, or a Transparent BSDF alone on the Surface (a white one lets camera and shadow rays through
    unchanged in Cycles, transparent bounces being counted apart from max_bounces; a coloured one would filter
    them, which the renderer cannot: warned)."""
    if is_volume_only(mat):
        return "volume-only materials (surface transparent, volume not simulated)"
    if mat is None or not mat.use_nodes or mat.node_tree is None:
        return None
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    node = _linked_node(out.inputs["Surface"]) if out is not None else None
    if node is None or node.bl_idname != "ShaderNodeBsdfTransparent":
        return None
    color = node.inputs["Color"]
    if not color.is_linked and all(float(v) >= 1 for v in color.default_value[:3]):
        return "Transparent BSDF surfaces (left out: transparent)"
    return "Transparent BSDF surfaces (left out: its colour filtering camera and shadow rays is not modelled)"


def export_material(sphrect, mat, log):
    if mat is None:
        return sphrect.Material(name="default")
    name = mat.name
    if not mat.use_nodes or mat.node_tree is None:
        return sphrect.Material(name=name, kind="diffuse", base_color=_rgb(mat.diffuse_color))
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    if transparent_surface(mat):  # its triangles are left out (geometry.triangulate), which warns per object
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.0, 0.0, 0.0))
    if out is not None and out.inputs["Volume"].is_linked:
        log.unsupported_feature("material volumes", name)
    if out is not None and out.inputs["Displacement"].is_linked:
        log.unsupported_feature("displacement", name)
    node = _linked_node(out.inputs["Surface"]) if out is not None else None
    if node is None:
        log.unsupported_feature("materials without a surface shader (black)", name)
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.0, 0.0, 0.0))
    return _shader(sphrect, node, log, name)


def _emission(node, color_input, strength_input, weight, log, owner):
    """weight x colour x strength (Cycles' emission closure weight); a negative strength is logged and
    read as 0 (Cycles 3.4 does not clamp it: its emission would be negative)."""
    color = np.asarray(_value(node, color_input, log, owner)[:3], dtype=float)
    strength = _value(node, strength_input, log, owner)
    if strength < 0:
        log.unsupported_feature("negative emission strength (0 used)", owner)
        strength = 0.0
    return _rgb(np.clip(color, 0, None) * strength * weight)


def _closures(node, weight, leaves, log, name):
    """Appends (weight, shader node) for each shader reached through Mix and Add Shader nodes
    (svm_node_mix_closure: the factor clamped to [0, 1], (1 - fac) to the first input, fac to the second;
    Add: 1 to each); False for a linked factor (not modelled)."""
    if node is None or weight <= 0:  # an unlinked shader input, or a side Cycles skips: no closure
        return True
    if node.bl_idname == "ShaderNodeMixShader":
        fac_socket = node.inputs[0]
        if fac_socket.is_linked:
            return False
        fac = min(max(float(fac_socket.default_value), 0.0), 1.0)
        return (_closures(_linked_node(node.inputs[1]), weight * (1 - fac), leaves, log, name)
                and _closures(_linked_node(node.inputs[2]), weight * fac, leaves, log, name))
    if node.bl_idname == "ShaderNodeAddShader":
        return (_closures(_linked_node(node.inputs[0]), weight, leaves, log, name)
                and _closures(_linked_node(node.inputs[1]), weight, leaves, log, name))
    leaves.append((weight, node))
    return True


# Shaders that add no light a zero-bounce render of an opaque surface can show here, each with its warning.
_BLACK_SHADERS = {
    "ShaderNodeHoldout": "Holdout (black; the image's alpha stays 1)",
    "ShaderNodeBsdfTranslucent": "Translucent BSDF (black: light through a thin surface is not modelled)",
    "ShaderNodeBsdfTransparent": "Transparent BSDF inside a mix (its share black and opaque)",
}


def _shader(sphrect, node, log, name):
    """The surface shader behind the output: one BSDF, or the weighted sum of the shaders a tree of Mix and Add
    Shader nodes reaches (kind 'mix'), emission summed."""
    leaves = []
    if not _closures(node, 1.0, leaves, log, name):
        log.unsupported_feature("linked Mix Shader factor (grey diffuse used)", name)
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.8, 0.8, 0.8))
    emission = np.zeros(3)
    layers = []
    for weight, leaf in leaves:
        if leaf.bl_idname == "ShaderNodeEmission":
            emission += _emission(leaf, "Color", "Strength", weight, log, name)
        elif leaf.bl_idname in _BLACK_SHADERS:
            log.unsupported_feature(_BLACK_SHADERS[leaf.bl_idname], name)
        else:
            layers.append(sphrect.MaterialLayer(weight=weight, material=_bsdf(sphrect, leaf, log, name)))
    layers = _fit_mix(sphrect, layers, log, name)
    if not layers:
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.0, 0.0, 0.0), emission=_rgb(emission))
    if all(l.material.kind == "diffuse" for l in layers):  # Lambert is linear in its colour: one diffuse, exactly
        color = sum(l.weight * np.asarray(l.material.base_color) for l in layers)
        return sphrect.Material(name=name, kind="diffuse", base_color=_rgb(color), emission=_rgb(emission))
    if len(layers) == 1 and layers[0].weight == 1:
        bsdf = layers[0].material
        return dataclasses.replace(bsdf, emission=_rgb(np.asarray(bsdf.emission) + emission))
    return sphrect.Material(name=name, kind="mix", layers=layers, emission=_rgb(emission))


def _lobe_key(mat):
    """What makes two glossy / glass layers one lobe in the renderer (bsdf.h MixIntoMaterial)."""
    return (mat.roughness, mat.distribution, mat.ior if mat.kind == "glass" else 0.0)


def _fit_mix(sphrect, layers, log, name):
    """The layers as the renderer's mix can hold them: several Principled BSDFs of equal inputs but for the base
    colour merge exactly (weights summed, colours weight-averaged) where no tint makes the closures non-linear in
    it; other ones are replaced by one of their weight-averaged inputs and total weight, and
    glossy / glass lobes beyond sphrect.MAX_MIX_GLOSSY_LOBES distinct ones are dropped, lightest first, both
    warned."""
    principled = [l for l in layers if l.material.kind == "principled"]
    if len(principled) > 1:
        total = sum(l.weight for l in principled)
        # Cycles' closures are linear in the base colour when neither tint divides it by its luminance.
        inputs = [dataclasses.replace(l.material, name="", emission=(0.0, 0.0, 0.0), base_color=(0.0, 0.0, 0.0))
                  for l in principled]
        m0 = principled[0].material
        linear_in_color = m0.specular_tint == 0 and (m0.sheen == 0 or m0.sheen_tint == 0)
        if any(m != inputs[0] for m in inputs[1:]) or not linear_in_color:
            log.unsupported_feature(f"a mix of {len(principled)} different Principled BSDFs (one of their "
                                    "weight-averaged inputs used)", name)
        fields = {f: getattr(principled[0].material, f) for f in
                  ("roughness", "metallic", "specular", "specular_tint", "sheen", "sheen_tint", "clearcoat",
                   "clearcoat_roughness")}
        averaged = {f: sum(l.weight * getattr(l.material, f) for l in principled) / total for f in fields}
        color = sum(l.weight * np.asarray(l.material.base_color) for l in principled) / total
        emission = sum(l.weight * np.asarray(l.material.emission) for l in principled) / total
        merged = dataclasses.replace(principled[0].material, base_color=_rgb(color), emission=_rgb(emission),
                                     **averaged)
        layers = [l for l in layers if l.material.kind != "principled"] + [sphrect.MaterialLayer(total, merged)]
    lobes = {}
    for l in layers:
        if l.material.kind in ("glass", "glossy_bsdf"):
            key = _lobe_key(l.material)
            lobes[key] = lobes.get(key, 0.0) + l.weight
    if len(lobes) > sphrect.MAX_MIX_GLOSSY_LOBES:
        kept = set(sorted(lobes, key=lobes.get, reverse=True)[:sphrect.MAX_MIX_GLOSSY_LOBES])
        log.unsupported_feature(f"a mix of {len(lobes)} glossy / glass shaders of different roughness or IOR "
                                f"(the {sphrect.MAX_MIX_GLOSSY_LOBES} heaviest kept)", name)
        layers = [l for l in layers if l.material.kind not in ("glass", "glossy_bsdf")
                  or _lobe_key(l.material) in kept]
    return layers


def _bsdf(sphrect, node, log, name):
    """A Diffuse, Principled, Glossy, Anisotropic, Glass or Refraction BSDF node (the Principled one's own emission
    included)."""
    if node.bl_idname == "ShaderNodeBsdfDiffuse":
        color = _rgb(_value(node, "Color", log, name))
        if _value(node, "Roughness", log, name) > 0:
            log.unsupported_feature("Oren-Nayar roughness of Diffuse BSDF (Lambert used)", name)
        _check_normal(node, log, name)
        return sphrect.Material(name=name, kind="diffuse", base_color=color)
    if node.bl_idname == "ShaderNodeBsdfPrincipled":
        return _principled(sphrect, node, log, name)
    if node.bl_idname in {"ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction"}:
        return _glass(sphrect, node, log, name)
    if node.bl_idname in {"ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic"}:
        return _glossy(sphrect, node, log, name)
    log.unsupported_feature(f"'{node.bl_label or node.bl_idname}' shader node (grey diffuse used)", name)
    return sphrect.Material(name=name, kind="diffuse", base_color=(0.8, 0.8, 0.8))


def _glossy(sphrect, node, log, name):
    """Glossy BSDF (and Blender 3.4's Anisotropic BSDF at anisotropy 0) as Cycles 3.4 evaluates it: Color x GGX
    or Beckmann reflection of alpha = Roughness^2, no Fresnel (kind 'glossy_bsdf'); Sharp is a delta lobe, black at
    zero bounces in both renderers."""
    distribution = getattr(node, "distribution", "GGX")
    roughness = 0.0 if distribution == "SHARP" else float(_value(node, "Roughness", log, name))
    if distribution in {"MULTI_GGX", "ASHIKHMIN_SHIRLEY"} and roughness > 0:
        label = {"MULTI_GGX": "Multiscatter GGX", "ASHIKHMIN_SHIRLEY": "Ashikhmin-Shirley"}[distribution]
        log.unsupported_feature(f"{node.bl_label} distribution '{label}' (GGX used)", name)
    if node.bl_idname == "ShaderNodeBsdfAnisotropic":
        if abs(_value(node, "Anisotropy", log, name)) > 0:
            log.unsupported_feature("anisotropy of Anisotropic BSDF (isotropic used)", name)
        tangent = node.inputs.get("Tangent")
        if tangent is not None and tangent.is_linked:
            log.unsupported_feature("linked 'Tangent' input", name)
    _check_normal(node, log, name)
    return sphrect.Material(name=name, kind="glossy_bsdf", base_color=_rgb(_value(node, "Color", log, name)),
                            roughness=roughness, distribution="beckmann" if distribution == "BECKMANN" else "ggx")


def _glass(sphrect, node, log, name):
    """Glass or Refraction BSDF as Cycles 3.4 shows it at zero bounces: the Glass BSDF's GGX / Beckmann reflection
    of the lights, weighted by the dielectric Fresnel of the view (kind 'glass'); the refracted part, the whole of a
    Refraction BSDF, is black (it needs a bounce, or a light seen through an open surface: not modelled)."""
    distribution = getattr(node, "distribution", "GGX")
    roughness = 0.0 if distribution == "SHARP" else float(_value(node, "Roughness", log, name))
    if distribution == "MULTI_GGX" and roughness > 0:
        log.unsupported_feature(f"{node.bl_label} distribution 'Multiscatter GGX' (GGX used)", name)
    _check_normal(node, log, name)
    log.unsupported_feature("refraction of lights seen through a surface (black, as Cycles at zero bounces "
                            "except behind open surfaces)", name)
    color = _rgb(_value(node, "Color", log, name))
    if node.bl_idname == "ShaderNodeBsdfRefraction":
        color = (0.0, 0.0, 0.0)
    return sphrect.Material(name=name, kind="glass", base_color=color, roughness=roughness,
                            ior=float(_value(node, "IOR", log, name)),
                            distribution="beckmann" if distribution == "BECKMANN" else "ggx")


# Principled BSDF inputs read into sphrect.Material (kind 'principled'), by the Material field they fill.
_PRINCIPLED_INPUTS = {"metallic": "Metallic", "specular": "Specular", "specular_tint": "Specular Tint",
                      "roughness": "Roughness", "sheen": "Sheen", "sheen_tint": "Sheen Tint",
                      "clearcoat": "Clearcoat", "clearcoat_roughness": "Clearcoat Roughness"}
# Above Cycles' closure cutoff these change the image and are not modelled.
_PRINCIPLED_UNSUPPORTED = (("Subsurface", "subsurface scattering (Burley diffuse used)"),
                           ("Transmission", "transmission"), ("Anisotropic", "anisotropy"))


def _principled(sphrect, node, log, name):
    """Cycles 3.4's Principled BSDF (svm_node_closure_bsdf) at its default GGX distribution."""
    if _value(node, "Transmission", log, name) >= 1 and _value(node, "Metallic", log, name) <= 0:
        glass = _principled_glass(sphrect, node, log, name)
        if glass is not None:
            return glass
    color = _rgb(_value(node, "Base Color", log, name))
    values = {field: float(_value(node, socket, log, name)) for field, socket in _PRINCIPLED_INPUTS.items()}
    for socket, what in _PRINCIPLED_UNSUPPORTED:
        _nonzero_input(node, socket, log, name, what)
    # Cycles uses multiscatter GGX for 'MULTI_GGX' above roughness 0.075 (single-scatter below).
    if getattr(node, "distribution", "GGX") == "MULTI_GGX" and values["roughness"] > 0.075:
        log.unsupported_feature("Principled BSDF distribution 'Multiscatter GGX' (GGX used)", name)
    clearcoat_normal = node.inputs.get("Clearcoat Normal")
    if values["clearcoat"] > 0 and clearcoat_normal is not None and clearcoat_normal.is_linked:
        log.unsupported_feature("linked 'Clearcoat Normal' input", name)
    emission = _emission(node, "Emission", "Emission Strength", 1.0, log, name)
    if _value(node, "Alpha", log, name) < 1:
        log.unsupported_feature("alpha", name)
    _check_normal(node, log, name)
    return sphrect.Material(name=name, kind="principled", base_color=color, emission=emission, **values)


def _principled_glass(sphrect, node, log, name):
    """A Principled BSDF of transmission 1, metallic 0: Cycles' closures are then only its glass (no diffuse,
    sheen or other specular), whose reflection is a white Glass BSDF's at the same roughness and IOR when the
    specular tint is 0 (cspec0 white) -- kind 'glass'.  None when a tint or clearcoat needs more."""
    if _value(node, "Specular Tint", log, name) > 0 or _value(node, "Clearcoat", log, name) > 0:
        return None
    if getattr(node, "distribution", "GGX") == "MULTI_GGX" and _value(node, "Roughness", log, name) > 0.05:
        log.unsupported_feature("Principled BSDF distribution 'Multiscatter GGX' (GGX used)", name)
    _check_normal(node, log, name)
    log.unsupported_feature("refraction of lights seen through a surface (black, as Cycles at zero bounces "
                            "except behind open surfaces)", name)
    if _value(node, "Alpha", log, name) < 1:
        log.unsupported_feature("alpha", name)
    return sphrect.Material(name=name, kind="glass", base_color=(1.0, 1.0, 1.0),
                            roughness=float(_value(node, "Roughness", log, name)),
                            ior=float(_value(node, "IOR", log, name)),
                            emission=_emission(node, "Emission", "Emission Strength", 1.0, log, name))


def _check_normal(node, log, owner):
    socket = node.inputs.get("Normal")
    if socket is not None and socket.is_linked:
        log.unsupported_feature("normal maps / bump", owner)


def export_world(sphrect, world, log):
    if world is None:
        return sphrect.World()
    if not world.use_nodes or world.node_tree is None:
        return sphrect.World(background=_rgb(world.color))
    out = _active_output(world.node_tree, "ShaderNodeOutputWorld")
    if out is None:
        return sphrect.World()
    background = (0.0, 0.0, 0.0)
    surface = _linked_node(out.inputs["Surface"])
    if surface is not None:
        if surface.bl_idname == "ShaderNodeBackground":
            color = np.array(_value(surface, "Color", log, world.name)[:3])
            background = _rgb(color * _value(surface, "Strength", log, world.name))
        else:
            log.unsupported_feature(f"'{surface.bl_label}' world surface (black used)", world.name)
    medium = _export_medium(sphrect, _linked_node(out.inputs["Volume"]), world.name, log)
    return sphrect.World(background=background, medium=medium)


def _export_medium(sphrect, node, owner, log):
    """Homogeneous medium from Cycles' volume nodes: Volume Scatter (sigma_s = density * colour),
    Volume Absorption (sigma_a = density * (1 - colour)), Principled Volume (both, as Cycles splits them)."""
    if node is None:
        return None
    if node.bl_idname not in {"ShaderNodeVolumeScatter", "ShaderNodeVolumeAbsorption",
                              "ShaderNodeVolumePrincipled"}:
        log.unsupported_feature(f"'{node.bl_label}' world volume (no medium used)", owner)
        return None
    color = np.array(_value(node, "Color", log, owner)[:3])
    density = max(_value(node, "Density", log, owner), 0.0)
    zero = np.zeros(3)
    g = 0.0
    if node.bl_idname == "ShaderNodeVolumeScatter":
        sigma_s, sigma_a = density * np.clip(color, 0, None), zero
        g = _value(node, "Anisotropy", log, owner)
    elif node.bl_idname == "ShaderNodeVolumeAbsorption":
        sigma_s, sigma_a = zero, density * np.clip(1.0 - color, 0, None)
    else:
        absorption_color = np.array(_value(node, "Absorption Color", log, owner)[:3])
        sigma_s = density * np.clip(color, 0, None)
        sigma_a = density * np.clip(1.0 - color, 0, None) * np.clip(1.0 - absorption_color, 0, None)
        g = _value(node, "Anisotropy", log, owner)
        _nonzero_input(node, "Emission Strength", log, owner, "volume emission")
        _nonzero_input(node, "Blackbody Intensity", log, owner, "volume blackbody emission")
    if not np.any(sigma_s + sigma_a > 0):
        return None
    return sphrect.Medium(sigma_s=_rgb(sigma_s), sigma_a=_rgb(sigma_a), g=float(np.clip(g, -0.99, 0.99)))
