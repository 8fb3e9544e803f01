"""The reference image and its own error estimate.

How it is made: the reference is one render of S samples per pixel split into M sample ranges ("chunks", M = 8
by default), each rendered as a job of its own -- on as many workers as there are chunks at once -- and rendered as
its pass of that render (sample_ranges.py, the path sphrect.render_distributed takes), so the reference is
``sphrect.render(scene, S, parts=M)`` up to the float32 rounding of the chunks' images. Each pass draws its own
pattern points (the patterns are seeded per pass) and its own random numbers (seeded per sample index), so the
chunks are M independent renders; with the 'sobol' pattern, whose passes continue one sequence and so are not
independent, each chunk has a seed of its own instead. The default configuration is
`rectangle` with balance-heuristic MIS and the jittered `stratified` pattern, the lowest-variance
configuration measured on the paper's scene (the renderer's `sobol` pattern converged worse than
`independent` beyond ~100 samples per pixel there). Independent seeds make the chunks
independent unbiased estimates of the true image, so per pixel the sample variance across the chunks,
divided by M, estimates the variance of their mean -- the reference's own mean squared error:

    MSE_ref ~= mean over pixels and channels of  s^2 / M,   s^2 = sum_i (x_i - mean)^2 / (M - 1)

(with M = 2 this is the familiar (A - B)^2 / 4 of two half-sample renders). Its square root is the
reference RMSE reported next to every study error. Because the reference is independent of the runs, a
run's measured MSE is its true MSE plus MSE_ref on average, so the study's errors are trustworthy only while
RMSE_ref is well below them: the report prints the ratio for the smallest error it shows.

The chunks are ordinary jobs (kind "reference"), so they run on the pool in parallel, show progress, and a
study interrupted while making its reference resumes from the chunks already rendered.
"""
from __future__ import annotations

import hashlib
import math
import os
from dataclasses import asdict, dataclass
from typing import Dict, List

import numpy as np

from ..render import MIS_MODES, PATTERNS, TECHNIQUES
from ..sample_ranges import sample_ranges
from .jobs import MAX_LIGHT_SAMPLES, MAX_SAMPLES, SAMPLE_INDEX_LIMIT, SPHRECT, Job, SettingError, check_int, check_names
from .metrics import RELMSE_EPSILON, colour
from .runner import REFERENCE_KIND
from .store import ResultStore, atomic_write_json

REFERENCE_IMAGE = "reference"
REFERENCE_JSON = "reference.json"
SEED_BASE = 1_000_003  # far from the study's seeds, so no run shares random numbers with the reference


@dataclass
class ReferenceSettings:
    samples: int = 16384        # total samples per pixel over all chunks
    chunks: int = 8
    technique: str = "rectangle"
    mis: str = "balance"
    pattern: str = "stratified"
    light_samples: int = 1

    def __post_init__(self):
        """Checks every setting; a SettingError names the study's option ("reference_" + the field's name, but
        light_samples: the study's own)."""
        self.chunks = check_int("reference_chunks", self.chunks, 2, 2 ** 16)  # >= 2 to estimate its own error
        self.samples = check_int("reference_samples", self.samples, self.chunks, self.chunks * MAX_SAMPLES)
        self.light_samples = check_int("light_samples", self.light_samples, 1, MAX_LIGHT_SAMPLES)
        (self.technique,) = check_names("reference_technique", "technique", (self.technique,), TECHNIQUES)
        (self.mis,) = check_names("reference_mis", "MIS mode", (self.mis,), MIS_MODES)
        (self.pattern,) = check_names("reference_pattern", "sample pattern", (self.pattern,), PATTERNS)
        if self.samples * self.light_samples >= SAMPLE_INDEX_LIMIT:  # the chunks' sample indices run over the whole
            raise SettingError("reference_samples", f"{self.samples} samples x {self.light_samples} light samples "
                                                    f"is more than a render takes (< {SAMPLE_INDEX_LIMIT})")


SEQUENCE_PATTERN = "sobol"  # its passes continue one sequence: chunks need seeds of their own to be independent


def reference_jobs(settings: ReferenceSettings, threads: int = 1) -> List[Job]:
    """The chunks: the sample ranges of the reference's render (see the module docstring)."""
    own_seeds = settings.pattern == SEQUENCE_PATTERN
    return [Job(SPHRECT, settings.technique, settings.mis, settings.pattern, r.samples, settings.light_samples,
                SEED_BASE + (r.pass_index if own_seeds else 0), threads, REFERENCE_KIND,
                first_sample=r.first, pass_index=r.pass_index)
            for r in sample_ranges(settings.samples, settings.chunks)]


def estimate_error(chunks: np.ndarray) -> Dict[str, float]:
    """Own-error estimate of the mean of M independent images stacked as [M, H, W, C] (see module doc)."""
    m = chunks.shape[0]
    rgb = np.stack([colour(c) for c in chunks])
    mean = rgb.mean(axis=0)
    variance_of_mean = rgb.var(axis=0, ddof=1) / m
    return {"rmse": math.sqrt(float(variance_of_mean.mean())),
            "relmse": float(np.mean(variance_of_mean / (mean * mean + RELMSE_EPSILON))),
            "chunks": m}


def combine_reference(store: ResultStore, settings: ReferenceSettings, jobs: List[Job],
                      scene_fingerprint: str) -> Dict:
    """Average the chunk images into the reference image, estimate its error, save both; returns the
    reference's description (also written to reference.json), whose "id" identifies it in run records."""
    images, wall, rays = [], 0.0, 0
    for job in jobs:
        record = store.read_run(job.key)
        if record is None or record.get("fingerprint") != scene_fingerprint:
            raise RuntimeError(f"reference chunk {job.key} has not been rendered")
        image = store.load_image(record["image"])
        if image is None:
            raise RuntimeError(f"reference chunk image {record['image']} is missing")
        images.append(image)
        wall += record.get("wall_time") or 0.0
        rays += record.get("rays") or 0
    stack = np.stack(images).astype(np.float64)
    if all(np.array_equal(stack[0], s) for s in stack[1:]):
        raise RuntimeError("the reference chunks are identical: the renderer ignores the seed, so the "
                           "reference's error cannot be estimated")
    samples = np.array([job.samples for job in jobs], dtype=np.float64)
    reference = np.tensordot(samples / samples.sum(), stack, axes=1).astype(np.float32)  # the mean of all samples
    estimate = estimate_error(stack)
    digest = hashlib.sha256((scene_fingerprint + "".join(j.key for j in jobs)).encode()).hexdigest()[:16]
    info = {"id": digest, "image": REFERENCE_IMAGE, "settings": asdict(settings), "chunk_keys": [j.key for j in jobs],
            "render_time_total": wall, "rays": rays, "estimated_rmse": estimate["rmse"],
            "estimated_relmse": estimate["relmse"], "scene_fingerprint": scene_fingerprint,
            "finite": bool(np.all(np.isfinite(reference)))}
    if not info["finite"]:
        raise RuntimeError("the reference image has NaN or Inf pixels")
    store.save_image(REFERENCE_IMAGE, reference)
    atomic_write_json(os.path.join(store.root, REFERENCE_JSON), info)
    return info


REFERENCE_INFO_KEYS = ("id", "image", "chunk_keys", "scene_fingerprint", "estimated_rmse")


def load_reference_info(store: ResultStore) -> Dict | None:
    """reference.json; None when there is none or it is damaged (then set aside: the reference is recombined)."""
    return store.read_json(REFERENCE_JSON, required=REFERENCE_INFO_KEYS)
