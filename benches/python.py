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

3. A notebook's sweep (issue 60), in one process on one renderer: a scene
   of a 20,000-triangle mesh given as numpy arrays and a sphere, per frame
   a colour changed, the sphere moved, the camera moved, each two ways:
   through `scene.params` then `render` (the scene updated in place on the
   device), and edited as a dict then `Scene.from_dict` and `render` (a
   new scene, prepared anew). Against a repeat render of the unchanged
   scene (`render` of the same scene again) and a fresh `glint.load` and
   render of the same scene from files. It prints each median (of at
   least 10 frames), how many frames compiled a shader, and the frames
   over the repeat render; it fails where a frame compiled, or a params
   frame is not the bits of a fresh render of its scene.
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
    swept = sweep(a.runs)
    return 0 if same and swept else 1


def set_in(d, key, value):
    """Sets a params key ("spheres[0].center") in the scene's dict."""
    import re

    *path, last = re.findall(r"[^.\[\]]+", key)
    for step in path:
        d = d[int(step)] if step.isdigit() else d[step]
    d[int(last) if last.isdigit() else last] = value


def grid_mesh(n):
    """An n x n grid of quads over a bumpy surface: 2 (n - 1)^2 triangles."""
    import numpy as np

    u, v = np.meshgrid(np.linspace(-1.5, 1.5, n), np.linspace(-1.5, 1.5, n))
    z = 0.15 * np.sin(3 * u) * np.cos(2 * v) - 0.5
    vertices = np.stack([u.ravel(), z.ravel(), v.ravel()], axis=1)
    i = np.arange(n * n).reshape(n, n)
    a, b, c, d = i[:-1, :-1].ravel(), i[:-1, 1:].ravel(), i[1:, :-1].ravel(), i[1:, 1:].ravel()
    faces = np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)])
    return vertices, faces


def sweep(runs):
    import numpy as np
    import glint

    vertices, faces = grid_mesh(101)
    d = {
        "image": {"width": 320, "height": 240},
        "camera": {"eye": [0, 1.5, 4], "look_at": [0, -0.3, 0], "vfov": 45},
        "materials": {
            "ground": {"ambient": [0.1, 0.1, 0.1], "diffuse": [0.6, 0.6, 0.6]},
            "ball": {"ambient": [0.1, 0.0, 0.0], "diffuse": [0.8, 0.2, 0.2], "reflectivity": 0.3},
        },
        "meshes": [{"vertices": vertices, "faces": faces, "material": "ground"}],
        "spheres": [{"center": [0, 0, 0], "radius": 0.3, "material": "ball"}],
        "lights": [{"type": "point", "position": [2, 3, 4], "diffuse": [1, 1, 1]}],
    }
    # Every render here counts its rays (stats=True: the frames need
    # stats["compiled"]), the repeat too, so that the ratios compare one
    # variant with itself.
    r = glint.Renderer()
    scene = glint.Scene.from_dict(d)
    r.render(scene, stats=True)
    repeat = []
    for _ in range(max(runs, 10)):
        t0 = time.perf_counter()
        r.render(scene, stats=True)
        repeat.append(time.perf_counter() - t0)

    def frames(edit, by_params):
        times, compiled, same = [], 0, True
        # The renderer keeps one scene prepared: this one, again.
        r.render(scene, stats=True)
        for k in range(max(runs, 10)):
            key, value = edit(k)
            t0 = time.perf_counter()
            if by_params:
                scene.params[key] = value
                image, stats = r.render(scene, stats=True)
            else:
                set_in(d, key, value)
                image, stats = r.render(glint.Scene.from_dict(d), stats=True)
            times.append(time.perf_counter() - t0)
            compiled += stats["compiled"]
            if by_params and k % 4 == 0:
                # The frame is a fresh scene's render, bit for bit.
                set_in(d, key, value)
                fresh = glint.Renderer().render(glint.Scene.from_dict(d), stats=True)[0]
                same &= fresh.tobytes() == image.tobytes()
        return statistics.median(times), compiled, same

    def colour(k):
        return "materials.ball.diffuse", [0.5 + 0.04 * k, 0.2, 0.2]

    def move(k):
        return "spheres[0].center", [-1.2 + 0.25 * k, 0.1 * (k % 3), 0.2 * (k % 4)]

    def camera(k):
        return "camera.eye", [0.3 * k - 1.5, 1.5, 4]

    with tempfile.TemporaryDirectory() as tmp:
        obj = os.path.join(tmp, "grid.obj")
        with open(obj, "w") as f:
            f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in vertices.tolist())
            f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces.tolist())
        text = (
            "[image]\nwidth = 320\nheight = 240\n[camera]\neye = [0, 1.5, 4]\nlook_at = [0, -0.3, 0]\n"
            "vfov = 45\n[materials.ground]\nambient = [0.1, 0.1, 0.1]\ndiffuse = [0.6, 0.6, 0.6]\n"
            "[materials.ball]\nambient = [0.1, 0.0, 0.0]\ndiffuse = [0.8, 0.2, 0.2]\nreflectivity = 0.3\n"
            '[[meshes]]\nfile = "grid.obj"\nmaterial = "ground"\n'
            '[[spheres]]\ncenter = [0, 0, 0]\nradius = 0.3\nmaterial = "ball"\n'
            '[[lights]]\ntype = "point"\nposition = [2, 3, 4]\ndiffuse = [1, 1, 1]\n'
        )
        path = os.path.join(tmp, "grid.toml")
        with open(path, "w") as f:
            f.write(text)
        fresh = []
        for _ in range(runs):
            t0 = time.perf_counter()
            glint.render(glint.load(path), stats=True, renderer=r)
            fresh.append(time.perf_counter() - t0)

    base = statistics.median(repeat)
    print(f"sweep          {len(faces)} triangles from numpy and a sphere, 320x240, one renderer, medians")
    print(f"  repeat render of the scene           {base:.4f} s")
    print(f"  fresh glint.load and render          {statistics.median(fresh):.4f} s   (files, the same renderer)")
    ok = True
    for name, edit in [("colour changed", colour), ("sphere moved", move), ("camera moved", camera)]:
        for by_params, how in [(True, "params + render   "), (False, "from_dict + render")]:
            t, compiled, same = frames(edit, by_params)
            ok &= compiled == 0 and same
            print(f"  {name:15s} {how}   {t:.4f} s   {t / base:.2f}x the repeat   compiled {compiled}"
                  + ("" if not by_params else f"   same bits as fresh: {same}"))
    return ok


if __name__ == "__main__":
    sys.exit(main())
