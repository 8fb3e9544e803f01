"""Ray visibility as Cycles 3.4 honours it (render/ray_visibility.h): a mesh hidden from camera, shadow or BSDF rays,
a light (analytic or an emissive mesh) that lights only some closure classes or not the medium, a light without Cast
Shadow or Multiple Importance.  Each test compares renders of the same seed, so the outcomes are deterministic: where
the feature must not change a light sample's value the images are compared bit for bit (the false-failure rate is 0),
elsewhere to float rounding; each case also checks that its scene shows the effect (it fails without the feature)."""
import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, save_as_older_version, top_camera

ALBEDO = 0.5
SAMPLES = 8


def board(z, half=0.6, name="board", material=0, **kw):
    """A horizontal square of side 2 half at height z (both windings: seen from either side)."""
    mesh = plane_mesh(size=half, z=z)
    mesh.name, mesh.material_ids = name, np.full(2, material, np.int32)
    for key, value in kw.items():
        setattr(mesh, key, value)
    return mesh


def rect_light(z=2.0, **kw):
    return sphrect.RectLight(corner=(-0.5, 0.5, z), edge_x=(1, 0, 0), edge_y=(0, -1, 0), radiance=(5, 5, 5),
                             visible=False, **kw)


def render(scene, technique="rectangle", samples=SAMPLES, **kw):
    r = sphrect.Renderer(scene, techniques=[technique], seed=7, **kw)
    assert r.render(samples)
    return r.image(technique)[:, :, :3].astype(np.float64)


def floor_scene(meshes=(), lights=None, materials=None, camera=None, world=None):
    return sphrect.Scene(camera=camera or top_camera(half=1.0, height_above=0.5),
                         meshes=[plane_mesh(), *meshes], lights=[rect_light()] if lights is None else list(lights),
                         materials=materials or [sphrect.Material(base_color=(ALBEDO,) * 3)],
                         world=world or sphrect.World(background=(0, 0, 0)))


def test_ray_kinds_are_blenders():
    assert sphrect.scene.RAY_KINDS == ("camera", "shadow", "diffuse", "glossy", "transmission", "volume_scatter")


# --- meshes -------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("light", ["rect", "point"])
def test_mesh_hidden_from_shadow_rays_casts_no_shadow(light):
    """A board between the floor and the light, hidden from shadow rays: the floor gets the unoccluded light (the
    image of the scene without the board, bit for bit); visible to them it is in the umbra (black)."""
    lights = [rect_light()] if light == "rect" else [sphrect.PointLight(position=(0.1, 0.2, 2.0), intensity=(3,) * 3)]
    free = render(floor_scene(lights=lights))
    assert free.min() > 0
    hidden = render(floor_scene([board(1.0, half=1e4, invisible_to=("shadow",))], lights))
    np.testing.assert_array_equal(hidden, free)
    np.testing.assert_array_equal(render(floor_scene([board(1.0, half=1e4)], lights)), 0)


def test_mesh_hidden_from_camera_rays_lets_them_through():
    """A black board between the camera and the lit floor: hidden from the camera, the pixels behind it show the
    floor (the board-free image, bit for bit, as the board is above the light and casts no shadow on the floor);
    seen, they are black."""
    cam = top_camera(half=1.0, height_above=5.0)
    materials = [sphrect.Material(base_color=(ALBEDO,) * 3), sphrect.Material(base_color=(0, 0, 0))]
    lights = [rect_light(z=0.8)]
    free = render(floor_scene(lights=lights, materials=materials, camera=cam))
    hidden = render(floor_scene([board(3.0, half=0.4, material=1, invisible_to=("camera",))], lights, materials,
                                cam))
    np.testing.assert_array_equal(hidden, free)
    seen = render(floor_scene([board(3.0, half=0.4, material=1)], lights, materials, cam))
    assert (seen[4:8, 4:8] == 0).all() and free[4:8, 4:8].min() > 0


def test_bsdf_rays_pass_a_mesh_hidden_from_their_kind():
    """A glossy floor under a board that shadow rays see but glossy rays do not (Cycles' BSDF rays follow the
    closure's kind): the light samples are blocked, the BSDF samples that find the light are not, so with MIS the
    floor gets some light; a board seen by both leaves it black."""
    glossy = [sphrect.Material(kind="glossy_bsdf", base_color=(0.8,) * 3, roughness=0.4)]
    blocked = render(floor_scene([board(1.0, half=1e4)], materials=glossy), mis="power")
    np.testing.assert_array_equal(blocked, 0)
    through = render(floor_scene([board(1.0, half=1e4, invisible_to=("glossy",))], materials=glossy), mis="power")
    assert through.max() > 0.01
    none = render(floor_scene([board(1.0, half=1e4, invisible_to=("glossy",))], materials=glossy), mis="none")
    np.testing.assert_array_equal(none, 0)  # without MIS no BSDF ray looks for the light


