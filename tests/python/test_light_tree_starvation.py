"""The light tree must not starve a light: on scenes of a few lights near surfaces, light_selection="tree" has at most
the variance of "power" at equal samples, within a small factor (docs/light_tree.md, starvation).

Two mechanisms hold it (native/render/light_tree.h): up to MAX_DELTA_LIGHTS_BESIDE_TREE point and spot lights stay
beside the tree, evaluated at every light sample as "power" does, and the tree's choice is a defensive mixture whose
pmf never falls below TREE_FLUX_SHARE x the flux pmf, so that a light sample's second moment is at most
1 / TREE_FLUX_SHARE = 10 times power selection's whatever the scene (the tree's rare fireflies).

Scenes (each a floor, a sphere standing on it, two disc lights 3 m away as key and fill, and a third light near the
surfaces): a soft point light of radius 1 m 0.3 m above the floor beside the sphere (the issue's character shot), a
1.5 m square light 0.2 m above the floor facing it, a 1 m disc 0.3 m above the floor.  Variance: per pixel, the
unbiased variance over SEEDS renders of 4 samples, averaged over the image, lights hidden from the camera.
Tree / power before the fix: 2.8, 0.60, 0.76 (40 seeds); now 0.94, 0.64, 0.74 with these seeds, and at most 0.95,
0.77, 0.88 over 10 other seed sets (run this file as a script).  Asserted below BOUND = 1.5, which the point light's
case before the fix fails; a correct renderer's largest ratio over 11 seed sets is 0.95, so a seed set drawn at random
fails it far less than 1 % of the time (the outcome with fixed seeds is deterministic)."""
import math

import numpy as np
import pytest

import sphrect

SEEDS = tuple(range(1, 9))
SAMPLES = 4
BOUND = 1.5


def _sphere(center, radius, n=16):
    theta = np.linspace(0, math.pi, n + 1)
    phi = np.linspace(0, 2 * math.pi, 2 * n, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    v = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3) * radius + center
    tris = []
    for i in range(n):
        for j in range(2 * n):
            a, b = i * 2 * n + j, i * 2 * n + (j + 1) % (2 * n)
            tris += [[a, a + 2 * n, b], [b, a + 2 * n, b + 2 * n]]
    return v.astype(np.float32), np.array(tris, np.int32)


def _disc(center, normal, radius, power):
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    a = np.cross(n, [0.3, 0.1, 1.0])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    return sphrect.EllipseLight(center=tuple(center), axis_x=tuple(radius * a), axis_y=tuple(radius * b),
                                radiance=sphrect.scene.area_light_radiance(power, (1, 1, 1), math.pi * radius ** 2),
                                visible=False)


def _scene(third_light, width=64, height=48):
    floor = sphrect.Mesh(vertices=np.array([[-6, -6, 0], [6, -6, 0], [6, 6, 0], [-6, 6, 0]], np.float32),
                         triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32))
    v, t = _sphere(np.array([0.0, 0.0, 1.0]), 0.8)
    lights = [_disc((3, -2, 2.5), np.array([0, 0, 1.0]) - (3, -2, 2.5), 0.5, 300),
              _disc((-3, -2.5, 2), np.array([0, 0, 1.0]) - (-3, -2.5, 2), 0.5, 150), third_light]
    eye, target = np.array([0.5, -7, 2.2]), np.array([0, 0, 0.8])
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, [0, 0, 1])
    r /= np.linalg.norm(r)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = r, np.cross(r, f), -f, eye
    return sphrect.Scene(camera=sphrect.Camera(width=width, height=height, to_world=m.tolist()),
                         materials=[sphrect.Material("grey", base_color=(0.7, 0.7, 0.7))],
                         meshes=[floor, sphrect.Mesh(vertices=v, triangles=t)], lights=lights)


def _square_near_floor():
    return sphrect.RectLight.from_power(center=(1.0, 0.3, 0.2), edge_x=(1.5, 0, 0), edge_y=(0, -1.5, 0), power=800,
                                        visible=False)


SCENES = {
    "soft_point_light_near_surfaces": lambda: sphrect.PointLight(
        position=(1.0, 0.3, 0.3), intensity=sphrect.scene.point_light_intensity(1000, (1, 0.8, 0.6)), radius=1.0,
        visible=False),
    "square_light_above_floor": _square_near_floor,
    "disc_light_above_floor": lambda: _disc((1.0, 0.3, 0.3), (0, 0, -1), 1.0, 800),
}


def variance(scene, light_selection, seeds=SEEDS):
    images = []
    for seed in seeds:
        r = sphrect.Renderer(scene, techniques=["rectangle"], light_selection=light_selection, seed=seed)
        r.render(SAMPLES)
        images.append(r.image("rectangle")[..., :3].astype(np.float64))
    return float(np.mean(np.var(np.array(images), axis=0, ddof=1)))


def variance_ratio(name, seeds=SEEDS):
    scene = _scene(SCENES[name]())
    return variance(scene, "tree", seeds) / variance(scene, "power", seeds)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_the_tree_does_not_starve_a_light_near_surfaces(name):
    ratio = variance_ratio(name)
    assert ratio < BOUND, f"{name}: the tree's variance is {ratio:.2f}x power selection's"


if __name__ == "__main__":
    for name in sorted(SCENES):
        ratios = [variance_ratio(name, tuple(range(100 * k + 1, 100 * k + 9))) for k in range(11)]
        print(f"{name:34} tree / power variance: this file's seeds {ratios[0]:.2f}, "
              f"10 other seed sets {min(ratios[1:]):.2f}..{max(ratios[1:]):.2f}")
