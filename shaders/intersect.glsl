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
const float NAIVE_EPSILON = 1e-4;

float intersect_sphere(Ray r, vec3 center, float radius, bool from_self) {
    ON_TEST();
    vec3 f = r.origin - center;
    float b = dot(f, r.dir);
    float disc = b * b - (dot(f, f) - radius * radius);
    if (disc < 0.0) {
        return -1.0;
    }
    float root = sqrt(disc);
    float t = -b - root;
    if (t > NAIVE_EPSILON) {
        return t;
    }
    t = -b + root;
    return t > NAIVE_EPSILON ? t : -1.0;
}

float intersect_plane(Ray r, vec3 point, vec3 normal, bool from_self) {
    ON_TEST();
    float t = dot(point - r.origin, normal) / dot(r.dir, normal);
    return t > NAIVE_EPSILON ? t : -1.0;
}
#else
// a + b as hi + lo exactly (Knuth's TwoSum); `precise` keeps the compiler
// from folding (s - a) back into b.
void two_sum(float a, float b, out float hi, out float lo) {
    precise float s = a + b;
    precise float bb = s - a;
    precise float e = (a - (s - bb)) + (b - bb);
    hi = s;
    lo = e;
}

// a^2 as hi + lo exactly. Veltkamp's split rather than fma: llvmpipe may
// compute fma as a multiply and an add, which would make lo zero.
void two_square(float a, out float hi, out float lo) {
    precise float c = 4097.0 * a;
    precise float ah = c - (c - a);
    precise float al = a - ah;
    precise float p = a * a;
    precise float e = ((ah * ah - p) + 2.0 * ah * al) + al * al;
    hi = p;
    lo = e;
}

// f.f - r^2 with every rounding of the squares and sums carried along; see
// power() in src/cpu/intersect.rs for why the plain form is not enough.
float power(vec3 f, float r) {
    float x, ex, y, ey, z, ez, rr, er;
    two_square(f.x, x, ex);
    two_square(f.y, y, ey);
    two_square(f.z, z, ez);
    two_square(r, rr, er);
    float s1, e1, s2, e2, s3, e3;
    two_sum(x, y, s1, e1);
    two_sum(s1, z, s2, e2);
    two_sum(s2, -rr, s3, e3);
    precise float lo = ((e1 + e2) + e3) + ((ex + ey) + ez - er);
    return s3 + lo;
}

// Distance to a sphere along a unit-direction ray; negative for a miss.
float intersect_sphere(Ray r, vec3 center, float radius, bool from_self) {
    ON_TEST();
    vec3 f = r.origin - center;
    float b = dot(f, r.dir);
    if (from_self) {
        return -2.0 * b;
    }
    // The discriminant from the perpendicular distance to the centre rather
    // than b^2 - c, which loses every digit when the sphere is small against
    // its distance (Ray Tracing Gems ch. 7).
    vec3 l = f - r.dir * b;
    float disc = radius * radius - dot(l, l);
    if (disc < 0.0) {
        return -1.0;
    }
    float c = power(f, radius);
    float root = sqrt(disc);
    // The stable root pair: q never cancels, and t0 = c/q is the other root.
    float q = b >= 0.0 ? -b - root : -b + root;
    float t0 = c / q;
    float t1 = q;
    float near = min(t0, t1);
    float far = max(t0, t1);
    return near > 0.0 ? near : far;
}

float intersect_plane(Ray r, vec3 point, vec3 normal, bool from_self) {
    ON_TEST();
    if (from_self) {
        return -1.0;
    }
    float denom = dot(r.dir, normal);
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
    float t;
    uint prim;
    uint material;
    vec4 shape;             // a sphere's centre and radius; a plane's normal
};

// The nearest hit with t in (0, t_max).
bool intersect_scene(Ray r, uint from, float t_max, out Hit hit) {
    hit = Hit(t_max, NONE, 0u, vec4(0.0));
#if HAS_SPHERES
    SCENE_LOOP for (uint i = 0u; i < SPHERE_COUNT; i++) {
        vec4 s = spheres[i].center_radius;
        float t = intersect_sphere(r, s.xyz, s.w, from == i);
        if (t > 0.0 && t < hit.t) {
            hit = Hit(t, i, spheres[i].meta.x, s);
        }
    }
#endif
#if HAS_PLANES
    SCENE_LOOP for (uint i = 0u; i < PLANE_COUNT; i++) {
        uint id = SPHERE_COUNT + i;
        vec4 n = planes[i].normal;
        float t = intersect_plane(r, planes[i].point.xyz, n.xyz, from == id);
        if (t > 0.0 && t < hit.t) {
            hit = Hit(t, id, planes[i].meta.x, n);
        }
    }
#endif
    return hit.prim != NONE;
}

// The outward normal at p.
vec3 surface(Hit hit, vec3 p) {
    return hit.prim < SPHERE_COUNT ? (p - hit.shape.xyz) / hit.shape.w : hit.shape.xyz;
}
