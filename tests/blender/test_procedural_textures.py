"""Cycles' procedural texture nodes against sphrect's (native/render/svm/procedural_textures.h), value by value.

Per node, one Cycles render of a grid of planes, one 64 x 64 tile per setting under test: each plane's material is
an Emission whose Color is the node's output, fed by Texture Coordinate > Object of a rotated, offset Empty (so that
all three coordinates vary over the plane) and, for 1D and 4D, W from a second Empty's object x through Separate
XYZ.  The camera is orthographic, straight down, one tile per plane; Cycles renders 1 sample with a 0.01-pixel
Gaussian filter (its ray passes through the pixel centre to ~1e-4 pixel), no bounces, Standard view, linear EXR.
sphrect's function runs at the pixel centres' points in closed form (Empty^-1 P), its settings read from the same
bpy node by the exporter's procedural_params.py.

Bound: max |ours - Cycles'| <= 1e-3 per tile.  The remaining differences are float rounding (Cycles' AVX2 kernel
fuses multiply-adds, its hit points carry ~1e-7 errors): ~1e-6 on smooth outputs.  Scales are chosen off round
numbers so that no pixel centre falls within rounding of a cell boundary (Voronoi, Checker, Brick)."""
import importlib
import math
import os

import bpy
import numpy as np
from mathutils import Euler, Matrix, Vector

from conftest import addon_module, set_resolution

TILE = 64
COLUMNS = 4
TOLERANCE = 1e-3
# A pixel further off is accepted only where ours takes Cycles' value within this distance in texture space (a
# discontinuity closer to the pixel centre than the rounding of Cycles' hit point), at most this many per tile.
BOUNDARY_EPS = 1e-5
MAX_BOUNDARY_PIXELS = 2
SAMPLES = 1  # more samples spread over the Gaussian's tails: 16 put some pixels 1e-3 off on fine noise

# Texture-space frames: the Empty giving the Vector, the one giving W (its object-space x).
VECTOR_FRAME = Matrix.LocRotScale(Vector((0.37, -0.21, 0.13)), Euler((0.5, 0.35, 0.2)), Vector((0.9, 1.1, 1.0)))
W_FRAME = Matrix.LocRotScale(Vector((-0.4, 0.6, 0.25)), Euler((0.3, -0.6, 0.9)), Vector((1.0, 1.0, 1.0)))


def procedural_params():
    return importlib.import_module("sphrect_blender.io.exporter.procedural_params").procedural_params


def _empty(name, matrix):
    obj = bpy.data.objects.new(name, None)
    obj.matrix_world = matrix
    bpy.context.scene.collection.objects.link(obj)
    return obj


def _plane(name, center):
    """A 2 x 2 plane in z = 0 centred at `center`, facing +z."""
    cx, cy = center
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(cx - 1, cy - 1, 0), (cx + 1, cy - 1, 0), (cx + 1, cy + 1, 0), (cx - 1, cy + 1, 0)], [],
                     [(0, 1, 2, 3)])
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def _material(case, vector_empty, w_empty):
    """An Emission material whose Color is the case's node output; returns (material, texture node)."""
    mat = bpy.data.materials.new(case["label"])
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    links.new(emission.outputs["Emission"], out.inputs["Surface"])
    tex = nodes.new(case["node"])
    for k, v in case.get("props", {}).items():
        setattr(tex, k, v)
    for k, v in case.get("inputs", {}).items():
        tex.inputs[k].default_value = v
    coords = nodes.new("ShaderNodeTexCoord")
    coords.object = vector_empty
    quantize = case.get("quantize")
    if "Vector" in tex.inputs:
        vector = coords.outputs["Object"]
        if quantize:  # floor(q p): Vector Math's Scale and Floor
            scaled = nodes.new("ShaderNodeVectorMath")
            scaled.operation = "SCALE"
            scaled.inputs["Scale"].default_value = quantize
            links.new(vector, scaled.inputs[0])
            floored = nodes.new("ShaderNodeVectorMath")
            floored.operation = "FLOOR"
            links.new(scaled.outputs["Vector"], floored.inputs[0])
            vector = floored.outputs["Vector"]
        links.new(vector, tex.inputs["Vector"])
    if "W" in tex.inputs:
        w_coords = nodes.new("ShaderNodeTexCoord")
        w_coords.object = w_empty
        separate = nodes.new("ShaderNodeSeparateXYZ")
        links.new(w_coords.outputs["Object"], separate.inputs["Vector"])
        w = separate.outputs["X"]
        if quantize:
            scaled = nodes.new("ShaderNodeMath")
            scaled.operation = "MULTIPLY"
            scaled.inputs[1].default_value = quantize
            links.new(w, scaled.inputs[0])
            floored = nodes.new("ShaderNodeMath")
            floored.operation = "FLOOR"
            links.new(scaled.outputs["Value"], floored.inputs[0])
            w = floored.outputs["Value"]
        links.new(w, tex.inputs["W"])
    links.new(tex.outputs[case["output"]], emission.inputs["Color"])
    return mat, tex


