"""A world node tree Cycles 3.4 evaluates, baked into an equirectangular image (sphrect.Environment's convention).

    pixels = bake_world(bl_world)   # float32 [H, W, 3], rows bottom to top (Texture.pixels), linear radiance
    with in_background(bakes):      # a Rendered viewport's export: an uncached world raises BakeNotReady at once,
        bake_world(bl_world)         # its bake runs on (BackgroundBakes), a stand-in is shown meanwhile

Cycles itself renders the world: a Blender child process (`blender -b --factory-startup`) appends the world from a
.blend this process writes, renders it alone (no objects, no lights) through an equirectangular panoramic camera
at the origin, and saves the radiance; so a Sky Texture (Nishita, Preetham, Hosek-Wilkie), gradients, noise,
mixes and adds of backgrounds are what Cycles shows, whatever the node.  A child process rather than this one's
render operator: the add-on's own render (F12) cannot start a Cycles render inside it, and the user's file gains no
scene, camera or image.  The result is cached on disk by the tree's content (world_signature).  A render waits for
the child; the Rendered viewport does not (in_background, BackgroundBakes: its timer polls the child).  No child
outlives this Blender: a viewport kills its own when it ends or a newer bake supersedes it, an exit kills any left
(atexit), and the child dies with its parent (Linux's parent-death signal) if this Blender crashes.

This file runs in the child too (`--python world_bake.py -- <json>`): it imports nothing from the add-on.
"""
import atexit
import contextlib
import hashlib
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import threading

import numpy as np

# Measured (docs/addon.md, "World"; experiments/measure_world_bake.py): Blender's default Nishita sky at 1024x512
# bakes in 4-6 s the first time on 2 busy cores (Blender's start and the sky's precomputation included; 512x256
# ~3.5 s, 2048x1024 ~14 s), then loads from the cache in a few ms.  0.35 degree pixels: its sun disc (0.545
# degrees) spans about two of them.
BAKE_WIDTH, BAKE_HEIGHT = 1024, 512
# Samples per pixel.  A sky is smooth over nearly every pixel, where 8 samples leave its light within ~0.01%;
# but the sun disc (~2 pixels wide; ~85% of the light on the ground under Blender's default sky) varies within its
# pixels, and 8 or 16 samples leave its power 1-10% off.  So the pixels around a peak (brighter than PEAK_RATIO x
# the image's mean, and PEAK_MARGIN pixels about them) are rendered again with PEAK_SAMPLES (a region render of
# a few pixels): the disc's power then within ~0.1% of a 16384-sample render's.  Cycles' adaptive sampling gets
# there in three times the time (its rounds go over the whole image while a few pixels go on).
BAKE_SAMPLES = 8
PEAK_SAMPLES = 4096
PEAK_RATIO = 20.0
PEAK_MARGIN = 2
PEAK_MAX_AREA = 0.01  # peaks covering more of the image than this are none: the image is left as rendered
# Cycles' panoramic camera looks along the Blender camera's view direction rotated so that pointing it at +X shows
# the environment texture's middle (blender/camera.cpp); Blender's camera looks down local -Z with +Y up, so this
# rotation points it at +X with +Z up: the bake's pixel (u, v) then sees sphrect.Environment's direction at (u, v)
# with to_world = identity (test_world_bake.py pins it).
CAMERA_ROTATION = (math.pi / 2, 0.0, -math.pi / 2)
CACHE_DIR = os.path.join(tempfile.gettempdir(), "sphrect_world_bake")
CACHE_ENTRIES = 32   # the newest kept (~6 MB each at the default size)
CHILD_TIMEOUT = 600  # seconds
# Bumped whenever what a bake holds changes, so that no older cache entry is used.
_BAKE_VERSION = 1


class BakeError(RuntimeError):
    pass


class BakeNotReady(Exception):
    """Raised by bake_world within in_background() when the world's bake is not at hand: it runs in the background
    (`error` None) or it failed (`error` says why; not tried again until the world changes).  `stand_in`: the pixels
    of the world's last bake this viewport showed, or None."""

    def __init__(self, stand_in, error=None):
        super().__init__(error or "the world is being baked")
        self.stand_in, self.error = stand_in, error


