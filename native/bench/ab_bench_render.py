#!/usr/bin/python3
"""A/B comparison of two bench_render builds on a shared, noisy machine.

    /usr/bin/python3 native/bench/ab_bench_render.py OLD/bench_render NEW/bench_render [rounds] [filter]

Runs the two executables alternately (`rounds` times each, order swapped every round, so that
load drifting over time hits both alike) and keeps, per benchmark, the fastest run's CPU time
per camera sample.  Prints, per technique / MIS / light samples, the ray-casting floor
(BM_RawEmbree: the same rays, no sampling or shading), the render time and their ratio, for
both builds, and the speed-up of the render.
"""
import collections
import json
import subprocess
import sys


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    bins = {"old": sys.argv[1], "new": sys.argv[2]}
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 6
    filt = sys.argv[4] if len(sys.argv) > 4 else "BM_Render|BM_RawEmbree"
    best = collections.defaultdict(dict)  # run name -> build -> min ns per camera sample
    for r in range(rounds):
        for tag in (("old", "new") if r % 2 == 0 else ("new", "old")):
            out = subprocess.run([bins[tag], f"--benchmark_filter={filt}", "--benchmark_min_time=0.15",
                                  "--benchmark_format=json"], capture_output=True, text=True, check=True).stdout
            for b in json.loads(out)["benchmarks"]:
                ns = b["s/sample"] * 1e9
                best[b["run_name"]][tag] = min(ns, best[b["run_name"]].get(tag, float("inf")))
    names = ["area", "triangles", "rectangle", "rectangle_cosine"]
    print(f"{'technique':17s} {'MIS':7s} ls | {'old: raw':>8s} {'render':>7s} {'ratio':>5s} | "
          f"{'new: raw':>8s} {'render':>7s} {'ratio':>5s} | speed-up   (ns per camera sample)")
    for ls in (1, 4):
        for mis in (0, 1):
            for t in range(4):
                raw = best.get(f"BM_RawEmbree/{t}/{mis}/{ls}/manual_time")
                ren = best.get(f"BM_Render/{t}/{mis}/4/{ls}/manual_time")
                if not raw or not ren or len(raw) < 2 or len(ren) < 2:
                    continue
                print(f"{names[t]:17s} {'balance' if mis else 'none':7s} {ls}  | {raw['old']:8.0f} {ren['old']:7.0f} "
                      f"{ren['old'] / raw['old']:5.2f} | {raw['new']:8.0f} {ren['new']:7.0f} {ren['new'] / raw['new']:5.2f}"
                      f" | {ren['old'] / ren['new']:5.2f}x")


if __name__ == "__main__":
    main()
