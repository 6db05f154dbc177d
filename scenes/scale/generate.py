#!/usr/bin/env python3
"""Writes the scaling scenes: the sphereflake at levels 1-6 (10, 91, 820,
7381, 66430 and 597871 spheres, built as the SPD's "balls" builds it) and
random sphere fields.

    python3 scenes/scale/generate.py [DIR] [--levels 1 2 3 4] [--fields 200 2000 20000]

Levels 1-4 and the field of 2,000 are kept in the repository; levels 5 and 6
(7 MB and 60 MB of TOML) are made when needed (`glint` benches/scale.py does).
Every scene: 512x512, max_depth 5, three point lights with shadows, as the
SPD's procedure has it (pixel centres here, not corners).
"""

import argparse
import math
import os
import random

HEADER = """# {title}
# Made by scenes/scale/generate.py; {count} spheres.

[image]
width = 512
height = 512

[render]
max_depth = 5
shadows = true
background = [0.078, 0.361, 0.753]

[camera]
eye = {eye}
look_at = {look_at}
up = {up}
vfov = 45.0

[materials.flake]
ambient = [0.1, 0.09, 0.07]
diffuse = [0.5, 0.45, 0.35]
specular = [0.5, 0.5, 0.5]
shininess = 3.0827
reflectivity = 0.5

[materials.floor]
ambient = [0.1, 0.075, 0.033]
diffuse = [0.8, 0.6, 0.264]

[[planes]]
point = {floor_point}
normal = {floor_normal}
material = "floor"
"""

LIGHTS = """
[[lights]]
type = "point"
position = {p}
ambient = [0.05, 0.05, 0.05]
diffuse = [0.6, 0.6, 0.6]
specular = [0.6, 0.6, 0.6]
"""


def vec(v):
    return "[" + ", ".join(f"{x:.9g}" for x in v) + "]"


def basis(d):
    """Two unit vectors perpendicular to unit d and to each other."""
    a = (1.0, 0.0, 0.0) if abs(d[0]) < 0.9 else (0.0, 1.0, 0.0)
    u = cross(d, a)
    u = scale(u, 1.0 / norm(u))
    return u, cross(d, u)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def scale(a, s):
    return tuple(x * s for x in a)


def add(*vs):
    return tuple(sum(c) for c in zip(*vs))


def norm(a):
    return math.sqrt(sum(x * x for x in a))


# The nine children of a sphere, as directions in its frame (u, v, axis):
# six around its equator and three above it, 54.7 degrees up (SPD balls).
UP = math.asin(math.sqrt(2.0 / 3.0))
CHILDREN = [(math.radians(60 * k), 0.0) for k in range(6)] + [
    (math.radians(30 + 120 * k), UP) for k in range(3)
]


def flake(center, radius, axis, level, out):
    out.append((center, radius))
    if level == 0:
        return
    u, v = basis(axis)
    r = radius / 3.0
    for azimuth, elevation in CHILDREN:
        d = add(
            scale(u, math.cos(elevation) * math.cos(azimuth)),
            scale(v, math.cos(elevation) * math.sin(azimuth)),
            scale(axis, math.sin(elevation)),
        )
        flake(add(center, scale(d, radius + r)), r, d, level - 1, out)


def write(path, title, spheres, eye, look_at, up, floor_point, floor_normal, lights):
    with open(path, "w") as f:
        f.write(
            HEADER.format(
                title=title,
                count=len(spheres),
                eye=vec(eye),
                look_at=vec(look_at),
                up=vec(up),
                floor_point=vec(floor_point),
                floor_normal=vec(floor_normal),
            )
        )
        for p in lights:
            f.write(LIGHTS.format(p=vec(p)))
        for c, r in spheres:
            f.write(f'\n[[spheres]]\ncenter = {vec(c)}\nradius = {r:.9g}\nmaterial = "flake"\n')


def sphereflake(directory, level):
    spheres = []
    flake((0.0, 0.0, 0.0), 0.5, (0.0, 0.0, 1.0), level, spheres)
    write(
        os.path.join(directory, f"flake-{level}.toml"),
        f"The sphereflake at level {level} (the SPD's balls is level 4).",
        spheres,
        eye=(2.1, 1.3, 1.7),
        look_at=(0.0, 0.0, 0.0),
        up=(0.0, 0.0, 1.0),
        floor_point=(0.0, 0.0, -0.5),
        floor_normal=(0.0, 0.0, 1.0),
        lights=[(4.0, 3.0, 2.0), (1.0, -4.0, 4.0), (-3.0, 1.0, 5.0)],
    )


def field(directory, n):
    rng = random.Random(n)
    side = 10.0 * n ** (1.0 / 3.0)
    radius = 1.5
    spheres = [
        (tuple(rng.uniform(-side / 2, side / 2) for _ in range(3)), radius * rng.uniform(0.3, 1.0))
        for _ in range(n)
    ]
    write(
        os.path.join(directory, f"field-{n}.toml"),
        f"A random field of {n} spheres in a cube of side {side:.1f}.",
        spheres,
        eye=(side * 1.1, side * 0.8, side * 1.3),
        look_at=(0.0, 0.0, 0.0),
        up=(0.0, 0.0, 1.0),
        floor_point=(0.0, 0.0, -side),
        floor_normal=(0.0, 0.0, 1.0),
        lights=[(side * 2, side * 1.5, side), (side, -side * 2, side * 2), (-side * 1.5, side * 0.5, side * 2.5)],
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir", nargs="?", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--levels", type=int, nargs="*", default=[1, 2, 3, 4])
    ap.add_argument("--fields", type=int, nargs="*", default=[2000])
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    for level in a.levels:
        sphereflake(a.dir, level)
    for n in a.fields:
        field(a.dir, n)


if __name__ == "__main__":
    main()