def _render(scene, path):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = SAMPLES
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = 0
    c.seed = 0
    c.pixel_filter_type = "GAUSSIAN"
    c.filter_width = 0.01
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return addon_module("images").read_image_rgba(path)


def _tile_points(row, column, rows):
    """Pixel centres of tile (row, column) in world space, (TILE*TILE, 3), row-major from the top."""
    step = 2.0 / TILE
    x0, y0 = 2.0 * column - 1.0, -2.0 * row + 1.0  # the plane's left and top edges
    xs = x0 + (np.arange(TILE) + 0.5) * step
    ys = y0 - (np.arange(TILE) + 0.5) * step
    gx, gy = np.meshgrid(xs, ys)
    return np.stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)], axis=1)


def _to_frame(points, matrix):
    inv = np.array(matrix.inverted())
    return points @ inv[:3, :3].T + inv[:3, 3]


def _tile_frame(frame, row, column):
    """`frame` moved onto tile (row, column): every tile sees the same texture-space points around the origin."""
    return Matrix.Translation((2.0 * column, -2.0 * row, 0.0)) @ frame


def _evaluate(tex, output, points, w, quantize=None, override=None):
    from sphrect import _native
    if quantize:
        q = np.float32(quantize)
        points, w = np.floor(points * q), np.floor(w * q)
    name, params = procedural_params()(tex)
    params.update(override or {})
    ours = _native.procedural_texture(name, points, w, **params)[output.lower()]
    return np.repeat(ours[:, None], 3, axis=1) if ours.ndim == 1 else ours


def _on_a_boundary(tex, case, points, w, theirs):
    """Which points take Cycles' value within BOUNDARY_EPS of themselves in texture space: a discontinuity (a Voronoi
    cell's edge, a checker or brick edge) closer than the rounding of Cycles' hit point."""
    found = np.zeros(len(points), bool)
    for axis in range(4):
        for sign in (-1.0, 1.0):
            p, q = points.copy(), w.copy()
            if axis < 3:
                p[:, axis] += sign * BOUNDARY_EPS
            else:
                q += sign * BOUNDARY_EPS
            ours = _evaluate(tex, case["output"], p, q, case.get("quantize"), case.get("override"))
            found |= np.abs(ours - theirs).max(axis=1) <= TOLERANCE
    return found


