#!/usr/bin/env python3
"""Issue 60's probe: what a notebook session's steps cost and give, in one
process (run with the Python of a venv that has the module, from the
repository's root): a 20,000-triangle mesh loaded through `from_dict` as an
OBJ file, as numpy arrays and as `[[triangles]]` rows; 0.5 through PNG,
EXR and PFM; a numpy texture of 0.5 rendered; a sphere moved in the mesh
scene through `scene.params` against a repeat render; an AOV render against
a plain one, its ids and ray counts against the CPU's.

    v/bin/python benches/notebook_probe.py
"""

import os
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

import glint  # noqa: E402
import python as b  # noqa: E402  (benches/python.py: the grid mesh)

def med(f, n=5):
    t = []
    for _ in range(n):
        t0 = time.perf_counter(); f(); t.append(time.perf_counter() - t0)
    return statistics.median(t)

v, f = b.grid_mesh(101)
base = {"image": {"width": 64, "height": 48}, "camera": {"eye": [0, 1.5, 4], "look_at": [0, -0.3, 0], "vfov": 45},
        "materials": {"g": {"diffuse": [0.6, 0.6, 0.6]}}, "lights": [{"type": "point", "position": [2, 3, 4], "diffuse": [1, 1, 1]}]}
with tempfile.TemporaryDirectory() as tmp:
    obj = os.path.join(tmp, "grid.obj")
    with open(obj, "w") as fh:
        fh.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v.tolist())
        fh.writelines(f"f {a+1} {b_+1} {c+1}\n" for a, b_, c in f.tolist())
    d_obj = dict(base, meshes=[{"file": obj, "material": "g"}])
    d_np = dict(base, meshes=[{"vertices": v, "faces": f, "material": "g"}])
    d_tri = dict(base, triangles=[{"vertices": v[t].tolist(), "material": "g"} for t in f])
    print(f"20,000 triangles, load (from_dict), medians of 5:")
    print(f"  as an OBJ file      {med(lambda: glint.Scene.from_dict(d_obj)):.4f} s")
    print(f"  as numpy arrays     {med(lambda: glint.Scene.from_dict(d_np)):.4f} s")
    print(f"  as [[triangles]]    {med(lambda: glint.Scene.from_dict(d_tri), 3):.4f} s")
    same = glint.render(glint.Scene.from_dict(d_obj), backend="cpu").tobytes() == glint.render(glint.Scene.from_dict(d_np), backend="cpu").tobytes()
    print(f"  numpy and OBJ render the same bits: {same}")
    half = np.full((4, 4, 3), 0.5, dtype=np.float32)
    for ext in ("png", "exr", "pfm"):
        p = os.path.join(tmp, f"h.{ext}"); glint.write(half, p)
        print(f"0.5 through {ext}: {float(glint.read(p)[0, 0, 0]):.4f}")
    tex = dict(base, textures={"t": {"image": half}}, materials={"g": {"texture": "t"}},
               spheres=[{"center": [0, 0, 0], "radius": 1, "material": "g"}],
               camera={"eye": [0, 0, 5], "look_at": [0, 0, 0], "vfov": 20},
               lights=[{"type": "directional", "direction": [0, 0, -1], "diffuse": [1, 1, 1]}])
    img = glint.render(glint.Scene.from_dict(tex), backend="cpu")
    print(f"a numpy 0.5 texture, lit head-on: the centre pixel {float(img[24, 32, 0]):.4f}")
    r = glint.Renderer()
    d = dict(base, meshes=[{"vertices": v, "faces": f, "material": "g"}], spheres=[{"center": [0, 0, 0], "radius": 0.3, "material": "g"}])
    d["image"] = {"width": 320, "height": 240}
    scene = glint.Scene.from_dict(d)
    r.render(scene, stats=True)
    rep = med(lambda: r.render(scene, stats=True), 7)
    at = [0.0]

    def move():
        at[0] += 0.1
        scene.params["spheres[0].center"] = [at[0], 0, 0]
        _, st = r.render(scene, stats=True)
        assert not st["compiled"] and st["update"] == "updated in place"

    mv = med(move, 7)
    # AOVs: a render that also gives them, against the plain render, and
    # the GPU's ids and ray counts against the CPU's.
    names = ["depth", "normal", "albedo", "prim_id", "rays"]
    plain = med(lambda: r.render(scene), 7)
    with_aovs = med(lambda: r.render(scene, aovs=names), 7)
    out = r.render(scene, aovs=names)
    cpu = glint.render(scene, backend="cpu", aovs=names)
    same_ids = (out["prim_id"] == cpu["prim_id"]).all() and (out["rays"] == cpu["rays"]).all()
    hit = out["prim_id"][..., 0] >= 0
    print(f"AOVs at 320x240: a render with all five {with_aovs:.4f} s, without {plain:.4f} s "
          f"({with_aovs / plain:.2f}x); {hit.mean():.0%} of pixels hit, {int(out['rays'].sum())} rays; "
          f"GPU ids and rays the CPU's: {bool(same_ids)}")
    print(f"a sphere moved by scene.params in the 20,000-triangle scene at 320x240: {mv:.4f} s a frame, "
          f"no compile; a repeat render {rep:.4f} s ({mv / rep:.2f}x)")
