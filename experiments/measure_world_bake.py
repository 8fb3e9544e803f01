"""The world bake's cost and accuracy (docs/addon.md, "World"): Blender's default Nishita sky baked at several sizes
and peak sample counts, uncached; prints each bake's time and the power of its sun disc (the sum of radiance x
solid angle over the pixels brighter than 3000, red channel) and of the rest of the sky.  Run inside Blender:

    blender -b --factory-startup --python experiments/measure_world_bake.py -- [--sizes 512x256,1024x512,2048x1024]
        [--peak-samples 1024,4096]
"""
import argparse
import os
import sys
import time

import bpy

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "addon"))
import addon_utils  # noqa: E402

addon_utils.enable("sphrect_blender", default_set=True)
bake = sys.modules["sphrect_blender.io.exporter.world_bake"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--sizes", default="512x256,1024x512,2048x1024")
    parser.add_argument("--peak-samples", default=str(bake.PEAK_SAMPLES))
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    world = bpy.data.worlds.new("Sky")
    world.use_nodes = True
    sky = world.node_tree.nodes.new("ShaderNodeTexSky")
    world.node_tree.links.new(sky.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
    for peak in (int(p) for p in args.peak_samples.split(",")):
        bake.PEAK_SAMPLES = peak
        for size in args.sizes.split(","):
            width, height = (int(v) for v in size.split("x"))
            bake._memory.clear()
            start = time.perf_counter()
            pixels = bake.bake_world(world, width, height, cache_dir=None)
            seconds = time.perf_counter() - start
            weighted = pixels[..., 0] * bake.row_solid_angles(height, width)[:, None]
            sun = pixels.mean(axis=2) > 3000.0
            print(f"{width}x{height}, {bake.BAKE_SAMPLES} samples, {peak} about peaks: {seconds:.1f} s; "
                  f"sun {weighted[sun].sum():.3f}, sky {weighted[~sun].sum():.4f}", flush=True)


main()
