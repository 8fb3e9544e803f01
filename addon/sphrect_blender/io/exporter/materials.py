"""Blender materials and world -> sphrect.Material / sphrect.World.

Read from the node tree behind the active output: Diffuse BSDF and Principled BSDF (base colour, metallic,
roughness, specular) for surfaces; Background for the world colour; Volume Scatter, Volume Absorption or
Principled Volume on the World output for a homogeneous medium. Only unlinked input values are read:
every linked input and every other node is logged as unsupported."""
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


def export_material(sphrect, mat, log):
    if mat is None:
        return sphrect.Material(name="default")
    name = mat.name
    if not mat.use_nodes or mat.node_tree is None:
        return sphrect.Material(name=name, kind="diffuse", base_color=_rgb(mat.diffuse_color))
    out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
    if out is not None and out.inputs["Volume"].is_linked:
        log.unsupported_feature("material volumes", name)
    if out is not None and out.inputs["Displacement"].is_linked:
        log.unsupported_feature("displacement", name)
    node = _linked_node(out.inputs["Surface"]) if out is not None else None
    if node is None:
        log.unsupported_feature("materials without a surface shader (black)", name)
        return sphrect.Material(name=name, kind="diffuse", base_color=(0.0, 0.0, 0.0))
    if node.bl_idname == "ShaderNodeBsdfDiffuse":
        color = _rgb(_value(node, "Color", log, name))
        if _value(node, "Roughness", log, name) > 0:
            log.unsupported_feature("Oren-Nayar roughness of Diffuse BSDF (Lambert used)", name)
        _check_normal(node, log, name)
        return sphrect.Material(name=name, kind="diffuse", base_color=color)
    if node.bl_idname == "ShaderNodeBsdfPrincipled":
        color = _rgb(_value(node, "Base Color", log, name))
        metallic = _value(node, "Metallic", log, name)
        roughness = _value(node, "Roughness", log, name)
        specular = _value(node, "Specular", log, name)
        for socket, what in (("Subsurface", "subsurface scattering"), ("Transmission", "transmission"),
                             ("Clearcoat", "clearcoat"), ("Sheen", "sheen"),
                             ("Specular Tint", "specular tint"), ("Anisotropic", "anisotropy")):
            _nonzero_input(node, socket, log, name, what)
        emission = _value(node, "Emission", log, name)
        strength = _value(node, "Emission Strength", log, name)
        if emission is not None and strength and np.any(np.asarray(emission[:3]) > 0):
            log.unsupported_feature("emission on meshes", name)
        if _value(node, "Alpha", log, name) < 1:
            log.unsupported_feature("alpha", name)
        _check_normal(node, log, name)
        kind = "diffuse" if metallic == 0 and specular == 0 else "glossy"
        return sphrect.Material(name=name, kind=kind, base_color=color, roughness=float(roughness),
                                metallic=float(metallic), specular=float(specular))
    what = "emission on meshes" if node.bl_idname == "ShaderNodeEmission" else \
        f"'{node.bl_label or node.bl_idname}' shader node (grey diffuse used)"
    log.unsupported_feature(what, name)
    return sphrect.Material(name=name, kind="diffuse", base_color=(0.8, 0.8, 0.8))


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
