#version 450
#extension GL_GOOGLE_include_directive : require

// One function of the Vulkan spec's precision table on each pixel's own
// inputs (tests/spec_worst.rs): pixel = (f(a, b), a, b, 1), so that the
// test holds each result to f64 on the inputs it was given. PROBE picks
// the function.

#include "bindings.glsl"
#include "own_math.glsl"

uint probe_hash(uint i) {
    uint h = i * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    return (h >> 22u) ^ h;
}

// A float of random significand, exponent in [lo, hi], sign + or (signed) either.
float probe_float(uint h, int lo, int hi, bool signed_) {
    uint span = uint(hi - lo + 1);
    int e = lo + int((h >> 23u) % span);
    uint bits = uint(e + 127) << 23u | (h & 0x7fffffu);
    if (signed_ && (probe_hash(h) & 1u) != 0u) {
        bits |= 0x80000000u;
    }
    return uintBitsToFloat(bits);
}

// Uniform in [lo, hi).
float probe_uniform(uint h, float lo, float hi) {
    return lo + (hi - lo) * (float(h >> 8u) * (1.0 / 16777216.0));
}

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    uint i = (tile.rect.y + local.y) * 4096u + tile.rect.x + local.x;
    uint h1 = probe_hash(i);
    uint h2 = probe_hash(h1 ^ 0x9e3779b9u);
    float a = 0.0;
    float b = 0.0;
    float r = 0.0;
#if PROBE == 0
    a = probe_float(h1, -20, 20, true);
    b = probe_float(h2, -20, 20, true);
    r = a / b;
#elif PROBE == 1
    a = probe_float(h1, -126, 127, false);
    r = inversesqrt(a);
#elif PROBE == 2
    a = probe_float(h1, -126, 127, false);
    r = sqrt(a);
#elif PROBE == 3
    a = probe_float(h1, -60, 60, false);
    if (a >= 0.5 && a <= 2.0) {
        a = 4.0;
    }
    r = log2(a);
#elif PROBE == 4
    a = probe_uniform(h1, 0.5, 2.0);
    r = log2(a);
#elif PROBE == 5
    a = probe_uniform(h1, -30.0, 30.0);
    r = exp2(a);
#elif PROBE == 6
    // Results within f32's normal range: |b log2(a)| <= 100.
    a = probe_uniform(h1, 0.25, 4.0);
    b = probe_uniform(h2, 0.0, 50.0);
    r = pow(a, b);
#elif PROBE == 7
    a = probe_float(h1, -20, 20, true);
    r = atan(a);
#elif PROBE == 8
    a = probe_uniform(h1, -1.0, 1.0);
    r = asin(a);
#elif PROBE == 9
    a = probe_uniform(h1, -1.0, 1.0);
    r = acos(a);
#elif PROBE == 10
    a = probe_float(h1, -20, 20, true);
    b = probe_float(h2, -20, 20, true);
    r = atan(a, b);
#elif PROBE == 11
    a = probe_uniform(h1, -3.14159265, 3.14159265);
    r = sin(a);
#elif PROBE == 12
    a = probe_uniform(h1, -3.14159265, 3.14159265);
    r = cos(a);
#elif PROBE == 13
    // a b - round(a b): 0 where the product and the sum are rounded apart,
    // the product's rounding error where they are fused.
    a = probe_float(h1, -4, 4, true);
    b = probe_float(h2, -4, 4, true);
    precise float p = a * b;
    r = a * b - p;
#elif PROBE == 14
    // A denormal product.
    a = probe_float(h1, -70, -66, true);
    b = probe_float(h2, -70, -66, true);
    r = a * b;
#elif PROBE == 15
    a = probe_float(h1, -20, 20, true);
    b = probe_float(h2, -20, 20, true);
    r = own_atan2(a, b);
#elif PROBE == 16
    a = probe_uniform(h1, -1.0, 1.0);
    r = own_asin(a);
#elif PROBE == 17
    a = probe_float(h1, -20, 20, false);
    r = log(a);
#elif PROBE == 18
    a = probe_uniform(h1, -20.0, 20.0);
    r = exp(a);
#elif PROBE == 19
    a = probe_float(h1, -4, 4, true);
    b = probe_float(h2, -4, 4, true);
    precise float p = a * b;
    r = fma(a, b, -p);
#endif
    pixels[local.y * tile.rect.z + local.x] = vec4(r, a, b, 1.0);
}
