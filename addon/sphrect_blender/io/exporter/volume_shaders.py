"""Blender's volume shaders -> sphrect.Medium.

A Volume output (a material's or the world's) is read once, as Cycles 3.4's SVM sums its volume closures
(kernel/svm/closure.h): Volume Scatter adds sigma_s = density x colour (Henyey-Greenstein of its Anisotropy), Volume
Absorption sigma_a = density x (1 - colour), Principled Volume sigma_s = density x colour and sigma_a = density x
max(1 - colour, 0) x max(1 - sqrt(absorption colour), 0); Add Shader adds its two sides, Mix Shader scales them by
(1 - fac) and fac (a shader's weight multiplies its density, svm_node_mix_closure); node groups, reroutes and muted
nodes as node_groups.py follows them.  The renderer's medium has one phase function: a combination's anisotropy is
the mean of its scattering shaders', weighted by their sigma_s (warned when they differ).  What the renderer does
not simulate is warned, naming the owner: volume emission, and inputs that vary in space (a texture or an attribute
driving Density or Color) -- a graph of constants folds to its value; a graph node_program.py compiles is evaluated
at the volume's centre where one is given (an object volume's bounding box: volumes.py); otherwise the input's own
value is used."""
import dataclasses

import numpy as np

from .node_groups import own_value
from .node_program import compile_socket
from .textures import TextureExport, follow_reroutes

_SCATTER, _ABSORPTION = "ShaderNodeVolumeScatter", "ShaderNodeVolumeAbsorption"
_PRINCIPLED = "ShaderNodeVolumePrincipled"
_ADD, _MIX = "ShaderNodeAddShader", "ShaderNodeMixShader"
_EMITTERS = {"ShaderNodeEmission", "ShaderNodeBackground"}
# Cycles' CLOSURE_WEIGHT_CUTOFF: a Principled Volume of less density adds nothing, and emits nothing below it.
_WEIGHT_CUTOFF = 1e-5
# The medium's Henyey-Greenstein anisotropy is kept inside (-MAX_ANISOTROPY, MAX_ANISOTROPY).
MAX_ANISOTROPY = 0.99


@dataclasses.dataclass
class VolumePoint:
    """Where an input that varies in space is read: the world position, object coordinates and Generated ones."""
    position: tuple
    object: tuple
    generated: tuple


def _shown(value):
    if isinstance(value, tuple):
        return "(" + ", ".join(f"{v:.3g}" for v in value) + ")"
    return f"{value:.3g}"


