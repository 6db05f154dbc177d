#!/usr/bin/env python3
"""Render time against object count: the sphereflake at levels 1-6 and
random sphere fields, on the GPU and the CPU, through the BVH; the linear
scan (--accel none) on the GPU where it still fits llvmpipe's loop budget.

    python3 benches/scale.py [--runs 3] [--levels 1 2 3 4 5 6] [--fields 200 2000 20000 200000] [-o DIR]

Levels 1-4 and field-2000 come from scenes/scale/; the others are written
to a temporary directory by scenes/scale/generate.py. Each point is the
median of RUNS `glint compare --json` runs (a warm GPU f32 render, CPU f32
and CPU f64). Prints a Markdown table; with -o also writes DIR/scale.md and
DIR/scale.svg (a log-log plot).
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KEPT = os.path.join(REPO, "scenes", "scale")


def glint():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "glint"], cwd=REPO, check=True)
    return os.path.join(target, "release", "glint")


def scene_path(tmp, name, make):
    kept = os.path.join(KEPT, name)
    if os.path.exists(kept):
        return kept
    path = os.path.join(tmp, name)
    if not os.path.exists(path):
        subprocess.run([sys.executable, os.path.join(KEPT, "generate.py"), tmp, *make], check=True)
    return path


def count_spheres(path):
    with open(path) as f:
        return sum(1 for line in f if line.startswith("[[spheres]]"))


def measure(binary, path, runs, extra):
    rows = []
    for _ in range(runs):
        out = subprocess.run([binary, "compare", path, "--json", *extra], capture_output=True, text=True)
        if out.returncode not in (0, 1):
            return None, out.stderr.strip()
        rows.append(json.loads(out.stdout))
    med = lambda f: statistics.median(f(r) for r in rows)
    return {
        "gpu": med(lambda r: r["gpu_f32"]["seconds"]),
        "cpu32": med(lambda r: r["cpu_f32"]["seconds"]),
        "cpu64": med(lambda r: r["cpu_f64"]["seconds"]),
        "load": med(lambda r: r["load_s"]),
        "bvh": med(lambda r: r["gpu_f32"]["times"]["bvh_s"]),
        "pass": all(r["pass"] for r in rows),
        "over": med(lambda r: r["gpu_f32"]["error"]["frac_over_1_255"]),
    }, None


def svg(points, path):
    """points: {series: [(count, seconds)]}; a log-log plot."""
    w, h, m = 640, 420, 60
    xs = [c for s in points.values() for c, _ in s]
    ys = [t for s in points.values() for _, t in s]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    px = lambda c: m + (math.log10(c) - x0) / (x1 - x0) * (w - 2 * m)
    py = lambda t: h - m - (math.log10(t) - y0) / (y1 - y0) * (h - 2 * m)
    colours = ["#c0392b", "#2471a3", "#999999", "#e67e22", "#5dade2", "#1e8449"]
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">']
    out.append(f'<rect width="{w}" height="{h}" fill="white"/>')
    for e in range(x0, x1 + 1):
        x = px(10**e)
        out.append(f'<line x1="{x:.1f}" y1="{m}" x2="{x:.1f}" y2="{h - m}" stroke="#ddd"/>')
        out.append(f'<text x="{x:.1f}" y="{h - m + 16}" text-anchor="middle">1e{e}</text>')
    for e in range(y0, y1 + 1):
        y = py(10**e)
        out.append(f'<line x1="{m}" y1="{y:.1f}" x2="{w - m}" y2="{y:.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{m - 6}" y="{y + 4:.1f}" text-anchor="end">1e{e} s</text>')
    out.append(f'<text x="{w / 2}" y="{h - 14}" text-anchor="middle">spheres (log)</text>')
    for i, (name, pts) in enumerate(points.items()):
        col = colours[i % len(colours)]
        pts = sorted(pts)
        d = " ".join(f"{px(c):.1f},{py(t):.1f}" for c, t in pts)
        out.append(f'<polyline points="{d}" fill="none" stroke="{col}" stroke-width="2"/>')
        for c, t in pts:
            out.append(f'<circle cx="{px(c):.1f}" cy="{py(t):.1f}" r="3" fill="{col}"/>')
        out.append(f'<text x="{m + 10 + 190 * (i // 3)}" y="{14 + 14 * (i % 3)}" fill="{col}">{name}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--levels", type=int, nargs="*", default=[1, 2, 3, 4, 5, 6])
    ap.add_argument("--fields", type=int, nargs="*", default=[200, 2000, 20000, 200000])
    ap.add_argument("-o", dest="out")
    a = ap.parse_args()
    binary = glint()
    tmp = tempfile.mkdtemp(prefix="glint-scale-")
    scenes = [(f"flake-{l}", ["--levels", str(l), "--fields"]) for l in a.levels]
    scenes += [(f"field-{n}", ["--levels", "--fields", str(n)]) for n in a.fields]
    table = []
    # One line per renderer and family: a sphereflake and a random field of
    # the same count cost differently.
    points = {}
    for name, make in scenes:
        path = scene_path(tmp, f"{name}.toml", make)
        n = count_spheres(path)
        print(f"{name} ({n} spheres) ...", file=sys.stderr)
        r, err = measure(binary, path, a.runs, ["--accel", "bvh"])
        if r is None:
            table.append(f"| {name} | {n} | {err} |")
            continue
        family = "flakes" if name.startswith("flake") else "fields"
        points.setdefault(f"GPU f32, {family}", []).append((n, r["gpu"]))
        points.setdefault(f"CPU f32, {family}", []).append((n, r["cpu32"]))
        none = "-"
        if n <= 100:
            rn, err = measure(binary, path, a.runs, ["--accel", "none"])
            if rn:
                none = f"{rn['gpu']:.3f} s"
                points.setdefault(f"GPU f32 none, {family}", []).append((n, rn["gpu"]))
        table.append(
            f"| {name} | {n} | {r['load']:.2f} s | {r['bvh']:.3f} s | {r['gpu']:.3f} s | {none} "
            f"| {r['cpu32']:.3f} s | {r['cpu64']:.3f} s | {r['cpu32'] / r['gpu']:.2f} "
            f"| {100 * r['over']:.3f} % {'pass' if r['pass'] else 'FAIL'} |"
        )
    head = (
        f"medians of {a.runs} runs of `glint compare --json --accel bvh` (512x512, depth 5, 3 lights, shadows)\n\n"
        "| scene | spheres | load | BVH build | GPU f32 | GPU f32, none | CPU f32 | CPU f64 | CPU f32 / GPU | GPU over 1/255, compare |\n"
        "|---|---|---|---|---|---|---|---|---|---|"
    )
    text = head + "\n" + "\n".join(table) + "\n"
    print(text)
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        with open(os.path.join(a.out, "scale.md"), "w") as f:
            f.write(text)
        svg({k: v for k, v in points.items() if v}, os.path.join(a.out, "scale.svg"))


if __name__ == "__main__":
    main()
