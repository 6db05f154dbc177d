#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#ifdef WAVEFRONT
#extension GL_KHR_shader_subgroup_ballot : require
#endif

// One invocation per pixel of the current tile: the mean of the pixel's
// samples*samples eye rays, each traced to the fixed depth.

#include "bindings.glsl"
#include "tree.glsl"
#include "ray.glsl"
#include "intersect.glsl"
#include "shade.glsl"
#include "trace.glsl"
// Its own include too: a user's trace.glsl (shaders/experiments) may have none.
#include "aov.glsl"
#include "budget.glsl"

#ifdef WAVEFRONT
#include "wavefront.glsl"
#elif defined(CONTRAST)
// A level of contrast sampling: each invocation traces one listed entry,
// some samples of one pixel, and writes four words: their sum, least and
// greatest colour, and trees.
#include "contrast.glsl"

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    uint entry = (tile.rect.y + local.y) * REFINE_WIDTH + tile.rect.x + local.x;
    uint out_at = (local.y * tile.rect.z + local.x) * 4u;
    begin_counts();
    ContrastBatch b = ContrastBatch(vec3r(0.0), vec3r(0.0), vec3r(0.0), TREE_BASIS, false);
    if (entry < uint(refine_list.length())) {
        b = contrast_samples(refine_list[entry]);
    }
    float done = loops_completed() ? 1.0 : 0.0;
    pixels[out_at] = vec4(vec3(b.sum), done);
    pixels[out_at + 1u] = vec4(vec3(b.least), done);
    pixels[out_at + 2u] = vec4(vec3(b.most), done);
    pixels[out_at + 3u] = vec4(float(b.word & 0xffffu), float(b.word >> 16u), b.differ ? 1.0 : 0.0, done);
    end_counts();
}
#elif defined(REFINE_POINTS)
// A level of adaptive sampling's refinement: each invocation traces
// REFINE_POINTS listed points, one after another.
#include "adaptive.glsl"

void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    uint first = ((tile.rect.y + local.y) * REFINE_WIDTH + tile.rect.x + local.x) * REFINE_POINTS;
    uint out_at = (local.y * tile.rect.z + local.x) * REFINE_POINTS;
    begin_counts();
    vec3r colours[REFINE_POINTS];
    [[dont_unroll]] for (uint j = 0u; j < REFINE_POINTS; j++) {
        colours[j] = vec3r(0.0);
        if (first + j < uint(refine_list.length())) {
            colours[j] = trace_point(refine_list[first + j]);
        }
    }
    float done = loops_completed() ? 1.0 : 0.0;
    [[unroll]] for (uint j = 0u; j < REFINE_POINTS; j++) {
        pixels[out_at + j] = vec4(vec3(colours[j]), done);
    }
    end_counts();
}
#else
void main() {
    uvec2 local = gl_GlobalInvocationID.xy;
    if (local.x >= tile.rect.z || local.y >= tile.rect.w) {
        return;
    }
    uint x = tile.rect.x + local.x;
    uint y = tile.rect.y + local.y;
    begin_counts();
    uint samples = SAMPLES;
    vec3r sum = vec3r(0.0);
    [[dont_unroll]] for (uint j = 0u; j < samples; j++) {
        [[dont_unroll]] for (uint i = 0u; i < samples; i++) {
            RECORD_BEGIN(x, y, i, j);
            AOV_SAMPLE(i, j);
            sum += trace(primary_ray(x, y, i, j));
        }
    }
    pixels[local.y * tile.rect.z + local.x] = vec4(vec3(sum * (1.0 / real(samples * samples))), loops_completed() ? 1.0 : 0.0);
    AOV_WRITE(local.y * tile.rect.z + local.x);
    end_counts();
}
#endif