def test_emissive_mesh_visibility():
    """An emissive board over the floor: hidden from the camera it still lights the floor (the pixels beside it as
    when seen, its own pixels the floor's light); hidden from diffuse rays it lights no diffuse closure (black
    floor) while the camera still sees it; hidden from every BSDF ray it is no light at all."""
    cam = top_camera(half=1.0, height_above=5.0)
    materials = [sphrect.Material(base_color=(ALBEDO,) * 3), sphrect.Material(base_color=(0, 0, 0),
                                                                              emission=(4, 4, 4))]
    emitter = dict(z=1.0, half=0.25, material=1)
    seen = render(floor_scene([board(**emitter)], [], materials, cam))
    unseen = render(floor_scene([board(**emitter, invisible_to=("camera",))], [], materials, cam))
    inside = np.zeros(seen.shape[:2], bool)
    inside[4:8, 4:8] = True  # the board covers pixels [4.5, 7.5): these show it or the floor under it
    np.testing.assert_array_equal(unseen[~inside], seen[~inside])
    assert unseen[~inside].min() > 0 and np.allclose(seen[5:7, 5:7], 4) and unseen[5:7, 5:7].max() < 4
    dark = render(floor_scene([board(**emitter, invisible_to=("diffuse",))], [], materials, cam))
    np.testing.assert_array_equal(dark[~inside], 0)
    np.testing.assert_array_equal(dark[5:7, 5:7], seen[5:7, 5:7])
    no_light = render(floor_scene([board(**emitter, invisible_to=("diffuse", "glossy", "transmission"))], [],
                                  materials, cam), mis="power", bsdf_samples_on_diffuse=True)
    np.testing.assert_array_equal(no_light[~inside], 0)


# --- lights -------------------------------------------------------------------------------------------------------

PRINCIPLED = sphrect.Material(kind="principled", base_color=(0.6, 0.5, 0.4), roughness=0.35)


@pytest.mark.parametrize("light", ["rect", "point", "soft_point"])
def test_light_lights_the_closure_classes_it_is_visible_to(light):
    """Without MIS a light sample's value is f of the lobes the light lights: a light hidden from diffuse plus one
    hidden from glossy, same seed, give the full light's image to float rounding; each alone is a real part of it.
    A diffuse floor under a light hidden from diffuse is black, and with every strategy (MIS, BSDF samples on the
    diffuse floor) it is bit for bit the full light's under a light hidden from glossy only."""
    def make(**kw):
        if light == "rect":
            return rect_light(**kw)
        return sphrect.PointLight(position=(0.1, 0.2, 2.0), intensity=(3,) * 3,
                                  radius=0.3 if light == "soft_point" else 0.0, visible=False, **kw)

    mats = [PRINCIPLED]
    full = render(floor_scene(lights=[make()], materials=mats), mis="none")
    diffuse_only = render(floor_scene(lights=[make(invisible_to=("glossy",))], materials=mats), mis="none")
    glossy_only = render(floor_scene(lights=[make(invisible_to=("diffuse",))], materials=mats), mis="none")
    np.testing.assert_allclose(diffuse_only + glossy_only, full, rtol=1e-5, atol=1e-7)
    assert diffuse_only.mean() > 0.1 * full.mean() and glossy_only.mean() > 0.01 * full.mean()
    for kw in ({}, {"mis": "power", "bsdf_samples_on_diffuse": True}):
        np.testing.assert_array_equal(render(floor_scene(lights=[make(invisible_to=("diffuse",))]), **kw), 0)
        np.testing.assert_array_equal(render(floor_scene(lights=[make(invisible_to=("glossy", "transmission"))]),
                                             **kw), render(floor_scene(lights=[make()]), **kw))


