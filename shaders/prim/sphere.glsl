// The sphere; mirrors src/prim/sphere.rs. A kind's include gives
// <name>_intersect (the distance along a unit-direction ray, negative for a
// miss; from_self: the ray leaves this primitive), <name>_shape (what the
// hit keeps of the primitive) and <name>_normal (the outward unit normal at
// a point of the surface, from that shape, or from the primitive at its
// index i in the kind's array where the shape cannot hold enough).
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

// As src/prim/sphere.rs's OFF_SURFACE: where a hit is off the surface by
// more than about 5e-4 of the radius (a ray from far away places it only to
// the rounding of its origin), the normal is the direction of p - c, not a
// vector of another length that would shade past the model's bound.
const real OFF_SURFACE = 1.0 / 1024.0;

vec3r sphere_normal(uint i, vec4r shape, vec3r p) {
    vec3r n = (p - shape.xyz) / shape.w;
    return abs(dot(n, n) - 1.0) > OFF_SURFACE ? normalize(n) : n;
}

#include "own_math.glsl"

// Latitude and longitude, as SphereR::uv: u about the y axis from 0 at -z
// through -x, +z (1/2) and +x; v from 0 at the -y pole to 1 at the +y pole.
// glint's own atan2 and asin (own_math.glsl): a driver's may be 4096 ULP
// off. They are f32 functions: the f64 shader takes them in f32, an error
// of about 1e-7 in uv.
vec2r sphere_uv(uint i, vec4r shape, vec3r p) {
    vec3r n = sphere_normal(i, shape, p);
    real y = clamp(n.y, -1.0, 1.0);
    real lon = real(own_atan2(float(n.x), float(n.z)));
    real lat = real(own_asin(float(y)));
    const real PI = 3.14159265358979323846;
    return vec2r(0.5 + lon / (PI + PI), 0.5 + lat / PI);
}
