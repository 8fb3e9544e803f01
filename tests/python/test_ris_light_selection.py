"""Light selection "ris" (resampled importance sampling of the tree's candidates, docs/light_selection_ris.md) from
Python: the Renderer takes it and its ris_candidates, refuses candidates out of range with a ValueError naming the
bounds, and its image of four rectangles over a Lambertian plane matches Lambert's polygon formula.

False-failure rate: the unbiasedness test is one family of pixel t-tests of family-wise rate 1e-4 (Sidak) per
(MIS mode, candidates) case, 4 cases: < 4e-4.  Seeds are fixed, so the outcome is deterministic."""
import pytest

import sphrect
from render_testing import expected_plane_image, pixel_t_test, polygon_irradiance, replicate_images, top_camera
from test_light_selection import ALBEDO, FOUR_LIGHTS, plane_scene, rect_verts


def test_ris_is_a_light_selection_with_its_candidates_default():
    assert "ris" in sphrect.light_selections
    assert 1 <= sphrect.RENDER_DEFAULTS["ris_candidates"] <= sphrect.MAX_RIS_CANDIDATES
    r = sphrect.Renderer(plane_scene(FOUR_LIGHTS, top_camera(4, 4)), light_selection="ris", ris_candidates=3)
    assert r.render(2)
    assert r.image()[:, :, 0].max() > 0


@pytest.mark.parametrize("bad", [0, -1, sphrect.MAX_RIS_CANDIDATES + 1, 2.5, True, "4"])
def test_ris_candidates_out_of_range_is_a_value_error(bad):
    bounds = rf"ris_candidates must be an integer in 1\.\.{sphrect.MAX_RIS_CANDIDATES}"
    with pytest.raises(ValueError, match=bounds):
        sphrect.Renderer(plane_scene(FOUR_LIGHTS, top_camera(4, 4)), light_selection="ris", ris_candidates=bad)


@pytest.mark.slow
@pytest.mark.parametrize("mis", ["none", "power"])
@pytest.mark.parametrize("candidates", [2, 16])
def test_ris_is_unbiased_against_lamberts_formula(mis, candidates):
    scene = plane_scene(FOUR_LIGHTS, top_camera())
    expected = sum(expected_plane_image(scene.camera, ALBEDO, lambda P, l=l: l.radiance[0] * polygon_irradiance(
        P, (0, 0, 1), rect_verts(l), two_sided=False)) for l in FOUR_LIGHTS)
    reps = replicate_images(scene, ["rectangle"], 24, 8, mis=mis, light_selection="ris", ris_candidates=candidates,
                            bsdf_samples_on_diffuse=True)
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, 1e-4)
    assert ok, f"{mis}/M={candidates}: worst p = {p_min:.3g} < {alpha:.3g}"
