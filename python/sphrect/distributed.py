"""Long renders split by samples over a Dask cluster (the `distributed` package, imported only when used).

    from distributed import Client
    images = sphrect.render_distributed(scene, 65536, client=Client("tcp://host:8786"), techniques=["rectangle"])

The samples are split into `parts` contiguous ranges (default: one per worker), each rendered on a worker as its
pass of the whole render; their accumulation buffers are merged in range order (sample_ranges.py), so the image is
bit-identical to ``sphrect.render(scene, samples, parts=parts, ...)`` on one machine, whichever workers render
which parts.

The scene is sent once to every worker (scattered); a part whose worker dies is rendered again by the scheduler on
another that holds the scene.  When every worker holding the scene died (a cluster of one worker, restarted by its
nanny), the scene went with them: it is sent again and the parts not rendered yet are submitted again, up to
SCENE_SENDS times in all, before WorkersLost says so.  The workers' warnings (a missing image, samples left out as
not finite) are warned again here, as sphrect.render warns them.  A relative texture path is made absolute first,
so that workers started in another directory read the file the client names.
"""
from __future__ import annotations

import dataclasses
import os
import warnings
from concurrent.futures import CancelledError
from typing import Dict, Iterable, List, Optional, Tuple, Union

import numpy as np

from .build import build_hash, check_same_build
from .arguments import int_argument
from .render import Renderer
from .sample_ranges import Accumulation, SampleRange, merge, sample_ranges
from .scene import Scene

# How many times in all the scene is sent to the workers while every worker holding it dies before the parts are done.
SCENE_SENDS = 3
SEND_TIMEOUT = 120.0  # seconds to wait for a worker to send the scene to


class WorkersLost(RuntimeError):
    """Every worker holding the scene died, SCENE_SENDS times over, before the render was done."""


def _render_part(scene, sample_range: SampleRange, techniques, options: Dict, client_build: str
                 ) -> Tuple[Accumulation, List[str]]:
    """On a worker: (the part's buffers, the warnings its render gave), which the client warns again."""
    check_same_build(client_build)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        accumulation, _ = render_range(scene, sample_range, techniques, options)
    return accumulation, [str(w.message) for w in caught]


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


def _with_absolute_texture_paths(scene):
    """`scene` (a copy, when it changes) whose relative texture paths, which a worker would read from its own
    current directory, are absolute: the files this process names."""
    if not isinstance(scene, Scene) or not any(t.path and not os.path.isabs(t.path) for t in scene.textures):
        return scene  # (a wrong type is the renderer's to refuse)
    return dataclasses.replace(scene, textures=[
        dataclasses.replace(t, path=os.path.abspath(t.path)) if t.path and not os.path.isabs(t.path) else t
        for t in scene.textures])


def _render_parts(client, scene, ranges: List[SampleRange], done: Dict[int, Tuple[Accumulation, List[str]]],
                  techniques, options: Dict) -> None:
    """Send `scene` to the workers and render the parts not in `done` ({part: _render_part's result}) there, adding
    each one rendered to `done`. A part whose scene was lost, with every worker holding it, is left for the next
    send; a part's own error (a BuildMismatch, a KilledWorker after the scheduler's allowed failures) is raised."""
    from distributed import as_completed
    try:
        scene_data = client.scatter(scene, broadcast=True, hash=False, timeout=SEND_TIMEOUT)  # released below
    except TimeoutError:  # (distributed's is the builtin)
        raise WorkersLost(f"no worker on the cluster to send the scene to for {SEND_TIMEOUT:g} s: start workers, "
                          f"then render again") from None
    futures = {client.submit(_render_part, scene_data, ranges[i], techniques, options, build_hash(), pure=False): i
               for i in range(len(ranges)) if i not in done}
    try:
        for future in as_completed(futures):
            try:
                done[futures[future]] = future.result()
            except CancelledError:  # the scene was lost with the workers holding it: sent again
                continue
    finally:
        client.cancel(list(futures) + [scene_data])


def render_distributed(scene, samples: int, client, techniques: Union[str, Iterable[str]] = ("rectangle",),
                       parts: Optional[int] = None, **options) -> Dict[str, np.ndarray]:
    """Render `scene` as sphrect.render does (the same options, the same {technique: float32 [H, W, 4]}, the same
    warnings), its samples split into `parts` ranges (default: the cluster's worker count, at most `samples`)
    rendered on the workers of the Dask `client`. A part whose worker dies is rendered again on another, the scene
    sent again when every worker holding it died (WorkersLost when that happens SCENE_SENDS times); a worker of
    another build refuses its part (sphrect.build.BuildMismatch)."""
    samples = int_argument("samples", samples, 1)
    if parts is None:
        parts = max(1, min(samples, cluster_workers(client)))
    ranges = sample_ranges(samples, int_argument("parts", parts, 1))
    techniques = [techniques] if isinstance(techniques, str) else list(techniques)
    scene = _with_absolute_texture_paths(scene)
    done: Dict[int, Tuple[Accumulation, List[str]]] = {}
    for _ in range(SCENE_SENDS):
        _render_parts(client, scene, ranges, done, techniques, options)
        if len(done) == len(ranges):
            parts_done = [done[i] for i in range(len(ranges))]
            for message in dict.fromkeys(m for _, messages in parts_done for m in messages):
                warnings.warn(message, RuntimeWarning, stacklevel=2)  # (a missing image, samples not finite)
            return merge([accumulation for accumulation, _ in parts_done]).images()
    sends = f"{SCENE_SENDS} time{'s' if SCENE_SENDS > 1 else ''}"
    raise WorkersLost(f"the scene was sent to the workers {sends}, and each time every worker holding it died before "
                      f"{len(ranges) - len(done)} of the {len(ranges)} parts were rendered: see the workers' logs (out "
                      f"of memory?), then render again")
