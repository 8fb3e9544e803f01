#!/usr/bin/python3
"""bench_render's figures on a shared, noisy machine: one build, or an A/B comparison of two.

    /usr/bin/python3 native/bench/ab_bench_render.py BUILD/bench_render [rounds]
    /usr/bin/python3 native/bench/ab_bench_render.py OLD/bench_render NEW/bench_render [rounds] [filter]

Runs the executable(s) `rounds` times (two builds alternately, order swapped every round, so that
load drifting over time hits both alike) and keeps, per benchmark, the fastest run's CPU time per
camera sample.

One build: per technique / MIS / light samples, the ray-casting floor (BM_RawEmbree: the same
rays, no sampling or shading), without MIS also the rays plus only the technique's setup and map
(BM_RaysAndSampler: the least a renderer on this sampling core can add), the render, and their
ratios to the raw rays; the issue's goal is render / raw <= 1.3.

Two builds: raw, render and their ratio for both, and the speed-up of the render.
"""
import collections
import json
import subprocess
import sys



def best_times(bins, rounds, filt):
    """{run name: {build tag: min ns per camera sample}} over `rounds` alternating runs, and the technique
    names by benchmark index (from the benchmarks' labels, which start with the technique's name)."""
    best = collections.defaultdict(dict)
    techniques = {}
    tags = list(bins)
    for r in range(rounds):
        for tag in (tags if r % 2 == 0 else tags[::-1]):
            out = subprocess.run([bins[tag], f"--benchmark_filter={filt}", "--benchmark_min_time=0.15",
                                  "--benchmark_format=json"], capture_output=True, text=True, check=True).stdout
            for b in json.loads(out)["benchmarks"]:
                if b.get("error_occurred"):
                    sys.exit(f"{b['run_name']}: {b.get('error_message')}")
                ns = b["s/sample"] * 1e9
                best[b["run_name"]][tag] = min(ns, best[b["run_name"]].get(tag, float("inf")))
                kind, index = b["run_name"].split("/")[:2]
                if kind in ("BM_Render", "BM_RawEmbree") and b.get("label"):
                    techniques[int(index)] = b["label"].split("/")[0]
    return best, techniques


def rows(best, techniques):
    """(technique, mis, light samples, raw, render, rays + sampler or None) for every measured case."""
    for ls in (1, 4):
        for mis in (0, 1):
            for t, name in sorted(techniques.items()):
                raw = best.get(f"BM_RawEmbree/{t}/{mis}/{ls}/manual_time")
                ren = best.get(f"BM_Render/{t}/{mis}/4/{ls}/manual_time")
                floor = best.get(f"BM_RaysAndSampler/{t}/{ls}/manual_time") if not mis else None
                if raw and ren:
                    yield name, "balance" if mis else "none", ls, raw, ren, floor


def report_one(binary, rounds):
    best, techniques = best_times({"build": binary}, rounds, "BM_Render/./././|BM_RawEmbree|BM_RaysAndSampler")
    print(f"{'technique':17s} {'MIS':7s} ls | {'raw':>5s} {'rays+sampler':>12s} {'render':>7s} | "
          f"{'floor/raw':>9s} {'render/raw':>10s}   (ns per camera sample; goal render/raw <= 1.3)")
    for name, mis, ls, raw, ren, floor in rows(best, techniques):
        r, n = raw["build"], ren["build"]
        f = floor["build"] if floor else None
        print(f"{name:17s} {mis:7s} {ls}  | {r:5.0f} {f'{f:12.0f}' if f else ' ' * 12} {n:7.0f} | "
              f"{f'{f / r:9.2f}' if f else ' ' * 9} {n / r:10.2f}")


def report_ab(old, new, rounds, filt):
    best, techniques = best_times({"old": old, "new": new}, rounds, filt)
    print(f"{'technique':17s} {'MIS':7s} ls | {'old: raw':>8s} {'render':>7s} {'ratio':>5s} | "
          f"{'new: raw':>8s} {'render':>7s} {'ratio':>5s} | speed-up   (ns per camera sample)")
    for name, mis, ls, raw, ren, _ in rows(best, techniques):
        if len(raw) < 2 or len(ren) < 2:
            continue
        print(f"{name:17s} {mis:7s} {ls}  | {raw['old']:8.0f} {ren['old']:7.0f} {ren['old'] / raw['old']:5.2f} | "
              f"{raw['new']:8.0f} {ren['new']:7.0f} {ren['new'] / raw['new']:5.2f} | {ren['old'] / ren['new']:5.2f}x")


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    if len(args) == 1 or args[1].isdigit():
        report_one(args[0], int(args[1]) if len(args) > 1 else 6)
    else:
        report_ab(args[0], args[1], int(args[2]) if len(args) > 2 else 6,
                  args[3] if len(args) > 3 else "BM_Render|BM_RawEmbree")


if __name__ == "__main__":
    main()
