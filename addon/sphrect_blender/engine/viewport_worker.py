"""The viewport's progressive renderer: one background thread per viewport that renders the current job
(a sphrect.Scene whose camera is the view, the techniques and the renderer options) first at reduced
resolution, then at full resolution in growing sample batches, and publishes each step's images.

A job whose scene differs from the last one's only in its camera (the view moved, a preview's or the full
resolution: the same `scene_version`) reuses the last renderer with the camera set (Renderer.set_camera): the
native scene, its BVH and light tree are not built again. A new job (the view or the scene changed) or stop()
cancels the renderer call in progress at its next tile (the native renderer releases the GIL while it renders and
checks its cancel flag between tiles), so a restart costs at most a tile. pause_all() holds every worker while an
F12 render runs, so that the viewport never takes CPU from it. Nothing here touches bpy: the thread only sees
sphrect objects."""
import dataclasses
import os
import threading
import time
import warnings
import weakref
from typing import List, NamedTuple, Optional, Tuple

from ..native import load_sphrect

# Reduced resolutions of the first images (Cycles' "start resolution"): the image side divided by these,
# one sample each, before the full resolution.
PREVIEW_DIVISORS = (4, 2)
# A full-resolution call aims at this many seconds: long enough that the per-call costs (copying the images,
# uploading them to the GPU) stay small, short enough that the image refreshes several times a second.
TARGET_CALL_SECONDS = 0.25
PAUSE_POLL_SECONDS = 0.1  # how often a paused worker looks whether it should stop instead
SLOW_BUILD_SECONDS = 0.1  # a renderer that took longer to make ready: no further preview
THREAD_NAME = "SPHRECT viewport"  # every viewport thread's name (tests look for it)
VIEWPORT_NICENESS = 10            # the worker's threads' nice value (Linux: per thread, inherited)

_workers = weakref.WeakSet()  # live workers, for pause_all / stop_all
_not_paused = threading.Event()
_not_paused.set()


class Job(NamedTuple):
    """What a viewport shows: `scene` (camera = the view at full resolution), rendered with `techniques`
    (one, or two for the split view) to `samples` per pixel, at the view's resolution divided by `pixel_size`
    (Blender's Viewport > Pixel Size: one rendered pixel per pixel_size^2 screen pixels).  Jobs with the same
    `scene_version` (not None) have the same scene but for the camera: the worker keeps their renderer."""
    scene: object
    techniques: Tuple[str, ...]
    options: dict
    samples: int
    pixel_size: int = 1
    scene_version: Optional[int] = None


class Frame(NamedTuple):
    """One published step: images (float32 [h, w, 4], row 0 = top) per technique, at `scale` of the job's
    resolution, after `samples` per pixel; `generation` names the job it belongs to."""
    generation: int
    images: Tuple
    samples: int
    total_samples: int
    scale: float
    seconds: float        # since the job started
    error: Optional[str] = None
    warnings: Tuple[str, ...] = ()
    preview: bool = False  # a reduced-resolution first image, before the job's own resolution


