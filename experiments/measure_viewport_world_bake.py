"""The Rendered viewport's main-thread time for the first export of a Nishita sky scene whose world is not baked yet
(docs/viewport.md, "A world that needs a bake"): the time `ViewportSession.update` holds Blender's main thread (the
interface is frozen meanwhile), then, where the bake runs in the background, how long the bake took to land and what
the export after it costs.  Each run's sky has a sun elevation no earlier run used: never in the bake's cache.  Run
inside Blender, with this repository's add-on or another checkout's (`--addon DIR`, its `addon/` folder):

    SPHRECT_PYTHON_PATH=$PWD/build/python blender -b --factory-startup \
        --python experiments/measure_viewport_world_bake.py -- [--runs 3] [--addon /path/to/addon]
"""
import argparse
import os
import random
import sys
import time

import bpy

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
parser = argparse.ArgumentParser()
parser.add_argument("--runs", type=int, default=3)
parser.add_argument("--addon", default=os.path.join(REPO, "addon"))
args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
sys.path.insert(0, args.addon)
sys.path.insert(0, os.path.join(REPO, "scripts"))
import addon_utils  # noqa: E402
import make_scenes  # noqa: E402

addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
viewport = sys.modules["sphrect_blender.engine.viewport"]
bake = sys.modules["sphrect_blender.io.exporter.world_bake"]


def sky_scene(elevation):
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "SPHRECT"
    make_scenes.sky_floor_scene(scene, elevation)
    bpy.context.view_layer.update()


def main():
    rng = random.Random()  # new skies every time: a fixed seed would find the last invocation's bakes cached
    print(f"add-on: {os.path.dirname(bake.__file__)}; bake {bake.BAKE_WIDTH}x{bake.BAKE_HEIGHT}")
    for run in range(args.runs):
        sky_scene(rng.uniform(0.2, 1.2))
        bake._memory.clear()
        session = viewport.ViewportSession()
        start = time.perf_counter()
        session.update(bpy.context.evaluated_depsgraph_get())
        blocked = time.perf_counter() - start
        line = (f"run {run}: first viewport export {blocked * 1e3:.0f} ms on the main thread, world "
                f"{'baked' if session.scene.world.environment is not None else 'a constant stand-in'}")
        bakes = getattr(session, "bakes", None)
        if bakes is not None and bakes.pending:  # the background bake: when it lands, the export that uses it
            bakes.job.join(bake.CHILD_TIMEOUT)
            landed = time.perf_counter() - start
            start = time.perf_counter()
            assert session.poll_bake()  # (the timer's: the bake read and cached)
            polled = time.perf_counter() - start
            start = time.perf_counter()
            session.refresh_world(bpy.context.evaluated_depsgraph_get())
            line += (f"; the bake landed after {landed:.1f} s; on the main thread then: its poll "
                     f"{polled * 1e3:.0f} ms, the export with it {(time.perf_counter() - start) * 1e3:.0f} ms (world "
                     f"{'baked' if session.scene.world.environment is not None else 'not baked'})")
        print(line, flush=True)
        session.free()


main()