class _Reader:
    """Reads one Volume output: the coefficients summed over its shaders (sigma_s, sigma_a, the scattering shaders'
    (weight, g)); `varies` whether an input was evaluated at `point` (the medium then belongs to that point)."""

    def __init__(self, sphrect, log, owner, point):
        self.sphrect, self.log, self.owner, self.point = sphrect, log, owner, point
        self.textures = TextureExport(sphrect, log)  # images a graph reads stay out of the scene: not evaluated
        self.sigma_s, self.sigma_a, self.phases = np.zeros(3), np.zeros(3), []
        self.varies = False

    def value(self, node, name):
        """Input `name` of `node`: its own value, the constant its graph folds to, or its graph's value at the point
        (warned); a colour as an RGB tuple."""
        socket = node.inputs[name]
        source = follow_reroutes(socket)[0]
        own = own_value(socket)
        colour = isinstance(own, tuple)
        if source is None:
            return own[:3] if colour else own
        program, constant = compile_socket(self.sphrect, self.textures, self.log, self.owner, socket)
        if constant is not None:
            return tuple(constant[:3]) if colour else float(constant)
        what = f"heterogeneous volume {'colour' if name == 'Color' else name.lower()} " \
               f"(a {source.bl_label or source.bl_idname} drives it)"
        if program is not None and self.point is not None \
                and not any(i.op in ("image", "attribute") for i in program.instructions):
            p = self.point
            v = self.sphrect._native._eval_node_program(dataclasses.asdict(program), p.position, (0.0, 0.0, 0.0),
                                                        p.generated, object=p.object)
            v = tuple(float(x) for x in v) if colour else float(v[0])
            self.varies = True
            self.log.unsupported_feature(f"{what}: the value at the volume's centre, {_shown(v)}, used instead",
                                         self.owner)
            return v
        own = own[:3] if colour else own
        self.log.unsupported_feature(f"{what}: the input's own value, {_shown(own)}, used instead", self.owner)
        return own

    def add(self, socket, weight):
        """Adds the closures of the shader linked into `socket`, scaled by `weight`."""
        node, output = follow_reroutes(socket)
        if node is None or weight <= 0:
            return
        if output.type != "SHADER" or node.bl_idname in _EMITTERS:  # a colour linked in: Cycles' implicit Emission
            self.log.unsupported_feature("volume emission not simulated", self.owner)
        elif node.bl_idname == _ADD:
            self.add(node.inputs[0], weight)
            self.add(node.inputs[1], weight)
        elif node.bl_idname == _MIX:
            fac = min(max(float(self.value(node, "Fac")), 0.0), 1.0)
            self.add(node.inputs[1], weight * (1.0 - fac))
            self.add(node.inputs[2], weight * fac)
        elif node.bl_idname in (_SCATTER, _ABSORPTION, _PRINCIPLED):
            self.shader(node, weight)
        # any other shader (a BSDF, Holdout...) has no volume closure in Cycles: nothing

    def shader(self, node, weight):
        density = weight * max(float(self.value(node, "Density")), 0.0)
        if node.bl_idname == _PRINCIPLED:
            for name in ("Emission Strength", "Blackbody Intensity"):
                socket = node.inputs[name]
                if follow_reroutes(socket)[0] is not None or own_value(socket) > _WEIGHT_CUTOFF:
                    self.log.unsupported_feature("volume emission not simulated", self.owner)
                    break
            if density <= _WEIGHT_CUTOFF:
                return
        color = np.array(self.value(node, "Color"), dtype=np.float64)
        if node.bl_idname == _ABSORPTION:
            self.sigma_a += density * np.clip(1.0 - color, 0.0, None)
            return
        sigma_s = density * np.clip(color, 0.0, None)
        self.sigma_s += sigma_s
        self.phases.append((float(sigma_s.sum()), float(self.value(node, "Anisotropy"))))
        if node.bl_idname == _PRINCIPLED:
            absorption = np.sqrt(np.clip(np.array(self.value(node, "Absorption Color"), dtype=np.float64), 0, None))
            self.sigma_a += density * np.clip(1.0 - color, 0.0, None) * np.clip(1.0 - absorption, 0.0, None)

    def anisotropy(self):
        """The scattering shaders' anisotropy, weighted by their scattering; their spread warned."""
        weights = np.array([w for w, _ in self.phases])
        gs = np.array([g for _, g in self.phases])
        if not len(gs) or not weights.sum() > 0:
            return 0.0
        g = float(np.dot(weights, gs) / weights.sum())
        if np.ptp(gs[weights > 0]) > 1e-6:
            self.log.unsupported_feature(f"volume scattering of different anisotropies (one phase function: their "
                                         f"mean weighted by scattering, {g:.3g})", self.owner)
        return g


def read_volume(sphrect, socket, owner, log, point=None):
    """(sphrect.Medium or None, varies) of the volume shaders linked into `socket` (a Material or World Output's
    Volume input; None: no extinction, nothing linked).  Inputs that vary in space are read at `point` (a
    VolumePoint) where given, else as their own values, warned naming `owner`; `varies`: whether the medium depends
    on the point."""
    reader = _Reader(sphrect, log, owner, point)
    reader.add(socket, 1.0)
    if not np.any(reader.sigma_s + reader.sigma_a > 0):
        return None, reader.varies
    g = float(np.clip(reader.anisotropy(), -MAX_ANISOTROPY, MAX_ANISOTROPY))
    return sphrect.Medium(sigma_s=tuple(float(x) for x in reader.sigma_s),
                          sigma_a=tuple(float(x) for x in reader.sigma_a), g=g), reader.varies
