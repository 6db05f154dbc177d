"""The coefficients of glint's own atan2 and asin (shaders/own_math.glsl,
src/base/own_math.rs): minimax fits of the relative error, by Lawson's
iteratively reweighted least squares on Chebyshev nodes, in f64.

    python3 benches/own_math_fit.py     (needs numpy)

atan(t) = t + t s P(s), s = t^2, |t| <= tan(pi/8): P of degree 4.
asin(a) = a + a s Q(s), s = a^2, a <= 1/2: Q of degree 5.
Prints each fit's relative error and its coefficients rounded to f32.
"""

import numpy as np


def fit(g, s_max, degree):
    nodes = (1 - np.cos(np.linspace(0, np.pi, 4000))) / 2 * s_max
    s = nodes[1:]
    y = g(s)
    w = np.ones_like(s)
    for _ in range(60):
        a = np.vander(s, degree + 1, increasing=True)
        scale = np.sqrt(w) / np.abs(y)
        c, *_ = np.linalg.lstsq(a * scale[:, None], y * scale, rcond=None)
        err = np.abs(a @ c - y) / np.abs(y)
        w = w * err
        w /= w.sum()
    return c, err.max()


def atan_g(s):
    t = np.sqrt(s)
    return (np.arctan(t) / t - 1) / s


def asin_g(s):
    a = np.sqrt(s)
    return (np.arcsin(a) / a - 1) / s


for name, g, s_max, degree in [
    ("atan P", atan_g, np.tan(np.pi / 8) ** 2, 4),
    ("asin Q", asin_g, 0.25, 5),
]:
    c, err = fit(g, s_max, degree)
    # The polynomial's error reaches the function scaled by s <= s_max.
    print(f"{name}: degree {degree}, relative error of the function {err * s_max:.2e}")
    print("  " + ", ".join(repr(float(np.float32(x))) for x in c))

# The simulation's own exp2 (src/spec_worst/own.rs): 2^f = 1 + f E(f) on
# [-1/2, 1/2], fitted in f rather than f^2; relative error of 2^f.
f = np.cos(np.linspace(0, np.pi, 4000)) / 2
f = f[np.abs(f) > 1e-9]
for degree in (5, 6):
    g = (np.exp2(f) - 1) / f
    w = np.ones_like(f)
    for _ in range(60):
        a = np.vander(f, degree + 1, increasing=True)
        c, *_ = np.linalg.lstsq(a * np.sqrt(w)[:, None], g * np.sqrt(w), rcond=None)
        err = np.abs(1 + f * (a @ c) - np.exp2(f)) / np.exp2(f)
        w = w * err
        w /= w.sum()
    print(f"exp2 E: degree {degree}, relative error {err.max():.2e}")
    print("  " + ", ".join(repr(float(np.float32(x))) for x in c))
