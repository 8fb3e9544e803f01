"""A Blender colour / shading-input node's settings as the parameters of its function in
native/render/svm/color_nodes.h and shading_nodes.h (sphrect._native.svm_color takes the same).

Only settings are read here (operations, flags, the Normal node's direction, sampled curves); the values of the
node's input sockets are the node program's business.  Curves are sampled as Cycles 3.4's Blender sync does
(intern/cycles/blender/util.h: curvemapping_minmax, curvemapping_color_to_array, curvemapping_float_to_array):
CURVE_TABLE_SIZE entries over the range of the curves' points, each through Blender's own CurveMapping.evaluate,
for RGB Curves a channel's curve applied to the combined (C) curve.
"""
import numpy as np

CURVE_TABLE_SIZE = 256  # Cycles' RAMP_TABLE_SIZE (color_nodes.h kCurveTableSize)

# The nodes this module reads, by bl_idname.
NODES = ("ShaderNodeLayerWeight", "ShaderNodeFresnel", "ShaderNodeLightFalloff", "ShaderNodeBump",
         "ShaderNodeBlackbody", "ShaderNodeWavelength", "ShaderNodeHueSaturation", "ShaderNodeBrightContrast",
         "ShaderNodeGamma", "ShaderNodeInvert", "ShaderNodeRGBCurve", "ShaderNodeVectorCurve", "ShaderNodeFloatCurve",
         "ShaderNodeVectorMath", "ShaderNodeVectorRotate", "ShaderNodeNormal", "ShaderNodeRGBToBW")


def _curve_range(mapping, count):
    """(min_x, max_x) over the first `count` curves' first and last points (curvemapping_minmax)."""
    lo, hi = np.float32(np.inf), np.float32(-np.inf)
    for curve in list(mapping.curves)[:count]:
        points = curve.points
        lo = min(lo, np.float32(points[0].location[0]))
        hi = max(hi, np.float32(points[len(points) - 1].location[0]))
    return float(lo), float(hi)


def _positions(lo, hi, size):
    """The table's sample positions, in float32 as Cycles computes them: min + i / (size - 1) * range."""
    i = np.arange(size, dtype=np.float32)
    return np.float32(lo) + i / np.float32(size - 1) * (np.float32(hi) - np.float32(lo))


def curve_table(mapping, kind, size=CURVE_TABLE_SIZE):
    """dict(table, min_x, max_x, extrapolate) of a CurveMapping: kind 'rgb' (RGB Curves: R, G, B, C; table
    (size, 3)), 'vector' (Vector Curves: X, Y, Z; (size, 3)) or 'float' (Float Curve; (size,))."""
    count = {"rgb": 4, "vector": 3, "float": 1}[kind]
    if hasattr(mapping, "initialize"):
        mapping.initialize()
    mapping.update()
    lo, hi = _curve_range(mapping, count)
    xs = _positions(lo, hi, size)
    curves = list(mapping.curves)
    evaluate = mapping.evaluate
    if kind == "float":
        table = np.array([evaluate(curves[0], float(x)) for x in xs], dtype=np.float32)
    elif kind == "rgb":
        combined = [evaluate(curves[3], float(x)) for x in xs]
        table = np.array([[evaluate(curves[c], v) for c in range(3)] for v in combined], dtype=np.float32)
    else:
        table = np.array([[evaluate(curves[c], float(x)) for c in range(3)] for x in xs], dtype=np.float32)
    return dict(table=table, min_x=lo, max_x=hi, extrapolate=mapping.extend == "EXTRAPOLATED")


def node_params(node):
    """The settings of `node` (a bpy shader node of NODES) as keyword arguments of its svm_color function ({} for
    the nodes whose function takes only inputs)."""
    kind = node.bl_idname
    if kind == "ShaderNodeVectorMath":
        return dict(operation=node.operation)
    if kind == "ShaderNodeVectorRotate":
        return dict(type=node.rotation_type, invert=bool(node.invert))
    if kind == "ShaderNodeBump":
        return dict(invert=bool(node.invert))
    if kind == "ShaderNodeNormal":
        return dict(direction=tuple(node.outputs["Normal"].default_value))
    if kind == "ShaderNodeRGBCurve":
        return curve_table(node.mapping, "rgb")
    if kind == "ShaderNodeVectorCurve":
        return curve_table(node.mapping, "vector")
    if kind == "ShaderNodeFloatCurve":
        return curve_table(node.mapping, "float")
    if kind not in NODES:
        raise ValueError(f"{node.name}: {kind} is not a node color_node_params reads")
    return {}


def light_falloff_kind(output):
    """The Light Falloff output socket's kind: 'Quadratic', 'Linear' or 'Constant' (its name)."""
    return output.name
