"""The study's job list, kept apart from whatever executes it.

A :class:`Job` is one independent render: an engine (our renderer or Cycles), its light-sampling settings
and a sample count (a "ladder" job) or a time budget (an "equal_time" job, whose image goes into the
report's grid). :func:`build_plan` expands a :class:`StudyConfig` into the ladder jobs; the equal-time jobs
need a time budget measured by the ladder, so :func:`equal_time_jobs` builds them afterwards.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import numbers
import re
from dataclasses import dataclass
from typing import Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple

from .. import _native
from ..render import (ELLIPSE_TECHNIQUES, LIGHT_SELECTIONS, MEDIUM_SAMPLING, MIS_MODES, PATTERNS, RENDER_DEFAULTS,
                      TECHNIQUES)

SPHRECT = "sphrect"
CYCLES = "cycles"
# The Renderer's own default, which runs recorded before light selection was a study axis were made with.
DEFAULT_LIGHT_SELECTION = RENDER_DEFAULTS["light_selection"]
# Likewise for the ellipse technique (how disk and ellipse lights are sampled): runs recorded before it was an axis.
DEFAULT_ELLIPSE_TECHNIQUE = RENDER_DEFAULTS["ellipse_technique"]
# Likewise for the medium's distance sampling (how camera rays through a volume pick their scattering point).
DEFAULT_MEDIUM_SAMPLING = RENDER_DEFAULTS["medium_sampling"]
# Light selection "ris": the candidates per light sample (a study's one value; other selections keep the default).
DEFAULT_RIS_CANDIDATES = RENDER_DEFAULTS["ris_candidates"]
RIS = "ris"


class CurveKey(NamedTuple):
    """What one curve of the study is made of: every setting of a run but its sample count."""
    technique: str
    mis: str
    pattern: str
    light_selection: str
    ellipse_technique: str = DEFAULT_ELLIPSE_TECHNIQUE
    medium_sampling: str = DEFAULT_MEDIUM_SAMPLING


# Cycles' curve in the terms of ours: it has its own sampling (its own light selection, disk and medium sampling).
CYCLES_CURVE = CurveKey("cycles", "power", "default", "default", "default", "default")


def curve_key(job: Mapping) -> CurveKey:
    """The curve of a job (a Job's or a stored record's dict; records made before the light selection, the
    ellipse technique or the medium sampling was recorded were rendered with the default)."""
    if job.get("engine") == CYCLES:
        return CYCLES_CURVE
    return CurveKey(job["technique"], job["mis"], job["pattern"],
                    job.get("light_selection", DEFAULT_LIGHT_SELECTION),
                    job.get("ellipse_technique", DEFAULT_ELLIPSE_TECHNIQUE),
                    job.get("medium_sampling", DEFAULT_MEDIUM_SAMPLING))


def selection_part(light_selection: str, show_selection: bool, separator: str = " / ") -> str:
    """The light selection as a part of a configuration's name; nothing unless `show_selection` (in a study of
    more than one)."""
    return f"{separator}selection={light_selection}" if show_selection else ""


def ellipse_part(ellipse_technique: str, show_ellipse: bool, separator: str = " / ") -> str:
    """The ellipse technique as a part of a configuration's name; nothing unless `show_ellipse` (in a study of
    more than one)."""
    return f"{separator}ellipse={ellipse_technique}" if show_ellipse else ""


def medium_part(medium_sampling: str, show_medium: bool, separator: str = " / ") -> str:
    """The medium sampling as a part of a configuration's name; nothing unless `show_medium` (in a study of more
    than one)."""
    return f"{separator}medium={medium_sampling}" if show_medium else ""


def curve_label(key: CurveKey, show_selection: bool = False, show_ellipse: bool = False,
                show_medium: bool = False) -> str:
    """The name of a curve, or Cycles'; the light selection is named when `show_selection`, the ellipse technique
    when `show_ellipse`, the medium sampling when `show_medium`."""
    if tuple(key) == CYCLES_CURVE:
        return "Cycles 3.4"
    technique, mis, pattern, light_selection, ellipse_technique, medium_sampling = key
    return (f"{technique} / mis={mis} / {pattern}" + selection_part(light_selection, show_selection)
            + ellipse_part(ellipse_technique, show_ellipse) + medium_part(medium_sampling, show_medium))


LADDER = "ladder"
EQUAL_TIME = "equal_time"


@dataclass(frozen=True)
class Job:
    engine: str                 # "sphrect" | "cycles"
    technique: str              # one of TECHNIQUES, or "cycles"
    mis: str                    # one of MIS_MODES ("power" for Cycles, which always combines by MIS)
    pattern: str                # one of PATTERNS ("default" for Cycles: its own pattern)
    samples: int                # camera samples per pixel (the maximum, for an equal-time job)
    light_samples: int = 1      # light samples per camera sample
    seed: int = 0
    threads: int = 1            # render threads inside the job (0 = all)
    kind: str = LADDER          # "ladder" | "equal_time"
    time_budget: Optional[float] = None  # seconds, for equal-time jobs
    light_selection: str = DEFAULT_LIGHT_SELECTION  # one of LIGHT_SELECTIONS (ours; Cycles' jobs keep the default)
    ellipse_technique: str = DEFAULT_ELLIPSE_TECHNIQUE  # one of ELLIPSE_TECHNIQUES (ours; Cycles' keep the default)
    medium_sampling: str = DEFAULT_MEDIUM_SAMPLING  # one of MEDIUM_SAMPLING (ours; Cycles' keep the default)
    ris_candidates: int = DEFAULT_RIS_CANDIDATES  # under light selection "ris" (the others keep the default)
    # A sample range of a longer render (the reference's chunks, sample_ranges.py): its first sample and its pass.
    first_sample: Optional[int] = None
    pass_index: Optional[int] = None

    @property
    def key(self) -> str:
        """A stable, file-name-safe identifier (the result file's name). The light selection, the ellipse
        technique, the medium sampling and the RIS candidates are part of it only when they are not the default, so
        that runs stored before they were settings keep their keys."""
        selection = [] if self.light_selection == DEFAULT_LIGHT_SELECTION else [f"sel_{self.light_selection}"]
        ellipse = [] if self.ellipse_technique == DEFAULT_ELLIPSE_TECHNIQUE else [f"ell_{self.ellipse_technique}"]
        medium = [] if self.medium_sampling == DEFAULT_MEDIUM_SAMPLING else [f"med_{self.medium_sampling}"]
        candidates = [] if self.ris_candidates == DEFAULT_RIS_CANDIDATES else [f"ris{self.ris_candidates}"]
        parts = [self.kind, self.engine, self.technique, self.mis, self.pattern, *selection, *ellipse, *medium,
                 *candidates, f"n{self.samples:06d}", f"l{self.light_samples}", f"s{self.seed}"]
        if self.time_budget is not None:
            parts.append(f"t{self.time_budget:.6g}")
        if self.first_sample is not None:
            parts.append(f"f{self.first_sample}p{self.pass_index or 0}")
        return re.sub(r"[^A-Za-z0-9_.-]", "_", "-".join(parts))

    @property
    def curve(self) -> CurveKey:
        return curve_key(self.to_dict())

    @property
    def label(self) -> str:
        """The curve this job belongs to (everything but the sample count); the light selection, the ellipse
        technique and the medium sampling are named when they are not the default (a job does not know how many
        its study has)."""
        return curve_label(self.curve, show_selection=self.light_selection != DEFAULT_LIGHT_SELECTION,
                           show_ellipse=self.ellipse_technique != DEFAULT_ELLIPSE_TECHNIQUE,
                           show_medium=self.medium_sampling != DEFAULT_MEDIUM_SAMPLING)

    def to_dict(self) -> Dict:
        return dataclasses.asdict(self)

    @staticmethod
    def from_dict(d: Dict) -> "Job":
        names = {f.name for f in dataclasses.fields(Job)}
        return Job(**{k: v for k, v in d.items() if k in names})


# The renderer's limits, checked here so that a study refuses them before it renders anything.
MAX_SEED = 2 ** 64 - 1                                    # render.Renderer's seed is an unsigned 64-bit integer
MAX_SAMPLES = _native.MAX_SAMPLES_PER_CALL                # one job is one render() call
MAX_LIGHT_SAMPLES = _native.MAX_LIGHT_SAMPLES
MAX_RIS_CANDIDATES = _native.MAX_RIS_CANDIDATES
MAX_THREADS = getattr(_native, "MAX_THREADS", 2 ** 31 - 1)  # render threads of one Renderer
SAMPLE_INDEX_LIMIT = _native.SAMPLE_INDEX_LIMIT  # camera samples x light samples of one render


def sample_ladder(max_samples: int, min_samples: int = 1) -> List[int]:
    """Powers of two from min_samples up to max_samples: 1, 2, 4, ... (SettingError naming the bad one)."""
    check_int("max_samples", max_samples, 1, MAX_SAMPLES)
    check_int("min_samples", min_samples, 1, max_samples)
    ladder, n = [], 1
    while n <= max_samples:
        if n >= min_samples:
            ladder.append(n)
        n *= 2
    return ladder


class SettingError(ValueError):
    """An invalid StudyConfig setting; `setting` is the field's name (the command line names its option)."""

    def __init__(self, setting: str, message: str):
        super().__init__(message)
        self.setting = setting


def check_int(setting: str, value, lo: int, hi: int) -> int:
    """`value` as an int in lo..hi, else SettingError naming `setting`."""
    if not isinstance(value, numbers.Integral) or isinstance(value, bool) or not lo <= value <= hi:
        raise SettingError(setting, f"must be an integer in {lo}..{hi}, got {value!r}")
    return int(value)


def check_positive(setting: str, value, optional: bool = False) -> Optional[float]:
    """`value` as a positive finite float (or None when `optional`), else SettingError naming `setting`."""
    if value is None and optional:
        return None
    if not isinstance(value, numbers.Real) or isinstance(value, bool) or not (value > 0 and math.isfinite(value)):
        raise SettingError(setting, f"must be a positive number, got {value!r}")
    return float(value)


def check_names(setting: str, kind: str, names: Sequence[str], allowed: Sequence[str]) -> Tuple[str, ...]:
    """The names (repeats dropped, order kept), each one of `allowed`, at least one; else SettingError."""
    if isinstance(names, str):
        names = (names,)
    names = tuple(dict.fromkeys(names))
    if not names:
        raise SettingError(setting, f"no {kind} chosen")
    for n in names:
        if n not in allowed:
            raise SettingError(setting, f"unknown {kind} {n!r}; choose from {', '.join(allowed)}")
    return names


@dataclass
class StudyConfig:
    """Everything that defines a study (saved as config.json in its output directory)."""
    techniques: Tuple[str, ...] = TECHNIQUES
    mis: Tuple[str, ...] = MIS_MODES
    patterns: Tuple[str, ...] = ("independent", "stratified", "sobol")
    light_selections: Tuple[str, ...] = (DEFAULT_LIGHT_SELECTION,)
    ellipse_techniques: Tuple[str, ...] = (DEFAULT_ELLIPSE_TECHNIQUE,)
    medium_samplings: Tuple[str, ...] = (DEFAULT_MEDIUM_SAMPLING,)
    ladder: Tuple[int, ...] = tuple(sample_ladder(256))
    light_samples: int = 1
    ris_candidates: int = DEFAULT_RIS_CANDIDATES  # for light selection "ris"
    seed: int = 0
    threads: int = 1                    # per job; see executors.py for why 1 is the default
    cycles: bool = False                # add Cycles as a peer (needs Blender and the .blend)
    grid_mis: Tuple[str, ...] = ("none", "balance")
    grid_pattern: str = "stratified"
    equal_time: Optional[float] = None  # seconds; None = measured from the ladder (see equal_time_budget)

    def __post_init__(self):
        self.techniques = check_names("techniques", "technique", self.techniques, TECHNIQUES)
        self.mis = check_names("mis", "MIS mode", self.mis, MIS_MODES)
        self.patterns = check_names("patterns", "sample pattern", self.patterns, PATTERNS)
        self.light_selections = check_names("light_selections", "light selection", self.light_selections,
                                             LIGHT_SELECTIONS)
        self.ellipse_techniques = check_names("ellipse_techniques", "ellipse technique", self.ellipse_techniques,
                                               ELLIPSE_TECHNIQUES)
        self.medium_samplings = check_names("medium_samplings", "medium sampling", self.medium_samplings,
                                            MEDIUM_SAMPLING)
        self.grid_mis = check_names("grid_mis", "MIS mode", self.grid_mis, MIS_MODES)
        # The grid's sample counts come from the ladder's costs: only MIS modes the ladder measures (a study of
        # --mis power alone, the add-on's default, would otherwise have no grid and no equal-time budget).
        self.grid_mis = tuple(m for m in self.grid_mis if m in self.mis) or (self.mis[-1],)
        check_names("grid_pattern", "sample pattern", (self.grid_pattern,), PATTERNS)
        if not self.ladder:
            raise SettingError("max_samples", "the sample ladder is empty")
        self.ladder = tuple(sorted(set(check_int("max_samples", n, 1, MAX_SAMPLES) for n in self.ladder)))
        self.light_samples = check_int("light_samples", self.light_samples, 1, MAX_LIGHT_SAMPLES)
        if self.ladder[-1] * self.light_samples >= SAMPLE_INDEX_LIMIT:  # the ladder's top job is the largest
            raise SettingError("max_samples", f"{self.ladder[-1]} samples x {self.light_samples} light samples "
                                              f"is more than a render takes (< {SAMPLE_INDEX_LIMIT})")
        self.ris_candidates = check_int("ris_candidates", self.ris_candidates, 1, MAX_RIS_CANDIDATES)
        self.seed = check_int("seed", self.seed, 0, MAX_SEED)
        self.threads = check_int("threads", self.threads, 0, MAX_THREADS)  # 0 = all cores
        self.equal_time = check_positive("equal_time", self.equal_time, optional=True)

    def candidates_of(self, light_selection: str) -> int:
        """The RIS candidates of a job under `light_selection`: the study's under "ris", else the default (which
        keeps the other selections' job keys as they were)."""
        return self.ris_candidates if light_selection == RIS else DEFAULT_RIS_CANDIDATES

    @property
    def shows_selection(self) -> bool:
        """Whether the report names the light selection in its labels: when the study compares several."""
        return len(self.light_selections) > 1

    @property
    def shows_ellipse(self) -> bool:
        """Whether the report names the ellipse technique in its labels: when the study compares several."""
        return len(self.ellipse_techniques) > 1

    @property
    def shows_medium(self) -> bool:
        """Whether the report names the medium sampling in its labels: when the study compares several."""
        return len(self.medium_samplings) > 1

    @property
    def findings_medium_sampling(self) -> str:
        """The medium sampling the light-sampling findings (ordering, slopes, technique, light-selection and
        ellipse comparisons) are read at: the renderer's default when the study has it, else the first. The
        medium samplings are compared with each other by report.equal_error.medium_comparisons."""
        return DEFAULT_MEDIUM_SAMPLING if DEFAULT_MEDIUM_SAMPLING in self.medium_samplings else \
            self.medium_samplings[0]

    @property
    def variants(self) -> List[Tuple[str, str, str]]:
        """Every (light selection, ellipse technique, medium sampling) of the study: the settings besides
        technique, MIS mode and pattern that one curve of each has."""
        return [(s, e, v) for s in self.light_selections for e in self.ellipse_techniques
                for v in self.medium_samplings]

    def to_dict(self) -> Dict:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in dataclasses.asdict(self).items()}

    @staticmethod
    def from_dict(d: Dict) -> "StudyConfig":
        names = {f.name for f in dataclasses.fields(StudyConfig)}
        return StudyConfig(**{k: (tuple(v) if isinstance(v, list) else v) for k, v in d.items() if k in names})


