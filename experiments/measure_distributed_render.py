#!/usr/bin/python3
"""How a long render's time falls with the workers of a Dask cluster: sphrect.render_distributed of the calibration
scene on a local cluster of 1, 2, ... worker processes (one render thread each), against sphrect.render in this
process with one thread, and whether the images are bit-identical to the local render of the same sample ranges.

    experiments/measure_distributed_render.py --samples 1024 --side 128 --workers 1,2

Wall times include sending the scene and merging the buffers (not starting the workers); on a machine whose cores
other processes share they scatter. Uses the package built in build/python.
"""
import argparse
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.environ.get("SPHRECT_PYTHON_PATH", os.path.join(ROOT, "build", "python")))

import numpy as np  # noqa: E402

import sphrect  # noqa: E402
from sphrect.study.dask_executor import DaskExecutor  # noqa: E402
from sphrect.study.machines import calibration_scene  # noqa: E402


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--samples", type=int, default=1024)
    p.add_argument("--side", type=int, default=128, help="image width and height")
    p.add_argument("--workers", default="1,2", help="comma list of local cluster sizes")
    args = p.parse_args()
    scene = calibration_scene()
    scene.camera.width = scene.camera.height = args.side
    options = dict(techniques=["rectangle"], pattern="stratified", light_samples=1, threads=1)
    start = time.perf_counter()
    sphrect.render(scene, args.samples, **options)
    single = time.perf_counter() - start
    print(f"sphrect.render, one thread: {single:.2f} s ({args.side}x{args.side}, {args.samples} spp; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    for workers in (int(w) for w in args.workers.split(",")):
        with DaskExecutor(workers=workers) as cluster:
            # Warm the workers up (importing sphrect, the first scene upload) before the clock starts.
            sphrect.render_distributed(scene, workers, client=cluster.client, parts=workers, **options)
            start = time.perf_counter()
            split = sphrect.render_distributed(scene, args.samples, client=cluster.client, **options)
            seconds = time.perf_counter() - start
        same = np.array_equal(split["rectangle"], sphrect.render(scene, args.samples, parts=workers,
                                                                 **options)["rectangle"])
        print(f"render_distributed, {workers} worker(s): {seconds:.2f} s, {single / seconds:.2f}x the single "
              f"render's speed; bit-identical to render(parts={workers}): {same}")


if __name__ == "__main__":
    main()
