#!/usr/bin/env python3
"""Writes the scenes of scenes/extreme/. Run from this directory; the TOML
files are committed, this script says how they were made. docs/stability.md
explains each case."""

def v(x):
    return "[" + ", ".join(repr(float(c)) for c in x) + "]"

def header(comment, width=320, height=240, depth=3, shadows=True, bg=(0.3, 0.45, 0.7), samples=1):
    lines = ["# " + l if l else "#" for l in comment.strip().splitlines()]
    return "\n".join(lines) + f"""

[image]
width = {width}
height = {height}
samples = {samples}

[render]
max_depth = {depth}
shadows = {str(shadows).lower()}
background = {v(bg)}
"""

def look_at(eye, at, vfov, up=(0, 1, 0)):
    return f"""
[camera]
eye = {v(eye)}
look_at = {v(at)}
up = {v(up)}
vfov = {float(vfov)!r}
"""

def screen(eye, center, right, up):
    return f"""
[camera]
eye = {v(eye)}
screen_center = {v(center)}
screen_right = {v(right)}
screen_up = {v(up)}
"""

def material(name, ambient=(0, 0, 0), diffuse=(0, 0, 0), specular=(0, 0, 0), shininess=1.0, reflectivity=0.0):
    return f"""
[materials.{name}]
ambient = {v(ambient)}
diffuse = {v(diffuse)}
specular = {v(specular)}
shininess = {float(shininess)!r}
reflectivity = {float(reflectivity)!r}
"""

def sphere(center, radius, mat):
    return f"""
[[spheres]]
center = {v(center)}
radius = {float(radius)!r}
material = "{mat}"
"""

def plane(point, normal, mat):
    return f"""
[[planes]]
point = {v(point)}
normal = {v(normal)}
material = "{mat}"
"""

def point_light(pos, ambient=(0.1, 0.1, 0.1), diffuse=(1, 1, 1), specular=(1, 1, 1), attenuation=None):
    s = f"""
[[lights]]
type = "point"
position = {v(pos)}
ambient = {v(ambient)}
diffuse = {v(diffuse)}
specular = {v(specular)}
"""
    if attenuation:
        s += f"attenuation = {v(attenuation)}\n"
    return s

def directional(direction, ambient=(0, 0, 0), diffuse=(1, 1, 1), specular=(1, 1, 1)):
    return f"""
[[lights]]
type = "directional"
direction = {v(direction)}
ambient = {v(ambient)}
diffuse = {v(diffuse)}
specular = {v(specular)}
"""

def spot(pos, direction, cutoff, exponent, ambient=(0, 0, 0), diffuse=(1, 1, 1), specular=(1, 1, 1)):
    return f"""
[[lights]]
type = "spot"
position = {v(pos)}
direction = {v(direction)}
ambient = {v(ambient)}
diffuse = {v(diffuse)}
specular = {v(specular)}
cutoff = {float(cutoff)!r}
exponent = {float(exponent)!r}
"""

def write(name, text):
    with open(name + ".toml", "w") as f:
        f.write(text)

BALL = material("ball", (0.1, 0.02, 0.02), (0.7, 0.15, 0.1), (0.6, 0.6, 0.6), 60, 0.3)
GROUND = material("ground", (0.08, 0.08, 0.06), (0.55, 0.55, 0.45), (0.1, 0.1, 0.1), 10)

# A unit sphere resting on a ground sphere of radius R.
for exp in (4, 5, 6):
    R = 10.0 ** exp
    write(f"giant-ground-1e{exp}", header(f"""
A unit sphere resting on a "ground plane" that is a sphere of radius 1e{exp}.
The camera is 1.5 units above the ground: f.f is about 1e{2*exp} while the
power f.f - r^2 is about 3e{exp}, so the plain form loses the hit distance.
Robust: no self-shadow speckles on the lit ground; agrees with f64.""", depth=2)
          + look_at((0, 1.5, 6), (0, 0, 0), 50) + BALL + GROUND
          + sphere((0, 0, 0), 1, "ball") + sphere((0, -1 - R, 0), R, "ground")
          + point_light((4, 8, 6), (0.2, 0.2, 0.2)))

