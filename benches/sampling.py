#!/usr/bin/env python3
"""Error against run time for antialiasing, measured in one run of this
checkout's release build:

    cargo build --release && python3 benches/sampling.py [SCENE ...] [--size 320x240] [--runs 3]

For each scene: a converged reference (CPU f64, 16x16 uniform samples),
then uniform sampling at 1x1, 2x2, 4x4 and 8x8, Whitted's adaptive
sampling at a few thresholds and levels, and contrast sampling at a few
thresholds and most samples, and with its range test at a few bounds
(docs/scene-format.md, Rays), each on the GPU
(f32) and the CPU (f32): the median trace time of RUNS renders (`render
--stats`, seconds.trace, setup apart) and the RMSE against the reference
(`glint diff`). Prints a Markdown table per scene, and, for each renderer
and each adaptive method, the cheapest setting that reaches uniform 4x4's
error with its share of 4x4's time (contrast sampling's two tests apart:
"contrast" rows are Mitchell's test, "range" rows the range test).
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENES = ["scenes/seed-fig5.toml", "scenes/whitted-1980.toml"]
UNIFORM = [1, 2, 4, 8]
ADAPTIVE = [(0.2, 2), (0.1, 2), (0.05, 2), (0.05, 3), (0.02, 3), (0.01, 4)]
CONTRAST = [("0.4, 0.3, 0.6", 17), (0.1, 17), (0.05, 17), (0.05, 33), (0.03, 17), (0.02, 33)]
# The range test (`range = r`, trees compared or not: "r / m" or "r / m, no trees").
RANGE = [(0.08, 33, False), (0.05, 17, False), (0.05, 33, False), (0.04, 33, False),
         (0.03, 33, False), (0.05, 33, True)]
SAMPLING_KEYS = ("samples =", "sampling =", "threshold =", "max_level =",
                 "thresholds =", "range =", "max_samples =", "compare_trees =")


def binary():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
    return os.path.join(target, "release", "glint")


def with_sampling(text, lines):
    """The scene text with its own sampling keys replaced by `lines`."""
    kept = [l for l in text.splitlines() if not l.strip().startswith(SAMPLING_KEYS)]
    out = []
    for l in kept:
        out.append(l)
        if l.strip() == "[image]":
            out.extend(lines)
    return "\n".join(out) + "\n"


def render(glint, scene, out, size, backend, precision, runs):
    """The median trace time of `runs` renders, and the last image."""
    w, h = size
    times = []
    with tempfile.TemporaryDirectory() as d:
        stats = os.path.join(d, "stats.json")
        for _ in range(runs):
            subprocess.run(
                [glint, "render", scene, "--width", str(w), "--height", str(h),
                 "--backend", backend, "--precision", precision,
                 "--stats", stats, "-o", out],
                check=True, capture_output=True)
            with open(stats) as f:
                times.append(json.load(f)["seconds"]["trace"])
    return statistics.median(times)


def rmse(glint, image, reference):
    r = subprocess.run([glint, "diff", "--json", image, reference],
                       check=True, capture_output=True, text=True)
    return json.loads(r.stdout)["rmse"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scenes", nargs="*", default=DEFAULT_SCENES)
    p.add_argument("--size", default="320x240")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--bin", default=binary())
    a = p.parse_args()
    size = tuple(int(v) for v in a.size.split("x"))
    for path in a.scenes:
        text = open(os.path.join(REPO, path)).read()
        with tempfile.TemporaryDirectory() as d:
            def scene_file(name, lines):
                f = os.path.join(d, name + ".toml")
                with open(f, "w") as out:
                    out.write(with_sampling(text, lines))
                return f

            reference = os.path.join(d, "reference.pfm")
            render(a.bin, scene_file("reference", ["samples = 16"]), reference,
                   size, "cpu", "f64", 1)
            rows = []
            settings = [(f"uniform {n}x{n}", [f"samples = {n}"]) for n in UNIFORM]
            settings += [(f"adaptive {t} / {l}",
                          ['sampling = "adaptive"', f"threshold = {t}", f"max_level = {l}"])
                         for t, l in ADAPTIVE]
            settings += [(f"contrast {t} / {m}",
                          ['sampling = "contrast"',
                           f"thresholds = [{t}]" if "," in str(t) else f"thresholds = [{t}, {t}, {t}]",
                           f"max_samples = {m}"])
                         for t, m in CONTRAST]
            settings += [(f"range {r} / {m}" + ("" if trees else ", no trees"),
                          ['sampling = "contrast"', f"range = {r}", f"max_samples = {m}",
                           f"compare_trees = {'true' if trees else 'false'}"])
                         for r, m, trees in RANGE]
            for name, lines in settings:
                f = scene_file(name.replace(" ", "_").replace("/", ""), lines)
                row = [name]
                for backend in ["gpu", "cpu"]:
                    img = os.path.join(d, f"{backend}.pfm")
                    t = render(a.bin, f, img, size, backend, "f32", a.runs)
                    row += [t, rmse(a.bin, img, reference)]
                rows.append(row)
            print(f"\n### {path} at {size[0]}x{size[1]}, against CPU f64 16x16; medians of {a.runs}\n")
            print("| sampling | GPU f32 trace | GPU RMSE | CPU f32 trace | CPU RMSE |")
            print("|---|---|---|---|---|")
            for r in rows:
                print(f"| {r[0]} | {r[1]:.3f} s | {r[2]:.2e} | {r[3]:.3f} s | {r[4]:.2e} |")
            four = next(r for r in rows if r[0] == "uniform 4x4")
            for method in ["adaptive", "contrast", "range"]:
                for label, t_i, e_i in [("GPU", 1, 2), ("CPU", 3, 4)]:
                    reaching = [r for r in rows if r[0].startswith(method) and r[e_i] <= four[e_i]]
                    if reaching:
                        best = min(reaching, key=lambda r: r[t_i])
                        print(f"\n{label}: {best[0]} reaches uniform 4x4's RMSE ({four[e_i]:.2e}) "
                              f"with {best[e_i]:.2e} in {best[t_i] / four[t_i]:.2f} of its time")
                    else:
                        print(f"\n{label}: no {method} setting here reaches uniform 4x4's RMSE ({four[e_i]:.2e})")


if __name__ == "__main__":
    main()
