#!/usr/bin/env python3
"""Writes the OBJ meshes that scenes/triangles.toml reads: a unit icosphere
subdivided twice (320 faces), with vertex normals (icosphere-smooth.obj) and
without (icosphere-flat.obj), and a unit octahedron (octahedron.obj), a
closed mesh whose shared edges and vertices the watertightness test aims at.

Run from anywhere: python3 scenes/meshes/generate.py
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def icosphere(levels):
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9),
             (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2),
             (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
             (8, 6, 7), (9, 8, 1)]
    verts = [unit(v) for v in verts]
    for _ in range(levels):
        mid = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                va, vb = verts[a], verts[b]
                verts.append(unit(tuple((x + y) / 2 for x, y in zip(va, vb))))
                mid[key] = len(verts) - 1
            return mid[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return verts, faces


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def write(name, verts, faces, normals, comment):
    with open(os.path.join(HERE, name), "w") as f:
        f.write(f"# {comment}\n# Written by scenes/meshes/generate.py.\n")
        for v in verts:
            f.write("v %.9f %.9f %.9f\n" % v)
        if normals:
            for v in verts:
                f.write("vn %.9f %.9f %.9f\n" % v)
        for a, b, c in faces:
            if normals:
                f.write(f"f {a+1}//{a+1} {b+1}//{b+1} {c+1}//{c+1}\n")
            else:
                f.write(f"f {a+1} {b+1} {c+1}\n")


verts, faces = icosphere(2)
write("icosphere-smooth.obj", verts, faces, True,
      "A unit icosphere, subdivided twice, with vertex normals.")
write("icosphere-flat.obj", verts, faces, False,
      "A unit icosphere, subdivided twice, without normals (flat shading).")
octa = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
octa_faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4),
              (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
write("octahedron.obj", octa, octa_faces, False,
      "A unit octahedron: closed, every edge shared by two faces.")