# Tiny spheres seen from 10 and 100 radii, magenta background for the hit mask.
for exp in (3, 4, 5):
    r = 10.0 ** -exp
    write(f"tiny-1e-{exp}", header(f"""
Two spheres of radius 1e-{exp}, one 10 radii from the eye and one 100 radii.
Magenta background, so that which pixels hit a sphere can be read off the
image. A fixed epsilon of 1e-4 is larger than these distances once the
radius is small enough; the robust forms have no epsilon.""", bg=(1, 0, 1), depth=1)
          + look_at((0, 0, 0), (0, 0, -1), 40)
          + material("white", (0.1, 0.1, 0.1), (0.8, 0.8, 0.8), (0.5, 0.5, 0.5), 20)
          + sphere((-2 * r, 0, -10 * r), r, "white") + sphere((20 * r, 5 * r, -100 * r), r, "white")
          + point_light((5 * r, 10 * r, 5 * r), (0.1, 0.1, 0.1)))

def small_world(offset=(0, 0, 0), scale=1.0, comment="", attenuation=None):
    o = offset
    def p(x):
        return tuple(scale * c + d for c, d in zip(x, o))
    return (look_at(p((0.0, 1.2, 4.0)), p((0.0, 0.2, 0.0)), 45)
            + BALL + GROUND + material("mirror", (0, 0, 0), (0.05, 0.05, 0.05), (0.9, 0.9, 0.9), 200, 0.8)
            + sphere(p((0.0, 0.3, 0.0)), 0.3 * scale, "ball")
            + sphere(p((0.7, 0.05, 0.4)), 0.05 * scale, "ball")
            + sphere(p((-0.8, 0.5, -0.5)), 0.5 * scale, "mirror")
            + plane(p((0.0, 0.0, 0.0)), (0, 1, 0), "ground")
            + point_light(p((2.0, 4.0, 3.0)), (0.15, 0.15, 0.15), attenuation=attenuation)
            + directional((-1, -2, -1), diffuse=(0.2, 0.2, 0.25), specular=(0.2, 0.2, 0.2)))

for name, off in [("0", 0.0), ("1e3", 1e3), ("1e4", 1e4), ("1e5", 1e5), ("1e6", 1e6)]:
    write(f"translated-{name}", header(f"""
The same small world (smallest feature: a sphere of radius 0.05, a plane
0.25 below a sphere) translated by {off:g} along every axis, camera and
lights too. glint renders camera-relative, so the image should not change;
in world coordinates f32 spaces {off:g} by {off * 2**-23 if off else 0:.2g}.""")
          + small_world((off, off, off)))

for k in (-56, -40, -20, -10, 0, 10, 20):
    s = 2.0 ** k
    write(f"scaled-2e{k}", header(f"""
The small world with every length scaled by 2^{k} (no attenuation, so the
light does not depend on scale). Scaling by a power of two is exact in
floating point: without an absolute epsilon the image must not change.""")
          + small_world(scale=s))

write("grazing", header("""
Grazing light and tangent rays: a directional light at N.L = 1e-3 over a
plane, a point light skimming a sphere's terminator, and the sphere's
silhouette, where eye rays are tangent to it.""", depth=2)
      + look_at((0, 2, 6), (0, 0.5, 0), 40) + BALL + GROUND
      + plane((0, 0, 0), (0, 1, 0), "ground") + sphere((0, 1, 0), 1, "ball")
      + directional((-1.0, -1e-3, 0.0), diffuse=(1, 1, 1), specular=(0.5, 0.5, 0.5))
      + point_light((4, 1, 0), (0.05, 0.05, 0.05), diffuse=(0.5, 0.5, 0.5)))

INSIDE = material("wall", (0.2, 0.1, 0.05), (0.6, 0.5, 0.4), (0, 0, 0), 1)
for name, eye in [("center", (0, 0, 0)), ("0999", (2.997, 0, 0))]:
    write(f"inside-{name}", header(f"""
The eye inside a sphere of radius 3 ({'at the centre' if name == 'center' else 'at 0.999 r'}),
a point light at the centre. N.L = 1 at every hit and the wall has no
specular term, so every pixel is att * (Ia Ka + Id Kd) with att = 1/(1 +
0.1*3 + 0.01*9): 0.2*0.2/1.39 + 0.6/1.39 and so on per channel.""", depth=1)
          + look_at(eye, (eye[0] - 1, 0, 0), 60) + INSIDE + sphere((0, 0, 0), 3, "wall")
          + point_light((0, 0, 0), (0.2, 0.2, 0.2), (1, 1, 1), (1, 1, 1), attenuation=(1, 0.1, 0.01)))