# ------------------------------------------------------------------------------------------ the tree's signature
# Node properties that say where a node is drawn, not what it computes.
_LAYOUT = {"rna_type", "location", "width", "width_hidden", "height", "dimensions", "label", "parent",
           "use_custom_color", "color", "select", "show_options", "show_preview", "hide", "show_texture",
           "internal_links", "inputs", "outputs", "bl_description", "bl_icon", "bl_width_default", "bl_width_min",
           "bl_width_max", "bl_height_default", "bl_height_min", "bl_height_max", "is_active_output"}


def _image_identity(image):
    """What decides an image's pixels: its file (path, size, time), its packed bytes, or its edited pixels."""
    import bpy
    image = getattr(image, "original", image)  # (an evaluated copy does not know the user's unsaved edits)
    parts = [image.source, image.filepath, image.colorspace_settings.name, image.alpha_mode,
             tuple(image.size), image.use_view_as_render, image.generated_type, tuple(image.generated_color),
             image.generated_width, image.generated_height, image.use_generated_float]
    if image.packed_file is not None:
        parts.append(hashlib.sha256(bytes(image.packed_file.data)).hexdigest())
    else:
        path = bpy.path.abspath(image.filepath, library=image.library)
        try:
            stat = os.stat(path)
            parts += [os.path.realpath(path), stat.st_size, stat.st_mtime_ns]
        except OSError:
            parts.append("missing")
    if image.is_dirty and image.has_data:  # painted or changed in Blender, not yet saved
        pixels = np.empty(len(image.pixels), dtype=np.float32)
        image.pixels.foreach_get(pixels)
        parts.append(hashlib.sha256(pixels.tobytes()).hexdigest())
    return parts


def _rna(value, trees, depth=0):
    """A plain, reproducible description of an RNA value (nested structs followed, IDs by their identity)."""
    import bpy
    if isinstance(value, bpy.types.ID):
        if isinstance(value, bpy.types.Image):
            return ["image", value.name_full] + _image_identity(value)
        if isinstance(value, bpy.types.NodeTree):
            return ["tree", _tree(value, trees)]
        if isinstance(value, bpy.types.Object):  # a Texture Coordinate node's object: where it is
            return ["object", value.name_full, [list(r) for r in value.matrix_world]]
        return [type(value).__name__, value.name_full]
    if isinstance(value, bpy.types.bpy_struct):
        if depth > 4:
            return "deep"
        return [[p.identifier, _rna(getattr(value, p.identifier), trees, depth + 1)]
                for p in value.bl_rna.properties if p.identifier != "rna_type" and p.type != "COLLECTION"]
    if isinstance(value, str) or value is None or isinstance(value, (bool, int, float)):
        return value
    try:
        return [_rna(v, trees, depth) for v in value]
    except TypeError:
        return repr(value)


def _tree(tree, trees):
    """A node tree's content: every node's type, properties and sockets' own values, and every link; a group's tree
    once (by name), however often it is used."""
    key = tree.name_full
    if key in trees:
        return key
    trees[key] = None  # (a group used inside itself stops here)
    nodes = []
    for node in sorted(tree.nodes, key=lambda n: n.name):
        props = [[p.identifier, _rna(getattr(node, p.identifier), trees)] for p in node.bl_rna.properties
                 if p.identifier not in _LAYOUT and p.type != "COLLECTION"]
        if node.bl_idname == "ShaderNodeOutputWorld":
            props.append(["is_active_output", node.is_active_output])
        # (RGB and Value nodes keep their value in their output)
        sockets = [[s.is_output, s.identifier, s.enabled, _rna(getattr(s, "default_value", None), trees)]
                   for s in list(node.inputs) + list(node.outputs)]
        nodes.append([node.bl_idname, node.name, props, sockets])
    links = sorted([l.from_node.name, l.from_socket.identifier, l.to_node.name, l.to_socket.identifier,
                    l.is_valid, l.is_muted] for l in tree.links)
    trees[key] = [nodes, links]
    return key


