"""Cycles 3.4's colour and shading-input nodes against their pure functions (native/render/svm/color_nodes.h,
shading_nodes.h through sphrect._native.svm_color), node by node and mode by mode.

Each test renders with Cycles a plane filling an orthographic camera (1 sample, filter width 0.01: rays through
the pixel centres; no bounces; Standard view; linear float EXR) whose material is an Emission of strength 1 and
colour the node's output.  The node's inputs vary across the image: the plane's Object coordinates, floored by a
Math node, number its pixels (column gx, row gy from the bottom), and Math Multiply Add nodes turn them into input
values -- computed here in float32 the same way -- so one render holds a grid of inputs, each pixel's exactly known
despite the rays' jitter.  The function is evaluated at the same inputs; the largest absolute difference over the
image must be <= 1e-3 (TOLERANCE), and is printed per node.  Deterministic (Cycles' image of an emitter at 1 sample
has no noise)."""
import importlib

import bpy
import numpy as np
import pytest

from conftest import addon_module, builders, ensure_addon, set_resolution

pytestmark = pytest.mark.slow

TOLERANCE = 1e-3
W, H = 33, 17  # the grid: gx in 0..32 (so gx / 32 hits 0.5 exactly), gy in 0..16
CAMERA_Z, CLIP_START = 10.0, 0.5


def svm():
    from sphrect._native import svm_color
    return svm_color


def params_module():
    return importlib.import_module("sphrect_blender.io.exporter.color_node_params")  # not imported by registering


def _fma32(a, b, c):
    """a b + c rounded once to float32, as Cycles' kernels (built with FMA) compute Multiply Add (the float32
    product is exact in float64)."""
    return (np.float64(a) * np.float64(b) + np.float64(c)).astype(np.float32)


class Grid:
    """A node tree under construction and the numbers its sockets carry at every pixel (float32 [H, W])."""

    def __init__(self, nt, gx, gy, gx_socket, gy_socket):
        self.nt, self.gx, self.gy = nt, gx, gy
        self.gx_socket, self.gy_socket = gx_socket, gy_socket

    def node(self, kind, **settings):
        n = self.nt.nodes.new(kind)
        for k, v in settings.items():
            setattr(n, k, v)
        return n

    def affine(self, sx, sy=0.0, offset=0.0):
        """(socket, values) of gx sx + gy sy + offset: two Math Multiply Add nodes, rounded as Cycles' (fused)."""
        f = np.float32
        inner = self.node("ShaderNodeMath", operation="MULTIPLY_ADD")
        self.nt.links.new(self.gy_socket, inner.inputs[0])
        inner.inputs[1].default_value, inner.inputs[2].default_value = sy, offset
        outer = self.node("ShaderNodeMath", operation="MULTIPLY_ADD")
        self.nt.links.new(self.gx_socket, outer.inputs[0])
        outer.inputs[1].default_value = sx
        self.nt.links.new(inner.outputs[0], outer.inputs[2])
        inner_values = _fma32(self.gy, f(sy), f(offset))
        return outer.outputs[0], _fma32(self.gx, f(sx), inner_values)

    def vector(self, parts):
        """(socket, values [H, W, 3]) of a Combine XYZ of three parts: (socket, values) or constants."""
        c = self.node("ShaderNodeCombineXYZ")
        columns = []
        for i, p in enumerate(parts):
            if isinstance(p, tuple):
                self.nt.links.new(p[0], c.inputs[i])
                columns.append(p[1])
            else:
                c.inputs[i].default_value = p
                columns.append(np.full(self.gx.shape, p, dtype=np.float32))
        return c.outputs[0], np.stack(columns, axis=-1)

    def link(self, socket, node_input):
        if isinstance(socket, tuple):
            self.nt.links.new(socket[0], node_input)
        else:
            node_input.default_value = socket


