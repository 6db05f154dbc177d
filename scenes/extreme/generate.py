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

for k in (-20, -10, 0, 10, 20):
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
