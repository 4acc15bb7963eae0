#!/usr/bin/env python3
"""A textured model through `pbdsplat check`, against the textured lit mesh: the splats read the
texture under each pixel, so a checker's edges cost little more colour error than the same
globe without a texture. Both globes are written here by tools/models/make-textured-globe
(a quarter of the benchmarks' triangles, so the test takes seconds).

Usage: check_textured.py PBDSPLAT MAKE_GLOBE WORK_DIR
"""
import json
import os
import subprocess
import sys

# 2026-11-29, Lavapipe, 640x360: 0.0039 textured, 0.0013 plain (ratio 3.05); one colour a splat
# (the code before) scored 0.037, a ratio of 28.8.
MAX_RATIO = 4.0


def check(pbdsplat, model):
    out = subprocess.run([pbdsplat, "check", model, "--frames", "30", "--every", "30", "--width", "640", "--height", "360",
                          "--json"], capture_output=True, text=True, timeout=300)
    if out.returncode != 0:
        sys.exit(f"check {model}: exit {out.returncode}\n{out.stderr}")
    report = json.loads(out.stdout)
    return report.get("report", report)["color_error_max"]


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    pbdsplat, make_globe, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    errors = {}
    for name, extra in (("textured", []), ("plain", ["--plain"])):
        path = os.path.join(work, f"globe_{name}.glb")
        subprocess.run([sys.executable, make_globe, path, "--segments", "128", "--rings", "98", *extra], check=True)
        errors[name] = check(pbdsplat, path)
    ratio = errors["textured"] / errors["plain"]
    print(f"colour error textured {errors['textured']:.5f}, plain {errors['plain']:.5f}, ratio {ratio:.2f} (limit {MAX_RATIO})")
    if not ratio <= MAX_RATIO:
        sys.exit("textured splats drew the texture blurred or misplaced: the colour error is too far above the plain globe's")


if __name__ == "__main__":
    main()
