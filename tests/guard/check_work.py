#!/usr/bin/env python3
"""The work guard: figures of speed and work that do not depend on how fast the machine is,
each held to about 1.5x what it measured when its limit was set, so that a change that makes
Stage A or a cut slower fails CI with the figure named.

Each figure is a ratio of two timings taken in one process, alternated or back to back (the
engine against the hand-written loop of the same workload; a cut against a Stage A frame of
the same body), so a slower or busier machine moves both sides; or a count of the work the GPU
did (the splat draws' primitives and fragments), which no machine's speed moves. A device without
pipeline-statistics queries skips the counts, saying so. Run serially (ctest's
RUN_SERIAL): another process on the two cores would land on one side only.

A figure over its limit is measured again, up to three times in all, and the lowest taken: noise
on a shared machine only ever slows one side of a ratio (CI once read the cut at 1.607 against
1.0-1.2 in every run before it), while a change that makes the work slower is slower every time.

Usage: check_work.py PBDSPLAT
"""
import json
import pathlib
import subprocess
import sys

SCENE = pathlib.Path(__file__).resolve().parents[2] / "scenes" / "default.toml"

# name, what it is, limit, measured when the limit was set (2026-11-29, the 2-vCPU VM, median
# of four runs: docs/BENCHMARKS.md, "Checks: claims as data").
LIMITS = {
    "stage_a_per_tuned_loop": ("Stage A of a hanging icosphere:5 over the tuned hand-written loop's", 1.55, 1.02),
    # Each cut against a Stage A frame timed just before it (six runs 1.07-1.32, 2026-12-02; the
    # frames timed apart from the cuts gave 1.0-1.2 on one day and 1.4-2.2 on another).
    "cut_per_stage_a_frame": ("a line cut through icosphere:5 over a Stage A frame of it timed before each cut", 1.8, 1.2),
    # The two halves lie on each other's cut faces: contact searches and four substeps a frame
    # (docs/BENCHMARKS.md, "Contact": the goal of 1.5x is not met).
    "stage_a_after_cut_per_before": ("Stage A after that cut over Stage A before it", 30.0, 20.5),
    # Counts, not times (pipeline statistics, 2026-12-02, Lavapipe): the same on any machine with
    # the same driver. The default scene's first 120 frames at its 1280x720, median a frame; its
    # far side and hidden splats are dropped before rasterisation, its footprints sized to cover.
    "default_splat_primitives": ("primitives the default scene's splat draws send to the rasteriser", 9400, 6279),
    "default_splat_fragments": ("fragments the default scene's splat draws shade", 1050000, 698851),
}



def run(pbdsplat, *args):
    out = subprocess.run([pbdsplat, *args, "--json"], capture_output=True, text=True, timeout=300)
    if out.returncode != 0:
        sys.exit(f"{' '.join(args)}: exit {out.returncode}\n{out.stderr}")
    return json.loads(out.stdout)


def figures(pbdsplat):
    sim = run(pbdsplat, "bench", "sim", "--mesh", "icosphere:5", "--pin", "top", "--frames", "120", "--warmup", "5",
              "--baseline")
    cut = run(pbdsplat, "bench", "cut", "--mesh", "icosphere:5", "--cuts", "20", "--frames", "20")
    before = cut["stage_a_ms_before"]
    work = run(pbdsplat, "bench", "scene", str(SCENE), "--frames", "120").get("splat_work_median", {})
    return {
        "default_splat_primitives": work.get("primitives"),
        "default_splat_fragments": work.get("fragments"),
        "stage_a_per_tuned_loop": sim["baseline"]["tuned_ratio"],
        "cut_per_stage_a_frame": cut["median_cut_ms"] / cut["stage_a_ms_between_cuts"],
        "stage_a_after_cut_per_before": cut["stage_a_ms_after"] / before,
    }


TRIES = 3


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    got = figures(sys.argv[1])
    for attempt in range(1, TRIES):
        over = [key for key, (_, limit, _) in LIMITS.items() if got[key] is not None and got[key] > limit]
        if not over:
            break
        print(f"measuring again ({attempt + 1} of {TRIES}): {', '.join(f'{k} = {got[k]:.3f}' for k in over)}")
        again = figures(sys.argv[1])
        got = {key: min(got[key], again[key]) if got[key] is not None else None for key in got}
    failed = []
    for key, (what, limit, measured) in LIMITS.items():
        value = got[key]
        if value is None:
            print(f"skip {key}: the device has no pipeline-statistics queries ({what})")
            continue
        ok = value <= limit
        print(f"{'ok  ' if ok else 'FAIL'} {key} = {value:.3f} (limit {limit}, {measured} when set): {what}")
        if not ok:
            failed.append(key)
    if failed:
        sys.exit(f"work guard: {', '.join(failed)} over the limit: a change made this work slower")


if __name__ == "__main__":
    main()
