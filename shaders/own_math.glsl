// glint's own atan2 and asin (docs/guarantees.md, glint's own functions);
// mirrors src/base/own_math.rs, which the CPU's f32 follows.
//
// The Vulkan spec lets a driver's atan and asin be 4096 ULP off (a relative
// 2.4e-4), and lavapipe's are about 1e-4 off: a texture that repeats
// thousands of times around a sphere showed it (tests/data/found/
// sphere-uv-accuracy.toml). These take only +, -, *, / and sqrt, whose
// errors the spec bounds to a few ULP, and are within about 4 ULP of the
// exact value (tests/own_math.rs measures them against f64).
//
// The polynomials are minimax fits of this project's own (benches/
// own_math_fit.py): atan(t) = t + t s P(s), s = t^2, on |t| <= tan(pi/8);
// asin(a) = a + a s Q(s), s = a^2, on a <= 1/2.
#ifndef GLINT_OWN_MATH_GLSL
#define GLINT_OWN_MATH_GLSL

const float OWN_PI = 3.14159265358979323846;
const float OWN_TAN_PI_8 = 0.41421356237309504880;

float own_atan_poly(float s) {
    return -0.3333333134651184
        + s * (0.1999954879283905
        + s * (-0.14264173805713654
        + s * (0.10745671391487122
        + s * -0.0645742416381836)));
}

float own_asin_poly(float s) {
    return 0.1666666567325592
        + s * (0.07500098645687103
        + s * (0.04459810256958008
        + s * (0.031115371733903885
        + s * (0.017081446945667267
        + s * 0.03380001708865166))));
}

// atan(y / x) in the quadrant of (x, y), as C's atan2, signed zeros
// included: atan2(+-0, -0) = +-pi, atan2(+-0, +0) = +-0.
float own_atan2(float y, float x) {
    float ax = abs(x);
    float ay = abs(y);
    float hi = max(ax, ay);
    float lo = min(ax, ay);
    float t = 0.0;
    float base = 0.0;
    if (lo > OWN_TAN_PI_8 * hi) {
        // atan(q) = pi/4 + atan((q - 1) / (q + 1)), q = lo / hi.
        t = (lo - hi) / (lo + hi);
        base = OWN_PI / 4.0;
    } else if (hi > 0.0) {
        t = lo / hi;
    }
    float s = t * t;
    float r = base + (t + t * s * own_atan_poly(s));
    if (ay > ax) {
        r = OWN_PI / 2.0 - r;
    }
    if ((floatBitsToUint(x) >> 31) != 0u) {
        r = OWN_PI - r;
    }
    return (floatBitsToUint(y) >> 31) != 0u ? -r : r;
}

// asin(y) for y in [-1, 1].
float own_asin(float y) {
    float a = abs(y);
    float r;
    if (a <= 0.5) {
        float s = a * a;
        r = a + a * s * own_asin_poly(s);
    } else {
        // asin(a) = pi/2 - 2 asin(w), w = sqrt((1 - a) / 2) <= 1/2; 1 - a
        // is exact here (Sterbenz).
        float s = (1.0 - a) * 0.5;
        float w = sqrt(s);
        r = OWN_PI / 2.0 - 2.0 * (w + w * s * own_asin_poly(s));
    }
    return (floatBitsToUint(y) >> 31) != 0u ? -r : r;
}

#endif
