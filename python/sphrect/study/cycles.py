"""Blender as a subprocess: export a .blend to a sphrect scene file, and render it with Cycles (the study's
peer). Blender runs headless and does both through the Blender add-on's headless entry point, a script
called with a command name and JSON arguments (see the add-on's headless.py):

    blender -b --factory-startup file.blend --python-exit-code 1 --python SCRIPT -- export|render_cycles JSON

This package does not know where the add-on is: SCRIPT is the `blender_script` argument, else
$SPHRECT_BLENDER_SCRIPT (the study's --blender-script option; scripts/study.py sets it to the repository's
copy). The add-on in Blender finds this package through $SPHRECT_PYTHON_PATH, set to the `sphrect` that runs
here.
"""
from __future__ import annotations

import functools
import json
import os
import re
import shutil
import socket
import subprocess
import tempfile
from typing import Dict, Optional, Tuple

import numpy as np

SCRIPT_ENV = "SPHRECT_BLENDER_SCRIPT"


def find_blender(explicit: Optional[str] = None) -> Optional[str]:
    """The Blender executable: `explicit`, $BLENDER, or `blender` on PATH; None when there is none."""
    for candidate in (explicit, os.environ.get("BLENDER"), "blender"):
        if candidate:
            path = shutil.which(candidate)
            if path:
                return path
    return None


@functools.lru_cache(maxsize=None)
def _check_worker_blender(explicit: Optional[str]) -> Tuple[Optional[str], Optional[str]]:
    """(Blender executable, None) when Blender starts on this worker, else (None, why not)."""
    host = socket.gethostname()
    exe = find_blender(explicit)
    if exe is None:
        return None, (f"Blender was not found on worker {host} (install Debian's blender there, or set $BLENDER in "
                      f"the worker's environment): its Cycles jobs cannot run")
    try:
        subprocess.run([exe, "--version"], capture_output=True, timeout=120, check=True)
    except (OSError, subprocess.SubprocessError) as e:
        return None, f"Blender {exe} does not start on worker {host}: {e}"
    return exe, None


def worker_blender(explicit: Optional[str] = None) -> str:
    """The Blender executable on this worker, checked once per worker process (it starts and says its version);
    RuntimeError naming the worker when it has none, which fails the Cycles job there, not the study."""
    exe, error = _check_worker_blender(explicit)
    if error:
        raise RuntimeError(error)
    return exe


def find_blender_script(explicit: Optional[str] = None) -> str:
    """The add-on's headless entry script: `explicit`, else $SPHRECT_BLENDER_SCRIPT; RuntimeError if neither
    names a file."""
    script = explicit or os.environ.get(SCRIPT_ENV)
    if not script or not os.path.isfile(script):
        raise RuntimeError(f"the Blender add-on's headless entry script was not found ({script or 'not set'}): "
                           f"pass --blender-script or set ${SCRIPT_ENV} to the add-on's headless.py")
    return os.path.abspath(script)


def _sphrect_python_dir() -> str:
    import sphrect
    return os.path.dirname(os.path.dirname(os.path.abspath(sphrect.__file__)))


class BlenderFailed(RuntimeError):
    """Blender ended with an error (the message has the tail of its output); `reason` is the line that says why."""

    def __init__(self, message: str, reason: str):
        super().__init__(message)
        self.reason = reason


_ERROR_LINE = re.compile(r"^(Error: |[A-Za-z_.]*(Error|Exception): )")


def blender_error_line(output: str) -> str:
    """The line of Blender's output that says why it failed: its last error line (Blender's "Error: ..." or a Python
    exception's), else its last line."""
    lines = [line.strip() for line in output.splitlines() if line.strip() and line.strip() != "Blender quit"]
    errors = [line for line in lines if _ERROR_LINE.match(line)]
    line = (errors or lines or ["no output"])[-1]
    return line[len("Error: "):] if line.startswith("Error: ") else line


def run_blender(blend: str, command: str, args: Dict, blender: Optional[str] = None,
                blender_script: Optional[str] = None, timeout: float = 3600) -> subprocess.CompletedProcess:
    """Run the add-on's headless `command` with `args` in Blender on `blend` (BlenderFailed when it fails)."""
    exe = find_blender(blender)
    if exe is None:
        raise RuntimeError("Blender was not found (install Debian's blender, or set $BLENDER)")
    if not os.path.isfile(blend):
        raise ValueError(f"{blend}: no such .blend file")
    command_line = [exe, "-b", "--factory-startup", blend, "--python-exit-code", "1",
                    "--python", find_blender_script(blender_script), "--", command, json.dumps(args)]
    env = dict(os.environ, SPHRECT_PYTHON_PATH=_sphrect_python_dir())
    result = subprocess.run(command_line, capture_output=True, text=True, timeout=timeout, env=env)
    if result.returncode != 0:
        output = result.stdout + result.stderr
        tail = "\n".join(output.strip().splitlines()[-25:])
        raise BlenderFailed(f"Blender failed on {blend} (exit {result.returncode}):\n{tail}",
                            blender_error_line(output))
    return result