def render_grid(tmp_path, build, back=False, tilt=0.0, name="grid"):
    """Render the grid plane whose Emission colour `build(grid)` returns (an output socket); returns (Cycles'
    RGB [H, W, 3] float64, grid, hits) with hits: dict of the world hit point per pixel and the ray length.
    back: the camera sees the plane's back face; tilt: the plane turned about the X axis by that many radians."""
    scene = _ortho_scene()

    # The plane spans [0, W] x [0, H] in object space (Object coordinates = pixel numbers + 0.5 at the centres) and
    # is scaled by 2 / W about the view's centre, tilted by `tilt` about X (then stretched by 1 / cos to fill the
    # view), or turned over about Y for `back`.
    mesh = bpy.data.meshes.new("Grid")
    mesh.from_pydata([(0, 0, 0), (W, 0, 0), (W, H, 0), (0, H, 0)], [], [(0, 1, 2, 3)])
    obj = bpy.data.objects.new("Grid", mesh)
    scene.collection.objects.link(obj)
    s = 2.0 / W
    obj.scale = (s, s / np.cos(tilt), s)
    obj.rotation_euler = (tilt, np.pi if back else 0.0, 0.0)
    bpy.context.view_layer.update()
    m = np.array(obj.matrix_world)
    offset = m[:3, :3] @ np.array([W / 2, H / 2, 0.0])
    obj.location = tuple(-offset)
    bpy.context.view_layer.update()
    m = np.array(obj.matrix_world, dtype=np.float64)

    # Pixel centres on the film, their rays (-Z) and where they hit the plane.
    u = -1 + (np.arange(W) + 0.5) * (2.0 / W)
    v = (H / W) * (1 - (np.arange(H) + 0.5) * (2.0 / H))
    uu, vv = np.meshgrid(u, v)
    a = np.stack([m[:3, 0], m[:3, 1], [0, 0, -1]], axis=1)  # ox M.x + oy M.y - z e_z = (u, v, 0) - M.t
    rhs = np.stack([uu - m[0, 3], vv - m[1, 3], -np.full_like(uu, m[2, 3])], axis=-1)
    sol = rhs @ np.linalg.inv(a).T
    ox, oy, hz = sol[..., 0], sol[..., 1], sol[..., 2]
    gx, gy = np.floor(ox).astype(np.float32), np.floor(oy).astype(np.float32)
    hits = dict(P=np.stack([uu, vv, hz], axis=-1), ray_length=(CAMERA_Z - CLIP_START) - hz, object=(ox, oy))

    mat = bpy.data.materials.new("Grid")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    tc = nt.nodes.new("ShaderNodeTexCoord")
    sep = nt.nodes.new("ShaderNodeSeparateXYZ")
    nt.links.new(tc.outputs["Object"], sep.inputs[0])
    floors = []
    for i in range(2):
        f = nt.nodes.new("ShaderNodeMath")
        f.operation = "FLOOR"
        nt.links.new(sep.outputs[i], f.inputs[0])
        floors.append(f.outputs[0])
    grid = Grid(nt, gx, gy, floors[0], floors[1])
    grid.separate = sep  # the Object coordinates, unfloored (for the bump's height)
    color = build(grid)
    emission = nt.nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    nt.links.new(color, emission.inputs["Color"])
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(emission.outputs[0], out.inputs["Surface"])
    obj.data.materials.append(mat)

    return _render_cycles(scene, tmp_path / f"{name}.exr"), grid, hits


def _ortho_scene():
    """An empty scene, black world, seen by an orthographic camera at z = CAMERA_Z looking down -Z (view 2 wide)."""
    bpy.ops.wm.read_homefile(use_empty=True)
    ensure_addon()
    scene = bpy.context.scene
    set_resolution(scene, W, H)
    scene.view_settings.view_transform = "Standard"
    builders.black_world(scene)
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.type, cam_data.ortho_scale, cam_data.clip_start, cam_data.clip_end = "ORTHO", 2.0, CLIP_START, 100.0
    cam = bpy.data.objects.new("Camera", cam_data)
    scene.collection.objects.link(cam)
    cam.location = (0.0, 0.0, CAMERA_Z)
    scene.camera = cam
    return scene


def _render_cycles(scene, path):
    """Cycles' RGB [H, W, 3] (float64, row 0 = top): 1 sample through the pixel centres, no bounces, float EXR."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.use_adaptive_sampling, c.use_denoising = "CPU", 1, False, False
    c.max_bounces, c.pixel_filter_type, c.filter_width = 0, "BOX", 0.01
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    scene.render.film_transparent = False
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return addon_module("images").read_image_rgba(scene.render.filepath)[..., :3].astype(np.float64)


def as_color(values):
    """A function's output as the Emission colour shows it: a scalar grey, a vector its components."""
    values = np.asarray(values, dtype=np.float64)
    return np.repeat(values[..., None], 3, axis=-1) if values.shape[-1:] != (3,) else values


def compare(label, cycles, ours, tolerance=TOLERANCE):
    """Assert that `ours` (the function's values) is within `tolerance` of Cycles' image (or part of it); print
    the largest difference and where it is."""
    ours = np.asarray(ours, dtype=np.float64)
    if ours.shape != cycles.shape:
        ours = as_color(ours).reshape(cycles.shape)
    assert np.isfinite(cycles).all()
    # Cycles' film drops a sample that is not finite (kernel/film: the pixel stays black).
    assert (cycles[~np.isfinite(ours)] == 0).all()
    ours = np.where(np.isfinite(ours), ours, 0.0)
    assert np.ptp(cycles) > 0.05  # the grid varies: the comparison sees a wrong function
    diff = np.abs(ours - cycles)
    worst = float(diff.max())
    at = np.unravel_index(int(diff.argmax()), diff.shape)
    print(f"{label}: max |ours - Cycles| = {worst:.2e} (at {tuple(int(i) for i in at)}: ours {ours[at]:.6g}, "
          f"Cycles {cycles[at]:.6g}); values span [{cycles.min():.3g}, {cycles.max():.3g}]")
    assert worst <= tolerance
    return worst


def flat(a):
    return np.asarray(a, dtype=np.float32).reshape(-1, *np.shape(a)[2:])


def combine_rgb(grid, r, g, b):
    c = grid.node("ShaderNodeCombineXYZ")
    for i, s in enumerate((r, g, b)):
        grid.nt.links.new(s, c.inputs[i])
    return c.outputs[0]