write("touching", header("""
Touching spheres (centres exactly 2r apart), nearly touching ones (2r -
1e-6, overlapping by a micron), and intersecting ones, on a floor, lit from
above so that the contact points are in each other's shadow.""")
      + look_at((0, 2.5, 7), (0, 0, -1), 45) + BALL + GROUND
      + sphere((-3, 0, 0), 1, "ball") + sphere((-1, 0, 0), 1, "ball")
      + sphere((1, 0, 0), 1, "ball") + sphere((3 - 1e-6, 0, 0), 1, "ball")
      + sphere((-0.5, 0, -3), 1, "ball") + sphere((0.5, 0.3, -3), 1, "ball")
      + plane((0, -1, 0), (0, 1, 0), "ground")
      + point_light((0, 10, 2), (0.1, 0.1, 0.1)))

write("light-on-surface", header("""
A point light exactly on the floor plane, beside a sphere: the floor sees it
edge-on (N.L = 0), the point under it is at distance 0. Output stays
finite.""")
      + look_at((0, 3, 6), (0, 0, 0), 45) + BALL + GROUND
      + plane((0, 0, 0), (0, 1, 0), "ground") + sphere((1.5, 1, 0), 1, "ball")
      + point_light((0, 0, 0), (0.1, 0.1, 0.1), attenuation=(1, 0, 0.1)))

write("light-inside-sphere", header("""
The only light is inside an opaque sphere: nothing outside can see it, so
with no ambient light and a black background the whole image is black.""", bg=(0, 0, 0))
      + look_at((0, 2, 6), (0, 0, 0), 45) + BALL + GROUND
      + plane((0, -1.5, 0), (0, 1, 0), "ground") + sphere((0, 0, 0), 1, "ball")
      + sphere((2.5, -0.5, 0), 1, "ball")
      + point_light((0, 0, 0), (0, 0, 0)))

shiny = header("""
Shininess 0, 1, 1e2, 1e3, 1e4 and 1e5, left to right. x^0 = 1, so the first
sphere's specular term is constant where N.L > 0; the last has a highlight
a pixel or two wide, where f32's N.H decides the value.""", depth=1)
shiny += look_at((0, 0, 9), (0, 0, 0), 40) + point_light((0, 2, 9), (0.1, 0.1, 0.1))
for i, n in enumerate([0, 1, 1e2, 1e3, 1e4, 1e5]):
    shiny += material(f"s{i}", (0.05, 0.05, 0.05), (0.3, 0.3, 0.5), (0.8, 0.8, 0.8), n)
    shiny += sphere((-3.75 + 1.5 * i, 0, 0), 0.65, f"s{i}")
write("shininess", shiny)

for name, kr in [("1", 1.0), ("09", 0.9)]:
    write(f"mirrors-{name}", header(f"""
The eye between two parallel mirrors of reflectivity {kr}, depth 64. The only
light is ambient, so every bounce adds Ia Ka and each pixel is
Ia Ka (1 + kr + ... + kr^63) = {'64 Ia Ka' if kr == 1 else 'Ia Ka (1 - 0.9^64) / 0.1'}.""", width=9, height=9, depth=64, bg=(0, 0, 0))
          + screen((0, 0, 0), (0, 0, -0.5), (0.5, 0, 0), (0, 0.5, 0))
          + material("mirror", (1.0, 0.5, 0.25), (0, 0, 0), (0, 0, 0), 1, kr)
          + plane((0, 0, -1), (0, 0, 1), "mirror") + plane((0, 0, 1), (0, 0, -1), "mirror")
          + directional((0, -1, 0), (0.01, 0.02, 0.03), (0, 0, 0), (0, 0, 0)))