def export_blend(blend: str, out_path: str, resolution: Optional[Tuple[int, int]] = None,
                 blender: Optional[str] = None, blender_script: Optional[str] = None) -> str:
    """Export `blend` with the add-on to `out_path` (.sphrect.npz); returns the exporter's warnings (what the
    scene holds that sphrect does not support), '' when none."""
    # Exported beside `out_path` and renamed over it: an interrupted export never leaves a partial scene file.
    partial = os.path.join(os.path.dirname(os.path.abspath(out_path)), ".export-partial.sphrect.npz")
    with tempfile.TemporaryDirectory() as tmp:
        warnings_path = os.path.join(tmp, "warnings.json")
        args = {"out": partial, "warnings": warnings_path}
        if resolution:
            args["width"], args["height"] = int(resolution[0]), int(resolution[1])
        run_blender(blend, "export", args, blender, blender_script, timeout=600)
        os.replace(partial, out_path)
        with open(warnings_path) as f:
            return json.load(f).get("warnings", "")


_STATUS = re.compile(r"Time:(?:(\d+):)?(\d+):(\d+(?:\.\d+)?).*\|\s*Sample (\d+)/(\d+)")


def parse_cycles_progress(stdout: str, operator_time: float) -> Dict:
    """Split a Cycles render's time using its status lines ("Time:00:01.27 | ... | Sample 64/64"): path tracing
    runs from the first "Sample 0/N" line to the latest status line (wall_time); what comes before is scene sync
    and BVH build (build_time). Cycles prints times in hundredths of a second. samples_done: the largest k."""
    marks = []
    for line in stdout.splitlines():
        m = _STATUS.search(line)
        if m:
            hours, minutes, seconds = int(m.group(1) or 0), int(m.group(2)), float(m.group(3))
            marks.append((3600 * hours + 60 * minutes + seconds, int(m.group(4))))
    if not marks:
        return {"wall_time": operator_time, "build_time": None, "samples_done": None, "timing_source": "operator"}
    start = next((t for t, k in marks if k == 0), marks[0][0])
    end = max(t for t, _ in marks)
    wall = max(end - start, 0.005)  # the clock's resolution is 0.01 s
    return {"wall_time": wall, "build_time": start, "samples_done": max(k for _, k in marks),
            "timing_source": "cycles status"}


def render_cycles(blend: str, samples: int, width: int, height: int, seed: int = 0, threads: int = 1,
                  time_limit: Optional[float] = None, blender: Optional[str] = None,
                  blender_script: Optional[str] = None, timeout: float = 7200) -> Tuple[np.ndarray, Dict]:
    """Render `blend` with Cycles 3.4 in direct-lighting settings (max_bounces 0, no denoising, no adaptive
    sampling, light_sampling_threshold 0, fixed seed, 1-pixel box filter, Standard view transform) at
    `samples` per pixel (or until `time_limit` seconds). Returns the linear [H, W, 4] float32 image, row 0 at
    the top, and the timings (see parse_cycles_progress): wall_time = path tracing, build_time = scene sync
    and BVH build before it, operator_time = the whole render operator, cpu_time = Blender's CPU time during
    the operator times the path-tracing share of its wall time (with one thread, the render's compute time)."""
    with tempfile.TemporaryDirectory() as tmp:
        args = {"samples": int(samples), "seed": int(seed), "threads": int(threads), "width": int(width),
                "height": int(height), "time_limit": time_limit,
                "npy": os.path.join(tmp, "image.npy"), "json": os.path.join(tmp, "timing.json"),
                "exr": os.path.join(tmp, "image.exr")}
        result = run_blender(blend, "render_cycles", args, blender, blender_script, timeout=timeout)
        image = np.load(args["npy"])
        with open(args["json"]) as f:
            timing = json.load(f)
    timing.update(parse_cycles_progress(result.stdout, timing["operator_time"]))
    # CPU time of the path tracing: the operator's CPU time, less the build's share of the operator's wall time.
    share = timing["wall_time"] / timing["operator_time"] if timing["operator_time"] > 0 else 1.0
    timing["cpu_time"] = timing["operator_cpu_time"] * min(share, 1.0)
    if image.shape[:2] != (height, width):
        raise RuntimeError(f"Cycles rendered {image.shape[1]}x{image.shape[0]}, expected {width}x{height}")
    return image, timing