# ---- Layer Weight and Fresnel ---------------------------------------------------------------------------------

@pytest.mark.parametrize("back", [False, True], ids=["front", "back"])
def test_layer_weight_and_fresnel(tmp_path, back):
    """Layer Weight (Fresnel, Facing) and Fresnel with the Normal input linked, so that I.N runs over [-1.05, 1.05]
    down the image (its z; the incoming direction is +Z) while Blend runs over [0, 1] (0.5 included) and the IOR
    over [0.2, 2.76] across it; on the front and on the back face (backfacing inverts the IOR)."""
    built = {}

    def build(grid):
        nz = grid.affine(0.0, 2.1 / (H - 1), -1.05)
        normal = grid.vector((0.3, 0.0, nz))
        blend = grid.affine(1.0 / (W - 1))
        ior = grid.affine(0.08, 0.0, 0.2)
        lw = grid.node("ShaderNodeLayerWeight")
        fr = grid.node("ShaderNodeFresnel")
        grid.link(normal, lw.inputs["Normal"])
        grid.link(normal, fr.inputs["Normal"])
        grid.link(blend, lw.inputs["Blend"])
        grid.link(ior, fr.inputs["IOR"])
        built.update(normal=normal[1], blend=blend[1], ior=ior[1])
        return combine_rgb(grid, lw.outputs["Fresnel"], lw.outputs["Facing"], fr.outputs["Fac"])

    cycles, grid, _ = render_grid(tmp_path, build, back=back)
    f = svm()
    incoming = (0.0, 0.0, 1.0)
    fresnel, facing = f.layer_weight(flat(built["blend"]), incoming, flat(built["normal"]), float(back))
    fac = f.fresnel(flat(built["ior"]), incoming, flat(built["normal"]), float(back))
    side = "back" if back else "front"
    compare(f"Layer Weight Fresnel ({side})", cycles[..., 0], fresnel.reshape(H, W))
    compare(f"Layer Weight Facing ({side})", cycles[..., 1], facing.reshape(H, W))
    compare(f"Fresnel ({side})", cycles[..., 2], fac.reshape(H, W))