def compare_with_cycles(cases, tmp_path):
    """Renders `cases` with Cycles and evaluates them with sphrect; returns {label: (max abs difference over the
    pixels not on a boundary, number of pixels on one)}."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    world = bpy.data.worlds.new("black")
    world.use_nodes = False
    world.color = (0.0, 0.0, 0.0)
    scene.world = world
    rows = math.ceil(len(cases) / COLUMNS)
    columns = min(len(cases), COLUMNS)
    set_resolution(scene, TILE * columns, TILE * rows)
    nodes = []
    for i, case in enumerate(cases):
        row, column = divmod(i, COLUMNS)
        plane = _plane(case["label"], (2.0 * column, -2.0 * row))
        vector_empty = _empty("Vector " + case["label"], _tile_frame(VECTOR_FRAME, row, column))
        w_empty = _empty("W " + case["label"], _tile_frame(W_FRAME, row, column))
        mat, tex = _material(case, vector_empty, w_empty)
        plane.data.materials.append(mat)
        nodes.append(tex)
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = 2.0 * max(columns, rows)
    cam_data.sensor_fit = "AUTO"
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = (columns - 1.0, -(rows - 1.0), 10.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    bpy.context.view_layer.update()
    image = _render(scene, str(tmp_path / "cycles.exr"))

    results = {}
    for i, (case, tex) in enumerate(zip(cases, nodes)):
        row, column = divmod(i, COLUMNS)
        world_points = _tile_points(row, column, rows)
        points = _to_frame(world_points, _tile_frame(VECTOR_FRAME, row, column)).astype(np.float32)
        w = _to_frame(world_points, _tile_frame(W_FRAME, row, column))[:, 0].astype(np.float32)
        ours = _evaluate(tex, case["output"], points, w, case.get("quantize"), case.get("override"))
        theirs = image[row * TILE:(row + 1) * TILE, column * TILE:(column + 1) * TILE, :3].reshape(-1, 3)
        assert np.isfinite(theirs).all()
        assert np.ptp(theirs) > 0.01 or case.get("flat"), f"{case['label']}: Cycles' tile is flat"
        difference = np.abs(ours - theirs).max(axis=1)
        off = difference > TOLERANCE
        boundary = np.zeros(len(points), bool)
        if off.any():
            boundary[off] = _on_a_boundary(tex, case, points[off], w[off], theirs[off])
        if os.environ.get("SPHRECT_DUMP"):
            np.savez(os.path.join(os.environ["SPHRECT_DUMP"], case["label"] + ".npz"), ours=ours, theirs=theirs,
                     points=points, w=w)
        results[case["label"]] = (float(difference[~boundary].max()), int(boundary.sum()))
        identical = float(np.mean(np.all(ours == theirs, axis=1)))
        print(f"{case['label']}: max |sphrect - Cycles| = {results[case['label']][0]:.2e}, "
              f"{identical:.0%} of pixels identical" + (f", {boundary.sum()} on a boundary" if boundary.any() else ""))
    return results


def check(cases, tmp_path):
    results = compare_with_cycles(cases, tmp_path)
    for node in sorted({c["node"] for c in cases}):
        labels = [c["label"] for c in cases if c["node"] == node]
        worst = max(labels, key=lambda k: results[k][0])
        print(f"{node}: worst {worst} {results[worst][0]:.2e} over {len(labels)} settings")
    assert all(d <= TOLERANCE for d, _ in results.values()), results
    # Boundary pixels are rare: a discontinuity within BOUNDARY_EPS of a pixel centre.
    assert all(b <= MAX_BOUNDARY_PIXELS for _, b in results.values()), results


def case(node, label, output, props=None, inputs=None, **extra):
    return dict(node=node, label=label, output=output, props=props or {}, inputs=inputs or {}, **extra)


DIMS = ["1D", "2D", "3D", "4D"]

NOISE = [case("ShaderNodeTexNoise", f"noise_{d}_{o}", o, {"noise_dimensions": d},
              {"Scale": 2.7, "Detail": 3.5, "Roughness": 0.6, "Distortion": 0.0})
         for d in DIMS for o in ("Fac", "Color")] + [
    case("ShaderNodeTexNoise", f"noise_{d}_distortion", "Color", {"noise_dimensions": d},
         {"Scale": 1.9, "Detail": 2.0, "Roughness": 0.45, "Distortion": 1.3}) for d in DIMS] + [
    case("ShaderNodeTexNoise", "noise_3D_detail0", "Fac", {"noise_dimensions": "3D"}, {"Scale": 3.1, "Detail": 0.0}),
    case("ShaderNodeTexNoise", "noise_3D_detail15", "Fac", {"noise_dimensions": "3D"},
         {"Scale": 0.9, "Detail": 15.0, "Roughness": 0.7}),
    case("ShaderNodeTexNoise", "noise_2D_rough1", "Fac", {"noise_dimensions": "2D"},
         {"Scale": 4.3, "Detail": 6.25, "Roughness": 1.0}),
    case("ShaderNodeTexNoise", "noise_4D_rough0", "Fac", {"noise_dimensions": "4D"},
         {"Scale": 1.3, "Detail": 4.0, "Roughness": 0.0}),
]

FEATURES = ["F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"]
METRICS = ["EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI"]
_VORONOI_OUT = {"F1": ["Distance", "Color", "Position", "W"], "F2": ["Distance", "Color", "Position", "W"],
                "SMOOTH_F1": ["Distance", "Color", "Position", "W"], "DISTANCE_TO_EDGE": ["Distance"],
                "N_SPHERE_RADIUS": ["Radius"]}


def _voronoi_cases(dims):
    cases = []
    for d in dims:
        for f in FEATURES:
            for o in _VORONOI_OUT[f]:
                if (o == "W" and d in ("2D", "3D")) or (o == "Position" and d == "1D"):
                    continue
                cases.append(case("ShaderNodeTexVoronoi", f"voronoi_{d}_{f}_{o}", o,
                                  {"voronoi_dimensions": d, "feature": f},
                                  {"Scale": 2.3, "Smoothness": 0.7, "Randomness": 0.85}))
        for f in ("F1", "SMOOTH_F1", "DISTANCE_TO_EDGE"):  # a regular lattice, and full smoothness
            cases.append(case("ShaderNodeTexVoronoi", f"voronoi_{d}_{f}_lattice", "Distance",
                              {"voronoi_dimensions": d, "feature": f},
                              {"Scale": 1.7, "Smoothness": 1.0, "Randomness": 0.0}))
        if d != "1D":
            for m in METRICS[1:]:
                for f in ("F1", "F2", "SMOOTH_F1"):
                    cases.append(case("ShaderNodeTexVoronoi", f"voronoi_{d}_{f}_{m}", "Distance",
                                      {"voronoi_dimensions": d, "feature": f, "distance": m},
                                      {"Scale": 2.1, "Exponent": 1.7, "Smoothness": 0.4, "Randomness": 1.0}))
    return cases


MUSGRAVE_TYPES = ["MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HYBRID_MULTIFRACTAL", "FBM", "HETERO_TERRAIN"]
MUSGRAVE = [case("ShaderNodeTexMusgrave", f"musgrave_{d}_{t}", "Fac", {"musgrave_dimensions": d, "musgrave_type": t},
                 {"Scale": 1.7, "Detail": 3.4, "Dimension": 1.3, "Lacunarity": 2.2, "Offset": 0.8, "Gain": 1.4})
            for d in DIMS for t in MUSGRAVE_TYPES] + [
    case("ShaderNodeTexMusgrave", f"musgrave_3D_{t}_{i}", "Fac", {"musgrave_dimensions": "3D", "musgrave_type": t},
         inputs, flat=inputs["Detail"] == 0 and t in ("MULTIFRACTAL", "FBM", "HYBRID_MULTIFRACTAL"))  # 1, 0, 0
    for t in MUSGRAVE_TYPES
    for i, inputs in enumerate([{"Scale": 2.3, "Detail": 0.0, "Dimension": 0.0, "Lacunarity": 0.5, "Offset": 0.2},
                                {"Scale": 0.9, "Detail": 7.0, "Dimension": 0.6, "Lacunarity": 3.1, "Offset": 1.1,
                                 "Gain": 3.0}])]

# White noise hashes the point's bits, which Cycles' hit point has only to rounding: its input is quantised,
# floor(7.3 p), to integers both sides compute exactly.
WHITE_NOISE = [case("ShaderNodeTexWhiteNoise", f"white_noise_{d}_{o}", o, {"noise_dimensions": d}, quantize=7.3)
               for d in DIMS for o in ("Value", "Color")]

GRADIENT = [case("ShaderNodeTexGradient", f"gradient_{t}", "Color", {"gradient_type": t})
            for t in ["LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL"]]

CHECKER = [case("ShaderNodeTexChecker", f"checker_{i}", o,
                inputs={"Scale": s, "Color1": (0.9, 0.3, 0.1, 1.0), "Color2": (0.05, 0.4, 0.7, 1.0)})
           for i, (s, o) in enumerate([(2.37, "Color"), (4.13, "Fac"), (0.77, "Color")])]

WAVE = ([case("ShaderNodeTexWave", f"wave_bands_{b}_{p}", "Fac",
              {"wave_type": "BANDS", "bands_direction": b, "wave_profile": p}, {"Scale": 0.83, "Phase Offset": 0.4})
         for b in ["X", "Y", "Z", "DIAGONAL"] for p in ["SIN", "SAW", "TRI"]]
        + [case("ShaderNodeTexWave", f"wave_rings_{r}", "Color", {"wave_type": "RINGS", "rings_direction": r},
                {"Scale": 0.61}) for r in ["X", "Y", "Z", "SPHERICAL"]]
        + [case("ShaderNodeTexWave", f"wave_distorted_{t}_{p}", "Fac", {"wave_type": t, "wave_profile": p,
                                                                          "rings_direction": "SPHERICAL"},
                {"Scale": 0.7, "Distortion": 4.5, "Detail": 3.3, "Detail Scale": 1.6, "Detail Roughness": 0.65})
           for t in ["BANDS", "RINGS"] for p in ["SIN", "SAW", "TRI"]])

# Deep Magic amplifies the hit point's rounding (d colour / d point ~ 5 scale distortion^depth): a small scale and
# distortion keep it under the bound at depth 10.
MAGIC = [case("ShaderNodeTexMagic", f"magic_depth{n}_{o}", o, {"turbulence_depth": n},
              {"Scale": 1.3 if n < 6 else 0.6, "Distortion": 1.7 if n < 6 else 1.1})
         for n in range(0, 11) for o in (["Color", "Fac"] if n == 2 else ["Color"])]

BRICK = [case("ShaderNodeTexBrick", "brick_hard_mortar", "Color", {},
              {"Scale": 2.3, "Mortar Smooth": 0.0, "Color1": (0.8, 0.3, 0.1, 1), "Color2": (0.2, 0.6, 0.3, 1),
               "Mortar": (0.1, 0.1, 0.5, 1)}),
         case("ShaderNodeTexBrick", "brick_smooth_bias", "Color",
              {"offset": 0.3, "offset_frequency": 3, "squash": 0.6, "squash_frequency": 2},
              {"Scale": 1.9, "Mortar Size": 0.05, "Mortar Smooth": 0.4, "Bias": -0.3, "Brick Width": 0.7,
               "Row Height": 0.31, "Color1": (0.8, 0.3, 0.1, 1), "Color2": (0.2, 0.6, 0.3, 1)}),
         case("ShaderNodeTexBrick", "brick_fac", "Fac", {"offset": 0.7, "squash": 1.6, "squash_frequency": 3},
              {"Scale": 2.9, "Mortar Size": 0.06, "Mortar Smooth": 0.5})]


def test_noise_matches_cycles(tmp_path):
    check(NOISE, tmp_path)


def test_comparison_sees_a_wrong_setting(tmp_path):
    """The comparison can fail: our side with a setting slightly off (or another Voronoi feature) is far from
    Cycles'."""
    cases = [dict(NOISE[4], label="noise_rough_off", override={"roughness": 0.55}),
             dict(NOISE[4], label="noise_seed_off", override={"dimensions": 4}),
             dict(_voronoi_cases(["2D"])[0], label="voronoi_feature_off", override={"feature": "f2"})]
    results = compare_with_cycles(cases, tmp_path)
    assert all(d > 10 * TOLERANCE for d, _ in results.values()), results


