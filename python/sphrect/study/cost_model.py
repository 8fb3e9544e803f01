"""What a camera sample costs, term by term, and the ray cost at which one configuration's accuracy pays for its time.

A run's time per camera sample is modelled as

    cost = fixed + sampler + rays x t_ray                                       (1)

each term measured in the run by the renderer's own stage timers and counters (Renderer.stats), per camera sample:
`rays` the camera and occlusion rays traced, `t_ray` the Embree streams' seconds per ray (camera_trace_time +
trace_time over those rays), `sampler` the light sampling (light_time: the light choice, the technique's setup and
map, its pdfs for MIS), `fixed` the rest of the tiles' time (tile_time: pattern, camera rays' generation, hits,
BSDFs, MIS weights, the queue, the image's accumulation; one technique per renderer, as the study renders).  The check:
(1) against the run's CPU time per camera sample measured around the render call, independently of the timers
(`check`; CHECK_TOLERANCE in the report): what the tiles leave out is the pass's own setup and the threads' start.

Another renderer differs in the terms, chiefly in what a ray costs (a production scene: microseconds) and what
shading a hit costs: with `hits` the surface hits per camera sample and `shading` an added cost per hit,

    cost(x, y) = fixed + sampler + rays x + hits y                              (2)

Two configurations A and B reach an error with N_A and N_B samples per pixel; B takes less time where
N_B cost_B(x, y) < N_A cost_A(x, y), linear in x (and in y), so there is at most one break-even ray cost
(break_even): the ray cost above (or below) which B reaches the error sooner.  The relative efficiency of B against
A at equal error, (N_A cost_A) / (N_B cost_B), is what the report plots against x and y.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence

from .metrics import COST_RUNS

# The renderer's counters and timers the model reads from a run's record (runner.render_sphrect).
MODEL_FIELDS = ("camera_rays", "rays", "surface_hits", "light_time", "tile_time", "trace_time", "camera_trace_time",
                "cpu_time")


@dataclass(frozen=True)
class CostTerms:
    """One run's (or a curve's) time per camera sample, term by term: seconds, and counts per camera sample."""
    fixed: float
    sampler: float
    rays: float
    t_ray: float
    hits: float
    measured: float  # CPU time per camera sample, measured around the render call (NaN: not measured)

    @property
    def modelled(self) -> float:
        """(1): the terms' sum at this run's own ray cost."""
        return self.at()

    @property
    def check(self) -> float:
        """(1) against the measured time: modelled / measured - 1 (NaN without a measurement)."""
        return self.modelled / self.measured - 1 if self.measured > 0 else float("nan")

    def at(self, ray_cost: Optional[float] = None, shading_cost: float = 0.0) -> float:
        """(2): the cost per camera sample with a ray costing `ray_cost` seconds (this run's t_ray when None) and
        `shading_cost` seconds added per surface hit."""
        t = self.t_ray if ray_cost is None else ray_cost
        return self.fixed + self.sampler + self.rays * t + self.hits * shading_cost


def cost_terms(measured: Dict) -> Optional[CostTerms]:
    """A run's CostTerms from its measurements (a record's fields, MODEL_FIELDS); None where they are missing (a
    Cycles run, a run recorded before the renderer had these timers) or it traced no camera ray."""
    values = {k: measured.get(k) for k in MODEL_FIELDS}
    if any(values[k] is None for k in MODEL_FIELDS if k != "cpu_time"):
        return None
    n = float(values["camera_rays"])
    if not n > 0:
        return None
    rays = float(values["camera_rays"]) + float(values["rays"])
    trace = float(values["camera_trace_time"]) + float(values["trace_time"])
    fixed = float(values["tile_time"]) - trace - float(values["light_time"])
    cpu = values["cpu_time"]
    return CostTerms(fixed=fixed / n, sampler=float(values["light_time"]) / n, rays=rays / n,
                     t_ray=trace / rays if rays > 0 else 0.0, hits=float(values["surface_hits"]) / n,
                     measured=float(cpu) / n if cpu is not None and cpu > 0 else float("nan"))


def mean_terms(terms: Sequence[CostTerms]) -> Optional[CostTerms]:
    """The mean of runs' terms (a curve's: its COST_RUNS largest runs, as its cost per sample; pass them in
    ascending samples), term by term; None for no runs."""
    terms = list(terms)[-COST_RUNS:]
    if not terms:
        return None

    def mean(field: str) -> float:
        values = [getattr(t, field) for t in terms if not math.isnan(getattr(t, field))]
        return sum(values) / len(values) if values else float("nan")
    return CostTerms(**{f: mean(f) for f in ("fixed", "sampler", "rays", "t_ray", "hits", "measured")})


@dataclass(frozen=True)
class BreakEven:
    """Where B (samples n_b per pixel to the error, terms b) reaches an error sooner than A (n_a, a), along the
    ray cost x (seconds per ray) with the shading cost per hit fixed, or along the shading cost with the ray cost
    fixed (`axis`): B is faster for x above `threshold` ("above"), below it ("below"), at every x >= 0 ("always")
    or at none ("never")."""
    axis: str
    threshold: float
    side: str

    def b_faster(self, x: float) -> bool:
        if self.side in ("always", "never"):
            return self.side == "always"
        return x > self.threshold if self.side == "above" else x < self.threshold


RAY_AXIS, SHADING_AXIS = "ray cost", "shading cost per hit"


def equal_error_time(n: float, terms: CostTerms, ray_cost: Optional[float] = None, shading_cost: float = 0.0) -> float:
    """Time per pixel to the error: samples per pixel x cost per camera sample (2)."""
    return n * terms.at(ray_cost, shading_cost)


def relative_efficiency(n_a: float, a: CostTerms, n_b: float, b: CostTerms, ray_cost: Optional[float] = None,
                        shading_cost: float = 0.0) -> float:
    """B's efficiency over A's at equal error: A's time to the error over B's (> 1: B is faster)."""
    return equal_error_time(n_a, a, ray_cost, shading_cost) / equal_error_time(n_b, b, ray_cost, shading_cost)


def break_even(n_a: float, a: CostTerms, n_b: float, b: CostTerms, axis: str = RAY_AXIS,
               ray_cost: Optional[float] = None, shading_cost: float = 0.0) -> BreakEven:
    """The ray cost (axis RAY_AXIS, the shading cost per hit held at `shading_cost`) or the shading cost per hit
    (SHADING_AXIS, each side's ray cost its own t_ray, or `ray_cost`) at which B's time to the error equals A's:
    n_b (c_b + k_b x) = n_a (c_a + k_a x), with k the rays (or hits) per camera sample and c the rest of (2)."""
    if axis == RAY_AXIS:
        c_a, k_a = a.at(0.0, shading_cost), a.rays
        c_b, k_b = b.at(0.0, shading_cost), b.rays
    else:
        c_a, k_a = a.at(ray_cost, 0.0), a.hits
        c_b, k_b = b.at(ray_cost, 0.0), b.hits
    slope = n_b * k_b - n_a * k_a   # d/dx of B's time minus A's
    offset = n_a * c_a - n_b * c_b  # A's time minus B's at x = 0
    if slope == 0:
        return BreakEven(axis, float("nan"), "always" if offset > 0 else "never")
    threshold = offset / slope  # where B's time minus A's, slope x - offset, is 0
    if slope < 0:  # B's time grows slower: faster above the threshold
        return BreakEven(axis, threshold, "always" if threshold <= 0 else "above")
    return BreakEven(axis, threshold, "never" if threshold <= 0 else "below")


def upper_median(values: Sequence[float]) -> float:
    """The median of values, the upper of the middle two for an even count (a value measured, not an average); NaN for
    none."""
    ordered = sorted(values)
    return ordered[len(ordered) // 2] if ordered else float("nan")


def log_grid(low: float, high: float, points: int) -> List[float]:
    """`points` values from low to high, evenly spaced in log."""
    step = (math.log(high) - math.log(low)) / (points - 1)
    return [math.exp(math.log(low) + i * step) for i in range(points)]
