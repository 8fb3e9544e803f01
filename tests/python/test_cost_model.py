"""The study's cost model (sphrect.study.cost_model): its terms from a run's measurements, their sum, the break-even
ray and shading costs and the relative efficiency at equal error -- worked by hand on small numbers -- and the
renderer's timers and counters it reads (nested as the model needs, the counts exact)."""
import math

import numpy as np
import pytest

import sphrect
from render_testing import plane_mesh, top_camera
from sphrect.study import cost_model as cm

US = 1e-6


def terms(fixed, sampler, rays, t_ray=0.1 * US, hits=1.0, measured=float("nan")):
    return cm.CostTerms(fixed=fixed, sampler=sampler, rays=rays, t_ray=t_ray, hits=hits, measured=measured)


def test_terms_from_a_runs_measurements():
    # 1000 camera samples, 1500 occlusion rays, 900 hits; 4.5 ms in the tiles, of which 0.4 ms tracing camera rays,
    # 1.1 ms tracing occlusion rays and 0.5 ms of light sampling; 4.4 ms of CPU time.
    measured = dict(camera_rays=1000, rays=1500, surface_hits=900, tile_time=4.5e-3, camera_trace_time=0.4e-3,
                    trace_time=1.1e-3, light_time=0.5e-3, cpu_time=4.4e-3)
    t = cm.cost_terms(measured)
    assert t.rays == pytest.approx(2.5) and t.hits == pytest.approx(0.9)
    assert t.t_ray == pytest.approx(1.5e-3 / 2500)
    assert t.sampler == pytest.approx(0.5 * US)
    assert t.fixed == pytest.approx((0.6e-3 + 1.9e-3) / 1000)
    # fixed + sampler + rays t_ray = (2.5 + 0.5 + 1.5) ms over 1000 samples = 4.5 us, against 4.4 us measured.
    assert t.modelled == pytest.approx(4.5 * US)
    assert t.check == pytest.approx(4.5 / 4.4 - 1)


def test_terms_need_the_renderers_timers():
    assert cm.cost_terms({"cpu_time": 1.0, "wall_time": 1.0}) is None  # a Cycles run
    assert cm.cost_terms(dict(camera_rays=0, rays=0, surface_hits=0, tile_time=0, camera_trace_time=0,
                              trace_time=0, light_time=0, cpu_time=0)) is None


def test_cost_at_other_ray_and_shading_costs():
    t = terms(fixed=1 * US, sampler=0.5 * US, rays=2, t_ray=0.1 * US, hits=0.8)
    assert t.at() == pytest.approx(1.7 * US)
    assert t.at(ray_cost=10 * US) == pytest.approx(21.5 * US)
    assert t.at(shading_cost=5 * US) == pytest.approx(5.7 * US)


def test_break_even_ray_cost_worked_by_hand():
    """A: 100 spp to the error at 1 us + 2 rays; B (a costlier, better sampler): 50 spp at 3 us + 2 rays.
    100 (1 + 2x) = 50 (3 + 2x) at x = 0.5 us: B is faster above it."""
    a, b = terms(fixed=0.6 * US, sampler=0.4 * US, rays=2), terms(fixed=0.6 * US, sampler=2.4 * US, rays=2)
    be = cm.break_even(100, a, 50, b)
    assert be.side == "above" and be.threshold == pytest.approx(0.5 * US)
    assert not be.b_faster(0.4 * US) and be.b_faster(0.6 * US)
    assert cm.relative_efficiency(100, a, 50, b, ray_cost=0.5 * US) == pytest.approx(1.0)
    # Far above, B's efficiency tends to the ratio of samples.
    assert cm.relative_efficiency(100, a, 50, b, ray_cost=1.0) == pytest.approx(2.0, rel=1e-5)
    # The reverse pair: A is faster below the same threshold.
    back = cm.break_even(50, b, 100, a)
    assert back.side == "below" and back.threshold == pytest.approx(0.5 * US)


def test_break_even_always_and_never():
    a = terms(fixed=1 * US, sampler=0.5 * US, rays=2)
    better_and_cheaper = terms(fixed=1 * US, sampler=0.4 * US, rays=2)
    assert cm.break_even(100, a, 50, better_and_cheaper).side == "always"
    assert cm.break_even(50, better_and_cheaper, 100, a).side == "never"
    # Equal samples and rays: only the rest of the cost decides, at every ray cost.
    assert cm.break_even(100, a, 100, better_and_cheaper).side == "always"
    assert cm.break_even(100, better_and_cheaper, 100, a).side == "never"