def world_signature(world, width, height, samples, camera_rays=True):
    """A hash of everything the bake of `world` depends on: its node tree (and the groups, images and objects it
    reads), the resolution and samples, the rays it is baked for, Blender's version and the bake's own."""
    import bpy
    trees = {}
    root = _tree(world.node_tree, trees)
    content = [_BAKE_VERSION, bpy.app.version_string, width, height, samples, PEAK_SAMPLES, PEAK_RATIO, PEAK_MARGIN,
               PEAK_MAX_AREA, root, sorted(trees.items())] + ([] if camera_rays else ["lighting"])
    return hashlib.sha256(json.dumps(content, default=repr).encode()).hexdigest()


def row_solid_angles(height, width):
    """The solid angle of one pixel of each row (row 0 the bottom) of a width x height equirectangular image."""
    z = np.cos(np.pi * (1.0 - np.arange(height + 1) / height))  # d.z at the rows' edges, bottom (-1) first
    return (2.0 * np.pi / width) * np.diff(z)


def sphere_mean(pixels):
    """The mean radiance over the sphere of directions of an equirectangular image (rows bottom to top)."""
    height, width = pixels.shape[:2]
    weights = row_solid_angles(height, width)
    return (pixels * weights[:, None, None]).sum(axis=(0, 1)) / (4.0 * np.pi)


# ------------------------------------------------------------------------------------------ the bake
_memory = {}  # signature -> pixels: the last bakes of this session (the viewport re-exports often)
_thread = threading.local()  # .bakes: the BackgroundBakes of an export within in_background()
_DEFAULT = object()  # bake_world's cache folder when none is given: CACHE_DIR as it is then (tests set it)


def bake_world(world, width=None, height=None, samples=None, cache_dir=_DEFAULT, camera_rays=True):
    """float32 [height, width, 3], rows bottom to top: the radiance Cycles 3.4 gives camera rays that escape into
    `world` (a bpy World with nodes; evaluated or original), in direction d at pixel (u, v) as sphrect.Environment
    maps it with to_world = identity, Strength included; camera_rays False: the light it gives the scene instead,
    its Light Path nodes' Is Camera Ray read as 0 (what Cycles' light samples and BSDF rays see).  Each pixel is the
    mean over its area in (u, v) (Cycles' box filter of 1 pixel; PEAK_SAMPLES about its peaks), so a sun disc
    smaller than a pixel keeps its power.  Cached by
    world_signature in `cache_dir` (CACHE_DIR unless given; None: no cache).  The size and samples default to
    BAKE_WIDTH, BAKE_HEIGHT and BAKE_SAMPLES.  Within in_background() a world not cached raises BakeNotReady
    instead of waiting; outside, a viewport's background bake of the same world is waited for, not started again."""
    width, height = width or BAKE_WIDTH, height or BAKE_HEIGHT
    samples = samples or BAKE_SAMPLES
    cache_dir = CACHE_DIR if cache_dir is _DEFAULT else cache_dir
    signature = world_signature(world, width, height, samples, camera_rays)
    background = getattr(_thread, "bakes", None)
    pixels = _cached(signature, cache_dir)
    if pixels is None:
        if background is not None:  # raises BakeNotReady
            background.request(world, signature, width, height, samples, cache_dir, camera_rays)
        pixels = _result_of_running(signature, cache_dir)
        if pixels is None:
            pixels = _render_world(world, width, height, samples, camera_rays)
        _keep(signature, pixels, cache_dir)
    if background is not None:
        background.showing(world, signature, pixels)
    return pixels


