"""Hard cases against the analytic answer (where Cycles 3.4 itself is unreliable: tiny or distant lights,
grazing angles): a Lambertian ground seen straight down by an orthographic camera, lit by one rectangle
light, must show radiance albedo / pi * E, with E from Lambert's polygon formula
    E(x) = L / 2 * sum_i angle(r_i, r_i+1) * (n . unit(r_i x r_i+1)),  r_i = unit(vertex_i - x).
Fixed seeds; with these sample counts the Monte Carlo error is far below the 1% tolerance."""
import math

import bpy
import numpy as np
import pytest

from conftest import builders, export, render, set_resolution

ALBEDO = 0.5
SIDE = 8             # pixels
VIEW = 0.02          # metres of ground seen by the camera


def polygon_irradiance(x, normal, corners, radiance):
    r = np.asarray(corners, dtype=np.float64) - x
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    total = 0.0
    for a, b in zip(r, np.roll(r, -1, axis=0)):
        c = np.cross(a, b)
        total += math.acos(np.clip(np.dot(a, b), -1, 1)) * np.dot(normal, c / np.linalg.norm(c))
    return 0.5 * radiance * abs(total)


CASES = {
    # 2 cm square 60 m away, tilted: a solid angle of ~1e-7 sr.
    "tiny_distant": dict(shape="SQUARE", size=0.02, size_y=0.02, power=2.0e4, location=(-30.0, 20.0, 45.0),
                         rotation=(0.5, -0.4, 0.0)),
    # 1 m x 0.4 m standing 3 m away, 0.1 m to 0.5 m high: seen 2 to 9.5 degrees above the horizon.
    "grazing": dict(shape="RECTANGLE", size=1.0, size_y=0.4, power=100.0, location=(0.0, 3.0, 0.3),
                    rotation=(-math.pi / 2, 0.0, 0.0)),
    # 3 m x 3 m, 2 cm above the ground: nearly the whole hemisphere.
    "huge_close": dict(shape="SQUARE", size=3.0, size_y=3.0, power=100.0, location=(0.3, -0.2, 0.02)),
}


@pytest.mark.parametrize("technique", ["RECTANGLE", "RECTANGLE_COSINE", "RECTANGLE_PROJECTED"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_ground_radiance_matches_polygon_formula(empty_scene, case, technique):
    builders.mesh_object("Ground", "plane", builders.material("Ground", (ALBEDO,) * 3), size=200)
    builders.area_light("Light", visible=False, **CASES[case])
    cam = empty_scene.camera
    cam.location, cam.rotation_euler = (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)  # straight down at the origin
    cam.data.type, cam.data.ortho_scale = "ORTHO", VIEW
    set_resolution(empty_scene, SIDE, SIDE)
    s = empty_scene.sphrect
    s.technique, s.samples, s.passes, s.light_samples = technique, 1024, 1, 1
    bpy.context.view_layer.update()
    (light,) = export()[0].lights
    corner, ex, ey = (np.array(v) for v in (light.corner, light.edge_x, light.edge_y))
    corners = [corner, corner + ex, corner + ex + ey, corner + ey]
    centres = (np.arange(SIDE) + 0.5) / SIDE * VIEW - VIEW / 2
    expected = np.mean([ALBEDO / math.pi * polygon_irradiance(np.array([x, y, 0.0]), np.array([0, 0, 1.0]),
                                                              corners, light.radiance[0])
                        for x in centres for y in centres])
    rec = render()
    image = rec["images"][technique.lower()]
    measured = float(image[..., :3].mean())
    print(f"{case} {technique}: measured {measured:.6g}, analytic {expected:.6g}")
    assert measured == pytest.approx(expected, rel=0.01)