def fingerprint(**identity) -> str:
    """A short hash of what a run's numbers depend on besides its job (scene, reference, resolution)."""
    text = json.dumps(identity, sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def build_plan(config: StudyConfig) -> List[Job]:
    """The ladder jobs: every technique x MIS x pattern x light selection x ellipse technique x medium sampling x
    sample count, then Cycles at every count. Ordered cheapest first so that an interrupted study has measured as
    many curves as possible."""
    jobs = [Job(SPHRECT, t, m, p, n, config.light_samples, config.seed, config.threads, light_selection=s,
                ellipse_technique=e, medium_sampling=v, ris_candidates=config.candidates_of(s))
            for n in config.ladder for t in config.techniques for m in config.mis for p in config.patterns
            for s, e, v in config.variants]
    if config.cycles:
        jobs += [Job(CYCLES, *CYCLES_CURVE[:3], n, 1, config.seed, config.threads) for n in config.ladder]
    jobs.sort(key=lambda j: (j.samples, j.engine != SPHRECT))
    return jobs


def stratifiable_count(n: int) -> int:
    """The largest count <= n that the stratified pattern lays out as a near-square grid (k x k or k x (k+1)):
    a prime count would make it a 1 x n grid, stratified in one dimension only, which would misrepresent the
    pattern in the equal-time comparison. Costs at most ~1/sqrt(n) of the budget."""
    k = max(1, int(n ** 0.5))
    while (k + 1) * (k + 1) <= n:
        k += 1
    return k * (k + 1) if k * (k + 1) <= n else k * k


CostKey = Tuple[str, str, str, str, str, str]  # (engine, technique, mis, light selection, ellipse, medium sampling)


def cost_key(job: Mapping) -> CostKey:
    """What a configuration's cost per sample is measured for (its patterns pooled): see equal_time_jobs."""
    key = curve_key(job)
    return job["engine"], key.technique, key.mis, key.light_selection, key.ellipse_technique, key.medium_sampling


def equal_time_jobs(config: StudyConfig, budget: float, seconds_per_sample: Dict[CostKey, float]) -> List[Job]:
    """One render per technique (x grid MIS mode x light selection x ellipse technique x medium sampling), and
    Cycles, each given the
    sample count that the ladder predicts to cost `budget` seconds: samples = budget / (seconds per sample of that
    configuration), keyed by cost_key. Fixed sample counts (rather than a wall-clock budget) keep the comparison
    independent of other load on the machine and let stratified patterns know their count."""
    if not budget > 0:
        raise ValueError(f"the equal-time budget must be positive, got {budget}")
    budget = float(f"{budget:.4g}")  # a stable key

    def samples(engine, technique, mis, light_selection, ellipse_technique, medium_sampling):
        cost = seconds_per_sample.get((engine, technique, mis, light_selection, ellipse_technique, medium_sampling))
        if not (cost and cost > 0 and math.isfinite(cost)):
            return None
        n = min(max(1, int(round(budget / cost))), MAX_SAMPLES)  # a render() call takes at most MAX_SAMPLES
        return stratifiable_count(n) if engine == SPHRECT and config.grid_pattern == "stratified" else n

    jobs = []
    for m in config.grid_mis:
        for s, e, v in config.variants:
            for t in config.techniques:
                n = samples(SPHRECT, t, m, s, e, v)
                if n:
                    jobs.append(Job(SPHRECT, t, m, config.grid_pattern, n, config.light_samples, config.seed,
                                    config.threads, EQUAL_TIME, budget, light_selection=s, ellipse_technique=e,
                                    medium_sampling=v, ris_candidates=config.candidates_of(s)))
    n = samples(CYCLES, *CYCLES_CURVE[:2], *CYCLES_CURVE[3:])
    if config.cycles and n:
        jobs.append(Job(CYCLES, *CYCLES_CURVE[:3], n, 1, config.seed, config.threads, EQUAL_TIME, budget))
    return jobs
