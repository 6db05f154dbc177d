#!/usr/bin/env python3
"""Same bits before and after a change: two glint binaries render every
scene of scenes/, scenes/spd/ and scenes/extreme/, with the default scene
management and with `--accel tables`, in f32 and f64, on the GPU (the
default lavapipe and Debian 12's, `ci/old-lavapipe`) and with the CPU
reference renderer (`--backend cpu`, no driver), and each pair of PFMs is
compared byte for byte. A pair that fails must fail the same way (the same
exit status and message). Build the base with `git worktree add`.

    python3 benches/same_bits.py --base /tmp/glint-base [--new target/release/glint] [--size 96x72] [--backends gpu,cpu]

It prints each pair that differs and a count; it exits 1 where any does.
"""

import argparse
import glob
import os
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def old_lavapipe():
    """The ICD file of Debian 12's lavapipe, or None where it cannot be had."""
    run = subprocess.run([os.path.join(REPO, "ci/old-lavapipe")], capture_output=True, text=True)
    return run.stdout.strip() if run.returncode == 0 and run.stdout.strip() else None


def render(binary, args, out, env):
    run = subprocess.run([binary, *args, "-o", out], capture_output=True, text=True, env=env, timeout=600)
    return run.returncode, run.stderr.replace(out, "OUT")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--base", required=True, help="the binary before the change")
    p.add_argument("--new", default=os.path.join(os.environ.get("CARGO_TARGET_DIR", "target"), "release/glint"))
    p.add_argument("--size", default="96x72")
    p.add_argument("--backends", default="gpu,cpu", help="gpu, cpu or both")
    a = p.parse_args()
    backends = a.backends.split(",")
    width, height = a.size.split("x")
    scenes = sorted(
        glob.glob(os.path.join(REPO, "scenes/*.toml"))
        + glob.glob(os.path.join(REPO, "scenes/spd/*.nff"))
        + glob.glob(os.path.join(REPO, "scenes/extreme/*.toml"))
    )
    drivers = [("default", None)]
    old = old_lavapipe() if "gpu" in backends else None
    if old:
        drivers.append(("22.3", old))
    elif "gpu" in backends:
        print("Debian 12's lavapipe cannot be had here: the default driver alone")
    # Each backend with the drivers it runs on: the CPU renderer needs none.
    runs = [("gpu", name, icd) for name, icd in drivers if "gpu" in backends]
    runs += [("cpu", "the CPU", None)] if "cpu" in backends else []
    pairs, differ = 0, 0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            for accel in ["auto", "tables"]:
                for precision in ["f32", "f64"]:
                    for backend, name, icd in runs:
                        env = dict(os.environ)
                        if icd:
                            env["VK_DRIVER_FILES"] = icd
                        args = ["render", scene, "--width", width, "--height", height,
                                "--accel", accel, "--precision", precision, "--backend", backend]
                        before, after = os.path.join(tmp, "b.pfm"), os.path.join(tmp, "n.pfm")
                        for f in (before, after):
                            if os.path.exists(f):
                                os.remove(f)
                        rb = render(a.base, args, before, env)
                        rn = render(a.new, args, after, env)
                        pairs += 1
                        if rb[0] != 0 or rn[0] != 0:
                            same = rb == rn
                        else:
                            with open(before, "rb") as x, open(after, "rb") as y:
                                same = x.read() == y.read()
                        if not same:
                            differ += 1
                            print(f"DIFFER {os.path.relpath(scene, REPO)} --accel {accel} {precision} --backend {backend} on {name}")
    print(f"{pairs} pairs ({len(scenes)} scenes x 2 accels x 2 precisions x {len(runs)} renderers: "
          f"{', '.join(f'{b} on {n}' if b == 'gpu' else n for b, n, _ in runs)}) at "
          f"{a.size}: {pairs - differ} the same bits, {differ} differ")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