def lights_scene(n):
    text = header(f"""
{'One point light of intensity I' if n == 1 else f'{n} point lights at the same place, each of intensity I/{n}'}.
lights-1 and lights-1024 must give the same image.""", width=160, height=120, depth=2)
    text += look_at((0, 1.5, 5), (0, 0.3, 0), 45) + BALL + GROUND
    text += sphere((0, 0.5, 0), 0.5, "ball") + plane((0, 0, 0), (0, 1, 0), "ground")
    for _ in range(n):
        text += point_light((2, 3, 2), (0.2 / n, 0.2 / n, 0.2 / n), (1.0 / n, 0.9 / n, 0.8 / n), (1.0 / n, 1.0 / n, 1.0 / n))
    return text
write("lights-1", lights_scene(1))
write("lights-1024", lights_scene(1024))

for e in (-30, -15, 15, 30):
    I = 10.0 ** e
    write(f"intensity-1e{e}", header(f"""
Every light {I:g} times as bright as usual (point, spot, directional). The
image is {I:g} times the usual one: never NaN or Inf, and the PFM and EXR
outputs keep the values.""", bg=(0, 0, 0))
          + look_at((0, 1.2, 4), (0, 0.2, 0), 45) + BALL + GROUND
          + sphere((0, 0.3, 0), 0.3, "ball") + plane((0, 0, 0), (0, 1, 0), "ground")
          + point_light((2, 4, 3), (0.15 * I,) * 3, (I,) * 3, (I,) * 3)
          + spot((-2, 3, 1), (2, -3, -1), 25, 5, diffuse=(0.5 * I,) * 3, specular=(0.5 * I,) * 3)
          + directional((-1, -2, -1), diffuse=(0.2 * I,) * 3, specular=(0.2 * I,) * 3))

# Refraction, triangles and cylinders (the refraction/triangles/SPD issue,
# part 7).

import math

def glass(name, ior, transmittance=1.0, reflectivity=0.0, ambient=(0, 0, 0), diffuse=(0, 0, 0), specular=(0, 0, 0), shininess=1.0):
    return material(name, ambient, diffuse, specular, shininess, reflectivity) + \
        f"transmittance = {float(transmittance)!r}\nior = {float(ior)!r}\n"

def triangle(a, b, c, mat):
    return f"""
[[triangles]]
vertices = [{v(a)}, {v(b)}, {v(c)}]
material = "{mat}"
"""

def mesh(file, mat, scale=1.0, translate=(0, 0, 0)):
    return f"""
[[meshes]]
file = "{file}"
material = "{mat}"
scale = {float(scale)!r}
translate = {v(translate)}
"""

def cylinder(base, base_radius, apex, apex_radius, mat):
    return f"""
[[cylinders]]
base = {v(base)}
base_radius = {float(base_radius)!r}
apex = {v(apex)}
apex_radius = {float(apex_radius)!r}
material = "{mat}"
"""

write("refract-grazing", header("""
Refraction at grazing entry: the eye 0.05 above a sheet of water (a plane
of index 1.33 that transmits 0.8 and reflects 0.2) looks toward the
horizon, so rays enter it at up to 89.9 degrees from the normal; under it a
floor and a sphere, over it a glass sphere of index 1.5 whose silhouette
rays enter it tangentially. Depth 5.""", depth=5)
      + look_at((0, 0.05, 6), (0, -0.1, 0), 50) + BALL + GROUND
      + glass("water", 1.33, 0.8, 0.2, specular=(0.3, 0.3, 0.3), shininess=50)
      + glass("glass", 1.5, 0.9, 0.1)
      + plane((0, 0, 0), (0, 1, 0), "water")
      + plane((0, -1, 0), (0, 1, 0), "ground")
      + sphere((0.8, -0.5, 1), 0.4, "ball")
      + sphere((-0.6, 0.45, 2), 0.4, "glass")
      + point_light((2, 5, 4), (0.1, 0.1, 0.1)))

