// One sample's ray tree, for `glint explain` (src/base/record.rs reads it;
// src/cpu records the same events at the same places): where the host
// defines RECORD_TREE, the invocation tracing the sample that record_at
// names (x, y, i, j) writes each event of its tree as an entry of
// RECORD_WORDS words into the Record block, its reals as floats, or as two
// words each in the f64 variant. Elsewhere every hook is empty and the
// shader is as it was: tests/explain.rs compiles the plain variants with
// the hooks cut out of the sources and requires the same SPIR-V.
#ifndef RECORD_GLSL
#define RECORD_GLSL
#ifdef RECORD_TREE
bool recording = false;
// The next word of the entry being written.
uint record_next = 0u;

// Opens an entry of `tag`; false where this invocation does not record or
// the record is full (the count still grows, and the host says so).
bool record_open(uint tag) {
    if (!recording) {
        return false;
    }
    uint k = record_count;
    record_count = k + 1u;
    if (k >= RECORD_CAPACITY) {
        return false;
    }
    record_next = k * RECORD_WORDS;
    record_words[record_next] = tag;
    record_next++;
    return true;
}

void record_word(uint w) {
    record_words[record_next] = w;
    record_next++;
}

void record_real(real v) {
#ifdef GLINT_F64
    uvec2 w = unpackDouble2x32(v);
    record_word(w.x);
    record_word(w.y);
#else
    record_word(floatBitsToUint(v));
#endif
}

void record_vec(vec3r v) {
    record_real(v.x);
    record_real(v.y);
    record_real(v.z);
}

void record_ray(uint type, uint depth, uint from, Ray r, real weight) {
    if (record_open(REC_RAY)) {
        record_word(type);
        record_word(depth);
        record_word(prim_in_file(from));
        record_vec(r.origin);
        record_vec(r.dir);
        record_real(weight);
    }
}

void record_miss(vec3r color) {
    if (record_open(REC_MISS)) {
        record_vec(color);
    }
}

void record_hit(Hit hit, vec3r p, vec3r outward, vec3r shading) {
    if (record_open(REC_HIT)) {
        record_word(prim_in_file(hit.prim));
        record_word(hit.material);
#if HAS_IMAGES
        // The generic variant has the images' code whatever the scene: the
        // uvs are recorded where the scene has image textures (g.lights.w),
        // as the CPU records them.
        bool uvs = g.lights.w != 0u;
        record_word(uvs ? 1u : 0u);
        vec2r uv = uvs ? surface_uv(hit, p) : vec2r(0.0);
#else
        record_word(0u);
        vec2r uv = vec2r(0.0);
#endif
        record_real(hit.t);
        record_vec(p);
        record_vec(outward);
        record_vec(shading);
        record_real(uv.x);
        record_real(uv.y);
    }
}

// The shadow ray to light k and whether it was blocked; then its nearest
// blocker, found again by a nearest-hit query (the any-hit query that
// decided stops at the first).
void record_shadow(uint k, Ray r, uint from, real dist, bool blocked) {
    if (record_open(REC_SHADOW)) {
        Hit b;
        bool found = blocked && intersect_ray(r, from, dist, false, b);
        record_word(k);
        record_word(blocked ? 1u : 0u);
        record_word(found ? prim_in_file(b.prim) : NONE);
        record_vec(r.origin);
        record_vec(r.dir);
        record_real(dist);
        record_real(found ? b.t : 0.0);
    }
}

void record_light(uint k, real n_dot_l, real cone, bool lit, vec3r ambient_term, vec3r diffuse_term, vec3r specular_term) {
    if (record_open(REC_LIGHT)) {
        record_word(k);
        record_word(lit ? 1u : 0u);
        record_real(n_dot_l);
        record_real(cone);
        record_vec(ambient_term);
        record_vec(lit ? diffuse_term : vec3r(0.0));
        record_vec(lit ? specular_term : vec3r(0.0));
    }
}

void record_color(uint tag, vec3r color) {
    if (record_open(tag)) {
        record_vec(color);
    }
}

void record_branch(real kr, real kt, bool follow) {
    if (record_open(REC_BRANCH)) {
        record_word(follow ? 1u : 0u);
        record_real(kr);
        record_real(kt);
    }
}

#define RECORD_BEGIN(x, y, i, j) recording = uvec4(x, y, i, j) == record_at
#define RECORD_RAY(type, depth, from, ray, weight) record_ray(type, depth, from, ray, weight)
#define RECORD_MISS(color) record_miss(color)
#define RECORD_HIT(hit, p, outward, shading) record_hit(hit, p, outward, shading)
#define RECORD_SHADOW(k, ray, from, dist, blocked) record_shadow(k, ray, from, dist, blocked)
#define RECORD_LIGHT(k, n_dot_l, cone, lit, a, d, s) record_light(k, n_dot_l, cone, lit, a, d, s)
#define RECORD_LOCAL(color) record_color(REC_LOCAL, color)
#define RECORD_BRANCH(kr, kt, follow) record_branch(kr, kt, follow)
#define RECORD_END(color) record_color(REC_END, color)
#else
#define RECORD_BEGIN(x, y, i, j)
#define RECORD_RAY(type, depth, from, ray, weight)
#define RECORD_MISS(color)
#define RECORD_HIT(hit, p, outward, shading)
#define RECORD_SHADOW(k, ray, from, dist, blocked)
#define RECORD_LIGHT(k, n_dot_l, cone, lit, a, d, s)
#define RECORD_LOCAL(color)
#define RECORD_BRANCH(kr, kt, follow)
#define RECORD_END(color)
#endif
#endif
