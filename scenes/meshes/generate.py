#!/usr/bin/env python3
"""Writes the OBJ meshes that scenes/triangles.toml reads: a unit icosphere
subdivided twice (320 faces), with vertex normals (icosphere-smooth.obj) and
without (icosphere-flat.obj), and a unit octahedron (octahedron.obj), a
closed mesh whose shared edges and vertices the watertightness test aims at.
And the textured mesh that scenes/textures.toml reads: a unit globe of
latitude and longitude (globe.obj, 24 x 12 quads with vt and vn), its MTL
file (globe.mtl: map_Kd globe.png) and its texture (globe.png, 128 x 64,
8-bit sRGB), a map of bands and meridians that shows which way uv runs.

Run from anywhere: python3 scenes/meshes/generate.py
"""
import math
import os
import struct
import zlib

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


def globe(lon, lat):
    """A UV sphere: (lon + 1) x (lat + 1) vertices (the seam and the poles
    repeated, each with its own vt), and two triangles a quad."""
    verts, uvs, faces = [], [], []
    for j in range(lat + 1):
        theta = math.pi * j / lat  # from the +y pole down
        for i in range(lon + 1):
            phi = 2 * math.pi * i / lon
            verts.append((-math.sin(theta) * math.sin(phi), math.cos(theta),
                          -math.sin(theta) * math.cos(phi)))
            uvs.append((i / lon, 1 - j / lat))
    for j in range(lat):
        for i in range(lon):
            a = j * (lon + 1) + i
            b, c, d = a + 1, a + lon + 1, a + lon + 2
            # Counter-clockwise seen from outside; the poles' quads lose a
            # corner and become one triangle.
            if j > 0:
                faces.append((a, c, b))
            if j < lat - 1:
                faces.append((b, c, d))
    return verts, uvs, faces


def png(name, width, height, pixel):
    """An 8-bit RGB PNG of pixel(x, y) (rows from the top)."""
    rows = b"".join(
        b"\0" + bytes(c for x in range(width) for c in pixel(x, y))
        for y in range(height))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def globe_texel(x, y):
    # Bands of latitude in four colours, darker meridians every 16 texels,
    # and a white mark left of the middle (u < 1/2, v > 1/2), so that a
    # mirrored or upside-down mapping shows.
    bands = [(40, 90, 200), (60, 170, 90), (220, 190, 80), (200, 70, 60)]
    r, g, b = bands[(y * 8 // 64) % 4]
    if x % 16 == 0:
        r, g, b = r // 3, g // 3, b // 3
    if 40 <= x < 56 and 16 <= y < 24:
        r, g, b = 250, 250, 250
    return (r, g, b)


gverts, guvs, gfaces = globe(24, 12)
with open(os.path.join(HERE, "globe.obj"), "w") as f:
    f.write("# A unit globe of latitude and longitude, 24 x 12, with texture\n"
            "# coordinates and vertex normals.\n# Written by scenes/meshes/generate.py.\n"
            "mtllib globe.mtl\nusemtl globe\n")
    for v in gverts:
        f.write("v %.9f %.9f %.9f\n" % v)
    for t in guvs:
        f.write("vt %.9f %.9f\n" % t)
    for v in gverts:
        f.write("vn %.9f %.9f %.9f\n" % v)
    for face in gfaces:
        f.write("f " + " ".join(f"{i+1}/{i+1}/{i+1}" for i in face) + "\n")
with open(os.path.join(HERE, "globe.mtl"), "w") as f:
    f.write("# The globe's material: its map, untinted.\n"
            "# Written by scenes/meshes/generate.py.\n"
            "newmtl globe\nKa 0.1 0.1 0.1\nKd 1 1 1\nKs 0.3 0.3 0.3\nNs 40\nillum 2\n"
            "map_Kd globe.png\nmap_Ka globe.png\n")
png("globe.png", 128, 64, globe_texel)
