#!/usr/bin/env python3
"""One design choice measured on both lavapipes: `glint bench --json` with
each lane's options, on the default driver and on Debian 12's stock 22.3
(ci/old-lavapipe), runs interleaved lane by lane and driver by driver so
that every lane sees the same machine load.

    python3 benches/choices.py --lane base= --lane stack="-D STACK_WALK" \\
        [--runs 3] [--drivers default,22.3] [SCENE ...]

A lane is NAME=ARGS: ARGS are glint bench options (shell words), and two
kinds of word are taken by this script: `bin:PATH` runs another glint
binary (a build with other constants), `env:NAME=VALUE` sets a variable
(GLINT_EXPERIMENT=...). The first lane is the base. Each run is one
`glint bench --runs 1` (a warm-up, then one timed GPU f32 render a scene).
Prints, for each driver, the medians of the GPU f32 times and each lane's
ratio to the base, as a Markdown table, and the median of those ratios and
of the CPU f32 ratios (which move only where a lane's binary builds the
scene differently, e.g. its BVH).
"""

import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_ICD = "/usr/share/vulkan/icd.d/lvp_icd.json"


def old_icd():
    out = subprocess.run([os.path.join(REPO, "ci", "old-lavapipe")], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"ci/old-lavapipe: {out.stderr.strip()}")
    return out.stdout.strip()


def parse_lane(text, default_binary):
    name, _, args = text.partition("=")
    lane = {"name": name, "binary": default_binary, "env": {}, "args": []}
    for word in shlex.split(args):
        if word.startswith("bin:"):
            lane["binary"] = word[4:]
        elif word.startswith("env:"):
            k, _, v = word[4:].partition("=")
            lane["env"][k] = v
        else:
            lane["args"].append(word)
    return lane


def bench(lane, icd, scenes):
    cmd = [lane["binary"], "bench", "--json", "--runs", "1", *lane["args"], *scenes]
    env = dict(os.environ, VK_DRIVER_FILES=icd, **lane["env"])
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO, env=env)
    if out.returncode != 0:
        # A lane that fails (a driver's crash, the watchdog) is reported as
        # failed beside the others rather than ending the measurement.
        print(f"{' '.join(cmd)}: {out.stderr.strip()}", file=sys.stderr)
        return out.stderr.strip().splitlines()[-1] if out.stderr.strip() else f"exit {out.returncode}"
    return {s["scene"]: (s["gpu_f32_s"], s["cpu_f32_s"]) for s in json.loads(out.stdout)["scenes"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--lane", action="append", required=True, help="NAME=ARGS (the first is the base)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--drivers", default="default,22.3", help="default, 22.3 or both, comma-separated")
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    ap.add_argument("--binary", default=os.path.join(target, "release", "glint"))
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    lanes = [parse_lane(t, a.binary) for t in a.lane]
    icds = {"default": DEFAULT_ICD, "22.3": None}
    drivers = [d.strip() for d in a.drivers.split(",") if d.strip()]
    for d in drivers:
        if d not in icds:
            sys.exit(f"--drivers: {d!r} is not default or 22.3")
        if d == "22.3":
            icds[d] = old_icd()
    runs = {(d, l["name"]): [] for d in drivers for l in lanes}
    failed = {}
    for i in range(a.runs):
        for d in drivers:
            for lane in lanes:
                key = (d, lane["name"])
                if key in failed:
                    continue
                print(f"run {i + 1}/{a.runs}: {d} {lane['name']}", file=sys.stderr)
                r = bench(lane, icds[d], a.scenes)
                if isinstance(r, str):
                    failed[key] = r
                else:
                    runs[key].append(r)
    if (failed.keys() & {(d, lanes[0]["name"]) for d in drivers}):
        sys.exit(f"the base lane failed: {failed}")
    every = [l["name"] for l in lanes]
    base = every[0]
    for d in drivers:
        print(f"\n{d} lavapipe: GPU f32, medians of {a.runs} interleaved runs\n")
        for n in every:
            if (d, n) in failed:
                print(f"{n} failed on {d}: {failed[(d, n)]}\n")
        names = [n for n in every if (d, n) not in failed]
        head = " | ".join(names) + " | " + " | ".join(f"{n}/{base}" for n in names[1:])
        print(f"| scene | {head} |")
        print("|---|" + "---|" * (2 * len(names) - 1))
        ratios = {n: [] for n in names[1:]}
        cpu_ratios = {n: [] for n in names[1:]}
        for scene in runs[(d, base)][0]:
            t = {n: statistics.median(r[scene][0] for r in runs[(d, n)]) for n in names}
            cpu = {n: statistics.median(r[scene][1] for r in runs[(d, n)]) for n in names}
            for n in names[1:]:
                ratios[n].append(t[n] / t[base])
                cpu_ratios[n].append(cpu[n] / cpu[base])
            cells = " | ".join(f"{t[n]:.4f} s" for n in names)
            rcells = " | ".join(f"{t[n] / t[base]:.2f}" for n in names[1:])
            print(f"| {os.path.basename(scene)} | {cells} | {rcells} |")
        for n in names[1:]:
            r = ratios[n]
            c = cpu_ratios[n]
            print(
                f"\n{n}/{base} on {d}: GPU median {statistics.median(r):.2f}, {min(r):.2f}–{max(r):.2f}; "
                f"CPU f32 median {statistics.median(c):.2f}, {min(c):.2f}–{max(c):.2f}"
            )


if __name__ == "__main__":
    main()
