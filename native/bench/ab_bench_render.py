#!/usr/bin/python3
"""bench_render's figures on a shared, noisy machine: one build, or an A/B comparison of two.

    /usr/bin/python3 native/bench/ab_bench_render.py BUILD/bench_render [rounds] [--markdown]
    /usr/bin/python3 native/bench/ab_bench_render.py OLD/bench_render NEW/bench_render [rounds] [filter]

Runs the executable(s) `rounds` times (two builds alternately, order swapped every round, so that
load drifting over time hits both alike) and keeps, per benchmark, the fastest run's CPU time per
camera sample.

One build: issue 31's goals table.  Per case (technique / MIS / light samples, on the bench scene,
its disk-light variant and its glossy + textured variant), the ray-casting floor (BM_RawEmbree:
the same rays, no sampling or shading), without MIS also the rays plus only the technique's setup
and map (BM_RaysAndSampler: the least a renderer on this sampling core can add), the render, their
ratios to the raw rays, the renderer's own work (render - (rays + sampler)) and the goals (GOALS)
next to them.  --markdown prints it as a Markdown table (for docs/renderer.md).

Two builds: raw, render and their ratio for both, and the speed-up of the render (cases the old
build does not have are left out).
"""
import collections
import json
import subprocess
import sys

# The benchmark families: (name prefix of their BM_*Render / BM_*RawEmbree / BM_*RaysAndSampler, the
# render's arguments between technique/MIS and light samples).  BM_Render also takes the pattern (4: Sobol).
FAMILIES = (("", "4/"), ("Disk", ""), ("Glossy", ""))

# Issue 31's goals, in one place.  (case name as the benchmark labels it, MIS, light samples) ->
# (render / raw, (rays + sampler) / raw); None where the issue sets none.
GOALS = {
    ("rectangle", "none", 1): (1.8, 1.3),
    ("rectangle", "none", 4): (1.5, None),
    ("area", "none", 1): (1.4, None),
    ("rectangle", "balance", 1): (2.0, None),
    ("triangles", "none", 1): (2.2, None),
    ("rectangle_cosine", "none", 1): (2.2, None),
    ("rectangle_projected", "none", 1): (2.5, None),
    ("spherical_ellipse (disk scene)", "none", 1): (2.0, None),
}
OWN_WORK_GOAL_NS = 40  # render - (rays + sampler), per camera sample, every case
PROJECTED_SAMPLER_GOAL = 2.0  # rectangle_projected's sampler (rays + sampler - raw) / the rectangle's


def best_times(bins, rounds, filt):
    """{run name: {build tag: min ns per camera sample}} over `rounds` alternating runs, and the case
    names by (family, benchmark index) (from the benchmarks' labels, which start with the case's name)."""
    best = collections.defaultdict(dict)
    names = {}
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
                for family, _ in FAMILIES:
                    if kind in (f"BM_{family}Render", f"BM_{family}RawEmbree") and b.get("label"):
                        names[family, int(index)] = b["label"].split("/")[0]
    return best, names


def rows(best, names):
    """(case name, mis, light samples, raw, render or None, rays + sampler or None) for every measured case
    (a case without a render, BM_DiskRaysAndSampler's map everywhere, has rays + sampler)."""
    for family, render_args in FAMILIES:
        for ls in (1, 4):
            for mis in (0, 1):
                for (fam, t), name in sorted(names.items()):
                    if fam != family:
                        continue
                    raw = best.get(f"BM_{family}RawEmbree/{t}/{mis}/{ls}/manual_time")
                    ren = best.get(f"BM_{family}Render/{t}/{mis}/{render_args}{ls}/manual_time")
                    floor = best.get(f"BM_{family}RaysAndSampler/{t}/{ls}/manual_time") if not mis else None
                    if raw and (ren or floor):
                        yield name, "balance" if mis else "none", ls, raw, ren, floor


def goal_cell(value, goal, markdown):
    """'<= goal' and whether value meets it, or '' without a goal."""
    if goal is None:
        return ""
    return f"≤ {goal:.1f} {'met' if value <= goal else 'missed'}" if markdown else \
        f"<= {goal:.1f} {'met' if value <= goal else 'MISSED'}"


