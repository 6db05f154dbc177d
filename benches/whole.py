#!/usr/bin/env python3
"""Whole-process time: `glint render SCENE -o FILE` from start to exit (the
scene read, the BVH and the tables built, the shader compiled or taken from
the cache, the render, the image written), for several binaries or
options, runs interleaved so that every lane sees the same machine load.

    python3 benches/whole.py --lane base=bin:/path/to/old/glint --lane new= \\
        [--runs 3] [--drivers default,22.3] [SCENE ...]

A lane is NAME=ARGS as in benches/choices.py: `bin:PATH` runs another glint
binary, `env:NAME=VALUE` sets a variable, other words are render options.
The first lane is the base. Default scenes: the seven SPD databases at
their own 512x512. Each lane renders every scene once untimed first, so
that the SPIR-V and pipeline caches are warm for all. Prints, for each
driver, the medians and each lane's ratio to the base, and the totals.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

# The lanes are choices.py's, and so are the two drivers.
from choices import DEFAULT_ICD, old_icd, parse_lane

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SPD = ["balls", "gears", "mount", "rings", "teapot", "tetra", "tree"]


def icd_of(driver):
    return DEFAULT_ICD if driver == "default" else old_icd()


def render(lane, icd, scene, out):
    env = dict(os.environ, VK_DRIVER_FILES=icd, VK_ICD_FILENAMES=icd, **lane["env"])
    cmd = [lane["binary"], "render", scene, "-o", out, *lane["args"]]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: {r.stderr.strip()}")
    return seconds


def main():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lane", action="append", required=True, help="NAME=ARGS (the first is the base)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--drivers", default="default,22.3")
    ap.add_argument("--binary", default=os.path.join(target, "release", "glint"))
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    lanes = [parse_lane(t, a.binary) for t in a.lane]
    scenes = a.scenes or [os.path.join(REPO, "scenes", "spd", f"{n}.nff") for n in SPD]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.png")
        for driver in a.drivers.split(","):
            icd = icd_of(driver)
            for lane in lanes:
                for scene in scenes:
                    render(lane, icd, scene, out)
            times = {(l["name"], s): [] for l in lanes for s in scenes}
            for run in range(a.runs):
                for lane in lanes:
                    print(f"run {run + 1}/{a.runs}: {driver} {lane['name']}", file=sys.stderr)
                    for scene in scenes:
                        times[(lane["name"], scene)].append(render(lane, icd, scene, out))
            names = [l["name"] for l in lanes]
            base = names[0]
            print(f"\n{driver} lavapipe: whole `glint render`, medians of {a.runs} interleaved runs\n")
            print("| scene | " + " | ".join(names) + " | " + " | ".join(f"{n}/{base}" for n in names[1:]) + " |")
            print("|---" * (2 * len(names)) + "|")
            totals = {n: 0.0 for n in names}
            for scene in scenes:
                med = {n: statistics.median(times[(n, scene)]) for n in names}
                for n in names:
                    totals[n] += med[n]
                cells = [f"{med[n]:.3f} s" for n in names] + [f"{med[n] / med[base]:.2f}" for n in names[1:]]
                print(f"| {os.path.basename(scene)} | " + " | ".join(cells) + " |")
            cells = [f"{totals[n]:.3f} s" for n in names] + [f"{totals[n] / totals[base]:.2f}" for n in names[1:]]
            print("| **total** | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
