#!/usr/bin/env python3
"""One design choice measured on both lavapipes: `glint bench --json` with
each lane's options, on the default driver and on Debian 12's stock 22.3
(ci/old-lavapipe), runs interleaved lane by lane and driver by driver so
that every lane sees the same machine load.

    python3 benches/choices.py --lane base= --lane pair="-I shaders/experiments/walk -D PAIR_VISIT" \\
        [--runs 3] [--drivers default,22.3] [--metric wall|cpu] [SCENE ...]

A lane is NAME=ARGS: ARGS are glint bench options (shell words), and two
kinds of word are taken by this script: `bin:PATH` runs another glint
binary (a build with other constants), `env:NAME=VALUE` sets a variable
(GLINT_EXPERIMENT=...). The first lane is the base. Each run is one
`glint bench --runs 1` (a warm-up, then one timed GPU f32 render a scene; --inner K: the
median of K). `--metric cpu` takes the CPU seconds the process spends in
each GPU render instead of its wall time: on lavapipe that is the render's
work, which a shared machine disturbs less.
Prints, for each driver, the medians of the GPU f32 times and each lane's
ratio to the base, as a Markdown table, and the median of those ratios and
of the CPU f32 ratios (which move only where a lane's binary builds the
scene differently, e.g. its BVH).

On a machine with a real GPU (ci/gpu-check), `--drivers device` leaves
the Vulkan driver as the environment has it (a lane's `--device NAME`
picks the device), and `--metric gpu` takes the GPU render's wall time
with no CPU reference (`glint bench --gpu-only`): a GPU's work is not the
process's CPU seconds.
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


def bench(lane, icd, scenes, metric, inner):
    extra = ["--gpu-only"] if metric in ("cpu", "gpu") else []
    cmd = [lane["binary"], "bench", "--json", "--runs", str(inner), *extra, *lane["args"], *scenes]
    # icd None: the driver the environment names (--drivers device).
    driver = {} if icd is None else {"VK_DRIVER_FILES": icd}
    env = dict(os.environ, **driver, **lane["env"])
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO, env=env)
    if out.returncode != 0:
        # A lane that fails (a driver's crash, the watchdog) is reported as
        # failed beside the others rather than ending the measurement.
        print(f"{' '.join(cmd)}: {out.stderr.strip()}", file=sys.stderr)
        return out.stderr.strip().splitlines()[-1] if out.stderr.strip() else f"exit {out.returncode}"
    scenes = json.loads(out.stdout)["scenes"]
    if metric == "cpu":
        # The GPU render's CPU seconds (lavapipe's work); no CPU reference.
        return {s["scene"]: (s["gpu_f32_cpu_s"], None) for s in scenes}
    if metric == "gpu":
        return {s["scene"]: (s["gpu_f32_s"], None) for s in scenes}
    return {s["scene"]: (s["gpu_f32_s"], s["cpu_f32_s"]) for s in scenes}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--lane", action="append", required=True, help="NAME=ARGS (the first is the base)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument(
        "--drivers",
        default="default,22.3",
        help="default, 22.3 or both, comma-separated; or device: the driver the environment names",
    )
    ap.add_argument(
        "--metric",
        choices=["wall", "cpu", "gpu"],
        default="wall",
        help="wall: the GPU render's wall time (and the CPU reference's); cpu: the CPU seconds "
        "the process spends in the GPU render, lavapipe's work, steadier on a shared machine "
        "(glint bench --gpu-only); gpu: the GPU render's wall time alone (--gpu-only)",
    )
    ap.add_argument("--inner", type=int, default=1, help="timed renders a scene in each glint bench (its median)")
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    ap.add_argument("--binary", default=os.path.join(target, "release", "glint"))
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    lanes = [parse_lane(t, a.binary) for t in a.lane]
    icds = {"default": DEFAULT_ICD, "22.3": None, "device": None}
    drivers = [d.strip() for d in a.drivers.split(",") if d.strip()]
    for d in drivers:
        if d not in icds:
            sys.exit(f"--drivers: {d!r} is not default, 22.3 or device")
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
                r = bench(lane, icds[d], a.scenes, a.metric, a.inner)
                if isinstance(r, str):
                    failed[key] = r
                else:
                    runs[key].append(r)
    if (failed.keys() & {(d, lanes[0]["name"]) for d in drivers}):
        sys.exit(f"the base lane failed: {failed}")
    every = [l["name"] for l in lanes]
    base = every[0]
    for d in drivers:
        what = "CPU seconds of the GPU f32 render" if a.metric == "cpu" else "GPU f32"
        where = "the environment's driver" if d == "device" else f"{d} lavapipe"
        print(f"\n{where}: {what}, medians of {a.runs} interleaved runs\n")
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
            for n in names[1:]:
                ratios[n].append(t[n] / t[base])
                if a.metric == "wall":
                    cpu = {m: statistics.median(r[scene][1] for r in runs[(d, m)]) for m in (base, n)}
                    cpu_ratios[n].append(cpu[n] / cpu[base])
            cells = " | ".join(f"{t[n]:.4f} s" for n in names)
            rcells = " | ".join(f"{t[n] / t[base]:.2f}" for n in names[1:])
            print(f"| {os.path.basename(scene)} | {cells} | {rcells} |")
        for n in names[1:]:
            r = ratios[n]
            c = cpu_ratios[n]
            line = f"\n{n}/{base} on {d}: GPU median {statistics.median(r):.2f}, {min(r):.2f}–{max(r):.2f}"
            if c:
                line += f"; CPU f32 median {statistics.median(c):.2f}, {min(c):.2f}–{max(c):.2f}"
            print(line)


if __name__ == "__main__":
    main()
