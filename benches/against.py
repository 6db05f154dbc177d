#!/usr/bin/env python3
"""Speed-ups as ratios measured in one run: this checkout's glint against a
build of another commit, on the same scenes, runs interleaved so that both
see the same machine load.

    python3 benches/against.py 9cf6b52 [SCENE ...] [--runs 5] [--old-binary PATH]

Builds REV in a git worktree (the cargo target directory is shared, so only
glint itself is compiled again), then for each scene alternates
`glint compare --json` of the old and the new binary RUNS times. Each
compare times a warm GPU f32 render, CPU f32 and CPU f64. --old-binary
takes a glint already built from REV instead of building it. The new binary
also runs with --intersect naive, for the robust/naive ratio. Prints the
medians and the ratios as a Markdown table.
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENES = [
    "scenes/seed-fig3.toml",
    "scenes/seed-fig4.toml",
    "scenes/seed-fig5.toml",
    "scenes/showcase.toml",
]


def target_dir():
    return os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))


def build(src, out, target):
    """Builds glint in `src` with the target directory `target`, copies the
    binary to `out`."""
    env = dict(os.environ, CARGO_TARGET_DIR=target)
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "glint"], cwd=src, env=env, check=True)
    shutil.copy(os.path.join(target, "release", "glint"), out)


def build_rev(rev, work, out):
    """Builds glint at `rev` in a worktree under `work`, copies it to `out`."""
    tree = os.path.join(work, "tree")
    subprocess.run(["git", "worktree", "add", "--detach", "-q", tree, rev], cwd=REPO, check=True)
    try:
        # Its own target directory, seeded with a copy of this checkout's so
        # that glslang's C++ is not compiled again: two checkouts of one
        # package in one target directory confuse cargo's freshness checks.
        old_target = os.path.join(work, "target")
        if os.path.isdir(target_dir()):
            subprocess.run(["cp", "-a", target_dir(), old_target], check=True)
        print(f"building {rev} ...", file=sys.stderr)
        build(tree, out, old_target)
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", tree], cwd=REPO, check=False)
        shutil.rmtree(os.path.join(work, "target"), ignore_errors=True)


def compare(binary, scene, extra):
    out = subprocess.run(
        [binary, "compare", scene, "--json", *extra],
        capture_output=True,
        text=True,
        check=False,
    )
    if out.returncode not in (0, 1):
        sys.exit(f"{binary} compare {scene}: {out.stderr.strip()}")
    d = json.loads(out.stdout)
    return d["gpu_f32"]["seconds"], d["cpu_f32"]["seconds"], d["cpu_f64"]["seconds"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("rev")
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--old-binary", help="a glint built from REV, used instead of building it")
    a = ap.parse_args()
    scenes = a.scenes or DEFAULT_SCENES
    work = tempfile.mkdtemp(prefix="glint-against-")
    old_bin, new_bin = os.path.join(work, "glint-old"), os.path.join(work, "glint-new")
    if a.old_binary:
        shutil.copy(a.old_binary, old_bin)
    else:
        build_rev(a.rev, work, old_bin)
    print("building this checkout ...", file=sys.stderr)
    build(REPO, new_bin, target_dir())

    rows = []
    for scene in scenes:
        old, new, naive = [], [], []
        for i in range(a.runs):
            print(f"{scene}: run {i + 1}/{a.runs}", file=sys.stderr)
            old.append(compare(old_bin, scene, []))
            new.append(compare(new_bin, scene, []))
            naive.append(compare(new_bin, scene, ["--intersect", "naive"]))
        med = lambda runs, k: statistics.median(r[k] for r in runs)
        rows.append(
            (
                os.path.basename(scene).removesuffix(".toml"),
                med(old, 0),
                med(new, 0),
                med(old, 1),
                med(new, 1),
                med(new, 2),
                med(naive, 0),
            )
        )
    print(f"\nmedians of {a.runs} interleaved runs; old = {a.rev}, new = this checkout\n")
    print(
        "| scene | GPU old | GPU new | GPU old/new | CPU f32 old | CPU f32 new "
        "| CPU f64 new | GPU new / CPU f32 new | robust/naive (GPU new) |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for name, g0, g1, c0, c1, d1, n1 in rows:
        print(
            f"| {name} | {g0:.4f} s | {g1:.4f} s | {g0 / g1:.2f}x | {c0:.4f} s | {c1:.4f} s "
            f"| {d1:.4f} s | {g1 / c1:.2f} | {g1 / n1:.2f} |"
        )
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