def _cached(signature, cache_dir):
    """The pixels of a bake done before (this session's last ones, or the cache folder's), else None."""
    pixels = _memory.get(signature)  # (one lookup: another thread may replace the entry)
    if pixels is not None:
        return pixels
    path = os.path.join(cache_dir, signature + ".npy") if cache_dir else None
    if path is None or not os.path.isfile(path):
        return None
    try:
        pixels = np.load(path)
    except (OSError, ValueError):  # a damaged entry: baked again
        return None
    _memory.clear()
    _memory[signature] = pixels
    return pixels


def _keep(signature, pixels, cache_dir):
    if cache_dir:
        _store(os.path.join(cache_dir, signature + ".npy"), pixels, cache_dir)
    _memory.clear()
    _memory[signature] = pixels


def _store(path, pixels, cache_dir):
    try:
        os.makedirs(cache_dir, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=cache_dir, suffix=".tmp", delete=False) as f:
            np.save(f, pixels)
        os.replace(f.name, path)  # whole or not at all: a reader never sees half an entry
        entries = sorted((e for e in os.scandir(cache_dir) if e.name.endswith(".npy")),
                         key=lambda e: e.stat().st_mtime, reverse=True)
        for old in entries[CACHE_ENTRIES:]:
            os.remove(old.path)
    except OSError:
        pass  # no cache: the next export bakes again


def _render_world(world, width, height, samples, camera_rays=True):
    """Bake `world` in a child Blender and wait for it (a render, a script)."""
    return start_bake(world, None, width, height, samples, camera_rays).wait(CHILD_TIMEOUT)


# ------------------------------------------------------------------------------------------ the child process
_running = {}  # signature -> BakeJob: the background bakes not yet in the cache (a render of the world waits for it)
_children = set()  # every BakeJob whose child may still run (killed at exit)
_running_lock = threading.Lock()


class BakeJob:
    """One child Blender baking a world (start_bake): done() asks without waiting, join() / wait() wait, kill() ends
    it.  Any thread may wait while another polls: the result is read once."""

    def __init__(self, signature, process, folder, out):
        self.signature, self.process, self._folder, self._out = signature, process, folder, out
        self._lock = threading.Lock()
        self._outcome = None  # ("pixels", array) or ("error", message), once read

    def done(self):
        return self.process.poll() is not None

    def join(self, timeout=None):
        """Wait until the child ends (at most `timeout` seconds); whether it has."""
        try:
            self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            return False
        return True

    def wait(self, timeout=CHILD_TIMEOUT):
        """The baked pixels; BakeError if the child failed, was killed, or ran past `timeout` (then it is killed)."""
        if not self.join(timeout):
            self._end("error", f"the world bake did not run: it took more than {timeout} s")
        with self._lock:
            if self._outcome is None:
                self._outcome = self._read()
                self._forget()
        kind, value = self._outcome
        if kind == "error":
            raise BakeError(value)
        return value

    def kill(self):
        """End the child now (a newer bake supersedes it, the viewport ends, Blender quits); its result is dropped."""
        self._end("error", "the world bake was cancelled")

    def _end(self, kind, value):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()  # reaped: no zombie
        with self._lock:
            if self._outcome is None:
                self._outcome = (kind, value)
                self._forget()

    def _read(self):
        code = self.process.returncode
        if code == 0 and os.path.isfile(self._out):
            try:
                return "pixels", np.load(self._out)
            except (OSError, ValueError) as e:
                return "error", f"the world bake's image could not be read: {e}"
        try:
            with open(os.path.join(self._folder, "output.txt"), errors="replace") as f:
                tail = "\n".join(f.read().strip().splitlines()[-5:])
        except OSError:
            tail = ""
        return "error", f"the world bake failed (Blender exit code {code}): {tail}"

    def _forget(self):
        """The child has ended: its folder goes (its place in _running only once its pixels are cached: unlisted)."""
        shutil.rmtree(self._folder, ignore_errors=True)
        with _running_lock:
            _children.discard(self)

    def unlist(self):
        """A render of the same world no longer waits for this bake (its pixels are cached, or it failed)."""
        with _running_lock:
            if _running.get(self.signature) is self:
                del _running[self.signature]


