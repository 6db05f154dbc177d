#!/usr/bin/env python3
"""What the Python module adds to a render (docs/python.md, Speed):
seed-fig5 at 1920x1080, through `import glint` and through the binary.

    v/bin/python benches/python.py [--runs 5] [--binary target/release/glint] [SCENE]

Run it with the Python of a virtual environment that has the module
(`pip install ./python`). It prints two figures:

1. Whole process, runs interleaved: `glint render SCENE -o X.pfm` against
   a Python process that imports glint, loads the scene, renders it and
   writes the same PFM, and how long `python -c "import glint"` takes
   alone. Both renders take the SPIR-V and pipelines from the same
   cache (warmed by one untimed run each), and the two images must be the
   same bits.
2. In one process: a prepared scene's `render()`, timed around the Python
   call, against the library's own time for that render
   (`stats["seconds"]["call"]`, the wall time of `gpu::Prepared::render`
   as the binary calls it): what the module adds to a render (the GIL
   released and taken, the thread, the array handed to numpy).

The budget is 5 % of the binary's time or 20 ms, whichever is larger.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

PYTHON_RENDER = """
import sys, glint
scene = glint.load(sys.argv[1], width=int(sys.argv[3]), height=int(sys.argv[4]))
glint.write(glint.render(scene), sys.argv[2])
"""


def timed(cmd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, cwd=REPO)
    return time.perf_counter() - t0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene", nargs="?", default="scenes/seed-fig5.toml")
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--width", type=int, default=1920)
    p.add_argument("--height", type=int, default=1080)
    p.add_argument("--binary", default=os.path.join(
        os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target")), "release", "glint"))
    a = p.parse_args()

    import numpy as np
    import glint

    size = [str(a.width), str(a.height)]
    with tempfile.TemporaryDirectory() as tmp:
        out_b, out_p = os.path.join(tmp, "binary.pfm"), os.path.join(tmp, "python.pfm")
        binary = [a.binary, "render", a.scene, "--width", size[0], "--height", size[1], "-o", out_b]
        python = [sys.executable, "-c", PYTHON_RENDER, a.scene, out_p, *size]
        timed(binary)
        timed(python)
        same = glint.read(out_b).tobytes() == glint.read(out_p).tobytes()
        start = [sys.executable, "-c", "import glint"]
        tb, tp, ts = [], [], []
        for _ in range(a.runs):
            tb.append(timed(binary))
            tp.append(timed(python))
            ts.append(timed(start))
    mb, mp, ms = statistics.median(tb), statistics.median(tp), statistics.median(ts)
    budget = max(0.05 * mb, 0.020)
    print(f"{a.scene} at {a.width}x{a.height}, {a.runs} interleaved runs, medians")
    print(f"whole process  binary {mb:.3f} s   python {mp:.3f} s   python/binary {mp / mb:.3f}"
          f"   added {1000 * (mp - mb):+.1f} ms (budget {1000 * budget:.1f} ms)"
          f"   images {'the same bits' if same else 'DIFFER'}")
    print(f"of which       python -c 'import glint' {ms:.3f} s (the interpreter, numpy and the module)")

    scene = glint.load(os.path.join(REPO, a.scene), width=a.width, height=a.height)
    prepared = glint.Renderer().prepare(scene)
    prepared.render()
    walls, traces = [], []
    for _ in range(a.runs):
        t0 = time.perf_counter()
        image, stats = prepared.render(stats=True)
        walls.append(time.perf_counter() - t0)
        traces.append(stats["seconds"]["call"])
    assert isinstance(image, np.ndarray)
    mw, mt = statistics.median(walls), statistics.median(traces)
    print(f"one render     python call {mw:.4f} s   library {mt:.4f} s   added {1000 * (mw - mt):+.2f} ms"
          f"   ({100 * (mw - mt) / mt:+.1f} %)")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
