"""The study's sampler table (sphrect.study.sampler_table): it measures the C++ tests' hard-case suite and
takes its timings from the module, so it works from an installed package (no build tree, no benchmark
binary)."""
import numpy as np

import sphrect
from sphrect.study import sampler_table

TECHNIQUES = tuple(sphrect.techniques)


def test_the_suite_is_the_tests_suite():
    cases = sampler_table.hard_cases()
    names = [c[0] for c in cases]
    assert len(names) == len(set(names)) == len(sphrect._native._study_hard_cases())
    # Every kind of configuration the tests check, and the study's former own ones.
    for kind in ("unit/above_center_d1e+06", "unit/above_center_d100", "unit/above_center_d10000",
                 "unit/beside_h1e-06", "aspect1e5/interior_h1e-09", "rotated/diagonal_d1e-06",
                 "long1e5/above_center_h1"):
        assert kind in names, kind
    for _, origin, corner, ex, ey in cases:  # float32 values, as the float path sees them
        for v in (origin, corner, ex, ey):
            assert np.array_equal(np.float32(v), np.asarray(v, np.float64))
    uv = sampler_table.uv_grid()
    assert uv.shape == (81, 2) and uv.min() == 0 and uv.max() == 1
    assert np.float32(np.nextafter(np.float32(1), np.float32(0))) in uv


def test_accuracy_table_robust_vs_textbook():
    errors = sampler_table.pdf_errors()
    for variant in ("robust float32", "robust float64"):
        e = errors[variant]
        assert e["invalid"] == 0 and e["samples"] > 0, variant
        assert e["omega"] < 1e-6 and e["pdf"] < 1e-5, (variant, e)
    textbook = errors["textbook float32"]
    assert textbook is not None and textbook["omega"] > 1.0   # the baseline fails far away


def test_cost_table_comes_from_the_module():
    costs, _ = sampler_table.sampler_costs(min_time=0.001)
    header, rows = sampler_table.cost_table(costs, [])
    assert header[:2] == ["technique", "precision"] and len(header) == 2 + len(sampler_table.STAGES)
    assert len(rows) == len(costs)
    for technique in TECHNIQUES:
        for precision in ("float", "double"):
            assert costs[(technique, precision)]["Sample"] > 0, (technique, precision)
    assert costs[("textbook_rectangle", "float")]["Sample"] > 0
    assert costs[("rectangle", "float")]["SampleEdgeOn"] > 0
