"""The cost-model sweep's scenes (sphrect.study.complexity): each level splits every triangle of the meshes that emit
nothing in four at its edges' midpoints (the vertex attributes their ends' mean), emissive meshes untouched, and the
image stays the same up to rounding while the BVH grows."""
import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, top_camera
from sphrect.study import complexity


def scene_with_an_emitter():
    ground = plane_mesh(2.0)
    ground.normals = np.tile(np.array([[0, 0, 1]], np.float32), (4, 1))
    ground.uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    ground.attributes = {"tint": np.array([[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 1, 1]], np.float32)}
    ground.material_ids = np.zeros(2, np.int32)
    panel = sphrect.Mesh(vertices=np.array([[-0.3, -0.3, 1], [0.3, -0.3, 1], [0.3, 0.3, 1], [-0.3, 0.3, 1]],
                                           np.float32),
                         triangles=np.array([[0, 2, 1], [0, 3, 2]], np.int32), material_ids=np.ones(2, np.int32),
                         name="panel")
    return sphrect.Scene(camera=top_camera(width=24, height=24, half=1.0), meshes=[ground, panel],
                         materials=[sphrect.Material(name="ground", base_color=(0.5, 0.5, 0.5)),
                                    sphrect.Material(name="panel", base_color=(0, 0, 0), emission=(3, 3, 3))])


def test_levels_split_the_triangles_of_meshes_that_emit_nothing():
    scene = scene_with_an_emitter()
    for levels in (0, 1, 3):
        s = complexity.subdivide_scene(scene, levels)
        assert len(s.meshes[0].triangles) == 2 * 4 ** levels
        assert s.meshes[1] is scene.meshes[1]  # the emitter, untouched
        assert complexity.triangle_count(s) == 2 * 4 ** levels + 2
        assert complexity.subdivided_triangle_count(scene, levels) == complexity.triangle_count(s)
    s = complexity.subdivide_scene(scene, 1).meshes[0]
    # Shared midpoints: 4 corners + 5 edges of the two triangles.
    assert len(s.vertices) == 9 and len(s.normals) == len(s.uvs) == len(s.attributes["tint"]) == 9
    assert np.all(s.material_ids == 0) and len(s.material_ids) == 8
    # A new vertex is the mean of its edge's ends, in every attribute.
    v = s.vertices
    for i in range(4, 9):
        ends = [j for j in range(4) for k in range(j + 1, 4)
                if np.allclose(v[i], 0.5 * (v[j] + v[k]))]
        assert ends, i
    uv_of = {tuple(np.round(p, 5)): uv for p, uv in zip(v, s.uvs)}
    assert np.allclose(uv_of[(0.0, 0.0, 0.0)], [0.5, 0.5])  # the diagonal's midpoint
    with pytest.raises(ValueError):
        complexity.subdivide_scene(scene, -1)


def test_the_image_is_the_same_up_to_rounding():
    scene = scene_with_an_emitter()

    def image(s):
        r = sphrect.Renderer(s, techniques=["rectangle"], seed=5, threads=1)
        r.render(4)
        return np.asarray(r.image())[..., :3]
    base = image(scene)
    for levels in (1, 3):
        assert np.abs(image(complexity.subdivide_scene(scene, levels)) - base).max() <= 1e-3 * base.max()


def test_emission_is_found_in_textures_programs_and_layers():
    plain = sphrect.Material(base_color=(0.5, 0.5, 0.5))
    assert not complexity.material_emits(plain)
    assert complexity.material_emits(sphrect.Material(emission=(0, 0, 1)))
    assert complexity.material_emits(sphrect.Material(textures={"emission": sphrect.TextureLookup(texture=0)}))
    mix = sphrect.Material(kind="mix", layers=[sphrect.MaterialLayer(0.5, plain),
                                               sphrect.MaterialLayer(0.5, sphrect.Material(emission=(1, 1, 1)))])
    assert complexity.material_emits(mix)