def start_bake(world, signature, width, height, samples, camera_rays=True):
    """A BakeJob: the child Blender started on `world` (its .blend written on the main thread), not waited for.  With
    a `signature`, a render of the same world waits for this child (bake_world) instead of starting its own."""
    import bpy
    original = getattr(world, "original", world)
    frame = bpy.context.scene.frame_current if bpy.context.scene is not None else 1
    folder = tempfile.mkdtemp(prefix="sphrect_world_bake_")
    try:
        blend = os.path.join(folder, "world.blend")
        _on_main_thread(lambda: bpy.data.libraries.write(blend, {original}, path_remap="ABSOLUTE", fake_user=True))
        out = os.path.join(folder, "world.npy")
        job = dict(blend=blend, world=original.name, out=out, exr=os.path.join(folder, "world.exr"), width=width,
                   height=height, samples=samples, peak_samples=PEAK_SAMPLES, frame=frame, parent=os.getpid(),
                   camera_rays=camera_rays)
        # Its output to a file, not a pipe nobody reads while it runs (Cycles' progress lines would fill it).
        with open(os.path.join(folder, "output.txt"), "wb") as output:
            process = subprocess.Popen(_child_command(job), stdin=subprocess.DEVNULL, stdout=output,
                                       stderr=subprocess.STDOUT)
    except OSError as e:
        shutil.rmtree(folder, ignore_errors=True)
        raise BakeError(f"the world bake did not run: {e}") from None
    except BaseException:
        shutil.rmtree(folder, ignore_errors=True)
        raise
    bake = BakeJob(signature, process, folder, out)
    with _running_lock:
        _children.add(bake)
        if signature is not None:
            _running[signature] = bake
    return bake


def _child_command(job):
    import bpy
    return [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
            "--python", os.path.abspath(__file__), "--", json.dumps(job)]


def _result_of_running(signature, cache_dir):
    """The pixels of a background bake of this signature (a render started while the viewport bakes the same world),
    None when there is none or it did not succeed (killed by a newer edit, failed)."""
    with _running_lock:
        job = _running.get(signature)
    if job is None:  # (or it was cached since this thread looked: a bake leaves _running once cached)
        return _cached(signature, cache_dir)
    try:
        return job.wait(CHILD_TIMEOUT)
    except BakeError:
        return None


@atexit.register
def kill_children():
    """Blender quits (or the add-on is disabled): no bake outlives it."""
    with _running_lock:
        jobs = list(_children)
    for job in jobs:
        job.kill()


# ------------------------------------------------------------------------------------------ in the background
@contextlib.contextmanager
def in_background(bakes):
    """Exports on this thread within the block do not wait for a bake: bake_world raises BakeNotReady and `bakes`
    (a BackgroundBakes) runs the child.  Other threads (an F12 render's) still wait."""
    outer = getattr(_thread, "bakes", None)
    _thread.bakes = bakes
    bakes.signatures = set()
    try:
        yield bakes
    finally:
        _thread.bakes = outer


def _world_key(world):
    return getattr(world, "original", world).name_full


