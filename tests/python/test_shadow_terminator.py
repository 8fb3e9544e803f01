"""Mesh.shadow_terminator_offset (Cycles 3.4's shadow terminator geometry offset, integrator/terminator.h): near the
terminator of a smooth-shaded mesh a light sample's shadow ray leaves from the smooth surface, and light directions
below the flat triangle are traced too.  Deterministic renders (fixed seeds): no statistical test.

- off (0, the default) and on a flat-shaded mesh (no normals) the image is the one without the setting, bit for bit;
- on a coarse smooth sphere under a sun just above its horizon the terminator band gets light the flat triangles
  shadowed, and nothing gets darker;
- bad values are refused; the scene file keeps the offset, and a format-14 file loads without one."""
import math

import numpy as np
import pytest

import sphrect
from render_testing import save_as_older_version


def coarse_sphere(segments=12, rings=6, smooth=True):
    """A UV sphere of radius 1 at (0, 0, 1): vertices, triangles and (smooth) its outward unit normals."""
    verts = [(0.0, 0.0, 1.0)]
    for i in range(1, rings):
        theta = math.pi * i / rings
        verts += [(math.sin(theta) * math.cos(2 * math.pi * j / segments),
                   math.sin(theta) * math.sin(2 * math.pi * j / segments), math.cos(theta)) for j in range(segments)]
    verts.append((0.0, 0.0, -1.0))
    tris = [(0, 1 + j, 1 + (j + 1) % segments) for j in range(segments)]
    for i in range(rings - 2):
        for j in range(segments):
            a, b = 1 + i * segments + j, 1 + i * segments + (j + 1) % segments
            tris += [(a, a + segments, b), (b, a + segments, b + segments)]
    last = len(verts) - 1
    tris += [(last, 1 + (rings - 2) * segments + (j + 1) % segments, 1 + (rings - 2) * segments + j)
             for j in range(segments)]
    unit = np.array(verts, np.float32)
    return sphrect.Mesh(vertices=unit + np.array([0, 0, 1], np.float32), triangles=np.array(tris, np.int32),
                        normals=unit if smooth else None, name="ball")


def scene(offset, smooth=True):
    ball = coarse_sphere(smooth=smooth)
    ball.shadow_terminator_offset = offset
    floor = sphrect.Mesh(vertices=np.array([[-8, -8, 0], [8, -8, 0], [8, 8, 0], [-8, 8, 0]], np.float32),
                         triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name="floor")
    sun = (-math.cos(math.radians(10)), 0.0, -math.sin(math.radians(10)))  # from +x, 10 degrees up
    m = np.eye(4)
    m[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]  # looking along +y
    m[:3, 3] = (0, -5, 1)
    return sphrect.Scene(camera=sphrect.Camera(width=40, height=30, to_world=m.tolist()),
                         materials=[sphrect.Material("grey", base_color=(0.7, 0.7, 0.7))], meshes=[floor, ball],
                         lights=[sphrect.SunLight(direction=sun, irradiance=(3, 3, 3))])


def render(s):
    r = sphrect.Renderer(s, techniques=["rectangle"], seed=4)
    r.render(16)
    return r.image("rectangle")[..., :3]


def test_off_and_flat_meshes_render_as_without_the_setting():
    base = render(scene(0.0))
    flat = render(scene(0.0, smooth=False))
    np.testing.assert_array_equal(render(scene(0.5, smooth=False)), flat)
    assert not np.array_equal(base, flat)  # the normals matter to this scene


def test_the_terminator_band_gets_light_and_nothing_darkens():
    off, on = render(scene(0.0)), render(scene(0.1))
    gained = on - off
    assert gained.min() >= -1e-6 * off.max()
    # The band down the sphere's middle, a pixel or two wide here (15 pixels gain, up to 11% of the image's peak).
    assert np.count_nonzero(gained.max(axis=2) > 0.01 * off.max()) >= 10
    assert gained.max() > 0.05 * off.max()


@pytest.mark.parametrize("bad", [-0.1, 1.5, float("nan"), True, "0.1"])
def test_bad_offsets_are_refused(bad):
    with pytest.raises(ValueError, match="shadow_terminator_offset"):
        sphrect.Renderer(scene(bad), techniques=["rectangle"])


def test_the_scene_file_keeps_the_offset_and_older_files_load_without_one(tmp_path):
    path = str(tmp_path / "t.sphrect.npz")
    sphrect.save_scene(scene(0.25), path)
    assert [m.shadow_terminator_offset for m in sphrect.load_scene(path).meshes] == [0.0, 0.25]
    old = str(tmp_path / "old.sphrect.npz")
    save_as_older_version(path, old, 14, lambda meta: [m.pop("shadow_terminator_offset", None)
                                                      for m in meta["meshes"]])
    assert [m.shadow_terminator_offset for m in sphrect.load_scene(old).meshes] == [0.0, 0.0]
