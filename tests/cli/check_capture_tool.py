#!/usr/bin/env python3
"""tools/models/make-capture writes a capture the renderer reads as one: a small one of each SH
degree renders, read back with its Gaussians' count and colour degree (the benchmarks' captures
are made by the same tool at a million).

Usage: check_capture_tool.py PBDSPLAT MAKE_CAPTURE WORK_DIR
"""
import os
import subprocess
import sys


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    pbdsplat, make_capture, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    for sh in (0, 3):
        path = os.path.join(work, f"capture_sh{sh}.ply")
        subprocess.run([sys.executable, make_capture, path, "--count", "3000", "--sh", str(sh)], check=True)
        out = subprocess.run([pbdsplat, "render", path, "--out", os.path.join(work, f"capture_sh{sh}.png"), "--width", "64",
                              "--height", "48", "--sort", "cpu", "--validation"], capture_output=True, text=True, timeout=120)
        if out.returncode != 0:
            sys.exit(f"render {path}: exit {out.returncode}\n{out.stderr}")
        said = out.stdout + out.stderr
        expected = "3000 anisotropic Gaussians" + (f", colour of degree {sh}" if sh else " from")
        if expected not in said:
            sys.exit(f"render {path} did not read it as {expected!r}: {said}")
        print(f"SH degree {sh}: {expected}")


if __name__ == "__main__":
    main()