def test_break_even_shading_cost():
    """A and B shade the same hits but B's extra rays (4 against 2 at 0.1 us) and cheaper sampler: 100 (2.7 + 0.9 y)
    = 60 (4.2 + 0.9 y) at y = (270 - 252) / (54 - 90) < 0 -> B is faster at every shading cost."""
    a = terms(fixed=1 * US, sampler=1.5 * US, rays=2, hits=0.9)
    b = terms(fixed=1 * US, sampler=2.8 * US, rays=4, hits=0.9)
    be = cm.break_even(100, a, 60, b, axis=cm.SHADING_AXIS)
    assert be.side == "always"
    # Twice the hits for B (say, shading its light samples' points too): B loses above a shading cost.
    b2 = terms(fixed=1 * US, sampler=2.8 * US, rays=4, hits=2.0)
    be2 = cm.break_even(100, a, 60, b2, axis=cm.SHADING_AXIS)
    y = be2.threshold
    assert be2.side == "below" and y > 0
    assert cm.relative_efficiency(100, a, 60, b2, shading_cost=y) == pytest.approx(1.0)


def test_mean_terms_over_a_curves_largest_runs():
    runs = [terms(fixed=f * US, sampler=1 * US, rays=2, measured=m * US) for f, m in
            [(9, 9), (1, 2), (2, float("nan")), (3, 4)]]
    t = cm.mean_terms(runs)
    assert t.fixed == pytest.approx(2 * US)  # the last three
    assert t.measured == pytest.approx(3 * US)  # NaN left out
    assert cm.mean_terms([]) is None


def test_log_grid():
    g = cm.log_grid(10e-9, 100e-6, 5)
    assert g[0] == pytest.approx(10e-9) and g[-1] == pytest.approx(100e-6)
    assert np.allclose(np.diff(np.log(g)), math.log(10))


def test_the_renderers_timers_nest_and_its_counts_are_exact():
    """What the model reads: tracing within its stages, light sampling within shading, one camera ray per camera
    sample, a hit for every camera ray that meets the plane (the camera sees only it), an occlusion ray per light
    sample at least (the light is above the plane, MIS draws more)."""
    light = sphrect.RectLight(corner=(-0.4, -0.3, 0.6), edge_x=(0, 0.8, 0), edge_y=(0.8, 0, 0), radiance=(3, 3, 3),
                              visible=False)
    scene = sphrect.Scene(camera=top_camera(width=12, height=10), meshes=[plane_mesh()], lights=[light])
    r = sphrect.Renderer(scene, techniques=["rectangle"], threads=1, light_samples=2, mis="power",
                         bsdf_samples_on_diffuse=True)
    r.render(8)
    s = r.stats()
    assert s["camera_rays"] == 12 * 10 * 8 and s["surface_hits"] == s["camera_rays"]
    assert s["rays"] >= 2 * s["camera_rays"]
    assert 0 < s["camera_trace_time"] <= s["camera_time"]
    assert 0 < s["trace_time"] <= s["shading_time"]
    assert s["camera_time"] + s["shading_time"] + s["light_time"] <= s["tile_time"]
    t = cm.cost_terms({**s, "cpu_time": None})
    assert t.rays == pytest.approx(1 + s["rays"] / s["camera_rays"]) and t.hits == 1
    assert t.fixed > 0 and t.sampler > 0 and t.t_ray > 0 and math.isnan(t.check)


def synthetic_curve(technique, sigma, fixed, light, t_ray, pixels=100, ladder=(1, 2, 4, 8, 16)):
    """A curve of records as the study stores them: RMSE sigma / sqrt(spp), a camera and an occlusion ray per camera
    sample, times from the terms."""
    records = []
    for n in ladder:
        cam = n * pixels
        tile = cam * (fixed + light + 2 * t_ray)
        records.append({"job": {"samples": n, "technique": technique}, "rmse": sigma / math.sqrt(n), "time": tile,
                        "cpu_time": tile, "tile_time": tile, "light_time": cam * light, "trace_time": cam * t_ray,
                        "camera_trace_time": cam * t_ray, "camera_rays": cam, "rays": cam, "surface_hits": cam})
    return records


