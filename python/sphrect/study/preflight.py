"""Checks of a study's settings that need more than one setting or the machine (the resolution against memory,
the worker count), and of its scene (read and built once), made before anything is rendered so that a bad setting
or scene fails in seconds, naming its option, rather than after the reference or the ladder (single settings are
checked by StudyConfig and ReferenceSettings themselves)."""
from __future__ import annotations

import os
from typing import List, Optional

from .. import _native
from .jobs import SettingError, check_int

# The study's share of the machine's physical memory: it is not alone on the machine.
MEMORY_FRACTION = 0.5
# Local workers beyond this many per core only slow each other down (and each holds the scene and its images).
MAX_WORKERS_PER_CORE = 4
RGBA = 4


def physical_memory() -> Optional[int]:
    """Bytes of physical memory (None where the system does not say)."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def render_bytes(width: int, height: int) -> int:
    """Bytes the renderer's images take for one job (one technique): the native estimate where the module has
    it, else its accumulators as float64 RGBA."""
    estimate = getattr(_native, "render_memory_bytes", None)
    if estimate is not None:
        return int(estimate(1, width, height))
    return width * height * RGBA * 8


def study_bytes(width: int, height: int, workers: int, chunks: int) -> int:
    """The study's peak memory, estimated: each worker's render plus its float32 image and the reference's,
    and the main process stacking the reference chunks as float64 (reference.combine_reference)."""
    image32 = width * height * RGBA * 4
    return workers * (render_bytes(width, height) + 2 * image32) + (chunks + 1) * 2 * image32


def check_resolution(width: int, height: int, workers: int, chunks: int, setting: str = "resolution",
                     memory: Optional[int] = None) -> None:
    """SettingError naming `setting` when a side is out of the renderer's range or the study would need more than
    MEMORY_FRACTION of the physical memory (`memory`, default: this machine's)."""
    check_int(setting, width, 1, _native.MAX_IMAGE_SIDE)
    check_int(setting, height, 1, _native.MAX_IMAGE_SIDE)
    memory = physical_memory() if memory is None else memory
    need = study_bytes(width, height, workers, chunks)
    if memory and need > MEMORY_FRACTION * memory:
        raise SettingError(setting, f"{width}x{height} with {workers} workers and {chunks} reference chunks needs "
                                    f"about {need / 2 ** 30:.3g} GiB, more than {MEMORY_FRACTION:g} of this "
                                    f"machine's {memory / 2 ** 30:.3g} GiB: lower the resolution or --workers")


def check_workers(workers: Optional[int]) -> Optional[int]:
    """The local worker count (None: one per core), else SettingError naming workers."""
    if workers is None:
        return None
    return check_int("workers", workers, 1, MAX_WORKERS_PER_CORE * (os.cpu_count() or 1))


def one_line(text) -> str:
    """`text` on one line, its lines joined by '; ' (the command line prints an error as one line)."""
    return "; ".join(line.strip() for line in str(text).splitlines() if line.strip())


def load_study_scene_file(scene_path: str):
    """The study's scene file (load_scene), else SettingError naming the scene when it cannot be read."""
    from ..scene import load_scene
    try:
        return load_scene(scene_path)
    except ValueError as e:  # its message names the file
        raise SettingError("scene", one_line(e)) from None


def check_scene(scene, input_path: str) -> List[str]:
    """Build `scene` once, as every job's renderer will (render.build_native_scene): SettingError naming the scene
    when it cannot be built (a NaN radiance, an index out of range...), which would fail every job; else the
    warnings of building it (a missing image, a light left out), which every run will give too."""
    from ..render import build_native_scene
    try:
        _, warnings = build_native_scene(scene)
    except (ValueError, TypeError) as e:
        raise SettingError("scene", f"{input_path}: cannot be rendered: {one_line(e)}") from None
    return list(warnings)
