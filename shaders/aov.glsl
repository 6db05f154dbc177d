// A render's AOVs (src/base/aov.rs, the table AOVS; src/cpu/aov.rs keeps
// the same): where the host defines AOVS, each pixel's invocation keeps
// what its first sample's eye ray met first, and writes it with the rays
// its samples traced (the counting variant's counts of this invocation)
// into the Aovs block. The words, what each captures and how they are
// stored come from the table, in the generated aovs.glsl. Elsewhere the
// hooks are empty and the shader is as it was.
#ifndef AOV_GLSL
#define AOV_GLSL
#ifdef AOVS
#include "aovs.glsl"

// Whether the sample being traced is the pixel's first.
bool aov_first = false;

#define AOV_SAMPLE(i, j) aov_first = (i) == 0u && (j) == 0u
// At a hit: the eye ray's (depth 1) of the pixel's first sample. `n` is the
// shading normal facing the ray, `m` the material with its textures applied.
#define AOV_HIT(depth, hit, n, m) \
    if ((depth) == 1u && aov_first) { \
        AOV_CAPTURE_HIT(hit, n, m) \
    }

void aov_write(uint at) {
    AOV_CAPTURE_PIXEL()
    AOV_STORE(at)
}
#define AOV_WRITE(at) aov_write(at)
#else
#define AOV_SAMPLE(i, j)
#define AOV_HIT(depth, hit, n, m)
#define AOV_WRITE(at)
#endif
#endif