def test_a_pair_from_the_studys_curves():
    """A (RMSE 0.1/sqrt(n)) and B (0.08/sqrt(n), light sampling 3 us against 1 us; both 1 us fixed and two rays of
    0.5 us): at A's top-rung error 0.025, A needs 16 spp and B 16 x 0.64 = 10.24; 16 (2 + 2x) = 10.24 (4 + 2x) at
    x = 8.96 / 11.52 us = 0.778 us, above which B is faster; here (0.5 us) A is."""
    from sphrect.study.jobs import CurveKey
    from sphrect.study.report import costs
    ka, kb = CurveKey("rectangle", "power", "sobol", "tree"), CurveKey("rectangle_projected", "power", "sobol", "tree")
    curves = {ka: synthetic_curve("rectangle", 0.1, 1 * US, 1 * US, 0.5 * US),
              kb: synthetic_curve("rectangle_projected", 0.08, 1 * US, 3 * US, 0.5 * US)}
    model = costs.configuration_costs(curves)
    assert model[kb].terms.sampler == pytest.approx(3 * US) and model[ka].terms.t_ray == pytest.approx(0.5 * US)
    assert model[ka].checks == [] or all(abs(c) < 1e-9 for c in model[ka].checks)
    assert model[ka].setup == pytest.approx(0.0, abs=1e-12)  # time proportional to samples
    pair = costs.pair_cost(ka, kb, curves, model, reference_rmse=0.0)
    assert (pair.a, pair.b) == (ka, kb) and pair.target == pytest.approx(0.025)
    assert pair.n_a == pytest.approx(16) and pair.n_b == pytest.approx(10.24)
    assert pair.ray.side == "above" and pair.ray.threshold == pytest.approx(8.96 / 11.52 * US)
    assert pair.efficiency() == pytest.approx(16 * 3 / (10.24 * 5))
    # Given the other way round, the pair is ordered by samples all the same; unordered, as given.
    assert costs.pair_cost(kb, ka, curves, model, 0.0).b == kb
    assert costs.pair_cost(kb, ka, curves, model, 0.0, ordered=False).b == ka


def test_light_selections_are_paired_too():
    """A study of one technique under tree and ris: pair_costs pairs the two selections (ris, 0.08 / sqrt(n) at 3 us
    of light sampling, against the tree's 0.1 / sqrt(n) at 1 us: the numbers of the pair above), and the sentence
    names them by their selection."""
    from sphrect.study.jobs import CurveKey, StudyConfig
    from sphrect.study.report import cost_wording, costs
    kt, kr = CurveKey("rectangle", "power", "sobol", "tree"), CurveKey("rectangle", "power", "sobol", "ris")
    curves = {kt: synthetic_curve("rectangle", 0.1, 1 * US, 1 * US, 0.5 * US),
              kr: synthetic_curve("rectangle", 0.08, 1 * US, 3 * US, 0.5 * US)}
    cfg = StudyConfig(techniques=("rectangle",), mis=("power",), patterns=("sobol",), light_selections=("tree", "ris"))
    (pair,) = costs.pair_costs(cfg, curves, costs.configuration_costs(curves), 0.0)
    assert (pair.a, pair.b) == (kt, kr) and pair.ray.threshold == pytest.approx(8.96 / 11.52 * US)
    assert cost_wording.pair_finding(pair, 0.5 * US).startswith(
        "- rectangle with light selection ris pays off against rectangle with tree above a ray cost of **778 ns**")


def test_the_check_summary_and_a_busy_machine():
    """Checks of +2%, -5%, +30% and +40% (and a NaN, not checked): 2 of 4 within 10%, the largest 40%, the median
    (the upper middle) 30%: above the tolerance, so the report says the timers ran ahead (elapsed time on a busy
    machine); a quiet run's checks do not say so."""
    from sphrect.study.jobs import CurveKey
    from sphrect.study.report import cost_wording, costs
    key = CurveKey("rectangle", "power", "sobol", "tree")
    busy = {key: costs.ConfigurationCost(key, terms(1 * US, 1 * US, 2.0), [0.02, -0.05, float("nan"), 0.3, 0.4],
                                         2e-3)}
    check = costs.checks_within(busy)
    assert (check.within, check.checked) == (2, 4)
    assert check.largest == pytest.approx(0.4) and check.median == pytest.approx(0.3) and check.setup == 2e-3
    assert any("run ahead" in line for line in cost_wording.model_lines(check, 0.1 * US))
    quiet = costs.checks_within({key: costs.ConfigurationCost(key, terms(1 * US, 1 * US, 2.0), [0.02, -0.05], 0.0)})
    assert not any("run ahead" in line for line in cost_wording.model_lines(quiet, 0.1 * US))