def test_bsdf_rays_do_not_find_a_light_hidden_from_their_kind():
    """A glossy floor and a light hidden from glossy: neither its light samples (no lobe lit) nor the glossy
    BSDF rays that reach it bring light, under any MIS."""
    glossy = [sphrect.Material(kind="glossy_bsdf", base_color=(0.8,) * 3, roughness=0.4)]
    for mis in sphrect.mis_modes:
        assert render(floor_scene(materials=glossy), mis=mis).max() > 0.01
        np.testing.assert_array_equal(render(floor_scene([], [rect_light(invisible_to=("glossy",))], glossy), mis=mis),
                                      0)


@pytest.mark.parametrize("light", ["rect", "point", "sun"])
def test_light_without_cast_shadow(light):
    """A light without Cast Shadow behind an opaque board: its samples trace no shadow ray, so the floor gets the
    board-free image (bit for bit, light samples alone on the diffuse floor)."""
    def make(**kw):
        if light == "rect":
            return rect_light(**kw)
        if light == "point":
            return sphrect.PointLight(position=(0.1, 0.2, 2.0), intensity=(3,) * 3, **kw)
        return sphrect.SunLight(direction=(0.1, 0.2, -1), irradiance=(2,) * 3, **kw)

    free = render(floor_scene(lights=[make()]))
    wall = [board(1.0, half=1e4)]
    np.testing.assert_array_equal(render(floor_scene(wall, [make()])), 0)
    np.testing.assert_array_equal(render(floor_scene(wall, [make(cast_shadow=False)])), free)


@pytest.mark.parametrize("light", ["rect", "soft_point", "soft_sun"])
def test_light_without_multiple_importance(light):
    """A light without Multiple Importance: BSDF rays do not find it and its samples weigh 1, so under any MIS
    heuristic the image is the MIS-free one, to float rounding; the light does show with MIS (the scene tests it)."""
    def make(**kw):
        if light == "rect":
            return rect_light(**kw)
        if light == "soft_point":
            return sphrect.PointLight(position=(0.1, 0.2, 2.0), intensity=(3,) * 3, radius=0.3, visible=False, **kw)
        return sphrect.SunLight(direction=(0.1, 0.2, -1), irradiance=(2,) * 3, angle=0.3, visible=False, **kw)

    mats = [PRINCIPLED]
    without = render(floor_scene(lights=[make()], materials=mats), mis="none")
    for mis in ("balance", "power"):
        with_mis = render(floor_scene(lights=[make()], materials=mats), mis=mis, bsdf_samples_on_diffuse=True)
        assert not np.allclose(with_mis, without, rtol=1e-3)  # MIS changes the image of this light
        off = render(floor_scene(lights=[make(use_mis=False)], materials=mats), mis=mis, bsdf_samples_on_diffuse=True)
        np.testing.assert_allclose(off, without, rtol=1e-5, atol=1e-7)


@pytest.mark.parametrize("light", ["rect", "point"])
def test_light_hidden_from_volume_scatter_does_not_light_the_medium(light):
    """A camera in fog looking at the sky: all it sees is in-scattered light, none from a light hidden from volume
    scatter (while the same light, visible, lights the fog); a diffuse floor still gets its light."""
    def make(**kw):
        if light == "rect":
            return rect_light(z=0.3, **kw)
        return sphrect.PointLight(position=(0.1, 0.2, 0.3), intensity=(3,) * 3, **kw)

    fog = sphrect.World(medium=sphrect.Medium(sigma_s=(0.5,) * 3, sigma_a=(0.0,) * 3))
    up = sphrect.Camera(width=8, height=8, type="orthographic", ortho_scale=2.0,
                        to_world=[[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, -1, 0.2], [0, 0, 0, 1]])

    def sky_scene(l):
        return sphrect.Scene(camera=up, lights=[l], materials=[sphrect.Material()], world=fog)
    for mis in ("none", "power"):
        assert render(sky_scene(make()), mis=mis).max() > 0
        np.testing.assert_array_equal(render(sky_scene(make(invisible_to=("volume_scatter",))), mis=mis), 0)
    np.testing.assert_array_equal(render(floor_scene(lights=[make(invisible_to=("volume_scatter",))])),
                                  render(floor_scene(lights=[make()])))


def test_visibility_names_are_checked():
    scene = floor_scene(lights=[rect_light(invisible_to=("difuse",))])
    with pytest.raises(ValueError, match="ray kind"):
        sphrect.Renderer(scene)
    with pytest.raises(ValueError, match="shadow"):
        sphrect.Renderer(floor_scene(lights=[rect_light(invisible_to=("shadow",))]))
    with pytest.raises(ValueError, match="ray kind"):
        sphrect.Renderer(floor_scene([board(1.0, invisible_to=("cam",))]))


