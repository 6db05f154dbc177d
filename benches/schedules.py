#!/usr/bin/env python3
"""The two schedules against each other: `glint bench --json --schedule S`
for megakernel and wavefront on one binary, runs interleaved, every bench
scene (or those given).

    python3 benches/schedules.py [--runs 3] [--binary PATH] [SCENE...]

Each run is one `glint bench --runs 1` per schedule (a warm-up, then one
timed GPU f32 render a scene). Prints the medians of the GPU f32 times, the
ratio wavefront / megakernel, and GPU/CPU for each, as a Markdown table.
Set VK_DRIVER_FILES to measure another driver.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCHEDULES = ["megakernel", "wavefront"]


def bench(binary, schedule, scenes):
    cmd = [binary, "bench", "--json", "--runs", "1", "--schedule", schedule, *scenes]
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO)
    if out.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: {out.stderr.strip()}")
    return {s["scene"]: (s["gpu_f32_s"], s["cpu_f32_s"]) for s in json.loads(out.stdout)["scenes"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    ap.add_argument("--binary", default=os.path.join(target, "release", "glint"))
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    runs = {s: [] for s in SCHEDULES}
    for i in range(a.runs):
        for s in SCHEDULES:
            print(f"run {i + 1}/{a.runs}: {s}", file=sys.stderr)
            runs[s].append(bench(a.binary, s, a.scenes))
    print(f"\nGPU f32, medians of {a.runs} interleaved runs\n")
    print("| scene | megakernel | wavefront | wavefront / megakernel | GPU/CPU megakernel | GPU/CPU wavefront |")
    print("|---|---|---|---|---|---|")
    for scene in runs["megakernel"][0]:
        gpu = {s: statistics.median(r[scene][0] for r in runs[s]) for s in SCHEDULES}
        cpu = statistics.median(r[scene][1] for s in SCHEDULES for r in runs[s])
        m, w = gpu["megakernel"], gpu["wavefront"]
        name = os.path.basename(scene)
        print(f"| {name} | {m:.4f} s | {w:.4f} s | {w / m:.2f} | {m / cpu:.2f} | {w / cpu:.2f} |")


if __name__ == "__main__":
    main()
