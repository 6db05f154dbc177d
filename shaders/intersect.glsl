// Nearest hit and any hit over every primitive; mirrors src/cpu/intersect.rs.
// Each kind's intersect and normal are in its include (shaders/prim/), the
// scans over the kinds in scans.glsl, over the lists of kinds that
// kinds.glsl defines: the host generates it from its table of kinds
// (src/prim/mod.rs, src/gpu/generated.rs).
//
// Self-intersection is prevented without an epsilon: a ray that leaves a
// surface carries that primitive's id (NONE for an eye ray), and each kind
// knows whether such a ray can meet it again.

#ifdef INTERSECT_NAIVE
// The textbook forms' fixed epsilon (--intersect naive), instead of knowing
// which surface a ray left.
const real NAIVE_EPSILON = 1e-4;
#else
#include "exact.glsl"
#endif

// How far rays leaving a triangle start off it, relative to the size of
// their coordinates (lift() below).
const real LIFT = 1.0 / 16384.0;

// The nearest hit. Besides t and the primitive's id it carries what shading
// needs of the primitive, picked up in the loop where the primitive's data
// is already loaded: reading it again by a per-pixel index would cost one
// load per lane.
struct Hit {
    real t;
    uint prim;
    uint material;
    vec4r shape;            // what the kind's normal needs (<kind>_shape)
};

// p moved off the surface along the unit `side`, by 2^-14 of the largest
// coordinate of p and of the ray's origin o (512 ulps in f32): more than
// the rounding of p = o + t d and of t can put it behind a neighbouring
// triangle's plane. The same distance in f64, so that both precisions
// trace the same model. For the kinds that ask for it (scans.glsl's
// leave()); mirrors lift() in src/cpu/intersect.rs.
vec3r lift(vec3r p, vec3r o, vec3r side) {
    vec3r a = max(abs(p), abs(o));
    return p + side * (max(a.x, max(a.y, a.z)) * LIFT);
}

#include "kinds.glsl"
#include "scans.glsl"

#ifdef USE_BVH
#include "bvh.glsl"
#endif

// The nearest hit with t in (0, t_max): the BVH's kinds, then the others.
// With the tables, an eye ray (`eye`) reads its tile's list in place of the
// walk (tables.glsl); mirrors intersect_scene and intersect_eye in
// src/cpu/intersect.rs.
bool intersect_ray(Ray r, uint from, real t_max, bool eye, out Hit hit) {
    hit = Hit(t_max, NONE, 0u, vec4r(0.0));
#if defined(USE_TABLES)
    bvh_nearest(r, from, hit, eye ? eye_list(r.dir) : uvec2(0u, TABLE_WALK));
#elif defined(USE_BVH)
    bvh_nearest(r, from, hit);
#endif
    scan_nearest(r, from, hit);
    return hit.prim != NONE;
}

// The nearest hit with t in (0, t_max), walking the tree.
bool intersect_scene(Ray r, uint from, real t_max, out Hit hit) {
    return intersect_ray(r, from, t_max, false, hit);
}

#if HAS_SHADOWS
// Whether anything lies on the ray strictly between 0 and dist, towards the
// light l: through its light buffer where it has one (tables.glsl).
bool occluded(Ray r, uint from, real dist, Light l) {
#if defined(USE_TABLES)
    real bound;
    uvec2 list = shadow_list(r, dist, l, bound);
    if (bvh_occluded(r, from, dist, list, bound)) {
        return true;
    }
#elif defined(USE_BVH)
    if (bvh_occluded(r, from, dist)) {
        return true;
    }
#endif
    return scan_occluded(r, from, dist);
}
#endif
