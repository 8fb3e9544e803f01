"""A render split into sample ranges, and the accumulation buffers that merge them exactly.

A render of S camera samples per pixel in P parts renders, as its pass k, the camera samples
[first_k, first_k + n_k) of a contiguous split of 0..S (sample_ranges). The renderer seeds everything a
sample draws by the seed, the pixel, the sample's index and the pass number (render.py), so a fresh
Renderer started at range k (Renderer.start_at) renders exactly what pass k of one Renderer rendering
the whole split does. Each renders per pixel the sum of its samples' radiance in double, the sample
count and the film's alpha sum (an :class:`Accumulation`); adding the parts' buffers in range order,
from zero, repeats the single renderer's own additions, so the merged image is bit-identical to
``sphrect.render(scene, S, parts=P)``. With the 'sobol' pattern, which continues one sequence across
passes, it also equals a render in any other number of parts up to float rounding of the sums; the
other patterns lay out their points per pass, so parts change which (equally good) points are drawn.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Sequence

import numpy as np

from . import _native


@dataclass(frozen=True)
class SampleRange:
    """Camera samples [first, first + samples) of a render, rendered as its pass `pass_index`."""
    first: int
    samples: int
    pass_index: int


def sample_ranges(samples: int, parts: int) -> List[SampleRange]:
    """`samples` split into `parts` contiguous ranges as equal as can be (the first ones one larger);
    ValueError unless 1 <= parts <= samples."""
    samples, parts = int(samples), int(parts)
    if not 1 <= parts <= samples:
        raise ValueError(f"cannot split {samples} samples into {parts} parts (1 <= parts <= samples)")
    base, extra = divmod(samples, parts)
    ranges, first = [], 0
    for k in range(parts):
        n = base + (1 if k < extra else 0)
        ranges.append(SampleRange(first, n, k))
        first += n
    return ranges


@dataclass
class Accumulation:
    """A render's accumulation buffers: per technique the RGB sums in double [H, W, 3], the camera samples
    per pixel [H, W] and the film's alpha sums [H, W]; its images are their means."""
    sums: Dict[str, np.ndarray]
    counts: np.ndarray
    alpha_sums: np.ndarray
    film_alpha: bool

    @staticmethod
    def zeros_like(other: "Accumulation") -> "Accumulation":
        return Accumulation({t: np.zeros_like(s) for t, s in other.sums.items()}, np.zeros_like(other.counts),
                            np.zeros_like(other.alpha_sums), other.film_alpha)

    def add(self, other: "Accumulation") -> None:
        """Adds `other`'s samples (a disjoint range of the same render) to these buffers."""
        if list(other.sums) != list(self.sums) or other.counts.shape != self.counts.shape:
            raise ValueError("cannot merge renders of different techniques or resolutions")
        for t in self.sums:
            self.sums[t] += other.sums[t]
        self.counts += other.counts
        self.alpha_sums += other.alpha_sums

    def image(self, technique: str) -> np.ndarray:
        """float32 [H, W, 4], exactly as Renderer.image() computes it from the same buffers."""
        return _native.resolve_image(self.sums[technique], self.counts, self.alpha_sums, self.film_alpha)

    def images(self) -> Dict[str, np.ndarray]:
        return {t: self.image(t) for t in self.sums}


def merge(parts: Sequence[Accumulation]) -> Accumulation:
    """The parts' buffers added from zero in the order given (range order: see the module docstring)."""
    if not parts:
        raise ValueError("nothing to merge")
    total = Accumulation.zeros_like(parts[0])
    for part in parts:
        total.add(part)
    return total
