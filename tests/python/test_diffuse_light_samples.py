"""Purely diffuse hits take light samples alone (Renderer(bsdf_samples_on_diffuse=False), the default; see
native/render/integrator/shade_surface.h, LightSamplesAlone): with MIS on and the lights sampled by solid angle,
a Lambert hit draws no BSDF sample for the area lights.  Checked by identities that hold bit for bit (fixed
seeds): a Lambert-only scene renders as without MIS; with BSDF samples on diffuse hits, as before the option;
glossy hits, the area technique, ellipses sampled by area, scenes with emissive meshes and lights chosen by power
among several keep MIS.  Unbiasedness of both settings is test_render_analytic.py's (every rectangle scene, technique
and heuristic)."""
import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, top_camera


def scene_with(material, light=None, background=(0, 0, 0)):
    light = light or sphrect.RectLight(corner=(-0.4, -0.3, 0.6), edge_x=(0, 0.8, 0), edge_y=(0.8, 0, 0),
                                       radiance=(3, 3, 3), visible=False)
    return sphrect.Scene(camera=top_camera(width=12, height=10), meshes=[plane_mesh()], lights=[light],
                         materials=[material], world=sphrect.World(background=background))


def image(scene, **kw):
    r = sphrect.Renderer(scene, seed=3, **kw)
    assert r.render(8) and r.stats()["dropped_samples"] == 0
    return r.image()


LAMBERT = sphrect.Material(base_color=(0.5, 0.5, 0.5))
DISK = sphrect.EllipseLight(center=(0, 0, 0.5), axis_x=(0, 0.4, 0), axis_y=(0.4, 0, 0), radiance=(3, 3, 3),
                            visible=False)


@pytest.mark.parametrize("mis", ["balance", "power"])
@pytest.mark.parametrize("technique", ["rectangle", "rectangle_cosine", "triangles"])
@pytest.mark.parametrize("light_selection", ["tree", "power"])
def test_lambert_hits_render_as_without_mis(mis, technique, light_selection):
    """One light (either selection), or several under the tree."""
    scene = scene_with(LAMBERT)
    kw = dict(techniques=[technique], light_selection=light_selection)
    none = image(scene, mis="none", **kw)
    assert none[..., :3].mean() > 0.01
    assert np.array_equal(image(scene, mis=mis, **kw), none)
    assert not np.array_equal(image(scene, mis=mis, bsdf_samples_on_diffuse=True, **kw), none)


def test_several_lights_under_the_tree_take_light_samples_alone():
    scene = scene_with(LAMBERT)
    scene.lights.append(sphrect.RectLight(corner=(0.6, 0.6, 0.3), edge_x=(0, 0.2, 0), edge_y=(0.2, 0, 0),
                                          radiance=(1, 1, 1), visible=False))
    assert np.array_equal(image(scene, mis="power", light_selection="tree"),
                          image(scene, mis="none", light_selection="tree"))


def test_disks_sampled_by_the_spherical_ellipse_map_too():
    scene = scene_with(LAMBERT, light=DISK)
    none = image(scene, mis="none")
    assert np.array_equal(image(scene, mis="power"), none)


def with_emissive_mesh(scene):
    """The scene with a small emissive mesh triangle beside its light."""
    scene.meshes.append(sphrect.Mesh(vertices=np.array([[0.6, 0.6, 0.4], [0.8, 0.6, 0.4], [0.6, 0.8, 0.4]], np.float32),
                                     triangles=np.array([[0, 1, 2]], np.int32), name="emitter",
                                     material_ids=np.array([1], np.int32)))
    scene.materials.append(sphrect.Material(name="emitter", base_color=(0, 0, 0), emission=(2, 2, 2)))
    return scene


@pytest.mark.parametrize("case", ["glossy", "area technique", "disk by area", "emissive mesh",
                                  "two lights by power"])
def test_mis_is_kept_where_the_light_sample_is_not_by_solid_angle_or_the_hit_not_diffuse(case):
    kw = {}
    if case == "emissive mesh":
        scene = with_emissive_mesh(scene_with(LAMBERT))
    elif case == "two lights by power":
        scene, kw = scene_with(LAMBERT), {"light_selection": "power"}
        scene.lights.append(sphrect.RectLight(corner=(0.6, 0.6, 0.3), edge_x=(0, 0.2, 0), edge_y=(0.2, 0, 0),
                                              radiance=(1, 1, 1), visible=False))
    elif case == "glossy":
        scene = scene_with(sphrect.Material(base_color=(0.5, 0.5, 0.5), kind="principled", roughness=0.3))
    elif case == "area technique":
        scene, kw = scene_with(LAMBERT), {"techniques": ["area"]}
    else:
        scene, kw = scene_with(LAMBERT, light=DISK), {"ellipse_technique": "area"}
    power = image(scene, mis="power", **kw)
    assert not np.array_equal(power, image(scene, mis="none", **kw))
    assert np.array_equal(power, image(scene, mis="power", bsdf_samples_on_diffuse=True, **kw))


def test_the_background_is_still_found_by_bsdf_samples():
    """A constant world lights the plane only through BSDF samples: they are still drawn at diffuse hits."""
    scene = scene_with(LAMBERT, background=(0.2, 0.2, 0.2))
    lit = image(scene, mis="power")
    dark = image(scene_with(LAMBERT), mis="power")
    # Lambert under a constant sky of 0.2 adds albedo x 0.2 = 0.1 everywhere the plane is seen.
    np.testing.assert_allclose((lit - dark)[..., 0].mean(), 0.1, rtol=0.1)
    assert np.array_equal(lit, image(scene, mis="none"))