class BackgroundBakes:
    """The bakes of one Rendered viewport (main thread only).  One child at a time, the newest request's: a request
    of another world or tree supersedes the running bake (killed, its result never used).  The last bake shown per
    world is its stand-in while the next one runs; a failed bake is remembered and not tried again until the world
    changes.  poll() (the viewport's timer) says when the running bake has ended: its pixels are then in the cache,
    and the next export of the world (within in_background) uses them."""

    def __init__(self):
        self.job = None             # the BakeJob running
        self.failure = None         # (signature, message): the last bake that failed
        self.failed_world = None    # why the bake of the world last exported failed, or None
        # The bakes bake_world asked for since in_background() began (a world's light and camera bakes; none: it was
        # not called).
        self.signatures = set()
        self._cache_dir = None      # the running bake's
        self._shown = {}            # world -> pixels of its last bake shown (one world kept)

    @property
    def pending(self):
        return self.job is not None

    def request(self, world, signature, width, height, samples, cache_dir, camera_rays=True):
        """bake_world of a world not cached: its bake started unless it runs already; raises BakeNotReady."""
        self.signatures.add(signature)
        stand_in = self._shown.get(_world_key(world))
        if self.failure is not None and self.failure[0] == signature:
            self.failed_world = self.failure[1]
            raise BakeNotReady(stand_in, self.failure[1])
        self.failed_world = None
        if self.job is None or self.job.signature != signature:
            self.cancel()
            try:
                self.job = start_bake(world, signature, width, height, samples, camera_rays)
            except BakeError as e:
                self.failure = (signature, str(e))
                self.failed_world = str(e)
                raise BakeNotReady(stand_in, str(e)) from None
            self._cache_dir = cache_dir
        raise BakeNotReady(stand_in)

    def showing(self, world, signature, pixels):
        """An export used this bake of `world` (cached): its stand-in while a later edit's bake runs."""
        self.failed_world = None
        self.signatures.add(signature)
        self._shown = {_world_key(world): pixels}

    def world_exported(self):
        """The world was exported (within in_background): a running bake it did not ask for (of another state of the
        world -- an edit undone --, or none at all: a constant or an image world now) is of no use any more."""
        if not self.signatures:
            self.failed_world = None
        if self.job is not None and self.job.signature not in self.signatures:
            self.cancel()

    def poll(self):
        """Whether the running bake has ended since the last call (its pixels cached, or its failure kept): the
        world is then to be exported again.  Costs a waitpid: called by the viewport's timer."""
        if self.job is None or not self.job.done():
            return False
        job, self.job = self.job, None
        try:
            _keep(job.signature, job.wait(0), self._cache_dir)
        except BakeError as e:
            self.failure = (job.signature, str(e))
        job.unlist()
        return True

    def cancel(self):
        """Kill the running child (a newer bake, a world that needs none, the viewport ends)."""
        if self.job is not None:
            self.job.kill()
            self.job.unlist()
            self.job = None


def _on_main_thread(call, timeout=60.0):
    """Run `call` on Blender's main thread: writing a .blend moves IDs between Main's lists for a moment, which the
    interface's drawing must not see.  F12 renders on a job thread (then a timer runs it there, and this thread
    waits); a headless render or a script runs on the main thread."""
    if threading.current_thread() is threading.main_thread():
        return call()
    import bpy
    done, outcome = threading.Event(), {}

    def run():
        try:
            outcome["value"] = call()
        except Exception as e:  # handed to the waiting thread
            outcome["error"] = e
        done.set()
        return None

    bpy.app.timers.register(run, first_interval=0.0)
    if not done.wait(timeout):
        raise BakeError("the world could not be saved for its bake: Blender's main thread did not answer")
    if "error" in outcome:
        raise outcome["error"]
    return outcome.get("value")


def peak_boxes(pixels, ratio=PEAK_RATIO, margin=PEAK_MARGIN):
    """Boxes (x0, y0, x1, y1), ends excluded, around the pixels brighter than `ratio` x the image's mean (a sun
    disc), `margin` pixels wider (its edge pixels that few samples missed); one per run of such columns."""
    height, width = pixels.shape[:2]
    luminance = pixels.mean(axis=2)
    rows, cols = np.nonzero(luminance > ratio * luminance.mean())
    if len(cols) == 0:
        return []
    occupied = np.unique(cols)
    boxes = []
    for run in np.split(occupied, np.nonzero(np.diff(occupied) > 2 * margin + 1)[0] + 1):
        inside = rows[(cols >= run[0]) & (cols <= run[-1])]
        boxes.append((max(int(run[0]) - margin, 0), max(int(inside.min()) - margin, 0),
                      min(int(run[-1]) + margin + 1, width), min(int(inside.max()) + margin + 1, height)))
    return boxes


# ------------------------------------------------------------------------------------------ in the child Blender
def _die_with_parent(parent):
    """Linux: this process is killed when the Blender that started it ends, even by a crash (PR_SET_PDEATHSIG);
    if that Blender is gone already, end now."""
    try:
        import ctypes
        import signal
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:
        os._exit(1)


