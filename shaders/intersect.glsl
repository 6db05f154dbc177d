// Nearest hit over spheres and planes; mirrors src/cpu/intersect.rs.
//
// Self-intersection is prevented without an epsilon: a ray that leaves a
// surface carries that primitive's id. A plane cannot be met again; a sphere
// is met again only by a ray leaving it inwards, at t = -2 (o - c).d.
// Primitive ids: spheres first, then planes; NONE for an eye ray.

#ifdef INTERSECT_NAIVE
// The textbook forms, kept to measure what the robust ones buy
// (--intersect naive): b^2 - c, the near root -b - sqrt, and a fixed epsilon
// instead of knowing which surface a ray left.
const real NAIVE_EPSILON = 1e-4;

real intersect_sphere(Ray r, vec3r center, real radius, bool from_self) {
    ON_TEST();
    vec3r f = r.origin - center;
    real b = dot(f, r.dir);
    real disc = b * b - (dot(f, f) - radius * radius);
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

real intersect_plane(Ray r, vec3r point, vec3r normal, bool from_self) {
    ON_TEST();
    real t = dot(point - r.origin, normal) / dot(r.dir, normal);
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
// power() in src/cpu/intersect.rs for why the plain form is not enough.
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

// Distance to a sphere along a unit-direction ray; negative for a miss.
real intersect_sphere(Ray r, vec3r center, real radius, bool from_self) {
    ON_TEST();
    vec3r f = r.origin - center;
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

real intersect_plane(Ray r, vec3r point, vec3r normal, bool from_self) {
    ON_TEST();
    if (from_self) {
        return -1.0;
    }
    real denom = dot(r.dir, normal);
    if (denom == 0.0) {
        return -1.0;
    }
    return dot(point - r.origin, normal) / denom;
}

#endif

// The nearest hit. Besides t and the primitive's id it carries what shading
// needs of the primitive, picked up in the loop where the primitive's data
// is already loaded: reading it again by a per-pixel index would cost one
// load per lane.
struct Hit {
    real t;
    uint prim;
    uint material;
    vec4r shape;            // a sphere's centre and radius; a plane's normal
};

#ifdef USE_BVH
#include "bvh.glsl"
#endif

// The nearest hit with t in (0, t_max); ties in t go to the lower primitive id.
bool intersect_scene(Ray r, uint from, real t_max, out Hit hit) {
    hit = Hit(t_max, NONE, 0u, vec4r(0.0));
#if HAS_SPHERES && defined(USE_BVH)
    bvh_nearest(r, from, hit);
#elif HAS_SPHERES
    SCENE_LOOP for (uint i = 0u; i < SPHERE_COUNT; i++) {
        vec4r s = spheres[i].center_radius;
        real t = intersect_sphere(r, s.xyz, s.w, from == i);
        if (t > 0.0 && t < hit.t) {
            hit = Hit(t, i, spheres[i].meta.x, s);
        }
    }
#endif
#if HAS_PLANES
    SCENE_LOOP for (uint i = 0u; i < PLANE_COUNT; i++) {
        uint id = SPHERE_COUNT + i;
        vec4r n = planes[i].normal;
        real t = intersect_plane(r, planes[i].point.xyz, n.xyz, from == id);
        if (t > 0.0 && t < hit.t) {
            hit = Hit(t, id, planes[i].meta.x, n);
        }
    }
#endif
    return hit.prim != NONE;
}

// The outward normal at p.
vec3r surface(Hit hit, vec3r p) {
    return hit.prim < SPHERE_COUNT ? (p - hit.shape.xyz) / hit.shape.w : hit.shape.xyz;
}
