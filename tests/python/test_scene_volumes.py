"""Scene.volumes (sphrect.Volume, format 20): saved and loaded with their media, older files load without, and
malformed ones -- in a file or handed to the renderer -- raise ValueError saying what is wrong."""
import numpy as np
import pytest

import sphrect
from render_testing import save_as_older_version, top_camera
from sphrect.render import build_native_scene


def box(lo=(-1.0, -1.0, -1.0), hi=(1.0, 1.0, 1.0)):
    """(vertices, triangles) of an axis-aligned box, wound counter-clockwise seen from outside."""
    lo, hi = np.asarray(lo, dtype=np.float32), np.asarray(hi, dtype=np.float32)
    corners = np.array([[(hi if (i >> k) & 1 else lo)[k] for k in range(3)] for i in range(8)], dtype=np.float32)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    triangles = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], dtype=np.int32)
    return corners, triangles


def fog_scene():
    v, t = box()
    w, u = box((0.5, 0.5, 0.5), (2.0, 2.0, 2.0))
    return sphrect.Scene(camera=top_camera(), volumes=[
        sphrect.Volume(v, t, sphrect.Medium(sigma_s=(0.5, 0.4, 0.3), sigma_a=(0.1, 0.0, 0.2), g=0.3), name="Fog"),
        sphrect.Volume(w, u, sphrect.Medium(sigma_s=(0.0, 0.0, 0.0), sigma_a=(2.0, 2.0, 2.0)), name="Ink")])


def test_box_helper_winds_outwards():
    """The fixture the other tests use: every triangle's normal points away from the box's centre."""
    v, t = box()
    p = v[t]
    normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert (np.einsum("ij,ij->i", normals, p.mean(axis=1)) > 0).all()


def test_volumes_round_trip(tmp_path):
    scene = fog_scene()
    path = tmp_path / "fog.sphrect.npz"
    sphrect.save_scene(scene, path)
    loaded = sphrect.load_scene(path)
    assert [v.name for v in loaded.volumes] == ["Fog", "Ink"]
    for ours, theirs in zip(loaded.volumes, scene.volumes):
        np.testing.assert_array_equal(ours.vertices, theirs.vertices)
        np.testing.assert_array_equal(ours.triangles, theirs.triangles)
        assert ours.vertices.dtype == np.float32 and ours.triangles.dtype == np.int32
        assert tuple(ours.medium.sigma_s) == pytest.approx(theirs.medium.sigma_s)
        assert tuple(ours.medium.sigma_a) == pytest.approx(theirs.medium.sigma_a)
        assert ours.medium.g == pytest.approx(theirs.medium.g)


def test_version_19_file_loads_without_volumes(tmp_path):
    path, old = tmp_path / "new.sphrect.npz", tmp_path / "old.sphrect.npz"
    sphrect.save_scene(fog_scene(), path)

    def strip(meta):  # what a version-19 writer wrote: no "volumes", no volume arrays (ignored if left)
        del meta["volumes"]
    save_as_older_version(path, old, 19, strip)
    loaded = sphrect.load_scene(old)
    assert loaded.volumes == []
    assert len(sphrect.load_scene(path).volumes) == 2  # the check can fail: the new file has them


def test_default_scene_has_no_volumes():
    assert sphrect.Scene().volumes == []


@pytest.mark.parametrize("edit, message", [
    (lambda a: a.update({"volume0.vertices": a["volume0.vertices"][:, :2]}), "volume0.vertices"),
    (lambda a: a.update({"volume0.triangles": a["volume0.triangles"].astype(np.float32)}), "volume0.triangles"),
    (lambda a: a.pop("volume0.triangles"), "has no triangles"),
])
def test_malformed_volume_arrays_in_a_file_raise(tmp_path, edit, message):
    path, bad = tmp_path / "good.sphrect.npz", tmp_path / "bad.sphrect.npz"
    sphrect.save_scene(fog_scene(), path)
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    edit(arrays)
    np.savez_compressed(bad, **arrays)
    with pytest.raises(ValueError, match=message):
        sphrect.load_scene(bad)


def test_volume_without_a_medium_in_a_file_raises(tmp_path):
    path, bad = tmp_path / "good.sphrect.npz", tmp_path / "bad.sphrect.npz"
    sphrect.save_scene(fog_scene(), path)
    save_as_older_version(path, bad, 20, lambda meta: meta["volumes"][0].pop("medium"))
    with pytest.raises(ValueError, match="no 'medium'"):
        sphrect.load_scene(bad)


@pytest.mark.parametrize("change, message", [
    (dict(vertices=np.zeros((8, 2), dtype=np.float32)), r"vertices must have shape \[V, 3\]"),
    (dict(triangles=np.zeros((12, 4), dtype=np.int32)), r"triangles must have shape \[T, 3\]"),
    (dict(triangles=np.zeros((12, 3), dtype=np.float32) + 0.5), "must be integers"),
    (dict(triangles=np.full((12, 3), 8, dtype=np.int32)), "index out of range"),
    (dict(medium=(0.1, 0.1, 0.1)), "must be a sphrect.Medium"),
])
def test_malformed_volumes_handed_to_the_renderer_raise(change, message):
    """Checked in Python before the native scene sees them (so these hold with or without its add_volume)."""
    scene = fog_scene()
    v = scene.volumes[0]
    for k, value in change.items():
        setattr(v, k, value)
    with pytest.raises(ValueError, match=f"volume 'Fog'.*{message}|{message}"):
        build_native_scene(scene)


def test_something_else_in_volumes_raises():
    scene = fog_scene()
    scene.volumes.insert(0, "fog")
    with pytest.raises(ValueError, match=r"scene.volumes\[0\] is not a sphrect.Volume"):
        build_native_scene(scene)


def test_absorbing_box_dims_what_it_covers_by_beer_lambert():
    """The plumbing to the renderer: a white diffuse ground under a sun straight above, seen from above; an absorbing
    box 1 m thick over the half x < 0 of the view (its edge on a pixel boundary) dims that half by the transmittance
    of the camera ray and of the sun's shadow ray, exp(-2 sigma_a), and leaves the other half as it is.  The sun is a
    delta light and the medium does not scatter: the image is exact up to float rounding (tolerance 1e-4)."""
    sigma_a = 0.7
    v, t = box((-3.0, -3.0, 0.5), (0.0, 3.0, 1.5))
    scene = sphrect.Scene(camera=top_camera(), materials=[sphrect.Material(base_color=(1.0, 1.0, 1.0))],
                          meshes=[sphrect.Mesh(vertices=np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]],
                                                                 np.float32),
                                               triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32))],
                          lights=[sphrect.SunLight(direction=(0.0, 0.0, -1.0), irradiance=(np.pi,) * 3)],
                          volumes=[sphrect.Volume(v, t, sphrect.Medium(sigma_s=(0.0,) * 3, sigma_a=(sigma_a,) * 3))])
    image = sphrect.render(scene, samples=4, techniques="rectangle")["rectangle"][..., :3]
    covered, open_ = image[:, :6], image[:, 6:]
    np.testing.assert_allclose(open_, 1.0, rtol=1e-4)
    np.testing.assert_allclose(covered, np.exp(-2 * sigma_a), rtol=1e-4)