def _not_camera_rays(tree, seen):
    """Every Light Path node's Is Camera Ray in `tree` and its groups read as 0 (a Value node in its place)."""
    seen.add(tree.name_full)
    for node in list(tree.nodes):
        group = getattr(node, "node_tree", None)
        if group is not None and group.name_full not in seen:
            _not_camera_rays(group, seen)
        if node.bl_idname != "ShaderNodeLightPath":
            continue
        targets = [l.to_socket for l in tree.links if l.from_node == node and l.from_socket.name == "Is Camera Ray"]
        if targets:
            zero = tree.nodes.new("ShaderNodeValue")
            zero.outputs[0].default_value = 0.0
            for socket in targets:
                tree.links.new(zero.outputs[0], socket)


def _child(job):
    import bpy
    if "parent" in job:
        _die_with_parent(job["parent"])
    with bpy.data.libraries.load(job["blend"]) as (source, target):
        target.worlds = [job["world"]]
    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    scene.world = target.worlds[0]
    if not job.get("camera_rays", True):
        _not_camera_rays(scene.world.node_tree, set())
    scene.world.cycles_visibility.camera = True  # the bake's camera sees the world, whatever the scene's camera may
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = 0
    cycles.use_animated_seed = False
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    cycles.film_exposure = 1.0
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    render = scene.render
    width, height = job["width"], job["height"]
    render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
    render.film_transparent = False
    render.use_crop_to_border = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure, scene.view_settings.gamma = 0.0, 1.0
    settings = render.image_settings
    settings.file_format, settings.color_depth, settings.exr_codec = "OPEN_EXR", "32", "NONE"
    settings.color_mode = "RGB"
    camera = bpy.data.cameras.new("sphrect_world_bake")
    camera.type = "PANO"
    camera.cycles.panorama_type = "EQUIRECTANGULAR"
    camera.cycles.latitude_min, camera.cycles.latitude_max = -math.pi / 2, math.pi / 2
    camera.cycles.longitude_min, camera.cycles.longitude_max = -math.pi, math.pi
    obj = bpy.data.objects.new("sphrect_world_bake", camera)
    obj.rotation_euler = CAMERA_ROTATION
    scene.collection.objects.link(obj)
    scene.camera = obj
    scene.frame_set(job["frame"])

    def rendered(samples, box, name):
        """[H, W, 3] rows bottom to top; with a box, only its pixels (and a pixel about it) rendered."""
        cycles.samples = samples
        render.use_border = box is not None
        if box is not None:  # a pixel wider, whatever Blender's rounding of the border to pixels
            x0, y0, x1, y1 = box
            render.border_min_x, render.border_max_x = max(x0 - 1, 0) / width, min(x1 + 1, width) / width
            render.border_min_y, render.border_max_y = max(y0 - 1, 0) / height, min(y1 + 1, height) / height
        render.filepath = os.path.join(os.path.dirname(job["exr"]), name + ".exr")
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(render.filepath)
        image.colorspace_settings.name = "Linear"  # the EXR holds linear radiance: read it back unchanged
        rgba = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(rgba)
        bpy.data.images.remove(image)
        return rgba.reshape(height, width, 4)[:, :, :3]

    pixels = rendered(job["samples"], None, "world")
    boxes = peak_boxes(pixels)
    if sum((x1 - x0) * (y1 - y0) for x0, y0, x1, y1 in boxes) <= PEAK_MAX_AREA * width * height:
        for i, (x0, y0, x1, y1) in enumerate(boxes):
            pixels[y0:y1, x0:x1] = rendered(job["peak_samples"], (x0, y0, x1, y1), f"peak{i}")[y0:y1, x0:x1]
    np.save(job["out"], np.ascontiguousarray(pixels))


if __name__ == "__main__":
    _child(json.loads(sys.argv[sys.argv.index("--") + 1]))
