#!/usr/bin/env python3
"""What image textures cost: scenes/textures.toml against the same scene
with its textures taken off (every `texture = ...` line dropped, the mesh
given the scene's material instead of its MTL map), on one binary, runs
interleaved.

    python3 benches/textures.py [--runs 5] [--binary PATH]

Each run is `glint compare --json` (a warm GPU f32 render, CPU f32, CPU
f64). Prints the medians and the ratios as a Markdown table.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(REPO, "scenes", "textures.toml")


def plain_copy():
    """The scene without textures, beside it (its paths are relative)."""
    text = open(SCENE).read()
    lines = [l for l in text.splitlines() if not l.startswith("texture = ")]
    text = "\n".join(lines).replace(
        'file = "meshes/globe.obj"', 'file = "meshes/globe.obj"\nmaterial = "globe"'
    )
    text = text.replace("[materials.globe]", "[materials.globe]\ndiffuse = [0.5, 0.5, 0.5]")
    path = os.path.join(REPO, "scenes", ".textures-plain.toml")
    with open(path, "w") as f:
        f.write(text + "\n")
    return path


def compare(binary, scene):
    out = subprocess.run([binary, "compare", scene, "--json"], capture_output=True, text=True)
    if out.returncode not in (0, 1):
        sys.exit(f"{binary} compare {scene}: {out.stderr.strip()}")
    d = json.loads(out.stdout)
    return [d[k]["seconds"] for k in ("gpu_f32", "cpu_f32", "cpu_f64")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    ap.add_argument("--binary", default=os.path.join(target, "release", "glint"))
    a = ap.parse_args()
    plain = plain_copy()
    try:
        textured, untextured = [], []
        for i in range(a.runs):
            print(f"run {i + 1}/{a.runs}", file=sys.stderr)
            textured.append(compare(a.binary, SCENE))
            untextured.append(compare(a.binary, plain))
    finally:
        os.remove(plain)
    print(f"\nscenes/textures.toml, medians of {a.runs} interleaved runs\n")
    print("| renderer | textured | untextured | textured / untextured |")
    print("|---|---|---|---|")
    for k, name in enumerate(["GPU f32", "CPU f32", "CPU f64"]):
        t = statistics.median(r[k] for r in textured)
        u = statistics.median(r[k] for r in untextured)
        print(f"| {name} | {t:.4f} s | {u:.4f} s | {t / u:.2f} |")


if __name__ == "__main__":
    main()