# --- the scene file -----------------------------------------------------------------------------------------------

def test_scene_file_round_trip_and_older_files(tmp_path):
    from render_testing import save_as_older_version
    scene = floor_scene([board(1.0, invisible_to=("shadow", "glossy"))],
                        [rect_light(invisible_to=("diffuse",), cast_shadow=False),
                         sphrect.SunLight(direction=(0, 0, -1), irradiance=(1,) * 3, use_mis=False)])
    path = str(tmp_path / "vis.sphrect.npz")
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert loaded.meshes[1].invisible_to == ("shadow", "glossy") and loaded.meshes[0].invisible_to == ()
    assert [(l.invisible_to, l.cast_shadow, l.use_mis) for l in loaded.lights] == [(("diffuse",), False, True),
                                                                                     ((), True, False)]
    np.testing.assert_array_equal(render(loaded), render(scene))

    def drop(meta):  # what version 11 lacked
        for m in meta["meshes"]:
            m.pop("invisible_to", None)
        for light in meta["lights"]:
            for key in ("invisible_to", "cast_shadow", "use_mis"):
                light.pop(key)
    old = str(tmp_path / "old.sphrect.npz")
    save_as_older_version(path, old, 11, drop)
    older = sphrect.load_scene(old)
    assert older.meshes[1].invisible_to == ()
    assert all(l.invisible_to == () and l.cast_shadow and l.use_mis for l in older.lights)


def sky_world(environment, **kw):
    """A constant sky, or (environment) a two-tone image world: brighter above the horizon."""
    if not environment:
        return sphrect.World(background=(0.8, 0.8, 0.8), **kw), []
    pixels = np.ones((8, 16, 3), np.float32) * 0.2
    pixels[4:] = 1.5  # rows 4.. : the upper half
    return (sphrect.World(environment=sphrect.Environment(texture=0), **kw),
            [sphrect.Texture(name="sky", pixels=pixels, colorspace="linear")])


@pytest.mark.parametrize("environment", [False, True])
def test_world_ray_visibility(environment):
    """World.invisible_to: hidden from the camera, the escaping rays show black while the floor is lit bit for bit as
    before; hidden from diffuse, a diffuse floor gets nothing from it (every MIS mode, BSDF samples on the floor too);
    hidden from glossy, the diffuse floor is lit bit for bit as before."""
    cam = top_camera(half=1.0, height_above=0.5)
    narrow = sphrect.Mesh(**{k: getattr(plane_mesh(size=0.5), k) for k in ("vertices", "triangles")})
    narrow.material_ids = np.zeros(2, np.int32)

    def scene(**kw):
        world, textures = sky_world(environment, **kw)
        return sphrect.Scene(camera=cam, meshes=[narrow], lights=[], textures=textures,
                             materials=[sphrect.Material(base_color=(ALBEDO,) * 3)], world=world)

    seen = render(scene())
    hidden = render(scene(invisible_to=("camera",)))
    floor = seen.mean(axis=2) < seen.max() * 0.9  # the floor's pixels; the rest is sky
    assert (~floor).any() and floor.any()
    np.testing.assert_array_equal(hidden[floor], seen[floor])
    assert hidden[~floor].max() == 0 and seen[~floor].min() > 0.1
    for kw in ({}, {"mis": "power", "bsdf_samples_on_diffuse": True}, {"mis": "none"}):
        np.testing.assert_array_equal(render(scene(invisible_to=("diffuse",)), **kw)[floor], 0)
        np.testing.assert_array_equal(render(scene(invisible_to=("glossy", "volume_scatter")), **kw),
                                      render(scene(), **kw))


def test_world_visibility_names_and_file(tmp_path):
    scene = floor_scene(world=sphrect.World(background=(0.5, 0.5, 0.5), invisible_to=("camera", "glossy")))
    path = tmp_path / "w.sphrect.npz"
    sphrect.save_scene(scene, path)
    assert sphrect.load_scene(path).world.invisible_to == ("camera", "glossy")
    old = tmp_path / "old.sphrect.npz"
    save_as_older_version(path, old, 16, lambda meta: meta["world"].pop("invisible_to"))
    assert sphrect.load_scene(old).world.invisible_to == ()
    scene.world.invisible_to = ("shadow",)
    with pytest.raises(ValueError, match="world invisible_to must name kinds of"):
        sphrect.Renderer(scene)
