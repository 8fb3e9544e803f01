"""Long renders split by samples over a Dask cluster (the `distributed` package, imported only when used).

    from distributed import Client
    images = sphrect.render_distributed(scene, 65536, client=Client("tcp://host:8786"), techniques=["rectangle"])

The samples are split into `parts` contiguous ranges (default: one per worker), each rendered on a worker as its
pass of the whole render; their accumulation buffers are merged in range order (sample_ranges.py), so the image is
bit-identical to ``sphrect.render(scene, samples, parts=parts, ...)`` on one machine, whichever workers render
which parts.
"""
from __future__ import annotations

from typing import Dict, Iterable, Optional, Tuple, Union

import numpy as np

from .build import build_hash, check_same_build
from .arguments import int_argument
from .render import Renderer
from .sample_ranges import Accumulation, SampleRange, merge, sample_ranges


def _render_part(scene, sample_range: SampleRange, techniques, options: Dict, client_build: str):
    check_same_build(client_build)
    accumulation, _ = render_range(scene, sample_range, techniques, options)
    return accumulation


def cluster_workers(client) -> int:
    """How many workers the client's cluster has now."""
    return len(client.scheduler_info().get("workers", {}))


def render_range(scene, sample_range: SampleRange, techniques, options: Dict) -> Tuple[Accumulation, Dict]:
    """Renders one range of a split render of `scene` (Renderer options `options`); (its buffers, the
    first technique's stats)."""
    renderer = Renderer(scene, techniques=techniques, **options)
    renderer.start_at(sample_range.first, sample_range.pass_index)
    renderer.render(sample_range.samples)
    return renderer.accumulation(), renderer.stats()


def render_distributed(scene, samples: int, client, techniques: Union[str, Iterable[str]] = ("rectangle",),
                       parts: Optional[int] = None, **options) -> Dict[str, np.ndarray]:
    """Render `scene` as sphrect.render does (the same options, the same {technique: float32 [H, W, 4]}), its
    samples split into `parts` ranges (default: the cluster's worker count, at most `samples`) rendered on the
    workers of the Dask `client`. A part whose worker dies is rendered again on another; a worker of another build
    refuses its part (sphrect.build.BuildMismatch)."""
    samples = int_argument("samples", samples, 1)
    if parts is None:
        parts = max(1, min(samples, cluster_workers(client)))
    ranges = sample_ranges(samples, int_argument("parts", parts, 1))
    techniques = [techniques] if isinstance(techniques, str) else list(techniques)
    scene_data = client.scatter(scene, broadcast=True, hash=False)  # a key of its own: released below
    futures = [client.submit(_render_part, scene_data, r, techniques, options, build_hash(), pure=False)
               for r in ranges]
    try:
        accumulations = client.gather(futures)
    finally:
        client.cancel(futures + [scene_data])
    return merge(accumulations).images()