def scaled_scene(scene, divisor):
    """`scene` with its camera's resolution divided by `divisor` (at least a pixel a side, the same view)."""
    if divisor == 1:
        return scene
    cam = scene.camera
    small = dataclasses.replace(cam, width=max(1, -(-cam.width // divisor)), height=max(1, -(-cam.height // divisor)))
    return dataclasses.replace(scene, camera=small)


def next_batch(done, total, seconds_per_sample):
    """Samples of the next full-resolution call: about TARGET_CALL_SECONDS of work (one sample until a call
    has been timed), never past `total`."""
    n = 1 if seconds_per_sample is None else int(TARGET_CALL_SECONDS / max(seconds_per_sample, 1e-9))
    return max(1, min(n, total - done))


def _lower_priority():
    """Give this thread, and the renderer's threads it starts (they inherit it), a lower CPU priority than
    Blender's interface: drawing and navigating stay fluid while the viewport renders on every core."""
    try:
        os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), VIEWPORT_NICENESS)
    except (AttributeError, OSError):  # not Linux (a process-wide priority elsewhere): keep the default
        pass


class ProgressiveWorker:
    """Renders the latest job on its own thread; `latest` is the newest Frame (None before the first)."""

    def __init__(self, on_frame=None):
        self._on_frame = on_frame        # called on the worker thread after each frame (no bpy calls!)
        self._lock = threading.Condition()
        self._job: Optional[Job] = None
        self._generation = 0
        self._stopping = False
        self._renderer = None             # the one inside a render() call, for cancel()
        self._kept = None                 # (key, renderer): the last renderer made, for jobs of the same scene
        self.renderers_built = 0          # how many sphrect.Renderer this worker made (the tests read it)
        self.latest: Optional[Frame] = None
        self.first_scale: Optional[float] = None  # the scale of the current job's first frame
        self.busy = False                 # a job is not finished yet
        self._thread = threading.Thread(target=self._run, name=THREAD_NAME, daemon=True)
        _workers.add(self)
        self._thread.start()

    # ------------------------------------------------------------------ main-thread side
    def restart(self, job: Job):
        """Render `job` from scratch (the current one is cancelled at its next tile)."""
        with self._lock:
            self._job = job
            self._generation += 1
            self.busy = True
            self._cancel_locked()
            self._lock.notify_all()

    def stop(self, timeout=5.0):
        """End the thread (cancels the call in progress) and wait for it. True if it ended."""
        with self._lock:
            self._stopping = True
            self._cancel_locked()
            self._lock.notify_all()
        if self._thread is not threading.current_thread():
            self._thread.join(timeout)
        return not self._thread.is_alive()

    @property
    def alive(self):
        return self._thread.is_alive()

    def _cancel_locked(self):
        if self._renderer is not None:
            self._renderer.cancel()

    # ------------------------------------------------------------------ worker-thread side
    def _current(self, generation):
        return not self._stopping and generation == self._generation and _not_paused.is_set()

    def _run(self):
        _lower_priority()
        while True:
            with self._lock:
                while not self._stopping and (self._job is None or not self.busy):
                    self._lock.wait()
                if self._stopping:
                    return
                job, generation = self._job, self._generation
            if not self._wait_unpaused(generation):
                continue
            try:
                finished = self._render_job(job, generation)
            except Exception as e:  # shown in the viewport; the thread waits for the next job
                self._publish(Frame(generation, (), 0, job.samples, 1.0, 0.0, error=f"{type(e).__name__}: {e}"))
                finished = True
            with self._lock:
                if finished and generation == self._generation:
                    self.busy = False

    def _wait_unpaused(self, generation):
        """Wait while F12 pauses the viewports; False if the job changed or the worker stops meanwhile."""
        while not _not_paused.wait(PAUSE_POLL_SECONDS):
            if self._stopping or generation != self._generation:
                return False
        return not self._stopping and generation == self._generation

    def _make_renderer(self, sphrect, job, divisor, caught):
        """A renderer of the job's scene at 1/divisor of its resolution: the kept one with the camera set when the
        job's scene is the kept one's but for the camera, else a new one (which is kept)."""
        scene = scaled_scene(job.scene, divisor)
        key = (job.scene_version, job.techniques, tuple(sorted(job.options.items())))
        if job.scene_version is not None and self._kept is not None and self._kept[0] == key:
            try:
                self._kept[1].set_camera(scene.camera)
                return self._kept[1]
            except ValueError:  # a camera the renderer cannot take (e.g. the film's transparency): a new one
                pass
        self._kept = None  # let the old one's images go before the new one's are allocated
        with warnings.catch_warnings(record=True) as new:
            warnings.simplefilter("always")
            renderer = sphrect.Renderer(scene, techniques=list(job.techniques), **job.options)
        caught.extend(str(w.message) for w in new if str(w.message) not in caught)
        self.renderers_built += 1
        self._kept = (key, renderer)
        return renderer

    def _render_call(self, renderer, samples, generation):
        """One cancellable renderer call; False if the job changed, the worker stops or F12 pauses it."""
        def progress(done, total):
            if not self._current(generation):
                renderer.cancel()
        with self._lock:
            if not self._current(generation):
                return False
            self._renderer = renderer
        try:
            # The renderer clears its cancel flag when a call starts: the progress callback cancels a call
            # that a restart() raced with, after its first tile.
            return renderer.render(samples, progress=progress) and self._current(generation)
        finally:
            with self._lock:
                self._renderer = None

    def _render_job(self, job, generation):
        """Render `job` (previews, then full resolution); False if it was interrupted before the end."""
        sphrect = load_sphrect()
        start = time.perf_counter()
        caught: List[str] = []
        frame = lambda images, samples, scale, preview=False: Frame(
            generation, images, samples, job.samples, scale, time.perf_counter() - start, warnings=tuple(caught),
            preview=preview)
        full = job.scene.camera.width, job.scene.camera.height
        base = max(1, int(job.pixel_size))
        for preview_divisor in PREVIEW_DIVISORS:
            divisor = base * preview_divisor
            if min(full) // divisor < 8:   # too small to be worth it
                continue
            built = time.perf_counter()
            renderer = self._make_renderer(sphrect, job, divisor, caught)
            # A new renderer builds the native scene (its BVH): for big scenes one preview only.
            slow_build = time.perf_counter() - built > SLOW_BUILD_SECONDS
            if not self._render_call(renderer, 1, generation):
                return False
            self._publish(frame(tuple(renderer.image(t) for t in job.techniques), 1, 1.0 / divisor, True))
            if slow_build:
                break
        renderer = self._make_renderer(sphrect, job, base, caught)
        done, seconds_per_sample = 0, None
        while done < job.samples:
            n = next_batch(done, job.samples, seconds_per_sample)
            t0 = time.perf_counter()
            if not self._render_call(renderer, n, generation):
                if _not_paused.is_set() or not self._wait_unpaused(generation):
                    return False
                continue  # F12 is over: go on accumulating where the pause left off
            seconds_per_sample = (time.perf_counter() - t0) / n
            done = int(renderer.stats(0)["samples"])  # the completed passes (a cancelled one adds none)
            self._publish(frame(tuple(renderer.image(t) for t in job.techniques), done, 1.0 / base))
        return True

    def _publish(self, frame):
        with self._lock:
            if frame.generation != self._generation:
                return
            if self.latest is None or self.latest.generation != frame.generation:
                self.first_scale = frame.scale  # a preview's, unless the view is too small for one
            self.latest = frame
        if self._on_frame is not None:
            self._on_frame()


def pause_all():
    """Hold every viewport worker (an F12 render starts): their calls in progress are cancelled."""
    _not_paused.clear()
    for worker in list(_workers):
        with worker._lock:
            worker._cancel_locked()


def resume_all():
    """Let the viewport workers go on (the F12 render ended)."""
    _not_paused.set()


def stop_all():
    """Stop every viewport worker (the add-on is unregistered, or no viewport shows SPHRECT any more)."""
    for worker in list(_workers):
        worker.stop()


def live_workers():
    return [w for w in list(_workers) if w.alive]
