// The ray tree to a fixed depth (docs/scene-format.md, Shading); mirrors
// src/cpu/trace.rs. A hit adds its local shading times its path weight and
// spawns a reflection ray (weight reflectivity) and a refraction ray
// (weight transmittance). The reflection ray is followed at once; a
// refraction ray waits on an explicit stack (GLSL has no recursion) and is
// traced when its path ends, the most recent first. Without a transmitting
// material (HAS_TRANSMISSION 0) there is no stack and this is the plain
// reflection loop.

#include "texture.glsl"
#include "record.glsl"
#include "aov.glsl"
#include "tree.glsl"

#if HAS_TRANSMISSION
// A refraction ray waiting to be traced.
struct Branch {
    Ray ray;
    uint from;
    uint depth;
    real weight;
};

// The direction of the ray refracted at a surface with unit normal n facing
// the incoming unit direction d, for eta = n_incoming / n_outgoing; false
// under total internal reflection. eta 1 passes d through unchanged.
bool refract_ray(vec3r d, vec3r n, real eta, out vec3r t) {
    t = d;
    if (eta == 1.0) {
        return true;
    }
    real cos_i = -dot(d, n);
    real k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if (k < 0.0) {
        return false;
    }
    t = normalize(d * eta + n * (eta * cos_i - sqrt(k)));
    return true;
}
#endif

#if HAS_OBJECTS
// A path through the ray tree, between two of its segments: the ray to
// trace next and what the path has gathered. The megakernel keeps one in
// registers for the whole tree (trace() below); the wavefront schedule
// (wavefront.glsl) keeps it in a buffer between its dispatches and runs one
// path_step per dispatch. Both run the same path_step, so both give the
// same bits.
struct Path {
    Ray ray;
    vec3r color;
    real weight;
    uint from;
    uint depth;
    // Only for the counters of --stats (count.glsl).
    uint ray_type;
    // The refraction rays waiting (branch_at / set_branch).
    uint top;
};

Path start_path(Ray ray) {
    return Path(ray, vec3r(0.0), 1.0, NONE, 1u, RAY_EYE, 0u);
}

#if HAS_TRANSMISSION && defined(WAVEFRONT)
// The wavefront's stack is in the path's buffer (wavefront.glsl).
Branch branch_at(uint k);
void set_branch(uint k, Branch b);
#elif HAS_TRANSMISSION
// The megakernel's stack: private to the invocation.
Branch branch_stack[STACK_SIZE];

Branch branch_at(uint k) {
    return branch_stack[k];
}

void set_branch(uint k, Branch b) {
    branch_stack[k] = b;
}
#endif

// Traces the path's ray and shades its hit, then sets up the next segment:
// the reflection ray where the surface reflects, else the latest refraction
// ray waiting. False where the path has ended (its colour is final).
bool path_step(inout Path s) {
    // Whether this path goes on with the reflection ray.
    bool follow = false;
    COUNT_AS(s.ray_type);
    RECORD_RAY(s.ray_type, s.depth, s.from, s.ray, s.weight);
    Ray ray = s.ray;
    real weight = s.weight;
    uint depth = s.depth;
    Hit hit;
    // An eye ray reads its tile's list where the scene has the tables.
    bool met = intersect_ray(ray, s.from, INF, depth == 1u, hit);
    if (!met) {
        s.color += g.background.rgb * weight;
        RECORD_MISS(g.background.rgb * weight);
        TREE_NOTE(TREE_MISS);
    } else {
        if (depth == 1u) {
            COUNT(COUNT_EYE_HIT);
        }
        vec3r p = ray.origin + ray.dir * hit.t;
        // The geometric normal says which side the ray is on; the shading
        // normal is turned with it to face the ray.
        vec3r outward = surface(hit, p);
        vec3r shading = shading_normal(hit, p, outward);
        bool back = dot(outward, ray.dir) > 0.0;
        vec3r n = back ? -shading : shading;
        vec3r face = back ? -outward : outward;
        // Where the rays that leave on the ray's side start.
        vec3r above = leave(hit, p, ray.origin, face);
        Material m = material_at(hit.material);
#if HAS_TEXTURES
        apply_textures(m, hit, p);
#endif
        RECORD_HIT(hit, p, outward, shading);
        TREE_NOTE(TREE_HIT(hit.material));
        AOV_HIT(depth, hit, n, m);
        s.color += shade(above, n, -ray.dir, m, hit.prim) * weight;
        real kr = m.params.y;
        // The SPD's procedure (SPD_RAYS) spawns a ray wherever the
        // surface reflects or transmits, whatever the weight, and a
        // reflection ray at a transmitter too.
        bool spd_reflects = SPD_RAYS && kr != 0.0;
#if HAS_TRANSMISSION
        real kt = m.params.z;
        spd_reflects = spd_reflects || SPD_RAYS && kt > 0.0;
        if (depth < MAX_DEPTH && kt > 0.0) {
            // Entering where the ray meets the outward side: eta = 1/ior.
            real eta = back ? m.params.w : 1.0 / m.params.w;
            vec3r t;
            if (!refract_ray(ray.dir, n, eta, t)) {
                kr += kt;
            } else if (SPD_RAYS || weight * kt != 0.0) {
                COUNT(COUNT_REFRACT);
                vec3r below = leave(hit, p, ray.origin, -face);
                set_branch(s.top, Branch(Ray(below, t), hit.prim, depth + 1u, weight * kt));
                s.top++;
            }
        }
#endif
        follow = depth < MAX_DEPTH && (kr != 0.0 && weight * kr != 0.0 || spd_reflects);
        RECORD_BRANCH(kr, m.params.z, follow);
        if (follow) {
            COUNT(COUNT_REFLECT);
            s.weight = weight * kr;
            vec3r d = ray.dir - n * (2.0 * dot(ray.dir, n));
            s.ray = Ray(above, normalize(d));
            s.from = hit.prim;
            s.depth = depth + 1u;
            s.ray_type = RAY_REFLECT;
        }
    }
    // One return, at the end, as the loop was before path_step was split
    // out: with early returns the megakernel measured 1.10x the old one's
    // time on Mesa 22.3 (median; docs/performance.md, Schedules).
    bool goes_on = follow;
#if HAS_TRANSMISSION
    if (!follow && s.top != 0u) {
        s.top--;
        Branch b = branch_at(s.top);
        s.ray = b.ray;
        s.from = b.from;
        s.depth = b.depth;
        s.weight = b.weight;
        s.ray_type = RAY_REFRACT;
        goes_on = true;
    }
#endif
    return goes_on;
}
#endif

vec3r trace(Ray ray) {
    COUNT(COUNT_EYE);
#if HAS_OBJECTS
    Path s = start_path(ray);
    // Never unrolled: with MAX_DEPTH a constant the compiler could copy the
    // whole bounce up to 64 times, for a large and slow-to-compile shader.
    [[dont_unroll]] while (path_step(s)) {
    }
    RECORD_END(s.color);
    return s.color;
#else
    return g.background.rgb;
#endif
}