def report_one(binary, rounds, markdown):
    best, names = best_times({"build": binary}, rounds, "BM_Render/./././|BM_RawEmbree|BM_RaysAndSampler|"
                             "BM_DiskRender|BM_DiskRawEmbree|BM_DiskRaysAndSampler|"
                             "BM_GlossyRender|BM_GlossyRawEmbree|BM_GlossyRaysAndSampler")
    header = ("case", "MIS", "light samples", "raw", "rays + sampler", "render", "(rays + sampler) / raw",
              "render / raw", f"own work (goal ≤ {OWN_WORK_GOAL_NS})", "goal render / raw",
              "goal (rays + sampler) / raw")
    if markdown:
        print("| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
    else:
        print(f"{'case':46s} {'MIS':7s} ls | {'raw':>5s} {'rays+smp':>8s} {'render':>7s} | {'smp/raw':>7s} "
              f"{'ren/raw':>7s} {'own':>5s} | {'goal ren/raw':14s} {'goal smp/raw':14s}"
              f"   (ns per camera sample; own = render - (rays + sampler), goal <= {OWN_WORK_GOAL_NS})")
    samplers = {}
    for name, mis, ls, raw, ren, floor in rows(best, names):
        r = raw["build"]
        n = ren["build"] if ren else None
        f = floor["build"] if floor else None
        if f is not None and ls == 1:
            samplers[name] = f - r
        goal_render, goal_floor = GOALS.get((name, mis, ls), (None, None))
        cells = (f"{f:.0f}" if f else "", f"{n:.0f}" if n else "", f"{f / r:.2f}" if f else "",
                 f"{n / r:.2f}" if n else "", f"{n - f:.0f}" if f and n else "",
                 goal_cell(n / r, goal_render, markdown) if n else "",
                 goal_cell(f / r, goal_floor, markdown) if f else "")
        if markdown:
            print(f"| {name} | {mis} | {ls} | {r:.0f} | " + " | ".join(cells) + " |")
        else:
            print(f"{name:46s} {mis:7s} {ls}  | {r:5.0f} {cells[0]:>8s} {cells[1]:>7s} | {cells[2]:>7s} {cells[3]:>7s} "
                  f"{cells[4]:>5s} | {cells[5]:14s} {cells[6]:14s}")
    if "rectangle_projected" in samplers and samplers.get("rectangle", 0) > 0:
        ratio = samplers["rectangle_projected"] / samplers["rectangle"]
        print(f"\nrectangle_projected's sampler (rays + sampler - raw, 1 light sample) / the rectangle's: "
              f"{ratio:.2f} ({samplers['rectangle_projected']:.0f} / {samplers['rectangle']:.0f} ns), "
              f"goal <= {PROJECTED_SAMPLER_GOAL:.1f}: {'met' if ratio <= PROJECTED_SAMPLER_GOAL else 'missed'}")


def report_ab(old, new, rounds, filt):
    best, names = best_times({"old": old, "new": new}, rounds, filt)
    print(f"{'technique':30s} {'MIS':7s} ls | {'old: raw':>8s} {'render':>7s} {'ratio':>5s} | "
          f"{'new: raw':>8s} {'render':>7s} {'ratio':>5s} | speed-up   (ns per camera sample)")
    for name, mis, ls, raw, ren, _ in rows(best, names):
        if len(raw) < 2 or not ren or len(ren) < 2:
            continue
        print(f"{name:30s} {mis:7s} {ls}  | {raw['old']:8.0f} {ren['old']:7.0f} {ren['old'] / raw['old']:5.2f} | "
              f"{raw['new']:8.0f} {ren['new']:7.0f} {ren['new'] / raw['new']:5.2f} | {ren['old'] / ren['new']:5.2f}x")


def main():
    args = sys.argv[1:]
    markdown = "--markdown" in args
    args = [a for a in args if a != "--markdown"]
    if not args:
        sys.exit(__doc__)
    if len(args) == 1 or args[1].isdigit():
        report_one(args[0], int(args[1]) if len(args) > 1 else 6, markdown)
    else:
        report_ab(args[0], args[1], int(args[2]) if len(args) > 2 else 6,
                  args[3] if len(args) > 3 else "BM_Render|BM_RawEmbree")


if __name__ == "__main__":
    main()