def test_sweep_crossing_and_verdicts():
    from sphrect.study import sweep
    from sphrect.study.jobs import CurveKey
    from sphrect.study.report import costs
    # The ratio crosses 1 between 20 and 80 ns, at 40 ns in log-linear interpolation (0.9 -> 1.1).
    assert sweep.crossing([10e-9, 20e-9, 80e-9], [0.8, 0.9, 1.1]) == pytest.approx(40e-9)
    assert sweep.crossing([0.0, 1e-6], [0.5, 1.5]) == pytest.approx(0.5e-6)
    assert sweep.crossing([1e-8, 1e-7], [1.2, 1.3]) is None
    # Within the timing noise of 1 a ratio is no side: 0.99 -> 1.02 is no crossing at 3%.
    assert sweep.crossing([1e-8, 2e-8], [0.99, 1.02], noise=0.03) is None
    assert sweep.crossing([1e-8, 2e-8, 4e-8], [0.9, 1.01, 1.1], noise=0.03) == pytest.approx(2e-8)
    # A pair from the worked example above, and three levels measured exactly as the model says: the predicted and
    # measured ratios agree, and the measured crossing is where the model's break-even is (0.778 us) up to the
    # log-linear interpolation between the levels that are beyond the noise (0.3 and 1.5 us: ratios 0.88 and 1.12).
    ka, kb = CurveKey("rectangle", "power", "sobol", "tree"), CurveKey("rectangle_projected", "power", "sobol", "tree")
    a, b = terms(1 * US, 1 * US, 2, 0.5 * US), terms(1 * US, 3 * US, 2, 0.5 * US)
    pair = costs.PairCost(ka, kb, 0.025, 16, 10.24, a, b, cm.break_even(16, a, 10.24, b),
                          cm.break_even(16, a, 10.24, b, cm.SHADING_AXIS))
    levels = [sweep.Level(sweep.ADDED_RAY, lv, 0, x, {sweep.label(ka): a.at(x), sweep.label(kb): b.at(x)}, {})
              for lv, x in ((0, 0.3 * US), (1, 0.7 * US), (2, 1.5 * US))]
    (v,) = sweep.verdicts([pair], levels, sweep.ADDED_RAY)
    assert v.side == "above" and v.break_even == pytest.approx(8.96 / 11.52 * US)
    assert v.measured == pytest.approx(v.predicted)
    assert 0.3 * US < v.measured_crossing < 1.5 * US
    assert v.measured_crossing == pytest.approx(v.break_even, rel=0.2)
    text = sweep.summary([v], levels, sweep.ADDED_RAY)
    assert "agrees in **2 of 2**" in text and "within the levels' range: 1; crossings measured: 1" in text
    assert "predicted B faster above 778 ns" in text


def test_added_costs_change_no_image_and_are_in_the_terms():
    """Renderer(added_ray_cost=..., added_shading_cost=...): the same image bit for bit, and the busy waits in the
    terms they belong to -- at least the cost added per ray in t_ray, and per hit in the fixed work (each wait lasts
    at least as long as asked)."""
    light = sphrect.RectLight(corner=(-0.4, -0.3, 0.6), edge_x=(0, 0.8, 0), edge_y=(0.8, 0, 0), radiance=(3, 3, 3),
                              visible=False)
    scene = sphrect.Scene(camera=top_camera(width=8, height=8), meshes=[plane_mesh()], lights=[light])

    def run(**kw):
        r = sphrect.Renderer(scene, techniques=["rectangle"], threads=1, seed=2, **kw)
        r.render(4)
        return np.asarray(r.image()), cm.cost_terms({**r.stats(), "cpu_time": None})
    base, _ = run()
    image, t = run(added_ray_cost=2 * US)
    assert np.array_equal(image, base) and t.t_ray >= 2 * US
    image, t = run(added_shading_cost=3 * US)
    assert np.array_equal(image, base) and t.fixed >= 3 * US * t.hits
    for bad in (-1e-9, 2e-3, float("nan")):
        with pytest.raises(ValueError):
            sphrect.Renderer(scene, added_ray_cost=bad)
