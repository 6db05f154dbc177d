// The sphere; mirrors src/prim/sphere.rs. A kind's include gives
// <name>_intersect (the distance along a unit-direction ray, negative for a
// miss; from_self: the ray leaves this primitive), <name>_shape (what the
// hit keeps of the primitive) and <name>_normal (the outward unit normal at
// a point of the surface, from that shape).
//
// Self-intersection is prevented without an epsilon: a sphere is met again
// only by a ray leaving it inwards, at t = -2 (o - c).d.

#ifdef INTERSECT_NAIVE
// The textbook form, kept to measure what the robust one buys
// (--intersect naive): b^2 - c, the near root -b - sqrt, and a fixed epsilon
// instead of knowing which surface a ray left.
real sphere_intersect(Ray r, Sphere s, bool from_self) {
    vec3r f = r.origin - s.center_radius.xyz;
    real b = dot(f, r.dir);
    real disc = b * b - (dot(f, f) - s.center_radius.w * s.center_radius.w);
    if (disc < 0.0) {
        return -1.0;
    }
    real root = sqrt(disc);
    real t = -b - root;
    if (t > NAIVE_EPSILON) {
        return t;
    }
    t = -b + root;
    return t > NAIVE_EPSILON ? t : -1.0;
}
#else
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
// power() in src/prim/sphere.rs for why the plain form is not enough.
real power(vec3r f, real r) {
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

real sphere_intersect(Ray r, Sphere s, bool from_self) {
    real radius = s.center_radius.w;
    vec3r f = r.origin - s.center_radius.xyz;
    real b = dot(f, r.dir);
    if (from_self) {
        return -2.0 * b;
    }
    // The discriminant from the perpendicular distance to the centre rather
    // than b^2 - c, which loses every digit when the sphere is small against
    // its distance (Ray Tracing Gems ch. 7).
    vec3r l = f - r.dir * b;
    real disc = radius * radius - dot(l, l);
    if (disc < 0.0) {
        return -1.0;
    }
    real c = power(f, radius);
    real root = sqrt(disc);
    // The stable root pair: q never cancels, and t0 = c/q is the other root.
    real q = b >= 0.0 ? -b - root : -b + root;
    real t0 = c / q;
    real t1 = q;
    real near = min(t0, t1);
    real far = max(t0, t1);
    return near > 0.0 ? near : far;
}
#endif

vec4r sphere_shape(Sphere s) {
    return s.center_radius;
}

vec3r sphere_normal(vec4r shape, vec3r p) {
    return (p - shape.xyz) / shape.w;
}