def test_layer_weight_and_fresnel_on_a_sphere(tmp_path):
    """Layer Weight and Fresnel with the Normal input unlinked (the shading normal) on a smooth sphere, where the
    incidence runs from normal to grazing.  The shading normal at each pixel is Cycles' own (a first render of the
    Geometry node's Normal); the second render's nodes are compared with the functions at that normal."""
    scene = _ortho_scene()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.5)
    bpy.ops.object.shade_smooth()
    sphere = bpy.context.object
    mat = bpy.data.materials.new("Sphere")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    emission = nt.nodes.new("ShaderNodeEmission")
    nt.links.new(emission.outputs[0], nt.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    sphere.data.materials.append(mat)
    nt.links.new(nt.nodes.new("ShaderNodeNewGeometry").outputs["Normal"], emission.inputs["Color"])
    normals = _render_cycles(scene, tmp_path / "normals.exr")
    hit = np.linalg.norm(normals, axis=-1) > 0.5
    assert hit.sum() > 100 and (normals[hit][:, 2] < 0.2).any()  # grazing incidence reached

    lw, fr, comb = (nt.nodes.new(t) for t in ("ShaderNodeLayerWeight", "ShaderNodeFresnel", "ShaderNodeCombineXYZ"))
    lw.inputs["Blend"].default_value, fr.inputs["IOR"].default_value = 0.3, 1.45
    for i, out in enumerate((lw.outputs["Fresnel"], lw.outputs["Facing"], fr.outputs["Fac"])):
        nt.links.new(out, comb.inputs[i])
    nt.links.new(comb.outputs[0], emission.inputs["Color"])
    cycles = _render_cycles(scene, tmp_path / "weights.exr")
    f = svm()
    n = normals[hit].astype(np.float32)
    fresnel, facing = f.layer_weight(0.3, (0.0, 0.0, 1.0), n)
    fac = f.fresnel(1.45, (0.0, 0.0, 1.0), n)
    assert (cycles[~hit] == 0).all()
    compare("Layer Weight Fresnel (sphere)", cycles[hit][:, 0], fresnel.reshape(-1))
    compare("Layer Weight Facing (sphere)", cycles[hit][:, 1], facing.reshape(-1))
    compare("Fresnel (sphere)", cycles[hit][:, 2], fac.reshape(-1))


# ---- Light Falloff ----------------------------------------------------------------------------------------------

def test_light_falloff(tmp_path):
    """Light Falloff's three outputs on a plane tilted by 0.6 rad, so that the camera rays' length (from the near
    clipping plane to the hit) runs over ~[8.6, 10.3] down the image; Strength over [0, 0.5] across it, Smooth over
    [0, 20] down it (0 included: no smoothing)."""
    built = {}

    def build(grid):
        strength = grid.affine(0.5 / (W - 1))
        smooth = grid.affine(0.0, 20.0 / (H - 1))
        lf = grid.node("ShaderNodeLightFalloff")
        grid.link(strength, lf.inputs["Strength"])
        grid.link(smooth, lf.inputs["Smooth"])
        built.update(strength=strength[1], smooth=smooth[1])
        return combine_rgb(grid, lf.outputs["Quadratic"], lf.outputs["Linear"], lf.outputs["Constant"])

    cycles, grid, hits = render_grid(tmp_path, build, tilt=0.6)
    f = svm()
    for channel, kind in enumerate(f.LIGHT_FALLOFF_KINDS):
        ours = f.light_falloff(kind, flat(built["strength"]), flat(built["smooth"]), flat(hits["ray_length"]))
        compare(f"Light Falloff {kind}", cycles[..., channel], ours.reshape(H, W), tolerance=TOLERANCE)


def test_light_falloff_ray_length_perspective(tmp_path):
    """The camera ray's length Light Falloff reads through a perspective camera: Cycles starts the ray on the near
    clipping plane, so at a pixel whose ray makes angle theta with the optical axis the length to a plane at
    distance d is (d - clip_start) / cos(theta).  Linear with Strength 1 shows the length itself."""
    scene = _ortho_scene()
    cam = scene.camera.data
    cam.type, cam.lens, cam.sensor_width, cam.sensor_fit = "PERSP", 50.0, 36.0, "AUTO"
    bpy.ops.mesh.primitive_plane_add(size=40.0)
    mat = bpy.data.materials.new("Falloff")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    lf, emission = nt.nodes.new("ShaderNodeLightFalloff"), nt.nodes.new("ShaderNodeEmission")
    lf.inputs["Strength"].default_value, lf.inputs["Smooth"].default_value = 1.0, 0.0
    nt.links.new(lf.outputs["Linear"], emission.inputs["Color"])
    nt.links.new(emission.outputs[0], nt.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    bpy.context.object.data.materials.append(mat)
    cycles = _render_cycles(scene, tmp_path / "perspective.exr")
    half = 18.0 / 50.0  # the half-width of the view at unit distance (sensor width 36 mm, lens 50 mm)
    u = (-1 + (np.arange(W) + 0.5) * (2.0 / W)) * half
    v = (1 - (np.arange(H) + 0.5) * (2.0 / H)) * half * H / W
    uu, vv = np.meshgrid(u, v)
    length = (CAMERA_Z - CLIP_START) * np.sqrt(1 + uu * uu + vv * vv)
    ours = svm().light_falloff("Linear", 1.0, 0.0, flat(length)).reshape(H, W)
    compare("Light Falloff ray length (perspective)", cycles, ours)


# ---- Colour nodes ------------------------------------------------------------------------------------------------

def test_blackbody(tmp_path):
    """Blackbody over 500-14500 K (every band of the fit and both clamps), 25 K apart."""
    built = {}

    def build(grid):
        t = grid.affine(25.0, 25.0 * W, 500.0)
        bb = grid.node("ShaderNodeBlackbody")
        grid.link(t, bb.inputs["Temperature"])
        built["t"] = t[1]
        return bb.outputs["Color"]

    cycles, _, _ = render_grid(tmp_path, build)
    compare("Blackbody", cycles, svm().blackbody(flat(built["t"])).reshape(H, W, 3))


def test_wavelength(tmp_path):
    """Wavelength over 370-792 nm (below, inside and above the table's 380-780 nm), 0.75 nm apart."""
    built = {}

    def build(grid):
        nm = grid.affine(0.75, 0.75 * W, 370.0)
        wl = grid.node("ShaderNodeWavelength")
        grid.link(nm, wl.inputs["Wavelength"])
        built["nm"] = nm[1]
        return wl.outputs["Color"]

    cycles, _, _ = render_grid(tmp_path, build)
    compare("Wavelength", cycles, svm().wavelength(flat(built["nm"])).reshape(H, W, 3))


# The colour driving the colour nodes: red across [-0.2, 1.4], green down [0, 1.2], blue from both.
def _color(grid):
    return grid.vector((grid.affine(1.6 / (W - 1), 0.0, -0.2), grid.affine(0.0, 1.2 / (H - 1)),
                        grid.affine(0.5 / (W - 1), -0.4 / (H - 1), 0.45)))


HSV_CASES = {
    # hue across, saturation down; value, fac constant
    "hue_saturation": dict(hue=("gx", 1.2 / (W - 1), -0.1), saturation=("gy", 2.0 / (H - 1), 0.0), value=1.3,
                           fac=0.85),
    # value across, fac down (beyond [0, 1] too)
    "value_fac": dict(hue=0.3, saturation=1.2, value=("gx", 2.0 / (W - 1), 0.0), fac=("gy", 1.4 / (H - 1), -0.2)),
}


def _input(grid, spec):
    if isinstance(spec, tuple):
        axis, scale, offset = spec
        return grid.affine(scale, 0.0, offset) if axis == "gx" else grid.affine(0.0, scale, offset)
    return spec


@pytest.mark.parametrize("case", sorted(HSV_CASES))
def test_hue_saturation_value(tmp_path, case):
    built = {}

    def build(grid):
        color = _color(grid)
        node = grid.node("ShaderNodeHueSaturation")
        grid.link(color, node.inputs["Color"])
        built["color"] = color[1]
        for name, socket in (("hue", "Hue"), ("saturation", "Saturation"), ("value", "Value"), ("fac", "Fac")):
            value = _input(grid, HSV_CASES[case][name])
            grid.link(value, node.inputs[socket])
            built[name] = flat(value[1]) if isinstance(value, tuple) else value
        return node.outputs["Color"]

    cycles, _, _ = render_grid(tmp_path, build)
    ours = svm().hue_saturation_value(flat(built["color"]), built["hue"], built["saturation"], built["value"],
                                      built["fac"])
    compare(f"Hue/Saturation/Value ({case})", cycles, ours.reshape(H, W, 3))


def test_bright_contrast(tmp_path):
    """Bright over [-0.5, 0.5] across, Contrast over [-1, 1.5] down (the clamp at 0 reached)."""
    built = {}

    def build(grid):
        color = _color(grid)
        bright, contrast = grid.affine(1.0 / (W - 1), 0.0, -0.5), grid.affine(0.0, 2.5 / (H - 1), -1.0)
        node = grid.node("ShaderNodeBrightContrast")
        grid.link(color, node.inputs["Color"])
        grid.link(bright, node.inputs["Bright"])
        grid.link(contrast, node.inputs["Contrast"])
        built.update(color=color[1], bright=bright[1], contrast=contrast[1])
        return node.outputs["Color"]

    cycles, _, _ = render_grid(tmp_path, build)
    ours = svm().bright_contrast(flat(built["color"]), flat(built["bright"]), flat(built["contrast"]))
    compare("Bright/Contrast", cycles, ours.reshape(H, W, 3))


def test_gamma(tmp_path):
    """Gamma over [0, 3.2] down the image (0: white), on components from -0.2 (kept) to 1.4."""
    built = {}

    def build(grid):
        color, gamma = _color(grid), grid.affine(0.0, 0.2)
        node = grid.node("ShaderNodeGamma")
        grid.link(color, node.inputs["Color"])
        grid.link(gamma, node.inputs["Gamma"])
        built.update(color=color[1], gamma=gamma[1])
        return node.outputs["Color"]

    cycles, _, _ = render_grid(tmp_path, build)
    compare("Gamma", cycles, svm().gamma(flat(built["color"]), flat(built["gamma"])).reshape(H, W, 3))


def test_invert_and_rgb_to_bw(tmp_path):
    """Invert with Fac over [-0.2, 1.2] down the image (red, green channels) and RGB to BW of the colour (blue)."""
    built = {}

    def build(grid):
        color, fac = _color(grid), grid.affine(0.0, 1.4 / (H - 1), -0.2)
        inv = grid.node("ShaderNodeInvert")
        grid.link(color, inv.inputs["Color"])
        grid.link(fac, inv.inputs["Fac"])
        bw = grid.node("ShaderNodeRGBToBW")
        grid.link(color, bw.inputs["Color"])
        sep = grid.node("ShaderNodeSeparateXYZ")
        grid.nt.links.new(inv.outputs["Color"], sep.inputs[0])
        built.update(color=color[1], fac=fac[1])
        return combine_rgb(grid, sep.outputs[0], sep.outputs[1], bw.outputs["Val"])

    cycles, _, _ = render_grid(tmp_path, build)
    f = svm()
    inverted = f.invert(flat(built["color"]), flat(built["fac"])).reshape(H, W, 3)
    compare("Invert", cycles[..., :2], inverted[..., :2])
    compare("RGB to BW", cycles[..., 2], f.rgb_to_bw(flat(built["color"])).reshape(H, W))


# ---- Curves ----------------------------------------------------------------------------------------------------

def _shape_curve(curve, points):
    """Set a CurveMap's points (x, y) (it starts with two)."""
    while len(curve.points) < len(points):
        curve.points.new(0.5, 0.5)
    for p, (x, y) in zip(curve.points, points):
        p.location = (x, y)


CURVE_POINTS = [
    [(0.0, 0.1), (0.3, 0.6), (0.7, 0.4), (1.0, 0.95)],
    [(0.1, 0.0), (0.5, 0.8), (0.9, 1.0)],
    [(0.0, 1.0), (0.4, 0.2), (1.0, 0.5)],
    [(0.0, 0.05), (0.6, 0.7), (1.0, 0.9)],  # RGB Curves' combined (C) curve
]


@pytest.mark.parametrize("wide", [False, True], ids=["unit", "wide"])
@pytest.mark.parametrize("extend", ["EXTRAPOLATED", "HORIZONTAL"])
@pytest.mark.parametrize("kind", ["rgb", "vector", "float"])
def test_curves(tmp_path, kind, extend, wide):
    """RGB Curves, Vector Curves and Float Curve with shaped curves (one smooth handle each), inputs from -0.2 to
    1.4 (outside the curves' range: extrapolated or held), Fac over [0, 1.2] down the image; `wide`: clipping off
    and the first curve's points spread over x in [-0.3, 1.1] (the table's range)."""
    built = {}
    node_type = {"rgb": "ShaderNodeRGBCurve", "vector": "ShaderNodeVectorCurve", "float": "ShaderNodeFloatCurve"}

    def build(grid):
        node = grid.node(node_type[kind])
        mapping = node.mapping
        mapping.extend = extend
        if wide:
            mapping.use_clip = False
        for i, (curve, points) in enumerate(zip(mapping.curves, CURVE_POINTS if kind == "rgb" else CURVE_POINTS[:3])):
            _shape_curve(curve, [(1.4 * x - 0.3, y) for x, y in points] if wide and i == 0 else points)
        mapping.curves[0].points[1].handle_type = "VECTOR"
        mapping.update()
        fac = grid.affine(0.0, 1.2 / (H - 1))
        grid.link(fac, node.inputs[0])
        if kind == "float":
            value = grid.affine(1.6 / (W - 1), 0.0, -0.2)
            grid.link(value, node.inputs[1])
            built.update(value=value[1])
        else:
            color = _color(grid)
            grid.link(color, node.inputs[1])
            built.update(color=color[1])
        built.update(fac=fac[1], params=params_module().node_params(node))
        return node.outputs[0]

    cycles, _, _ = render_grid(tmp_path, build)
    f, p = svm(), built["params"]
    assert p["table"].shape[0] == f.CURVE_TABLE_SIZE and p["extrapolate"] == (extend == "EXTRAPOLATED")
    if kind == "float":
        ours = f.curve_float(p["table"], p["min_x"], p["max_x"], p["extrapolate"], flat(built["fac"]),
                             flat(built["value"])).reshape(H, W)
    else:
        ours = f.curves_rgb(p["table"], p["min_x"], p["max_x"], p["extrapolate"], flat(built["fac"]),
                            flat(built["color"])).reshape(H, W, 3)
    if wide:
        assert p["min_x"] == pytest.approx(-0.3) and p["max_x"] == pytest.approx(1.1)
    compare(f"{node_type[kind][len('ShaderNode'):]} ({extend.lower()}, {'wide' if wide else 'unit'})", cycles, ours)


# ---- Vector Math, Vector Rotate, Normal ---------------------------------------------------------------------

def _vectors(grid):
    """Vector Math's three inputs and Scale: a over [-2, 2] x [-1.5, 1.5] x 0.7; b with components crossing 0
    (exactly at some pixels); c; scale over [-1, 2] down the image."""
    a = grid.vector((grid.affine(4.0 / (W - 1), 0.0, -2.0), grid.affine(0.0, 3.0 / (H - 1), -1.5), 0.7))
    b = grid.vector((grid.affine(0.0, 0.25, -2.0), 0.6, grid.affine(0.125, 0.0, -1.0)))
    c = grid.vector((0.35, grid.affine(0.1, 0.0, -1.2), grid.affine(0.0, 0.15, 0.4)))
    scale = grid.affine(0.0, 3.0 / (H - 1), -1.0)
    return a, b, c, scale


@pytest.mark.parametrize("operation", ["ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "CROSS_PRODUCT",
                                       "PROJECT", "REFLECT", "REFRACT", "FACEFORWARD", "DOT_PRODUCT", "DISTANCE",
                                       "LENGTH", "SCALE", "NORMALIZE", "ABSOLUTE", "MINIMUM", "MAXIMUM", "FLOOR",
                                       "CEIL", "FRACTION", "MODULO", "WRAP", "SNAP", "SINE", "COSINE", "TANGENT"])
def test_vector_math(tmp_path, operation):
    built = {}
    f = svm()
    assert operation in f.VECTOR_MATH_OPERATIONS

    def build(grid):
        a, b, c, scale = _vectors(grid)
        node = grid.node("ShaderNodeVectorMath", operation=operation)
        for socket, value in zip(node.inputs, (a, b, c, scale)):
            grid.link(value, socket)
        built.update(a=a[1], b=b[1], c=c[1], scale=scale[1], params=params_module().node_params(node))
        uses_value = operation in ("DOT_PRODUCT", "DISTANCE", "LENGTH")
        return node.outputs["Value" if uses_value else "Vector"]

    cycles, _, _ = render_grid(tmp_path, build)
    value, vector = f.vector_math(built["params"]["operation"], flat(built["a"]), flat(built["b"]), flat(built["c"]),
                                  flat(built["scale"]))
    ours = value.reshape(H, W) if operation in ("DOT_PRODUCT", "DISTANCE", "LENGTH") else vector.reshape(H, W, 3)
    compare(f"Vector Math {operation}", cycles, ours)


@pytest.mark.parametrize("invert", [False, True], ids=["forward", "inverted"])
@pytest.mark.parametrize("rotation_type", ["AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ"])
def test_vector_rotate(tmp_path, rotation_type, invert):
    """Vector Rotate: the vector of _vectors' a about a centre; the angle over [-3, 3] across, the axis tilting
    down the image (through zero length at one row: the vector unchanged), Euler angles from both."""
    built = {}

    def build(grid):
        a, _, _, _ = _vectors(grid)
        center = (0.1, -0.2, 0.3)
        axis = grid.vector((grid.affine(0.0, 0.125, -1.0), 0.0, 0.0))
        angle = grid.affine(6.0 / (W - 1), 0.0, -3.0)
        rotation = grid.vector((grid.affine(0.15), grid.affine(0.0, 0.3, -2.0), 0.4))
        node = grid.node("ShaderNodeVectorRotate", rotation_type=rotation_type, invert=invert)
        grid.link(a, node.inputs["Vector"])
        node.inputs["Center"].default_value = center
        grid.link(axis, node.inputs["Axis"])
        grid.link(angle, node.inputs["Angle"])
        grid.link(rotation, node.inputs["Rotation"])
        built.update(a=a[1], center=center, axis=axis[1], angle=angle[1], rotation=rotation[1],
                     params=params_module().node_params(node))
        return node.outputs["Vector"]

    cycles, _, _ = render_grid(tmp_path, build)
    p = built["params"]
    ours = svm().vector_rotate(p["type"], p["invert"], flat(built["a"]), built["center"], flat(built["axis"]),
                               flat(built["angle"]), flat(built["rotation"]))
    compare(f"Vector Rotate {rotation_type} {'inverted' if invert else 'forward'}", cycles, ours.reshape(H, W, 3))


def test_normal_node(tmp_path):
    """The Normal node's Dot output with a tilted direction and the Normal input varying over both axes."""
    built = {}

    def build(grid):
        normal = grid.vector((grid.affine(2.0 / (W - 1), 0.0, -1.0), grid.affine(0.0, 2.0 / (H - 1), -1.0), 0.5))
        node = grid.node("ShaderNodeNormal")
        node.outputs["Normal"].default_value = (0.3, -0.5, 0.81)
        grid.link(normal, node.inputs["Normal"])
        built.update(normal=normal[1], params=params_module().node_params(node))
        return node.outputs["Dot"]

    cycles, _, _ = render_grid(tmp_path, build)
    ours = svm().normal_dot(built["params"]["direction"], flat(built["normal"]))
    compare("Normal (Dot)", cycles, ours.reshape(H, W))


# ---- Bump ------------------------------------------------------------------------------------------------------

BUMP_CASES = {"flat": (0.0, False), "tilted_inverted": (0.7, True)}


@pytest.mark.parametrize("case", sorted(BUMP_CASES))
def test_bump(tmp_path, case):
    """Bump of a height of the Object coordinates (o): 0.03 o.x + 0.1 sin(0.15 o.y), with Strength over
    [-0.2, 1.4] across the image and Distance over [-1, 3] down it, on the plane facing the camera or tilted by
    0.7 rad (inverted).  The heights at the point and at P + dx, P + dy (BumpDifferentials of the geometric normal
    and the orthographic camera's differential radius: one pixel's width on the film) are computed here in float64
    from the hit points; Cycles' rays are jittered by up to 0.005 pixel, which moves the height's gradient by
    < 2e-4 here (its curvature is small)."""
    tilt, invert = BUMP_CASES[case]
    built = {}

    def build(grid):
        sep = grid.separate
        lin = grid.node("ShaderNodeMath", operation="MULTIPLY")
        grid.nt.links.new(sep.outputs[0], lin.inputs[0])
        lin.inputs[1].default_value = 0.03
        arg = grid.node("ShaderNodeMath", operation="MULTIPLY")
        grid.nt.links.new(sep.outputs[1], arg.inputs[0])
        arg.inputs[1].default_value = 0.15
        sine = grid.node("ShaderNodeMath", operation="SINE")
        grid.nt.links.new(arg.outputs[0], sine.inputs[0])
        height = grid.node("ShaderNodeMath", operation="MULTIPLY_ADD")
        grid.nt.links.new(sine.outputs[0], height.inputs[0])
        height.inputs[1].default_value = 0.1
        grid.nt.links.new(lin.outputs[0], height.inputs[2])
        strength = grid.affine(1.6 / (W - 1), 0.0, -0.2)
        distance = grid.affine(0.0, 4.0 / (H - 1), -1.0)
        bump = grid.node("ShaderNodeBump", invert=invert)
        grid.nt.links.new(height.outputs[0], bump.inputs["Height"])
        grid.link(strength, bump.inputs["Strength"])
        grid.link(distance, bump.inputs["Distance"])
        built.update(strength=strength[1], distance=distance[1], params=params_module().node_params(bump))
        return bump.outputs["Normal"]

    cycles, grid, hits = render_grid(tmp_path, build, tilt=tilt)
    obj = bpy.data.objects["Grid"]
    m = np.array(obj.matrix_world, dtype=np.float64)
    inverse = np.linalg.inv(m)
    ng = m[:3, :3] @ np.array([0.0, 0.0, 1.0])  # the plane's normal, towards the camera
    ng = ng / np.linalg.norm(ng)
    f = svm()
    n = H * W
    P = hits["P"].reshape(n, 3)
    dx, dy = f.bump_differentials(np.tile(ng, (n, 1)), np.full(n, 2.0 / W))

    def height(points):
        o = points @ inverse[:3, :3].T + inverse[:3, 3]
        return 0.03 * o[:, 0] + 0.1 * np.sin(0.15 * o[:, 1])

    h_c, h_x, h_y = height(P), height(P + dx), height(P + dy)
    ours = f.bump(np.tile(ng, (n, 1)), np.tile(ng, (n, 1)), (0.0, 0.0, 1.0), dx, dy, h_c, h_x, h_y,
                  flat(built["strength"]), flat(built["distance"]), built["params"]["invert"])
    compare(f"Bump ({case})", cycles, ours.reshape(H, W, 3))


def test_bump_perspective(tmp_path):
    """Bump through a perspective camera, where the differential radius grows with the distance from the eye:
    dP = |P - eye| dD, dD the mean length of the unit direction's change over one pixel in x and in y (Cycles'
    camera_sample_perspective).  Height 0.5 x + 0.3 sin(0.5 y) of the world position, Strength and Distance 1."""
    scene = _ortho_scene()
    cam = scene.camera.data
    cam.type, cam.lens, cam.sensor_width, cam.sensor_fit = "PERSP", 50.0, 36.0, "AUTO"
    bpy.ops.mesh.primitive_plane_add(size=40.0)
    mat = bpy.data.materials.new("Bumped")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    tc, sep = nt.nodes.new("ShaderNodeTexCoord"), nt.nodes.new("ShaderNodeSeparateXYZ")
    nt.links.new(tc.outputs["Object"], sep.inputs[0])
    arg, sine, height = (nt.nodes.new("ShaderNodeMath") for _ in range(3))
    arg.operation, sine.operation, height.operation = "MULTIPLY", "SINE", "MULTIPLY_ADD"
    nt.links.new(sep.outputs[1], arg.inputs[0])
    arg.inputs[1].default_value = 0.5
    nt.links.new(arg.outputs[0], sine.inputs[0])
    lin = nt.nodes.new("ShaderNodeMath")
    lin.operation = "MULTIPLY"
    nt.links.new(sep.outputs[0], lin.inputs[0])
    lin.inputs[1].default_value = 0.5
    nt.links.new(sine.outputs[0], height.inputs[0])
    height.inputs[1].default_value = 0.3
    nt.links.new(lin.outputs[0], height.inputs[2])
    bump, emission = nt.nodes.new("ShaderNodeBump"), nt.nodes.new("ShaderNodeEmission")
    nt.links.new(height.outputs[0], bump.inputs["Height"])
    nt.links.new(bump.outputs["Normal"], emission.inputs["Color"])
    nt.links.new(emission.outputs[0], nt.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    bpy.context.object.data.materials.append(mat)
    cycles = _render_cycles(scene, tmp_path / "bump_perspective.exr")

    half = 18.0 / 50.0
    step = 2 * half / W  # one pixel on the plane at unit distance
    u = (-1 + (np.arange(W) + 0.5) * (2.0 / W)) * half
    v = (1 - (np.arange(H) + 0.5) * (2.0 / H)) * half * H / W
    uu, vv = np.meshgrid(u, v)
    d = np.stack([uu, vv, -np.ones_like(uu)], axis=-1).reshape(-1, 3)

    def unit(x):
        return x / np.linalg.norm(x, axis=-1, keepdims=True)

    d_dx = np.linalg.norm(unit(d + [step, 0, 0]) - unit(d), axis=-1)
    d_dy = np.linalg.norm(unit(d + [0, step, 0]) - unit(d), axis=-1)
    P = np.array([0.0, 0.0, CAMERA_Z]) + d * CAMERA_Z  # the hits on z = 0
    dp = np.linalg.norm(P - [0.0, 0.0, CAMERA_Z], axis=-1) * 0.5 * (d_dx + d_dy)
    n = len(P)
    f = svm()
    ng = np.tile([0.0, 0.0, 1.0], (n, 1))
    dx, dy = f.bump_differentials(ng, dp)

    def h(points):
        return 0.5 * points[:, 0] + 0.3 * np.sin(0.5 * points[:, 1])

    incoming = -unit(d)
    ours = f.bump(ng, ng, incoming, dx, dy, h(P), h(P + dx), h(P + dy), 1.0, 1.0, False)
    compare("Bump (perspective)", cycles, ours.reshape(H, W, 3))


def test_node_params_reads_every_node():
    """color_node_params.node_params gives every node it lists the keyword arguments of its function, and refuses
    a node it does not read."""
    mod = params_module()
    mat = bpy.data.materials.new("Params")
    mat.use_nodes = True
    for kind in mod.NODES:
        params = mod.node_params(mat.node_tree.nodes.new(kind))
        assert isinstance(params, dict)
    curve = mod.node_params(mat.node_tree.nodes.new("ShaderNodeFloatCurve"))
    np.testing.assert_allclose(curve["table"], np.linspace(0, 1, 256), atol=1e-6)  # the default: identity
    assert (curve["min_x"], curve["max_x"], curve["extrapolate"]) == (0.0, 1.0, True)  # a new node extrapolates
    assert mod.node_params(mat.node_tree.nodes.new("ShaderNodeVectorRotate")) == dict(type="AXIS_ANGLE",
                                                                                       invert=False)
    with pytest.raises(ValueError, match="is not a node color_node_params reads"):
        mod.node_params(mat.node_tree.nodes.new("ShaderNodeTexNoise"))
