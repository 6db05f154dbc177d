// A render's AOVs (src/base/aov.rs reads them; src/cpu/aov.rs keeps the
// same): where the host defines AOVS, each pixel's invocation keeps what
// its first sample's eye ray met first, and writes it with the rays its
// samples traced (the counting variant's counts of this invocation) into
// the Aovs block, three uvec4s a pixel. Elsewhere the hooks are empty and
// the shader is as it was.
#ifndef AOV_GLSL
#define AOV_GLSL
#ifdef AOVS
// Whether the sample being traced is the pixel's first.
bool aov_first = false;
uint aov_prim = NONE;
real aov_depth = 0.0;
vec3r aov_normal = vec3r(0.0);
vec3r aov_albedo = vec3r(0.0);

#define AOV_SAMPLE(i, j) aov_first = (i) == 0u && (j) == 0u
// At a hit: the eye ray's (depth 1) of the pixel's first sample. `n` is the
// shading normal facing the ray, `m` the material with its textures applied.
#define AOV_HIT(depth, hit, n, m) \
    if ((depth) == 1u && aov_first) { \
        aov_prim = prim_in_file((hit).prim); \
        aov_depth = (hit).t; \
        aov_normal = (n); \
        aov_albedo = (m).diffuse.rgb; \
    }

void aov_write(uint at) {
    uint rays = counted[COUNT_EYE] + counted[COUNT_REFLECT] + counted[COUNT_REFRACT]
        + counted[COUNT_SHADOW];
    aov_words[3u * at] = uvec4(floatBitsToUint(float(aov_depth)), aov_prim, rays, 0u);
    aov_words[3u * at + 1u] = uvec4(floatBitsToUint(vec3(aov_normal)), 0u);
    aov_words[3u * at + 2u] = uvec4(floatBitsToUint(vec3(aov_albedo)), 0u);
}
#define AOV_WRITE(at) aov_write(at)
#else
#define AOV_SAMPLE(i, j)
#define AOV_HIT(depth, hit, n, m)
#define AOV_WRITE(at)
#endif
#endif
