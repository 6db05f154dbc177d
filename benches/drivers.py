#!/usr/bin/env python3
"""glint bench on several lavapipes (or binaries) in one run, interleaved
scene by scene, so that every lane sees the same machine load.

    python3 benches/drivers.py [SCENE ...] [--runs 3] [--old BINARY]

Lanes: this checkout's release binary on the default lavapipe (the ICD in
/usr/share/vulkan/icd.d) and on Debian 12's stock 22.3 (ci/old-lavapipe);
with --old BINARY (a build of another commit, e.g. from `git worktree
add`), that binary on 22.3 too; with --chroot DIR (benches/sid-chroot),
the same binary inside that chroot on its lavapipe (Debian unstable's). Each lane runs `glint bench SCENE --json`
with VK_DRIVER_FILES pointing at its ICD file. Prints a Markdown table:
GPU f32 and CPU f32 medians, GPU/CPU per lane, the new build's 25-over-22.3
GPU ratio, the new/old ratio on 22.3, and the BVH scenes' share of the
device's ceiling.
"""

import argparse
import glob
import json
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def default_scenes():
    return sorted(glob.glob(os.path.join(REPO, "scenes", "*.toml"))) + sorted(
        glob.glob(os.path.join(REPO, "scenes", "spd", "*.nff"))
    )


def bench(binary, icd, scene, runs, extra, chroot=None):
    env = dict(os.environ, VK_DRIVER_FILES=icd, VK_ICD_FILENAMES=icd)
    command = [binary, "bench", scene, "--json", "--runs", str(runs), *extra]
    if chroot:
        # The chroot holds the binary and the scenes under /glint.
        scene = "/glint/" + os.path.relpath(scene, REPO)
        command = ["chroot", chroot, "env", f"VK_DRIVER_FILES={icd}", "/glint/glint",
                   "bench", scene, "--json", "--runs", str(runs), *extra]
    out = subprocess.run(
        command,
        capture_output=True,
        text=True,
        env=env,
        check=False,
        cwd=REPO,
    )
    if out.returncode != 0:
        sys.exit(f"{binary} bench {scene} on {icd}: {out.stderr.strip()}")
    d = json.loads(out.stdout)
    s = d["scenes"][0]
    # As the bench's own ceiling column: ray-primitive tests, node visits left out.
    tests = sum(n for w in s["by_ray"].values() for k, n in w["tests"].items() if k != "bvh_nodes")
    return {
        "driver": d["device"]["driver"],
        "gpu": s["gpu_f32_s"],
        "cpu": s["cpu_f32_s"],
        "ceiling": d["ceiling"]["tests_per_s"],
        "tests": tests,
        "bvh": s["tests"].get("bvh_nodes", 0) > 0,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--old", help="a glint binary of another commit, run on 22.3")
    ap.add_argument("--naive", action="store_true", help="also the naive forms on the default driver")
    ap.add_argument("--chroot", help="a chroot made by benches/sid-chroot: its lavapipe as a lane")
    a = ap.parse_args()
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    new = os.path.join(target, "release", "glint")
    default_icd = sorted(glob.glob("/usr/share/vulkan/icd.d/lvp_icd*.json"))[0]
    old_icd = subprocess.run(
        [os.path.join(REPO, "ci", "old-lavapipe")], capture_output=True, text=True, check=True
    ).stdout.strip()
    lanes = [("new", new, default_icd, [], None), ("new@22.3", new, old_icd, [], None)]
    if a.old:
        lanes.append(("old@22.3", a.old, old_icd, [], None))
    if a.naive:
        lanes.append(("naive", new, default_icd, ["--intersect", "naive"], None))
    mounted = []
    if a.chroot:
        icd = sorted(glob.glob(os.path.join(a.chroot, "usr/share/vulkan/icd.d/lvp_icd*.json")))[0]
        lanes.append(("sid", None, "/" + os.path.relpath(icd, a.chroot), [], a.chroot))
        # lavapipe counts the CPUs through /sys and /proc.
        for fs in ["proc", "sys"]:
            subprocess.run(["mount", "--bind", f"/{fs}", os.path.join(a.chroot, fs)], check=True)
            mounted.append(os.path.join(a.chroot, fs))
    try:
        rows = run_lanes(a, lanes)
    finally:
        for m in mounted:
            subprocess.run(["umount", m], check=False)
    print_table(a, rows)


def run_lanes(a, lanes):
    rows = []
    for scene in a.scenes or default_scenes():
        scene = os.path.abspath(scene)
        r = {name: bench(b, icd, scene, a.runs, extra, chroot) for name, b, icd, extra, chroot in lanes}
        rows.append((os.path.basename(scene), r))
        print(f"{rows[-1][0]}: " + ", ".join(f"{n} {v['gpu']:.4f}s" for n, v in r.items()), file=sys.stderr)
    return rows


def print_table(a, rows):
    first = rows[0][1]
    sid = f", sid {first['sid']['driver']}" if a.chroot else ""
    print(f"drivers: default {first['new']['driver']}, old {first['new@22.3']['driver']}{sid}; medians of {a.runs}\n")
    head = "| scene | GPU 25 | CPU | GPU/CPU 25 | GPU 22.3 | GPU/CPU 22.3 | GPU 25/22.3 |"
    sep = "|---|---|---|---|---|---|---|"
    if a.old:
        head += " old GPU 22.3 | new/old 22.3 |"
        sep += "---|---|"
    if a.naive:
        head += " robust/naive |"
        sep += "---|"
    if a.chroot:
        head += " GPU sid | GPU/CPU sid | sid/25 |"
        sep += "---|---|---|"
    head += " ceiling share (25) |"
    sep += "---|"
    print(head)
    print(sep)
    for name, r in rows:
        n, o = r["new"], r["new@22.3"]
        line = (
            f"| {name} | {n['gpu']:.4f} s | {n['cpu']:.4f} s | {n['gpu'] / n['cpu']:.2f} | "
            f"{o['gpu']:.4f} s | {o['gpu'] / o['cpu']:.2f} | {n['gpu'] / o['gpu']:.2f} |"
        )
        if a.old:
            line += f" {r['old@22.3']['gpu']:.4f} s | {o['gpu'] / r['old@22.3']['gpu']:.2f} |"
        if a.naive:
            line += f" {n['gpu'] / r['naive']['gpu']:.2f} |"
        if a.chroot:
            d = r["sid"]
            line += f" {d['gpu']:.4f} s | {d['gpu'] / d['cpu']:.2f} | {d['gpu'] / n['gpu']:.2f} |"
        share = 100.0 * n["tests"] / n["gpu"] / n["ceiling"]
        line += f" {share:.1f} %{' (BVH)' if n['bvh'] else ''} |"
        print(line)


if __name__ == "__main__":
    main()