def test_voronoi_1d_2d_matches_cycles(tmp_path):
    check(_voronoi_cases(["1D", "2D"]), tmp_path)


def test_voronoi_3d_4d_matches_cycles(tmp_path):
    check(_voronoi_cases(["3D", "4D"]), tmp_path)


def test_musgrave_matches_cycles(tmp_path):
    check(MUSGRAVE, tmp_path)


def test_white_noise_gradient_checker_match_cycles(tmp_path):
    check(WHITE_NOISE + GRADIENT + CHECKER, tmp_path)


def test_wave_magic_brick_match_cycles(tmp_path):
    check(WAVE + MAGIC + BRICK, tmp_path)


def test_defaults_are_blenders():
    """A new node's settings, as the exporter reads them, give what the functions give with no settings: the params
    structs' defaults are Blender's."""
    from sphrect import _native
    read = importlib.import_module("sphrect_blender.io.exporter.procedural_params")
    mat = bpy.data.materials.new("defaults")
    mat.use_nodes = True
    points = np.random.default_rng(1).uniform(-2, 2, (256, 3)).astype(np.float32)
    w = np.linspace(-2, 2, 256, dtype=np.float32)
    for bl_idname, (name, _) in read.PROCEDURAL_NODES.items():
        got_name, params = read.procedural_params(mat.node_tree.nodes.new(bl_idname))
        assert got_name == name and name in _native.procedural_textures
        ours = _native.procedural_texture(name, points, w, **params)
        defaults = _native.procedural_texture(name, points, w)
        for output in ours:
            assert np.array_equal(ours[output], defaults[output]), (name, output, params)
    assert set(_native.procedural_textures) == {n for n, _ in read.PROCEDURAL_NODES.values()}