R_GLASS = 1000.0
write("refract-critical", header(f"""
Total internal reflection near the critical angle: the eye inside a glass
sphere of radius {R_GLASS:g} and index 1.5, at 0.999 r, looking along the
wall with a 120-degree field. A ray whose line passes at h from the centre
meets the wall at sin(theta) = h / r and is totally reflected where that is
over 1/1.5, at every hit of its chord. The glass reflects nothing, transmits
everything and has an ambient colour; the only light is ambient and the
background black, so a pixel is Ka (the ray leaves) or 6 Ka (it is
reflected at all six hits of depth 6).""", width=160, height=120, depth=6, bg=(0, 0, 0))
      + look_at((0.999 * R_GLASS, 0, 0), (0.999 * R_GLASS - 1, 0.3, 0.2), 120)
      + glass("glass", 1.5, ambient=(0.5, 0.25, 0.125))
      + sphere((0, 0, 0), R_GLASS, "glass")
      + directional((0, -1, 0), (0.2, 0.2, 0.2), (0, 0, 0), (0, 0, 0)))

IOR1_WORLD = (look_at((0, 1.2, 4), (0, 0.2, 0), 45) + BALL + GROUND
              + sphere((0.0, 0.3, 0.0), 0.3, "ball") + sphere((-0.8, 0.5, -0.5), 0.5, "ball")
              + plane((0, 0, 0), (0, 1, 0), "ground")
              + point_light((2, 4, 3), (0.15, 0.15, 0.15)))
write("refract-ior1", header("""
Index 1 passes rays straight through: transmitters of index 1 with no
colour of their own (a sphere whose silhouette crosses the ball, a pane of
two triangles seen almost edge-on, at 1e-3 rad, and an open cylinder) in
front of a small world, shadows off. The image must be that of the world
without them: a ray goes on in the same direction from where it entered,
however grazing.""", depth=8, shadows=False)
      + IOR1_WORLD + glass("air", 1.0)
      + sphere((0.25, 0.45, 1.2), 0.35, "air")
      + triangle((-1.2, -0.1, 2.5), (-0.2, -0.1, 2.5 - 1e-3), (-1.2, 1.5, 2.5), "air")
      + triangle((-0.2, -0.1, 2.5 - 1e-3), (-0.2, 1.5, 2.5 - 1e-3), (-1.2, 1.5, 2.5), "air")
      + cylinder((0.6, 0.0, 0.8), 0.15, (0.6, 0.9, 0.8), 0.15, "air"))

WHITE = material("white", (0.1, 0.1, 0.1), (0.8, 0.8, 0.8), (0.3, 0.3, 0.3), 20)
for name, scale, translate in [("huge-1e5", 1e5, (0, 0, 0)), ("tiny-1e-5", 1e-5, (0, 0, 0)),
                               ("far-1e6", 1.0, (1e6, 1e6, 1e6)), ("near", 1.0, (0, 0, 0))]:
    s, t = scale, translate
    write(f"mesh-{name}", header(f"""
The smooth icosphere mesh (320 faces) scaled by {s:g} and moved by {t[0]:g}
along every axis, camera and light with it: seen from 3 radii, with a
floor triangle under it. Its image is the same at every scale and
offset: no holes at edges and vertices, no self-shadowing.""", bg=(1, 0, 1))
          + look_at((t[0], t[1] + 1.2 * s, t[2] + 3 * s), (t[0], t[1], t[2]), 45)
          + WHITE + GROUND
          + mesh("../meshes/icosphere-smooth.obj", "white", s, t)
          + triangle((t[0] - 4 * s, t[1] - s, t[2] + 4 * s), (t[0] + 4 * s, t[1] - s, t[2] + 4 * s),
                     (t[0], t[1] - s, t[2] - 6 * s), "ground")
          + point_light((t[0] + 3 * s, t[1] + 5 * s, t[2] + 4 * s), (0.1, 0.1, 0.1)))

# Slivers, as a mesh (slivers.obj): a rectangle cut into vertical strips
# 8 to a pixel, each two triangles, whose edges every eighth fall on a
# column of pixel centres; and a disc of fan triangles whose common vertex
# is on a pixel centre. The camera looks down -z at z = 0 from z = 3
# through a screen of half-size 0.8 x 0.6 at distance 1, so pixel (x, y)
# of 320 x 240 looks at (0.015 (x + 0.5) - 2.4, 1.8 - 0.015 (y + 0.5)).
def pixel_centre(x, y):
    return 0.015 * (x + 0.5) - 2.4, 1.8 - 0.015 * (y + 0.5)

