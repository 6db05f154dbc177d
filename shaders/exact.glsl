// Exact sums and squares for the robust intersections (sphere.glsl,
// cylinder.glsl); mirrors src/base/exact.rs.

// a + b as hi + lo exactly (Knuth's TwoSum); `precise` keeps the compiler
// from folding (s - a) back into b.
void two_sum(real a, real b, out real hi, out real lo) {
    precise real s = a + b;
    precise real bb = s - a;
    precise real e = (a - (s - bb)) + (b - bb);
    hi = s;
    lo = e;
}

// a^2 as hi + lo exactly (split at half the significand: 2^12 + 1 for
// float, 2^27 + 1 for double). Veltkamp's split rather than fma: llvmpipe may
// compute fma as a multiply and an add, which would make lo zero.
void two_square(real a, out real hi, out real lo) {
#ifdef GLINT_F64
    precise real c = 134217729.0LF * a;
#else
    precise real c = 4097.0 * a;
#endif
    precise real ah = c - (c - a);
    precise real al = a - ah;
    precise real p = a * a;
    precise real e = ((ah * ah - p) + 2.0 * ah * al) + al * al;
    hi = p;
    lo = e;
}

// f.f - r^2 with every rounding of the squares and sums carried along; see
// power() in src/base/exact.rs for why the plain form is not enough.
//
// POWER_FILTER (a device that skips a branch no invocation takes: llvmpipe
// from Mesa 24.3, a GPU): where f.f >= 2 r^2 the difference keeps at least
// half of f.f, so the plain form is within a few roundings of the exact one,
// and only origins near the surface pay for the exact sum. On a driver that
// runs both sides of every branch (llvmpipe before 24.3) the filter only
// adds work. The CPU reference keeps the exact sum everywhere: it is the
// oracle (docs/performance.md, The robust forms' cheap filter).
real power(vec3r f, real r) {
#ifdef POWER_FILTER
    real ff = dot(f, f);
    real r2 = r * r;
    if (ff >= 2.0 * r2) {
        return ff - r2;
    }
#endif
    real x, ex, y, ey, z, ez, rr, er;
    two_square(f.x, x, ex);
    two_square(f.y, y, ey);
    two_square(f.z, z, ez);
    two_square(r, rr, er);
    real s1, e1, s2, e2, s3, e3;
    two_sum(x, y, s1, e1);
    two_sum(s1, z, s2, e2);
    two_sum(s2, -rr, s3, e3);
    precise real lo = ((e1 + e2) + e3) + ((ex + ey) + ez - er);
    return s3 + lo;
}
