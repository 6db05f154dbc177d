#!/usr/bin/env python3
"""The SPD tables of docs/spd.md, measured in one run of this checkout's
release build:

    cargo build --release && python3 benches/spd.py [--runs 3] [--bin PATH]

For each database in scenes/spd/: the ray and test counts of CPU f64 and of
the GPU (`render --stats`), beside the SPD's published ray statistics; the
times (medians of RUNS `glint compare --json`, which times a warm GPU f32
render and both CPU renders); and `compare`'s verdict, over every pixel and,
where that fails, over the well-conditioned ones. Prints Markdown.
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATABASES = ["balls", "gears", "mount", "rings", "teapot", "tetra", "tree"]
# eye hit, reflect, refract, shadow (scenes/spd/README.md)
PUBLISHED = {
    "balls": [263169, 175095, 0, 954368],
    "gears": [245086, 304643, 207564, 2246955],
    "mount": [173125, 354769, 354769, 412922],
    "rings": [263169, 315236, 0, 1085002],
    "teapot": [161120, 225248, 0, 407656],
    "tetra": [49788, 0, 0, 46112],
    "tree": [169836, 0, 0, 1097419],
}
RAYS = ["eye_hit", "reflect", "refract", "shadow"]
TESTS = ["spheres", "triangles", "cylinders", "planes", "bvh_nodes"]


def stats(glint, scene, backend, tmp):
    out = os.path.join(tmp, "stats.json")
    subprocess.run(
        [glint, "render", scene, "-o", os.path.join(tmp, "x.png"), "--force",
         "--backend", backend, "--stats", out],
        check=True, capture_output=True)
    with open(out) as f:
        return json.load(f)


def off(a, b):
    return abs(a - b) / max(a, b, 1)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--bin", default=os.path.join(
        os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target")), "release", "glint"))
    a = p.parse_args()
    rows_rays, rows_tests, rows_times, rows_cmp = [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for db in DATABASES:
            scene = os.path.join(REPO, "scenes", "spd", db + ".nff")
            cpu = stats(a.bin, scene, "cpu", tmp)
            gpu = stats(a.bin, scene, "gpu", tmp)
            rays = [cpu["rays"][k] for k in RAYS]
            rows_rays.append(f"| {db} | " + " | ".join(
                f"{g} ({p})" for g, p in zip(rays, PUBLISHED[db])) + " |")
            gpu_all = {**gpu["rays"], **gpu["tests"]}
            cpu_all = {**cpu["rays"], **cpu["tests"]}
            worst = max(off(gpu_all[k], cpu_all[k]) for k in cpu_all)
            rows_tests.append(f"| {db} | " + " | ".join(
                f"{cpu['tests'][k]}" for k in TESTS) + f" | {100 * worst:.3f} % |")
            runs = []
            for _ in range(a.runs):
                r = subprocess.run([a.bin, "compare", scene, "--json"],
                                   capture_output=True, text=True)
                runs.append(json.loads(r.stdout))
            med = lambda f: statistics.median(f(r) for r in runs)
            total = sum(cpu["rays"][k] for k in ["eye", "reflect", "refract", "shadow"])
            f64 = med(lambda r: r["cpu_f64"]["seconds"])
            rows_times.append(
                f"| {db} | {cpu['seconds']['input']:.3f} s | {cpu['seconds']['setup']:.3f} s "
                f"| {med(lambda r: r['gpu_f32']['seconds']):.3f} s "
                f"| {med(lambda r: r['cpu_f32']['seconds']):.3f} s | {f64:.3f} s "
                f"| {total / f64 / 1e6:.1f} M |")
            r = runs[0]
            e = r["gpu_f32"]["error"]
            c = r["conditioned"]
            cond = "— | — | —" if c is None else (
                f"{100 * c['ill']:.2f} % | {100 * c['error']['frac_over_1_255']:.4f} % "
                f"| {c['error']['rmse']:.1e}")
            rows_cmp.append(
                f"| {db} | {100 * e['frac_over_1_255']:.4f} % | {e['rmse']:.1e} | {cond} "
                f"| {'pass' if r['pass'] else 'FAIL'} |")
    print("| database | eye hit (published) | reflect (published) | refract (published) | shadow (published) |")
    print("|---|---|---|---|---|")
    print("\n".join(rows_rays))
    print()
    print("| database | " + " | ".join(TESTS) + " | largest GPU/CPU difference |")
    print("|---|" + "---|" * (len(TESTS) + 1))
    print("\n".join(rows_tests))
    print()
    print("| database | input | setup | GPU f32 trace | CPU f32 trace | CPU f64 trace | rays/s (CPU f64) |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(rows_times))
    print()
    print("| database | over 1/255 | rmse | ill-conditioned | over 1/255 (well-conditioned) | rmse (well-conditioned) | compare |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(rows_cmp))


if __name__ == "__main__":
    main()