STRIPS, FAN = 640, 1000
width = 0.015 / 8
# The outer edges half-way between pixel centres, edge 4 on one.
x0 = pixel_centre(60, 0)[0] - 4 * width
cx, cy = pixel_centre(220, 119)
with open("slivers.obj", "w") as f:
    f.write("# Slivers for slivers.toml; written by generate.py.\n")
    for i in range(STRIPS + 1):
        f.write(f"v {x0 + i * width!r} -0.5 0.0\nv {x0 + i * width!r} 0.5 0.0\n")
    for i in range(STRIPS):
        a, b, c, d = 2 * i + 1, 2 * i + 3, 2 * i + 4, 2 * i + 2
        f.write(f"f {a} {b} {c}\nf {a} {c} {d}\n")
    centre = 2 * (STRIPS + 1) + 1
    f.write(f"v {cx!r} {cy!r} 0.0\n")
    for i in range(FAN):
        t = 2 * math.pi * i / FAN
        f.write(f"v {cx + 0.5 * math.cos(t)!r} {cy + 0.5 * math.sin(t)!r} 0.0\n")
    for i in range(FAN):
        f.write(f"f {centre} {centre + 1 + i} {centre + 1 + (i + 1) % FAN}\n")

write("triangle-slivers", header(f"""
Slivers: a rectangle 1.2 wide cut into {STRIPS} vertical strips 8 to a
pixel, each two triangles of aspect 530, and a disc of radius 0.5 cut into
{FAN} fan triangles that all meet at its centre, on a magenta background
(slivers.obj, written by generate.py). Every eighth strip edge lies on a
column of pixel centres and the disc's centre on a pixel centre, so eye
rays pass within rounding of shared edges and of a vertex shared by {FAN}
triangles: watertight intersection leaves no magenta pixel inside either
shape.""", bg=(1, 0, 1), depth=1)
      + screen((0, 0, 3), (0, 0, 2), (0.8, 0, 0), (0, 0.6, 0)) + WHITE
      + mesh("slivers.obj", "white")
      + point_light((0, 0, 5), (0.2, 0.2, 0.2)))

write("cylinder-axis", header("""
Rays along a cylinder's axis: the eye on the axis of an open pipe of radius
1 and length 40, looking down it, so that the centre pixel's ray is
parallel to the axis (A = 0: no hit, the background at the far end) and
the others meet the wall at ever smaller angles; inside it, a cone seen
from straight above its apex, whose axis is another ray's.""", width=161, height=121, depth=3)
      + look_at((0, 0, 0), (0, 0, -1), 60)
      + BALL + GROUND
      + cylinder((0, 0, -40), 1, (0, 0, 0.5), 1, "ground")
      + cylinder((0.5, 0.3, -6), 0.3, (0.5, 0.3, -5), 0, "ball")
      + point_light((0, 0.5, -3), (0.1, 0.1, 0.1)))

write("cylinder-along", header("""
Rays along a cone's surface: the eye on the line of one of the sides of a
cone of half-angle 45 degrees, 0.5 beyond its apex, looking down that
side, so that the centre pixel's ray lies in the surface (A = 0, solved
linearly) and its neighbours graze it; with a thin rod (radius 1e-3,
length 10) seen end-on and one side-on, and a cylinder's silhouette, where
eye rays are tangent to it.""", width=321, height=241, depth=2)
      + look_at((0, 0.5, 0.5), (0, -0.5, -0.5), 70)
      + BALL + GROUND
      + cylinder((0, -3, 0), 3, (0, 0, 0), 0, "ground")
      + cylinder((0.5, -1.5, -2), 1e-3, (0.5, -1.5, -12), 1e-3, "ball")
      + cylinder((-1, -1, -2.5), 1e-3, (1, -2.5, -2.5), 1e-3, "ball")
      + cylinder((-1.2, -3, -3), 0.4, (-1.2, 0, -3), 0.4, "ball")
      + point_light((2, 3, 2), (0.15, 0.15, 0.15)))
